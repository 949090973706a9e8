#pragma once
/// @file polygon.hpp  Planar polygons: Newell normal, area, centroid, clipping to a plane.
/// Vertices are counter-clockwise seen from the side the normal points to.

#include <radiosity/geometry/vec.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace radiosity {

/// Newell's vector of a polygon: normal times twice the area (Newell 1972; exact for planar
/// polygons, the projected-area normal for slightly non-planar ones). O(n).
inline Vec3 newell_vector(std::span<const Vec3> p) {
    Vec3 n(0.0);
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3& a = p[k];
        const Vec3& b = p[(k + 1) % p.size()];
        n += glm::cross(a, b);
    }
    return n;
}

/// Area of a polygon (half the length of its Newell vector).
inline double polygon_area(std::span<const Vec3> p) {
    return 0.5 * glm::length(newell_vector(p));
}

/// Unit normal of a polygon by Newell's method; the zero vector for a degenerate polygon.
inline Vec3 polygon_normal(std::span<const Vec3> p) {
    const Vec3 n = newell_vector(p);
    const double len = glm::length(n);
    return len > 0.0 ? n / len : Vec3(0.0);
}

/// Area centroid of a planar polygon (fan of triangles from the first vertex, each weighted by
/// its signed area along the polygon normal).
inline Vec3 polygon_centroid(std::span<const Vec3> p) {
    const Vec3 n = polygon_normal(p);
    Vec3 c(0.0);
    double w = 0.0;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
        const double a = glm::dot(glm::cross(p[k] - p[0], p[k + 1] - p[0]), n);
        c += a * (p[0] + p[k] + p[k + 1]) / 3.0;
        w += a;
    }
    if (w == 0.0) {  // degenerate: fall back to the vertex mean
        for (const Vec3& v : p) c += v;
        return c / static_cast<double>(p.size());
    }
    return c / w;
}

/// Clips a polygon to the half-space dot(x - origin, normal) >= 0 (Sutherland & Hodgman 1974).
/// The result may be empty; it keeps the input's orientation. O(n).
inline std::vector<Vec3> clip_to_plane(std::span<const Vec3> p, const Vec3& origin,
                                       const Vec3& normal) {
    std::vector<Vec3> out;
    out.reserve(p.size() + 2);
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3& a = p[k];
        const Vec3& b = p[(k + 1) % p.size()];
        const double da = glm::dot(a - origin, normal);
        const double db = glm::dot(b - origin, normal);
        if (da >= 0.0) out.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    return out;
}

}  // namespace radiosity
