#pragma once
/// @file raster.hpp  The one triangle rasteriser of the library, shared by the hemicube (which
/// draws patch ids into five small z-buffers) and the camera (which draws Gouraud-shaded
/// pictures): homogeneous near-plane clipping, edge functions with the top-left fill rule, and
/// perspective-correct barycentric coordinates (Pineda 1988; Heckbert & Moreton 1991).

#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

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

/// A clip-space vertex carrying its barycentric weights with respect to the original triangle,
/// so that clipped pieces still interpolate the original vertices' attributes.
struct ClipVertex {
    Vec4 p;
    glm::dvec3 b;
};

/// Clips a convex polygon to the near plane z + w >= 0 (Sutherland & Hodgman 1974, done in
/// homogeneous coordinates so that nothing behind the eye is ever divided by w). A triangle
/// becomes at most a quadrilateral. Returns the vertex count written into out.
inline int clip_near(const std::array<ClipVertex, 3>& in, std::array<ClipVertex, 4>& out) {
    int n = 0;
    for (int k = 0; k < 3; ++k) {
        const ClipVertex& a = in[k];
        const ClipVertex& c = in[(k + 1) % 3];
        const double da = a.p.z + a.p.w, dc = c.p.z + c.p.w;
        if (da >= 0.0) out[n++] = a;
        if ((da >= 0.0) != (dc >= 0.0)) {
            const double t = da / (da - dc);
            out[n++] = {a.p + (c.p - a.p) * t, a.b + (c.b - a.b) * t};
        }
    }
    return n;
}

/// A vertex after the perspective division and the viewport transform.
struct ScreenVertex {
    double x, y;     // pixel coordinates, y down
    double z;        // z / w
    double inv_w;    // 1 / w, for perspective-correct interpolation
    glm::dvec3 b_w;  // barycentric weights divided by w
};

inline ScreenVertex to_screen(const ClipVertex& v, int width, int height) {
    const double iw = 1.0 / v.p.w;
    return {(v.p.x * iw * 0.5 + 0.5) * width, (0.5 - v.p.y * iw * 0.5) * height, v.p.z * iw, iw,
            v.b * iw};
}

/// Edge function of the directed edge a -> b at point (x, y): twice the signed area of the
/// triangle (a, b, p); positive on one side, zero on the edge (Pineda 1988).
inline double edge(const ScreenVertex& a, const ScreenVertex& b, double x, double y) {
    return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
}

/// Top-left rule: a pixel centre exactly on an edge belongs to only one of the two triangles
/// sharing that edge, so neighbouring patches neither overlap nor leave cracks (each pixel of a
/// hemicube is counted once). With both triangles oriented alike, the shared edge runs in
/// opposite directions, and exactly one direction passes this test.
inline bool owns_edge(const ScreenVertex& a, const ScreenVertex& b) {
    const double dy = b.y - a.y, dx = b.x - a.x;
    return dy > 0.0 || (dy == 0.0 && dx < 0.0);
}

/// Scan-converts one screen-space triangle over its clamped bounding box.
template <class Visit>
void fill_triangle(ScreenVertex v0, ScreenVertex v1, ScreenVertex v2, int width, int height,
                   Visit&& visit) {
    double area = edge(v0, v1, v2.x, v2.y);
    if (area == 0.0 || !std::isfinite(area)) return;  // seen edge-on: covers no pixel
    if (area < 0.0) {  // orient consistently; both windings are drawn (no culling)
        std::swap(v1, v2);
        area = -area;
    }
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({v0.x, v1.x, v2.x}))));
    const int x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({v0.x, v1.x, v2.x}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({v0.y, v1.y, v2.y}))));
    const int y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({v0.y, v1.y, v2.y}))));
    const bool own0 = owns_edge(v1, v2), own1 = owns_edge(v2, v0), own2 = owns_edge(v0, v1);
    for (int y = y0; y <= y1; ++y) {
        const double py = y + 0.5;
        for (int x = x0; x <= x1; ++x) {
            const double px = x + 0.5;
            const double e0 = edge(v1, v2, px, py), e1 = edge(v2, v0, px, py),
                         e2 = edge(v0, v1, px, py);
            if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) continue;
            if ((e0 == 0.0 && !own0) || (e1 == 0.0 && !own1) || (e2 == 0.0 && !own2)) continue;
            // Screen-space weights l_k are linear in x, y; z/w is too, but attributes are not:
            // interpolate b/w and 1/w, and divide (perspective-correct interpolation).
            const double l0 = e0 / area, l1 = e1 / area, l2 = e2 / area;
            const double depth = l0 * v0.z + l1 * v1.z + l2 * v2.z;
            const double inv_w = l0 * v0.inv_w + l1 * v1.inv_w + l2 * v2.inv_w;
            const glm::dvec3 b = (l0 * v0.b_w + l1 * v1.b_w + l2 * v2.b_w) / inv_w;
            visit(Fragment{x, y, depth, b});
        }
    }
}

}  // namespace detail

/// Rasterises one triangle given in clip space into a width x height raster: clips it to the
/// near plane, divides by w, and calls visit(Fragment) for every pixel whose centre it covers
/// (top-left rule on shared edges). Both windings are drawn; depth testing is the caller's (the
/// hemicube keeps ids, the camera colours). Pixels outside the raster are skipped.
/// Cost: O(pixels of the bounding box).
template <class Visit>
void rasterize_triangle(const std::array<Vec4, 3>& clip, int width, int height, Visit&& visit) {
    const std::array<detail::ClipVertex, 3> in{
        {{clip[0], {1, 0, 0}}, {clip[1], {0, 1, 0}}, {clip[2], {0, 0, 1}}}};
    std::array<detail::ClipVertex, 4> poly;
    const int n = detail::clip_near(in, poly);
    if (n < 3) return;
    std::array<detail::ScreenVertex, 4> s;
    for (int k = 0; k < n; ++k) s[k] = detail::to_screen(poly[k], width, height);
    for (int k = 1; k + 1 < n; ++k)
        detail::fill_triangle(s[0], s[k], s[k + 1], width, height, visit);
}

}  // namespace radiosity
