#pragma once
/// @file raster.hpp  The one triangle rasteriser of the library, shared by the hemicube (which
/// draws patch ids into five small z-buffers) and the camera (which draws Gouraud-shaded
/// pictures): homogeneous near-plane clipping, edge functions with the top-left fill rule, and
/// perspective-correct barycentric coordinates (Pineda 1988; Heckbert & Moreton 1991). Here is
/// the plain path: clip, project, snap to fixed point, step the edge functions pixel by pixel
/// (step_rows). Its fast paths cover exactly the same pixels: wide boxes walked edge by edge
/// (walk_rows, detail/raster_walk.hpp) and the hemicube's branch-free z-buffer (draw_nearest,
/// detail/draw_nearest.hpp).

#include <radiosity/config.hpp>
#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace radiosity {

/// A point in homogeneous clip space (OpenGL convention): visible where -w <= x, y, z <= w.
using Vec4 = glm::dvec4;

/// One covered pixel: its column x and row y (row 0 at the top), its depth z/w in [-1, 1]
/// (smaller is nearer), and the perspective-correct barycentric weights of the triangle's three
/// original vertices (they sum to 1), for interpolating colours or anything else.
struct Fragment {
    int x = 0;             ///< pixel column
    int y = 0;             ///< pixel row, 0 at the top
    double depth = 0.0;    ///< z/w, -1 at the near plane, +1 at the far plane
    glm::dvec3 weight{0};  ///< perspective-correct barycentric weights of the 3 vertices
};

/// A perspective projection as a 4x4 matrix in the OpenGL convention (right-handed eye space,
/// looking down -z): vertical field of view, aspect = width / height, near and far planes.
inline glm::dmat4 perspective(double fov_y_radians, double aspect, double near, double far) {
    const double f = 1.0 / std::tan(fov_y_radians / 2.0);
    glm::dmat4 m(0.0);
    m[0][0] = f / aspect;
    m[1][1] = f;
    m[2][2] = (far + near) / (near - far);
    m[2][3] = -1.0;
    m[3][2] = 2.0 * far * near / (near - far);
    return m;
}

namespace detail {

/// Fixed-point screen coordinates with 8 fractional bits (1/256 pixel), as in hardware
/// rasterisers: edge functions of snapped vertices are exact integers, so two triangles sharing
/// an edge agree on every pixel centre, and stepping from one pixel to the next adds integers
/// without rounding (Pineda 1988; Olano & Greer 1997).
inline constexpr int subpixel_bits = 8;
inline constexpr std::int64_t subpixels = std::int64_t{1} << subpixel_bits;

/// The guard band: vertices may lie this many pixels beyond the raster before their polygon is
/// clipped to it, so that coordinates keep below 2^28 subpixels and edge functions (products of
/// two coordinate differences) below 2^59, inside 64-bit integers.
inline constexpr double guard_pixels = 1 << 20;

/// A clip-space vertex carrying its barycentric weights with respect to the original triangle,
/// so that clipped pieces still interpolate the original vertices' attributes.
struct ClipVertex {
    Vec4 p;
    glm::dvec3 b;
};

/// Clips a convex polygon of n vertices to the half space distance(p) >= 0 (Sutherland &
/// Hodgman 1974), in homogeneous coordinates so that nothing behind the eye is ever divided by
/// w. A crossing edge is always cut from its inside end, so the two triangles sharing an edge
/// get bit-identical new vertices (no cracks). Returns the vertex count written into out.
template <std::size_t N, class Distance>
int clip_polygon(const std::array<ClipVertex, N>& in, int n, std::array<ClipVertex, N>& out,
                 Distance&& distance) {
    int m = 0;
    for (int k = 0; k < n; ++k) {
        const ClipVertex& a = in[static_cast<std::size_t>(k)];
        const ClipVertex& c = in[static_cast<std::size_t>((k + 1) % n)];
        const double da = distance(a.p), dc = distance(c.p);
        if (da >= 0.0) out[static_cast<std::size_t>(m++)] = a;
        if ((da >= 0.0) != (dc >= 0.0)) {
            const ClipVertex& i = da >= 0.0 ? a : c;  // inside end
            const ClipVertex& o = da >= 0.0 ? c : a;
            const double di = std::max(da, dc), d_o = std::min(da, dc);
            const double t = di / (di - d_o);
            out[static_cast<std::size_t>(m++)] = {i.p + (o.p - i.p) * t, i.b + (o.b - i.b) * t};
        }
    }
    return m;
}

/// Clips a triangle to the near plane z + w >= 0 and to the guard band |x|, |y| <= g w. A
/// triangle becomes a polygon of at most 8 vertices. Returns the vertex count.
inline int clip_triangle(const std::array<Vec4, 3>& clip, double g,
                         std::array<ClipVertex, 8>& poly) {
    std::array<ClipVertex, 8> tmp;
    tmp[0] = {clip[0], {1, 0, 0}};
    tmp[1] = {clip[1], {0, 1, 0}};
    tmp[2] = {clip[2], {0, 0, 1}};
    int n = clip_polygon(tmp, 3, poly, [](const Vec4& p) { return p.z + p.w; });
    n = clip_polygon(poly, n, tmp, [g](const Vec4& p) { return g * p.w - p.x; });
    n = clip_polygon(tmp, n, poly, [g](const Vec4& p) { return g * p.w + p.x; });
    n = clip_polygon(poly, n, tmp, [g](const Vec4& p) { return g * p.w - p.y; });
    return clip_polygon(tmp, n, poly, [g](const Vec4& p) { return g * p.w + p.y; });
}

/// Whether a clip-space vertex lies in front of the near plane and inside the guard band of a
/// raster whose longer side is `extent` pixels: |x/w|, |y/w| <= guard_pixels / extent, tested
/// without a division (this runs for every vertex drawn).
inline bool inside_guard_band(const Vec4& p, double extent) {
    const double reach = guard_pixels * p.w;
    return p.z + p.w >= 0.0 && std::abs(p.x) * extent <= reach && std::abs(p.y) * extent <= reach;
}

/// The guard band in clip space for a width x height raster: |x/w|, |y/w| <= g keeps every
/// vertex within guard_pixels of the raster.
inline double guard_band(int width, int height) {
    return guard_pixels / std::max(width, height);
}

/// A vertex after the perspective division and the viewport transform.
struct ScreenVertex {
    double x, y;          // pixel coordinates, y down
    double z;             // z / w
    double inv_w;         // 1 / w, for perspective-correct interpolation
    std::int64_t sx, sy;  // x and y in fixed point (subpixels), rounded to nearest
    const glm::dvec3* b;  // barycentric weights of the original triangle's vertices
};

/// Rounds a pixel coordinate (within the guard band) to fixed point, to nearest, without a
/// branch: shifted by 2^31 subpixels it is positive, where truncation rounds down.
inline std::int64_t to_subpixels(double x) {
    constexpr double offset = 0x1p31;
    return static_cast<std::int64_t>(x * static_cast<double>(subpixels) + (offset + 0.5)) -
           static_cast<std::int64_t>(offset);
}

inline ScreenVertex to_screen(const Vec4& p, const glm::dvec3& b, int width, int height) {
    const double iw = 1.0 / p.w;
    const double x = (p.x * iw * 0.5 + 0.5) * width, y = (0.5 - p.y * iw * 0.5) * height;
    return {x, y, p.z * iw, iw, to_subpixels(x), to_subpixels(y), &b};
}

/// Edge function of the directed edge a -> b at point (x, y): twice the signed area of the
/// triangle (a, b, p); positive on one side, zero on the edge (Pineda 1988).
inline double edge(const ScreenVertex& a, const ScreenVertex& b, double x, double y) {
    return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
}

/// The same in fixed point, exact: at (x, y) in subpixels.
inline std::int64_t edge(const ScreenVertex& a, const ScreenVertex& b, std::int64_t x,
                         std::int64_t y) {
    return (b.sx - a.sx) * (y - a.sy) - (b.sy - a.sy) * (x - a.sx);
}

/// Top-left rule: a pixel centre exactly on an edge belongs to only one of the two triangles
/// sharing that edge, so neighbouring patches neither overlap nor leave cracks (each pixel of a
/// hemicube is counted once). With both triangles oriented alike, the shared edge runs in
/// opposite directions, and exactly one direction passes this test.
inline bool owns_edge(const ScreenVertex& a, const ScreenVertex& b) {
    const std::int64_t dy = b.sy - a.sy, dx = b.sx - a.sx;
    return dy > 0 || (dy == 0 && dx < 0);
}

/// Boxes at least this many columns wide and of more than walk_min_pixels pixels are walked
/// edge by edge (EdgeWalker); smaller ones are stepped pixel by pixel, where the walk's set-up
/// (a division and a dozen multiplications) would cost more than it saves. Both measured on
/// the hemicubes of a cluttered room (RRV's room3).
inline constexpr int walk_min_columns = 8;
inline constexpr int walk_min_pixels = 48;  ///< see walk_min_columns

/// One edge function of a triangle set up for stepping: its value at the current pixel centre,
/// lowered by 1 where the edge is not owned so that "covered" is simply value >= 0, and its
/// increments per pixel to the right and per row down.
struct EdgeStepper {
    std::int64_t value, step_x, step_y;
};

inline EdgeStepper edge_stepper(const ScreenVertex& a, const ScreenVertex& b, std::int64_t x,
                                std::int64_t y) {
    return {edge(a, b, x, y) - (owns_edge(a, b) ? 0 : 1), -(b.sy - a.sy) * subpixels,
            (b.sx - a.sx) * subpixels};
}

/// scan_triangle's rows of a narrow box (columns x0 .. x1, rows y0 .. y1, pixel (x0, y0) at
/// centre (px, py)): the three edge functions stepped by additions across each row; a pixel is
/// covered when none is negative, i.e. when their bitwise or is not negative. A row stops at
/// the end of its run.
template <class Span>
void step_rows(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2, int x0,
               int x1, int y0, int y1, std::int64_t px, std::int64_t py, Span& span) {
    RADIOSITY_ASSERT(edge(v0, v1, v2.sx, v2.sy) > 0 && x0 <= x1 && y0 <= y1);
    EdgeStepper e0 = edge_stepper(v1, v2, px, py), e1 = edge_stepper(v2, v0, px, py),
                e2 = edge_stepper(v0, v1, px, py);
    for (int y = y0; y <= y1; ++y) {
        std::int64_t a = e0.value, b = e1.value, c = e2.value;
        int x = x0;
        for (; x <= x1 && (a | b | c) < 0; ++x) {  // up to the run of covered pixels
            a += e0.step_x;
            b += e1.step_x;
            c += e2.step_x;
        }
        const int begin = x;
        for (; x <= x1 && (a | b | c) >= 0; ++x) {  // to its end
            a += e0.step_x;
            b += e1.step_x;
            c += e2.step_x;
        }
        if (x > begin) span(y, begin, x);
        e0.value += e0.step_y;
        e1.value += e1.step_y;
        e2.value += e2.step_y;
    }
}

/// The rows of a wide box walked edge by edge (detail/raster_walk.hpp, the fast path): the same
/// pixels as step_rows, at O(1) a row.
template <class Span>
void walk_rows(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2, int x0,
               int x1, int y0, int y1, std::int64_t px, std::int64_t py0, Span& span);

/// Scan-converts one screen-space triangle: calls span(y, begin, end) for every row y with
/// pixels begin .. end - 1 covered (their centres inside; a triangle is convex, so a row covers
/// one run). Coverage is that of the three exact integer edge functions (Pineda 1988): a pixel
/// is covered when none is negative, with the top-left rule on edges. A narrow or small box
/// (walk_min_columns) is stepped pixel by pixel (step_rows); a wide one is walked edge by edge
/// (walk_rows), so that its long thin triangles, common near a hemicube's centre, cost O(rows),
/// not O(rows x width). Both cover exactly the same pixels. A caller may handle the narrow
/// boxes itself: narrow(v0, v1, v2, x0, x1, y0, y1, px, py) gets the oriented triangle, its
/// box and the centre of its first pixel. Cost: O(rows + pixels drawn), plus O(box) when narrow.
template <class Span, class NarrowBox>
void scan_triangle(const ScreenVertex& v0, const ScreenVertex& a, const ScreenVertex& b, int width,
                   int height, Span&& span, NarrowBox&& narrow) {
    const std::int64_t area = edge(v0, a, b.sx, b.sy);
    if (area == 0) return;  // seen edge-on: covers no pixel
    // Oriented consistently (positive area); both windings are drawn (no culling).
    const ScreenVertex& v1 = area > 0 ? a : b;
    const ScreenVertex& v2 = area > 0 ? b : a;
    // Pixel x covers the centre x + 1/2: the columns and rows whose centres lie in the box.
    constexpr std::int64_t half = subpixels / 2;
    auto first = [](std::int64_t lo) { return -((half - lo) >> subpixel_bits); };  // ceil
    auto last = [](std::int64_t hi) { return (hi - half) >> subpixel_bits; };      // floor
    const auto x0 =
        static_cast<int>(std::max<std::int64_t>(0, first(std::min({v0.sx, v1.sx, v2.sx}))));
    const auto x1 =
        static_cast<int>(std::min<std::int64_t>(width - 1, last(std::max({v0.sx, v1.sx, v2.sx}))));
    const auto y0 =
        static_cast<int>(std::max<std::int64_t>(0, first(std::min({v0.sy, v1.sy, v2.sy}))));
    const auto y1 =
        static_cast<int>(std::min<std::int64_t>(height - 1, last(std::max({v0.sy, v1.sy, v2.sy}))));
    if (x0 > x1 || y0 > y1) return;
    const std::int64_t px = x0 * subpixels + half, py = y0 * subpixels + half;
    if (x1 - x0 + 1 < walk_min_columns || (x1 - x0 + 1) * (y1 - y0 + 1) <= walk_min_pixels) {
        narrow(v0, v1, v2, x0, x1, y0, y1, px, py);
        return;
    }
    walk_rows(v0, v1, v2, x0, x1, y0, y1, px, py, span);
}

/// scan_triangle as above, with the rows of a narrow box stepped pixel by pixel (step_rows).
template <class Span>
void scan_triangle(const ScreenVertex& v0, const ScreenVertex& a, const ScreenVertex& b, int width,
                   int height, Span&& span) {
    scan_triangle(v0, a, b, width, height, span,
                  [&span](const ScreenVertex& u0, const ScreenVertex& u1, const ScreenVertex& u2,
                          int x0, int x1, int y0, int y1, std::int64_t px, std::int64_t py) {
                      step_rows(u0, u1, u2, x0, x1, y0, y1, px, py, span);
                  });
}

/// Clips a clip-space triangle (near plane, guard band), projects it, and scan-converts the
/// pieces: calls piece(s0, s1, s2) for each screen triangle of the clipped polygon's fan. A
/// triangle wholly in front of the near plane and inside the guard band (the usual case)
/// skips the clipper.
template <class Piece>
void project_triangle(const std::array<Vec4, 3>& clip, int width, int height, Piece&& piece) {
    const double extent = std::max(width, height);
    if (inside_guard_band(clip[0], extent) && inside_guard_band(clip[1], extent) &&
        inside_guard_band(clip[2], extent)) {
        static constexpr std::array<glm::dvec3, 3> corner{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
        piece(to_screen(clip[0], corner[0], width, height),
              to_screen(clip[1], corner[1], width, height),
              to_screen(clip[2], corner[2], width, height));
        return;
    }
    std::array<ClipVertex, 8> poly;
    const int n = clip_triangle(clip, guard_band(width, height), poly);
    if (n < 3) return;
    std::array<ScreenVertex, 8> s;
    for (int k = 0; k < n; ++k)
        s[static_cast<std::size_t>(k)] =
            to_screen(poly[static_cast<std::size_t>(k)].p, poly[static_cast<std::size_t>(k)].b,
                      width, height);
    for (std::size_t k = 1; k + 1 < static_cast<std::size_t>(n); ++k) piece(s[0], s[k], s[k + 1]);
}

}  // namespace detail

/// Rasterises one triangle given in clip space into a width x height raster (each at most
/// 2^20): clips it to the near plane, divides by w, and calls visit(Fragment) for every pixel
/// whose centre it covers (top-left rule on shared edges; vertices snapped to 1/256 pixel).
/// Both windings are drawn; depth testing is the caller's (the camera keeps colours). Pixels
/// outside the raster are skipped. Cost: O(rows + pixels drawn), O(box) for narrow boxes.
template <class Visit>
void rasterize_triangle(const std::array<Vec4, 3>& clip, int width, int height, Visit&& visit) {
    detail::project_triangle(
        clip, width, height,
        [&](const detail::ScreenVertex& v0, const detail::ScreenVertex& v1,
            const detail::ScreenVertex& v2) {
            const double area = detail::edge(v0, v1, v2.x, v2.y);
            if (area == 0.0 || !std::isfinite(area)) return;
            detail::scan_triangle(v0, v1, v2, width, height, [&](int y, int begin, int end) {
                for (int x = begin; x < end; ++x) {
                    const double px = x + 0.5, py = y + 0.5;
                    // Screen-space weights l_k are linear in x, y; z/w is too, but attributes are
                    // not: interpolate b/w and 1/w, and divide (perspective-correct interpolation).
                    const double l0 = detail::edge(v1, v2, px, py) / area,
                                 l1 = detail::edge(v2, v0, px, py) / area,
                                 l2 = detail::edge(v0, v1, px, py) / area;
                    const double depth = l0 * v0.z + l1 * v1.z + l2 * v2.z;
                    const double inv_w = l0 * v0.inv_w + l1 * v1.inv_w + l2 * v2.inv_w;
                    const glm::dvec3 b =
                        (l0 * v0.inv_w * *v0.b + l1 * v1.inv_w * *v1.b + l2 * v2.inv_w * *v2.b) /
                        inv_w;
                    visit(Fragment{x, y, depth, b});
                }
            });
        });
}

/// A run of covered pixels begin .. end - 1 of row y, and the depth z/w along it: z/w is linear
/// in screen space, so along a row it is z0 + dzdx x.
struct DepthSpan {
    int y = 0, begin = 0, end = 0;  ///< row, first pixel, one past the last
    double z0 = 0.0, dzdx = 0.0;    ///< depth at x = 0 of this row, and its step per pixel
    double depth(int x) const { return z0 + dzdx * x; }  ///< z/w at the centre of pixel x
};

namespace detail {

/// The plane of z/w over the screen, z/w = z0 + dzdx x + dzdy y at the centre of pixel (x, y)
/// (z/w is linear in screen space).
struct DepthPlane {
    double z0, dzdx, dzdy;
};

/// The depth plane through three screen vertices: z = v0.z + dzdx (x - v0.x) + dzdy (y - v0.y),
/// solved from the other two; nothing for a triangle seen edge-on (or not finite).
inline std::optional<DepthPlane> depth_plane(const ScreenVertex& v0, const ScreenVertex& v1,
                                             const ScreenVertex& v2) {
    const double x1 = v1.x - v0.x, y1 = v1.y - v0.y, z1 = v1.z - v0.z;
    const double x2 = v2.x - v0.x, y2 = v2.y - v0.y, z2 = v2.z - v0.z;
    const double det = x1 * y2 - x2 * y1;
    if (det == 0.0 || !std::isfinite(det)) return std::nullopt;
    const double inv_det = 1.0 / det;
    const double dzdx = (z1 * y2 - z2 * y1) * inv_det, dzdy = (z2 * x1 - z1 * x2) * inv_det;
    return DepthPlane{v0.z + dzdx * (0.5 - v0.x) + dzdy * (0.5 - v0.y), dzdx, dzdy};
}

/// Draws one screen-space triangle for a z-buffer: calls visit(DepthSpan) for every row's run
/// of covered pixels, with z/w from the plane through the three vertices: the run-based path of
/// rasterize_depth, and the reference that draw_nearest must match.
template <class Visit>
void draw_depth(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2, int width,
                int height, Visit&& visit) {
    const std::optional<DepthPlane> plane = depth_plane(v0, v1, v2);
    if (!plane) return;
    const double z0 = plane->z0, dzdx = plane->dzdx, dzdy = plane->dzdy;
    // The plane by value: the caller's stores to its depth buffer cannot touch copies.
    scan_triangle(v0, v1, v2, width, height, [&visit, z0, dzdx, dzdy](int y, int begin, int end) {
        visit(DepthSpan{y, begin, end, z0 + dzdy * y, dzdx});
    });
}

/// A z-buffer with an item per pixel, rows of `width` pixels, and the item `who` being drawn:
/// as a DepthSpan visitor, keeps who wherever its depth is less than the buffer's (the first
/// drawn wins a tie).
struct NearestItems {
    double* depth;
    std::int32_t* item;
    int width;
    std::int32_t who;

    void operator()(const DepthSpan& s) const {
        const auto row = static_cast<std::size_t>(s.y) * static_cast<std::size_t>(width);
        double* const d = depth + row;
        std::int32_t* const it = item + row;
        const double z0 = s.z0, dzdx = s.dzdx;
        const std::int32_t id = who;
        double x = s.begin;  // pixel column as a double: no conversion per pixel
        for (int px = s.begin; px < s.end; ++px, x += 1.0) {
            const double z = z0 + dzdx * x;
            if (z < d[px]) {
                d[px] = z;
                it[px] = id;
            }
        }
    }
};

}  // namespace detail

/// Rasterises one clip-space triangle for a z-buffer only: calls visit(DepthSpan) for every
/// row's run of covered pixels, exactly those rasterize_triangle visits, with z/w from the plane
/// through the three projected vertices. What the hemicube needs, without per-pixel barycentric
/// weights, and with a tight loop per run for the caller's depth test.
template <class Visit>
void rasterize_depth(const std::array<Vec4, 3>& clip, int width, int height, Visit&& visit) {
    detail::project_triangle(clip, width, height,
                             [&](const detail::ScreenVertex& v0, const detail::ScreenVertex& v1,
                                 const detail::ScreenVertex& v2) {
                                 detail::draw_depth(v0, v1, v2, width, height, visit);
                             });
}

}  // namespace radiosity

// The definition of walk_rows, after everything it builds on.
#include <radiosity/detail/raster_walk.hpp>
