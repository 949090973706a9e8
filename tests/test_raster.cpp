// The scan converter of geometry/raster.hpp against its definition: a pixel is covered when its
// centre passes all three exact fixed-point edge-function tests (top-left rule on the edges).
// Thousands of seeded random triangles, small, huge (to the guard band), long and thin,
// degenerate, on pixel-centre ties and off the raster, are scanned and compared pixel by pixel
// with that test made over the whole raster; and clip-space triangles give the same pixels
// through rasterize_triangle (the camera's) and rasterize_depth (the hemicube's).
#include <radiosity/detail/draw_nearest.hpp>
#include <radiosity/geometry/raster.hpp>
#include <radiosity/geometry/sampling.hpp>

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

using namespace radiosity;
using detail::ScreenVertex;

namespace {

constexpr std::int64_t sub = detail::subpixels;

/// A screen vertex at fixed-point position (sx, sy): all that coverage reads.
ScreenVertex at(std::int64_t sx, std::int64_t sy) {
    return {double(sx) / sub, double(sy) / sub, 0.0, 1.0, sx, sy, nullptr};
}

/// The definition: pixel (x, y) is covered when its centre lies inside all three edges of the
/// positively oriented triangle, or on an edge that the triangle owns (top-left rule).
std::vector<int> brute_force(ScreenVertex a, ScreenVertex b, ScreenVertex c, int width,
                             int height) {
    std::vector<int> hits(std::size_t(width) * height, 0);
    const std::int64_t area = detail::edge(a, b, c.sx, c.sy);
    if (area == 0) return hits;
    if (area < 0) std::swap(b, c);
    auto inside = [](const ScreenVertex& p, const ScreenVertex& q, std::int64_t x, std::int64_t y) {
        const std::int64_t e = detail::edge(p, q, x, y);
        return e > 0 || (e == 0 && detail::owns_edge(p, q));
    };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::int64_t cx = x * sub + sub / 2, cy = y * sub + sub / 2;
            if (inside(b, c, cx, cy) && inside(c, a, cx, cy) && inside(a, b, cx, cy))
                hits[std::size_t(y) * width + x] = 1;
        }
    return hits;
}

/// The pixels scan_triangle reports, counted (a pixel reported twice counts 2); runs must be
/// non-empty, inside the raster and in increasing rows.
std::vector<int> scanned(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c,
                         int width, int height, bool& well_formed) {
    std::vector<int> hits(std::size_t(width) * height, 0);
    int previous_row = -1;
    detail::scan_triangle(a, b, c, width, height, [&](int y, int begin, int end) {
        well_formed = well_formed && y > previous_row && y < height && 0 <= begin && begin < end &&
                      end <= width;
        previous_row = y;
        if (!well_formed) return;
        for (int x = begin; x < end; ++x) ++hits[std::size_t(y) * width + x];
    });
    return hits;
}

/// A random fixed-point coordinate in [lo, hi] pixels; on a pixel centre or a pixel corner
/// one time in four each, where the top-left rule decides.
std::int64_t coordinate(Rng& rng, double lo, double hi) {
    const double p = lo + (hi - lo) * rng.uniform();
    switch (rng.next() % 4) {
        case 0:
            return std::int64_t(std::floor(p)) * sub + sub / 2;
        case 1:
            return std::int64_t(std::floor(p)) * sub;
        default:
            return detail::to_subpixels(p);
    }
}

/// Three vertices of one of several kinds of triangle on a width x height raster.
std::array<ScreenVertex, 3> random_triangle(Rng& rng, int kind, int width, int height) {
    const double w = width, h = height, guard = detail::guard_pixels - 4096.0;
    auto point = [&](double lo_x, double hi_x, double lo_y, double hi_y) {
        return at(coordinate(rng, lo_x, hi_x), coordinate(rng, lo_y, hi_y));
    };
    switch (kind) {
        case 0:  // small, on and around the raster
            return {point(-3, w + 3, -3, h + 3), point(-3, w + 3, -3, h + 3),
                    point(-3, w + 3, -3, h + 3)};
        case 1:  // huge: vertices anywhere in the guard band
            return {point(-guard, guard, -guard, guard), point(-guard, guard, -guard, guard),
                    point(-guard, guard, -guard, guard)};
        case 2: {  // long and thin: two vertices close together, the third far away
            const ScreenVertex a = point(-w, 2 * w, -h, 2 * h);
            const std::int64_t dx = std::int64_t(rng.next() % 600) - 300,
                               dy = std::int64_t(rng.next() % 600) - 300;
            const double reach = rng.uniform() < 0.5 ? 4 * w : guard;
            return {a, at(a.sx + dx, a.sy + dy), point(-reach, reach, -reach, reach)};
        }
        case 3: {  // degenerate: collinear (all on a line through a), or two vertices equal
            const ScreenVertex a = point(-3, w + 3, -3, h + 3), b = point(-3, w + 3, -3, h + 3);
            const std::int64_t k = std::int64_t(rng.next() % 7) - 3;
            const ScreenVertex c =
                rng.uniform() < 0.5 ? at(a.sx + k * (b.sx - a.sx), a.sy + k * (b.sy - a.sy)) : a;
            return {a, b, c};
        }
        case 4: {  // an axis-aligned edge: horizontal or vertical, through pixel centres
            const ScreenVertex a = point(-3, w + 3, -3, h + 3), c = point(-3, w + 3, -3, h + 3);
            const ScreenVertex b = rng.uniform() < 0.5 ? at(c.sx, a.sy) : at(a.sx, c.sy);
            return {a, b, c};
        }
        default:  // off the raster, on one side, some far out
            const double d = rng.uniform() < 0.5 ? 3.0 : guard;
            return {point(-d, -0.6, -3, h + 3), point(-d, -0.4, -d, h + d), point(-d, -0.5, -d, d)};
    }
}

}  // namespace

TEST_CASE("scan_triangle covers exactly the pixels of the per-pixel edge-function test") {
    Rng rng(2024);
    const int kinds = 6, per_kind = 3000;
    for (int kind = 0; kind < kinds; ++kind) {
        int covered = 0, differing = 0, malformed = 0;
        for (int n = 0; n < per_kind; ++n) {
            const int width = 1 + int(rng.next() % 48), height = 1 + int(rng.next() % 40);
            const auto v = random_triangle(rng, kind, width, height);
            bool well_formed = true;
            const std::vector<int> got = scanned(v[0], v[1], v[2], width, height, well_formed);
            const std::vector<int> want = brute_force(v[0], v[1], v[2], width, height);
            malformed += well_formed ? 0 : 1;
            differing += got == want ? 0 : 1;
            for (int h : want) covered += h;
        }
        CAPTURE(kind);
        CHECK(malformed == 0);
        CHECK(differing == 0);
        if (kind != 3 && kind != 5) CHECK(covered > 1000);  // the tests were not vacuous
        if (kind == 3 || kind == 5) CHECK(covered == 0);    // degenerate or off the raster
    }
}

TEST_CASE("rasterize_triangle and rasterize_depth cover the same pixels as the definition") {
    // Clip-space triangles, some crossing the near plane or the guard band (clipped into
    // fans), drawn by the camera's and the hemicube's entry points.
    Rng rng(77);
    const int width = 37, height = 29;
    int differing = 0, covered = 0;
    for (int n = 0; n < 3000; ++n) {
        std::array<Vec4, 3> clip;
        const double spread = n % 3 == 0 ? 1.5 : n % 3 == 1 ? 40.0 : 3e6;
        for (Vec4& p : clip) {
            const double w = n % 5 == 0 ? 2.0 * rng.uniform() - 0.5 : 0.2 + rng.uniform();
            p = {spread * (2.0 * rng.uniform() - 1.0) * w, spread * (2.0 * rng.uniform() - 1.0) * w,
                 0.5 * w, w};
        }
        std::vector<int> colour(std::size_t(width) * height, 0), depth = colour, want = colour;
        rasterize_triangle(clip, width, height,
                           [&](const Fragment& f) { ++colour[std::size_t(f.y) * width + f.x]; });
        rasterize_depth(clip, width, height, [&](const DepthSpan& s) {
            for (int x = s.begin; x < s.end; ++x) ++depth[std::size_t(s.y) * width + x];
        });
        detail::project_triangle(
            clip, width, height,
            [&](const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c) {
                if (!std::isfinite(detail::edge(a, b, c.x, c.y))) return;
                const std::vector<int> piece = brute_force(a, b, c, width, height);
                for (std::size_t k = 0; k < want.size(); ++k) want[k] += piece[k];
            });
        differing += colour == want && depth == want ? 0 : 1;
        for (int h : want) covered += h;
    }
    CHECK(differing == 0);
    CHECK(covered > 10000);
}

TEST_CASE("draw_nearest keeps the same nearest items and depths as draw_depth's runs") {
    // Overlapping random triangles at random depths, narrow and wide, drawn in turn into two
    // z-buffers: one by draw_nearest (branch-free boxes), one by the runs of draw_depth with a
    // plain depth test. Same pixels, same z/w, same winners: the buffers agree bit for bit.
    Rng rng(5);
    const int width = 40, height = 32;
    const auto pixels = std::size_t(width) * height;
    int differing = 0;
    std::size_t drawn = 0;  // pixels holding an item: the test sees something drawn
    for (int scene = 0; scene < 50; ++scene) {
        std::vector<double> depth(pixels, 1e300), want_depth = depth;
        std::vector<std::int32_t> item(pixels, -1), want_item = item;
        for (std::int32_t who = 0; who < 60; ++who) {
            auto v = random_triangle(rng, who % 3 == 2 ? 2 : 0, width, height);
            for (ScreenVertex& p : v) p.z = rng.uniform();
            detail::draw_nearest(v[0], v[1], v[2], width, height,
                                 {depth.data(), item.data(), width, who});
            detail::draw_depth(v[0], v[1], v[2], width, height, [&](const DepthSpan& s) {
                for (int x = s.begin; x < s.end; ++x) {
                    const auto k = std::size_t(s.y) * width + x;
                    if (s.depth(x) < want_depth[k]) {
                        want_depth[k] = s.depth(x);
                        want_item[k] = who;
                    }
                }
            });
        }
        differing += depth == want_depth && item == want_item ? 0 : 1;
        drawn += static_cast<std::size_t>(
            std::count_if(item.begin(), item.end(), [](std::int32_t i) { return i >= 0; }));
    }
    CHECK(differing == 0);
    CHECK(drawn > pixels * 50 / 4);
}
