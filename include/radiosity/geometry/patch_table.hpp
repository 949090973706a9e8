#pragma once
/// @file patch_table.hpp  The flat, cache-friendly table of patch geometry that hot loops read
/// (rasterising, quadrature, matrix sweeps), made once from the mesh. Index i is patch i.

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>

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

}  // namespace radiosity
