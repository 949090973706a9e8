#pragma once
/// @file polygon.hpp  Planar polygons: Newell normal, area, centroid, clipping to a plane.
/// Vertices are counter-clockwise seen from the side the normal points to.

#include <radiosity/config.hpp>
#include <radiosity/geometry/vec.hpp>

#include <cstddef>
#include <array>
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

/// Clips a polygon to the half-space dot(x - origin, normal) >= 0 (Sutherland & Hodgman 1974),
/// writing the corners to `out` (room for 2 p.size(): each edge adds at most its start and one
/// crossing) and returning how many. The result may be empty; it keeps the input's orientation.
/// No allocation: the form-factor kernels clip millions of small polygons. O(n).
inline std::size_t clip_to_plane(std::span<const Vec3> p, const Vec3& origin, const Vec3& normal,
                                 std::span<Vec3> out) {
    RADIOSITY_ASSERT(out.size() >= 2 * p.size());
    std::size_t count = 0;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3& a = p[k];
        const Vec3& b = p[(k + 1) % p.size()];
        const double da = glm::dot(a - origin, normal);
        const double db = glm::dot(b - origin, normal);
        if (da >= 0.0) out[count++] = a;
        if ((da >= 0.0) != (db >= 0.0)) out[count++] = a + (b - a) * (da / (da - db));
    }
    return count;
}

/// clip_to_plane into a new vector.
inline std::vector<Vec3> clip_to_plane(std::span<const Vec3> p, const Vec3& origin,
                                       const Vec3& normal) {
    std::vector<Vec3> out(2 * p.size());
    out.resize(clip_to_plane(p, origin, normal, std::span<Vec3>(out)));
    return out;
}

/// A polygon clipped in place: up to N corners on the stack, more on the heap (polygons of more
/// than N / 2 corners are rare: patches are triangles and quads).
template <std::size_t N = 16>
class ClippedPolygon {
  public:
    /// p clipped to the half-space dot(x - origin, normal) >= 0 (clip_to_plane).
    ClippedPolygon(std::span<const Vec3> p, const Vec3& origin, const Vec3& normal) {
        if (2 * p.size() <= N) {
            count_ = clip_to_plane(p, origin, normal, std::span<Vec3>(small_));
        } else {
            large_ = clip_to_plane(p, origin, normal);
            count_ = large_.size();
        }
    }
    /// The corners.
    std::span<const Vec3> corners() const {
        return large_.empty() ? std::span<const Vec3>(small_.data(), count_)
                              : std::span<const Vec3>(large_);
    }

  private:
    std::array<Vec3, N> small_;
    std::vector<Vec3> large_;
    std::size_t count_ = 0;
};

}  // namespace radiosity
