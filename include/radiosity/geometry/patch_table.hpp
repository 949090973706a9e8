#pragma once
/// @file patch_table.hpp  The flat, cache-friendly table of patch geometry that hot loops read
/// (rasterising, quadrature, matrix sweeps), made once from the mesh. Index i is patch i. Also
/// the fan triangles of the patches, which every visibility model is built over.

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace radiosity {

/// Geometry of n planar patches: polygon vertices (counter-clockwise about the normal), centroid,
/// unit normal and area. A patch radiates from its front (normal) side only.
class PatchTable {
  public:
    /// Appends a patch; throws Error naming `what` if the polygon has fewer than 3 vertices,
    /// a non-finite coordinate or zero area.
    void add(std::span<const Vec3> polygon, const std::string& what = "patch") {
        if (polygon.size() < 3) throw Error(what + ": a patch needs at least 3 vertices");
        for (const Vec3& v : polygon)
            if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
                throw Error(what + ": vertex coordinate is not a finite number");
        const double a = polygon_area(polygon);
        if (!(a > 0.0)) throw Error(what + ": zero area");
        vertices_.insert(vertices_.end(), polygon.begin(), polygon.end());
        first_.push_back(static_cast<std::uint32_t>(vertices_.size()));
        area_.push_back(a);
        normal_.push_back(polygon_normal(polygon));
        centroid_.push_back(polygon_centroid(polygon));
    }

    /// Number of patches.
    std::size_t size() const { return area_.size(); }
    /// The vertices of all patches in one array, patch after patch: polygon(i) is the piece
    /// from first(i) to first(i + 1). Loops over every vertex (the hemicube's) read it at once.
    std::span<const Vec3> vertices() const { return vertices_; }
    /// Index in vertices() of patch i's first vertex; first(size()) is the vertex count.
    std::size_t first(std::size_t i) const { return first_[i]; }
    /// Vertices of patch i, counter-clockwise about its normal.
    std::span<const Vec3> polygon(std::size_t i) const {
        return {vertices_.data() + first_[i], vertices_.data() + first_[i + 1]};
    }
    const Vec3& centroid(std::size_t i) const { return centroid_[i]; }  ///< area centroid
    const Vec3& normal(std::size_t i) const { return normal_[i]; }      ///< unit normal
    double area(std::size_t i) const { return area_[i]; }               ///< area A_i
    std::span<const double> areas() const { return area_; }             ///< all areas

  private:
    std::vector<Vec3> vertices_;
    std::vector<std::uint32_t> first_{0};
    std::vector<Vec3> centroid_, normal_;
    std::vector<double> area_;
};

/// A triangle of a patch's fan, tagged with the patch it belongs to: what ray queries test.
struct PatchTriangle {
    std::array<Vec3, 3> v;  ///< vertices, counter-clockwise about the patch's normal
    std::uint32_t patch;    ///< index of the patch in its table
};

/// The fan triangles (v0, v_k, v_k+1) of every patch, patch after patch: the one triangulation
/// that the BVH, the brute-force visibility and Embree share, so that their answers compare.
/// Cost: O(vertices).
inline std::vector<PatchTriangle> fan_triangles(const PatchTable& patches) {
    std::vector<PatchTriangle> out;
    out.reserve(patches.vertices().size());
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const auto p = patches.polygon(i);
        for (std::size_t k = 1; k + 1 < p.size(); ++k)
            out.push_back({{p[0], p[k], p[k + 1]}, static_cast<std::uint32_t>(i)});
    }
    return out;
}

}  // namespace radiosity
