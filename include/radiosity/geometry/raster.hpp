#pragma once
/// @file raster.hpp  The one triangle rasteriser of the library, shared by the hemicube (which
/// draws patch ids into five small z-buffers) and the camera (which draws Gouraud-shaded
/// pictures): homogeneous near-plane clipping, edge functions with the top-left fill rule, and
/// perspective-correct barycentric coordinates (Pineda 1988; Heckbert & Moreton 1991).

#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <bit>
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

/// Floor division n = q a + r with 0 <= r < a, for a > 0 and |n / a| < 2^52, without an integer
/// division (tens of cycles): the quotient is estimated in floating point from an estimate of
/// 1 / a (a few ulps off), and corrected by exact integer tests. Rounding and truncation leave
/// the estimate between 1 below and 2 above the true quotient, so two rounds of corrections
/// reach it; they use sign masks, not branches, which mispredict here.
struct FloorDivision {
    std::int64_t q, r;
};

inline FloorDivision floor_divide(std::int64_t n, std::int64_t a, double inv_a) {
    auto q = static_cast<std::int64_t>(static_cast<double>(n) * inv_a);
    std::int64_t r = n - q * a;
    for (int k = 0; k < 2; ++k) {
        const std::int64_t below = r >> 63;  // -1 where r < 0 (arithmetic shift, C++20)
        q += below;
        r += a & below;
        const std::int64_t above = (a - 1 - r) >> 63;  // -1 where r >= a
        q -= above;
        r -= a & above;
    }
    return {q, r};
}

/// One edge of a triangle walked down its rows (an exact DDA, as Bresenham's line algorithm):
/// t is where the edge cuts the current row, in columns counted from the left of the bounding
/// box: for a left edge the first column it lets in, for a right edge the first it keeps out.
/// The edge's function along the row is u + a x (a > 0; see edge_walker), and r = u + a t in
/// [0, a) is its remainder at t. A row down adds q a + rem to u, so t moves by -q, or by -q - 1
/// when r + rem carries past a: one compare per edge and row, where stepping across the box
/// costs one per pixel and a mispredicted branch at each end of the run.
struct EdgeWalker {
    std::int64_t t, r, a, q, rem;

    void next_row() {
        r += rem;
        const std::int64_t carry = (a - 1 - r) >> 63;  // -1 where r >= a
        t -= q;
        t += carry;
        r -= a & carry;
    }
};

/// Beyond any column: where a horizontal edge, which bounds no run, stands.
inline constexpr std::int64_t far_columns = std::int64_t{1} << 60;

/// Sets up the walk of edge a -> b of a positively oriented triangle from pixel centre
/// (px, py), the top-left corner of the box. A pixel is covered where
/// v = E(x, y) - (owned ? 0 : 1) >= 0 (the top-left rule); along a row v grows by
/// s_x = -dy per subpixel of x. Where s_x > 0 (a left edge) the covered columns are those from
/// t = ceil(-v / s_x) = -floor(v / s_x) on; where s_x < 0 (a right edge), those before the
/// first with v < 0, i.e. with u + |s_x| x >= 0 for u = -v - 1. A horizontal edge bounds the
/// rows instead (horizontal_rows); its walker stays at far_columns on the side of its run.
inline EdgeWalker edge_walker(const ScreenVertex& a, const ScreenVertex& b, std::int64_t px,
                              std::int64_t py, bool left_side, double inv_slope) {
    const std::int64_t step_x = -(b.sy - a.sy) * subpixels, step_y = (b.sx - a.sx) * subpixels;
    if (step_x == 0) return {left_side ? -far_columns : far_columns, 0, 1, 0, 0};
    const std::int64_t v = edge(a, b, px, py) - (owns_edge(a, b) ? 0 : 1);
    const std::int64_t right = step_x >> 63;  // -1 for a right edge: u = -v - 1 = ~v
    const std::int64_t u = v ^ right, slope = (step_x ^ right) - right;
    const FloorDivision start = floor_divide(u, slope, inv_slope),
                        row = floor_divide((step_y ^ right) - right, slope, inv_slope);
    return {-start.q, start.r, slope, row.q, row.r};
}

/// The rows k = 0, 1, ... (counted from the box's top) that a horizontal edge a -> b lets in:
/// where v + s_y k >= 0, a half line of rows. Narrows [first, last] to them.
inline void horizontal_rows(const ScreenVertex& a, const ScreenVertex& b, std::int64_t px,
                            std::int64_t py, std::int64_t& first, std::int64_t& last) {
    const std::int64_t v = edge(a, b, px, py) - (owns_edge(a, b) ? 0 : 1);
    const std::int64_t step_y = (b.sx - a.sx) * subpixels;
    if (step_y > 0) {  // rows from -floor(v / s_y) on
        first = std::max(first, -floor_divide(v, step_y, 1.0 / static_cast<double>(step_y)).q);
    } else {  // rows up to floor(v / -s_y)
        last = std::min(last, floor_divide(v, -step_y, -1.0 / static_cast<double>(step_y)).q);
    }
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

/// Rows first .. last of a walk: each run lies between a left and a right edge. The walkers
/// are copied in, so that they live in registers.
template <class Span>
void walk_run_rows(EdgeWalker& left, EdgeWalker& right, int first, int last, int x0,
                   std::int64_t columns, Span& span) {
    EdgeWalker a = left, b = right;
    for (int y = first; y <= last; ++y) {
        const std::int64_t begin = std::max<std::int64_t>(0, a.t), end = std::min(columns, b.t);
        if (begin < end) span(y, x0 + static_cast<int>(begin), x0 + static_cast<int>(end));
        a.next_row();
        b.next_row();
    }
    left = a;
    right = b;
}

/// scan_triangle's rows of a wide box, each edge walked down the rows (EdgeWalker), so that a
/// row costs the same however wide the box. Rows above the middle vertex lie between the long
/// edge and the upper short edge, rows below it between the long edge and the lower one: the
/// third edge's test is then implied (inside the angle of the other two at their shared vertex,
/// strictly nearer than the third edge). Only the row through the middle vertex tests all three.
template <class Span>
void walk_rows(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2, int x0,
               int x1, int y0, int y1, std::int64_t px, std::int64_t py0, Span& span) {
    // A horizontal edge lets in a half line of rows; the other edges bound each row's run.
    std::int64_t top = 0, bottom = y1 - y0;
    if (v1.sy == v2.sy) horizontal_rows(v1, v2, px, py0, top, bottom);
    if (v2.sy == v0.sy) horizontal_rows(v2, v0, px, py0, top, bottom);
    if (v0.sy == v1.sy) horizontal_rows(v0, v1, px, py0, top, bottom);
    if (top > bottom) return;
    // Edge k runs between the two vertices other than v_k. The long edge spans the most rows;
    // it lies opposite the middle vertex m, the upper short edge opposite the bottom vertex.
    const std::array<const ScreenVertex*, 3> v{&v0, &v1, &v2};
    auto rows = [&](std::size_t k) { return std::abs(v[(k + 2) % 3]->sy - v[(k + 1) % 3]->sy); };
    const std::size_t m =
        rows(0) >= rows(1) ? (rows(0) >= rows(2) ? 0 : 2) : (rows(1) >= rows(2) ? 1 : 2);
    const std::size_t i = (m + 1) % 3, j = (m + 2) % 3;  // the long edge runs from v_i to v_j
    const std::size_t bottom_vertex = v[i]->sy > v[j]->sy ? i : j;
    const std::size_t top_vertex = bottom_vertex == i ? j : i;
    // The long edge is left (upwards, dy < 0) or right; the short edges are on the other side.
    const bool long_on_left = v[j]->sy < v[i]->sy;
    const std::int64_t py = (y0 + top) * subpixels + subpixels / 2;
    // The edges' slopes |dy| in subpixels^2 per column, and their reciprocals from a single
    // division (a horizontal edge counts as 1: it is not walked).
    std::array<double, 3> slope{};
    for (std::size_t k = 0; k < 3; ++k)
        slope[k] = rows(k) != 0 ? static_cast<double>(rows(k) * subpixels) : 1.0;
    const double inv_product = 1.0 / (slope[0] * slope[1] * slope[2]);
    auto walker = [&](std::size_t k, bool left_side, std::int64_t at_y) {
        const double inv = slope[(k + 1) % 3] * slope[(k + 2) % 3] * inv_product;
        return edge_walker(*v[(k + 1) % 3], *v[(k + 2) % 3], px, at_y, left_side, inv);
    };
    // The long edge, the upper and the lower short edge; which pair bounds a run on the left
    // and which on the right is picked by index, not by a branch (either way is as likely).
    std::array<EdgeWalker, 3> e{walker(m, long_on_left, py),
                                walker(bottom_vertex, !long_on_left, py), EdgeWalker{}};
    const std::size_t l = long_on_left ? 0 : 1, r = long_on_left ? 1 : 0;
    // Rows above the middle vertex's, the row through it (or the first below), the rest.
    const std::int64_t split = std::clamp<std::int64_t>(
        -((subpixels / 2 - v[m]->sy) >> subpixel_bits) - y0, top, bottom + 1);
    const std::int64_t columns = x1 - x0 + 1;
    const int first = y0 + static_cast<int>(top), middle = y0 + static_cast<int>(split),
              last = y0 + static_cast<int>(bottom);
    walk_run_rows(e[l], e[r], first, middle - 1, x0, columns, span);
    if (middle > last) return;
    e[2] = walker(top_vertex, !long_on_left,
                  static_cast<std::int64_t>(middle) * subpixels + subpixels / 2);
    const std::size_t l2 = long_on_left ? 0 : 2, r2 = long_on_left ? 2 : 0;
    const std::int64_t begin = std::max({std::int64_t{0}, e[l].t, e[l2].t});
    const std::int64_t end = std::min({columns, e[r].t, e[r2].t});
    if (begin < end) span(middle, x0 + static_cast<int>(begin), x0 + static_cast<int>(end));
    e[0].next_row();
    e[2].next_row();
    walk_run_rows(e[l2], e[r2], middle + 1, last, x0, columns, span);
}

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

/// Draws one screen-space triangle into a z-buffer with items (NearestItems): the pixels that
/// draw_depth visits, with the same z/w, and the same decisions. A wide box goes by runs; in a
/// narrow one (a few columns, most triangles of a hemicube) every pixel of the box is tested,
/// coverage and depth together, without a branch: the runs there are a pixel or two, and the
/// branches that find and draw them mispredict more often than not.
inline void draw_nearest(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2,
                         int width, int height, NearestItems items) {
    const std::optional<DepthPlane> plane = depth_plane(v0, v1, v2);
    if (!plane) return;
    const double z0 = plane->z0, dzdx = plane->dzdx, dzdy = plane->dzdy;
    auto span = [items, z0, dzdx, dzdy](int y, int begin, int end) {
        items(DepthSpan{y, begin, end, z0 + dzdy * y, dzdx});
    };
    auto narrow = [items, z0, dzdx, dzdy](const ScreenVertex& u0, const ScreenVertex& u1,
                                          const ScreenVertex& u2, int bx0, int bx1, int by0,
                                          int by1, std::int64_t px, std::int64_t py) {
        EdgeStepper e0 = edge_stepper(u1, u2, px, py), e1 = edge_stepper(u2, u0, px, py),
                    e2 = edge_stepper(u0, u1, px, py);
        for (int y = by0; y <= by1; ++y) {
            const auto row = static_cast<std::size_t>(y) * static_cast<std::size_t>(items.width);
            double* const d = items.depth + row;
            std::int32_t* const it = items.item + row;
            const double zy = z0 + dzdy * y;  // as DepthSpan's z0: the same z, bit for bit
            std::int64_t a = e0.value, b = e1.value, c = e2.value;
            double x = bx0;
            for (int col = bx0; col <= bx1; ++col, x += 1.0) {
                const double z = zy + dzdx * x;
                // All ones where covered and nearer: the stores below select by mask (as
                // written, with ?:, the compiler would branch).
                const std::int64_t nearer =
                    -static_cast<std::int64_t>(((a | b | c) >= 0) & (z < d[col]));
                const auto old_z = std::bit_cast<std::int64_t>(d[col]);
                d[col] = std::bit_cast<double>(old_z ^
                                               ((old_z ^ std::bit_cast<std::int64_t>(z)) & nearer));
                it[col] ^= (it[col] ^ items.who) & static_cast<std::int32_t>(nearer);
                a += e0.step_x;
                b += e1.step_x;
                c += e2.step_x;
            }
            e0.value += e0.step_y;
            e1.value += e1.step_y;
            e2.value += e2.step_y;
        }
    };
    scan_triangle(v0, v1, v2, width, height, span, narrow);
}

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
