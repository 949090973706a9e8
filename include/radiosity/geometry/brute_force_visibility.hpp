#pragma once
/// @file brute_force_visibility.hpp  Visibility by its definition: the segment from p to q is
/// blocked if it meets any triangle of any patch but its two end patches, and every triangle
/// is tested, with the watertight test (Woop, Benthin & Wald 2013). Read this first: the BVH
/// (geometry/bvh.hpp) answers exactly the same, only faster, by skipping what a ray cannot reach.
/// The reference that the BVH and Embree are tested against.

#include <radiosity/concepts.hpp>
#include <radiosity/geometry/bvh/triangle.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace radiosity {

/// Visibility with no acceleration structure: every fan triangle of every patch tested against
/// every segment (the plain definition of the visibility term V). Build O(n), query O(n): for
/// tests and teaching, and for scenes of a few hundred patches. No pair culling (PairCulling),
/// so form-factor methods over it cast rays for every pair. Thread-safe queries.
class BruteForceVisibility {
  public:
    /// The fan triangles of the table's patches (fan_triangles, as the BVH takes them).
    explicit BruteForceVisibility(const PatchTable& patches) : triangles_(fan_triangles(patches)) {}

    std::size_t triangle_count() const { return triangles_.size(); }  ///< triangles held

    /// Visibility: true if the open segment p -> q (endpoints excluded by segment_margin) hits
    /// a triangle of any patch other than a and b: the first triangle hit ends the search.
    bool occluded(const Vec3& p, const Vec3& q, std::uint32_t a, std::uint32_t b) const {
        const Vec3 d = q - p;
        if (d == Vec3(0.0)) return false;
        const ShearedRay ray(d);
        for (const PatchTriangle& triangle : triangles_) {
            if (triangle.patch == a || triangle.patch == b) continue;
            double t, u, v;
            if (hit_triangle(triangle, p, ray, segment_margin, 1.0 - segment_margin, t, u, v))
                return true;
        }
        return false;
    }

  private:
    std::vector<PatchTriangle> triangles_;
};

static_assert(Visibility<BruteForceVisibility>);
static_assert(!PairCulling<BruteForceVisibility>);

}  // namespace radiosity
