#pragma once
/// @file raster_walk.hpp  The fast path of the rasteriser's scan (geometry/raster.hpp): a wide
/// box is walked edge by edge down its rows, each edge an exact integer DDA (as Bresenham's line
/// algorithm) whose set-up takes one floating-point reciprocal and no integer division, so a row
/// costs O(1) however wide the triangle. It covers exactly the pixels of the plain per-pixel
/// stepping (step_rows, in raster.hpp), which is what to read first; tests/test_raster.cpp
/// checks both against the definition on thousands of triangles.

#include <radiosity/config.hpp>
#include <radiosity/geometry/raster.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace radiosity::detail {

/// Floor division n = q a + r with 0 <= r < a, for a > 0 and |n / a| < 2^52, without an integer
/// division (tens of cycles): the quotient is estimated in floating point from an estimate of
/// 1 / a (a few ulps off), and corrected by exact integer tests. Rounding and truncation leave
/// the estimate between 1 below and 2 above the true quotient, so two rounds of corrections
/// reach it; they use sign masks, not branches, which mispredict here.
struct FloorDivision {
    std::int64_t q, r;
};

inline FloorDivision floor_divide(std::int64_t n, std::int64_t a, double inv_a) {
    RADIOSITY_ASSERT(a > 0);
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

/// How a triangle is walked: edge k runs between the two vertices other than v_k; the long edge
/// (spanning the most rows) lies opposite the middle vertex m and bounds every run on one side,
/// the upper short edge (opposite the bottom vertex) and then the lower one (opposite the top
/// vertex) on the other. Also the edges' slopes |dy| in subpixels^2 per column (a horizontal
/// edge counts as 1: it is not walked) and the reciprocal of their product, from which each
/// edge's reciprocal comes without a division of its own.
struct WalkPlan {
    std::array<const ScreenVertex*, 3> v;
    std::size_t m, top_vertex, bottom_vertex;
    bool long_on_left;  // the long edge runs upwards (dy < 0): it bounds the runs on the left
    std::array<double, 3> slope;
    double inv_product;

    WalkPlan(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2)
        : v{&v0, &v1, &v2} {
        m = rows(0) >= rows(1) ? (rows(0) >= rows(2) ? 0 : 2) : (rows(1) >= rows(2) ? 1 : 2);
        const std::size_t i = (m + 1) % 3, j = (m + 2) % 3;  // the long edge runs from v_i to v_j
        bottom_vertex = v[i]->sy > v[j]->sy ? i : j;
        top_vertex = bottom_vertex == i ? j : i;
        long_on_left = v[j]->sy < v[i]->sy;
        for (std::size_t k = 0; k < 3; ++k)
            slope[k] = rows(k) != 0 ? static_cast<double>(rows(k) * subpixels) : 1.0;
        inv_product = 1.0 / (slope[0] * slope[1] * slope[2]);
    }

    /// Subpixel rows that edge k spans.
    std::int64_t rows(std::size_t k) const {
        return std::abs(v[(k + 2) % 3]->sy - v[(k + 1) % 3]->sy);
    }

    /// The walker of edge k from pixel centre (px, at_y), on the left or right of the runs.
    EdgeWalker walker(std::size_t k, bool left_side, std::int64_t px, std::int64_t at_y) const {
        const double inv = slope[(k + 1) % 3] * slope[(k + 2) % 3] * inv_product;
        return edge_walker(*v[(k + 1) % 3], *v[(k + 2) % 3], px, at_y, left_side, inv);
    }
};

/// Narrows the rows [top, bottom] (counted from the box's top, pixel centre py0) to those that
/// the triangle's horizontal edges let in: such an edge bounds no run, only the rows.
inline void limit_to_horizontal_edges(const ScreenVertex& v0, const ScreenVertex& v1,
                                      const ScreenVertex& v2, std::int64_t px, std::int64_t py0,
                                      std::int64_t& top, std::int64_t& bottom) {
    if (v1.sy == v2.sy) horizontal_rows(v1, v2, px, py0, top, bottom);
    if (v2.sy == v0.sy) horizontal_rows(v2, v0, px, py0, top, bottom);
    if (v0.sy == v1.sy) horizontal_rows(v0, v1, px, py0, top, bottom);
}

/// scan_triangle's rows of a wide box, each edge walked down the rows (EdgeWalker), so that a
/// row costs the same however wide the box. Rows above the middle vertex lie between the long
/// edge and the upper short edge, rows below it between the long edge and the lower one: the
/// third edge's test is then implied (inside the angle of the other two at their shared vertex,
/// strictly nearer than the third edge). Only the row through the middle vertex tests all three.
/// Steps: the rows the horizontal edges allow; the plan; the upper rows; the middle row; the
/// lower rows.
template <class Span>
void walk_rows(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2, int x0,
               int x1, int y0, int y1, std::int64_t px, std::int64_t py0, Span& span) {
    RADIOSITY_ASSERT(edge(v0, v1, v2.sx, v2.sy) > 0 && x0 <= x1 && y0 <= y1);
    std::int64_t top = 0, bottom = y1 - y0;
    limit_to_horizontal_edges(v0, v1, v2, px, py0, top, bottom);
    if (top > bottom) return;
    const WalkPlan plan(v0, v1, v2);
    const bool left = plan.long_on_left;
    const std::int64_t py = (y0 + top) * subpixels + subpixels / 2;
    // The long edge, the upper and the lower short edge; which pair bounds a run on the left
    // and which on the right is picked by index, not by a branch (either way is as likely).
    std::array<EdgeWalker, 3> e{plan.walker(plan.m, left, px, py),
                                plan.walker(plan.bottom_vertex, !left, px, py), EdgeWalker{}};
    const std::size_t l = left ? 0 : 1, r = left ? 1 : 0;
    // Rows above the middle vertex's, the row through it (or the first below), the rest.
    const std::int64_t split = std::clamp<std::int64_t>(
        -((subpixels / 2 - plan.v[plan.m]->sy) >> subpixel_bits) - y0, top, bottom + 1);
    const std::int64_t columns = x1 - x0 + 1;
    const int first = y0 + static_cast<int>(top), middle = y0 + static_cast<int>(split),
              last = y0 + static_cast<int>(bottom);
    walk_run_rows(e[l], e[r], first, middle - 1, x0, columns, span);
    if (middle > last) return;
    e[2] = plan.walker(plan.top_vertex, !left, px,
                       static_cast<std::int64_t>(middle) * subpixels + subpixels / 2);
    const std::size_t l2 = left ? 0 : 2, r2 = left ? 2 : 0;
    const std::int64_t begin = std::max({std::int64_t{0}, e[l].t, e[l2].t});
    const std::int64_t end = std::min({columns, e[r].t, e[r2].t});
    if (begin < end) span(middle, x0 + static_cast<int>(begin), x0 + static_cast<int>(end));
    e[0].next_row();
    e[2].next_row();
    walk_run_rows(e[l2], e[r2], middle + 1, last, x0, columns, span);
}

}  // namespace radiosity::detail
