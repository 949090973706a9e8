#pragma once
/// @file atlas.hpp  Automatic lightmap UVs: the charts of charts.hpp packed into one square
/// texture atlas at a common texel density, so every texel of a chart stands for the same area
/// of the scene. Packing is next-fit decreasing-height shelf packing (Coffman et al. 1980,
/// "Performance bounds for level-oriented two-dimensional packing algorithms"); the density, or
/// the atlas size, is found by bisection.

#include <radiosity/error.hpp>
#include <radiosity/lightmap/charts.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

namespace radiosity {

/// Settings of automatic lightmap UVs.
struct UnwrapOptions {
    int size = 512;              ///< atlas width = height in texels (used when texel_density == 0)
    double texel_density = 0.0;  ///< texels per scene unit; > 0: the atlas size follows from it
    int gutter =
        2;  ///< empty texels kept on every side of each chart (charts are >= 2*gutter apart)
    ChartOptions charts{};  ///< how faces join charts (angles, creases, materials)
};

/// What make_lightmap_uvs made.
struct Atlas {
    int width = 0, height = 0;              ///< texels
    double texel_density = 0.0;             ///< texels per scene unit actually used
    std::size_t charts = 0;                 ///< number of charts
    std::vector<std::uint32_t> face_chart;  ///< chart of each face
};

namespace detail {

/// Largest atlas side, in texels (the texture limit of common GPUs).
inline constexpr int max_atlas_size = 16384;

/// Packing-rectangle sizes (texels) of the charts at a density: the chart's texels, at least
/// one in each direction, plus the gutter on both sides. Saturates far above any atlas size so
/// that huge densities cannot overflow.
inline std::vector<std::array<int, 2>> chart_rectangles(const std::vector<Chart>& charts,
                                                        double density, int gutter) {
    std::vector<std::array<int, 2>> r;
    r.reserve(charts.size());
    auto texels = [&](double extent) {
        const double t = std::ceil(extent * density);
        return static_cast<int>(std::clamp(t, 1.0, 4.0 * max_atlas_size)) + 2 * gutter;
    };
    for (const Chart& c : charts) r.push_back({texels(c.extent.x), texels(c.extent.y)});
    return r;
}

/// Next-fit decreasing-height shelf packing: rectangles in the given order (tallest first) go
/// left to right along a shelf as tall as its first one; one that does not fit starts a new
/// shelf on top. Writes each rectangle's corner to at; false when the shelves are higher than
/// height. The shelves' total height never grows with the width (a wider shelf holds at least
/// the same rectangles), so bisection over the size is sound. O(n).
inline bool pack_shelves(const std::vector<std::array<int, 2>>& rect,
                         const std::vector<std::uint32_t>& order, int width, int height,
                         std::vector<std::array<int, 2>>& at) {
    at.assign(rect.size(), {0, 0});
    long long x = 0, y = 0, shelf = 0;
    for (std::uint32_t i : order) {
        const auto [w, h] = rect[i];
        if (w > width) return false;
        if (x + w > width) {  // start a new shelf above the current one
            y += shelf;
            x = 0;
            shelf = 0;
        }
        if (shelf == 0) shelf = h;
        if (y + shelf > height) return false;
        at[i] = {static_cast<int>(x), static_cast<int>(y)};
        x += w;
    }
    return true;
}

}  // namespace detail

/// Makes lightmap UVs for every face corner: splits and flattens the faces into charts
/// (make_charts), then packs the charts' rectangles, each with `gutter` empty texels around it,
/// into a square atlas (shelf packing, tallest first, ties by chart index). With texel_density
/// 0 the atlas is size x size and the largest density that fits is found by bisection; with
/// texel_density > 0 the atlas is the smallest square (side a multiple of 4, at most 16384)
/// that holds the charts at that density. Each chart sits at an integer texel offset, so its
/// texels line up with the atlas. The UVs go to the mesh's halfedge texcoords (requested
/// here): the texcoord of halfedge h in face f is that of the corner h points to. Convention:
/// u, v in [0, 1], texel (x, y) covers [x/W, (x+1)/W] x [y/H, (y+1)/H], row 0 is the top of the
/// image (glTF); faces are counter-clockwise in (u, v). Throws Error for bad options, an empty
/// mesh, or charts that cannot fit. Deterministic. Cost: O(n log n) for n corners plus
/// O(charts) per bisection step.
template <class M>
Atlas make_lightmap_uvs(M& mesh, const UnwrapOptions& options = {}) {
    const int max_size = detail::max_atlas_size;
    if (options.size < 8 || options.size > max_size)
        throw Error("lightmap UVs: atlas size must lie in [8, " + std::to_string(max_size) +
                    "] texels, not " + std::to_string(options.size));
    if (!std::isfinite(options.texel_density) || options.texel_density < 0.0)
        throw Error("lightmap UVs: texel density must be finite and >= 0, not " +
                    std::to_string(options.texel_density));
    if (options.gutter < 0 || options.gutter > 64)
        throw Error("lightmap UVs: gutter must lie in [0, 64] texels, not " +
                    std::to_string(options.gutter));
    detail::check_chart_options(options.charts);
    if (mesh.n_faces() == 0) throw Error("lightmap UVs: the mesh has no faces");

    const std::vector<Chart> charts = make_charts(mesh, options.charts);
    const int gutter = options.gutter;
    // Tallest first, ties by index: the shelf order is the same at every density.
    std::vector<std::uint32_t> order(charts.size());
    std::iota(order.begin(), order.end(), std::uint32_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return charts[a].extent.y > charts[b].extent.y;
    });
    double widest = 0.0;
    for (const Chart& c : charts) widest = std::max(widest, c.extent.x);
    if (!(widest > 0.0)) widest = 1.0;  // only degenerate faces: any density will do

    std::vector<std::array<int, 2>> at;
    auto fits = [&](double density, int side) {
        return detail::pack_shelves(detail::chart_rectangles(charts, density, gutter), order, side,
                                    side, at);
    };
    auto too_many = [&](int side) {
        return Error("lightmap UVs: " + std::to_string(charts.size()) + " charts of at least " +
                     std::to_string(1 + 2 * gutter) + " x " + std::to_string(1 + 2 * gutter) +
                     " texels (with the gutter) do not fit in " + std::to_string(side) + " x " +
                     std::to_string(side) + " texels");
    };

    Atlas atlas;
    double density = options.texel_density;
    int side = options.size;
    if (density == 0.0) {
        // The widest chart must fit across: that bounds the density from above. At the bottom,
        // every chart is one texel wide.
        double hi = (side - 2 * gutter) / widest;
        double lo = std::min(hi, 1.0 / widest);
        if (!(lo > 0.0) || !fits(lo, side)) throw too_many(side);
        if (fits(hi, side)) {
            lo = hi;
        } else {
            for (int step = 0; step < 64 && hi - lo > 1e-9 * hi; ++step) {
                const double mid = 0.5 * (lo + hi);
                (fits(mid, side) ? lo : hi) = mid;
            }
        }
        density = lo;
    } else {
        // The smallest multiple of 4 that fits: bisection over side / 4, from a lower bound of
        // the rectangles' total area.
        const auto rect = detail::chart_rectangles(charts, density, gutter);
        double area = 0.0;
        for (const auto& r : rect) area += double(r[0]) * double(r[1]);
        // 4 lo is below the square root of the area, so it fails (but for the floor of 8).
        int lo = std::max(2, static_cast<int>(std::ceil(std::sqrt(area) / 4.0)) - 1);
        int hi = max_size / 4;
        if (lo >= hi || !fits(density, 4 * hi))
            throw Error("lightmap UVs: at " + std::to_string(density) +
                        " texels per unit the charts do not fit in " + std::to_string(max_size) +
                        " x " + std::to_string(max_size) + " texels");
        if (fits(density, 4 * lo)) lo = 1;  // 8 x 8 already holds them
        while (hi - lo > 1) {
            const int mid = lo + (hi - lo) / 2;
            (fits(density, 4 * mid) ? hi : lo) = mid;
        }
        side = 4 * hi;
    }
    if (!fits(density, side)) throw too_many(side);  // leaves the final placement in `at`

    atlas.width = atlas.height = side;
    atlas.texel_density = density;
    atlas.charts = charts.size();
    atlas.face_chart.assign(mesh.n_faces(), 0);
    const double W = atlas.width, H = atlas.height;
    std::vector<glm::vec2> uv;  // one face's corners, reused
    for (std::size_t c = 0; c < charts.size(); ++c) {
        const Chart& chart = charts[c];
        // The chart's texels start `gutter` texels inside its packing rectangle.
        const double x0 = at[c][0] + gutter, y0 = at[c][1] + gutter;
        for (std::size_t k = 0; k < chart.faces.size(); ++k) {
            const auto f = mesh.face_handle(static_cast<int>(chart.faces[k]));
            atlas.face_chart[chart.faces[k]] = static_cast<std::uint32_t>(c);
            uv.clear();
            for (const Vec2& p : chart.corners(k))
                uv.emplace_back((x0 + p.x * density) / W, (y0 + p.y * density) / H);
            set_corner_uvs(mesh, f, uv);
        }
    }
    return atlas;
}

}  // namespace radiosity
