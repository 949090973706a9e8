#pragma once
/// @file ray_cast.hpp  Ray-cast form factors: F_ij = (1/A_i) integral over A_i integral over A_j
/// of V cos(phi_i) cos(phi_j) / (pi r^2), estimated with stratified, jittered sample points on
/// both patches and one visibility ray per sample pair through the BVH (Wallace, Elmquist &
/// Haines 1989; Cook 1986 for jittering).
///
/// The inner integral over patch j is taken analytically at each sample point (Lambert's contour
/// integral), and the rays give the kernel-weighted visible fraction. This removes the 1/r^2
/// blow-up of the plain estimator for adjacent patches (near field): a shared edge costs no more
/// samples than any other pair, and unoccluded pairs are exact up to the outer quadrature.

#include <radiosity/concepts.hpp>
#include <radiosity/error.hpp>
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/visibility.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/geometry/patch_table.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace radiosity {

/// Settings of the ray-cast method.
struct RayCastOptions {
    int samples = 16;           ///< sample pairs per patch pair (rounded up to a square, k x k)
    int penumbra_samples = 64;  ///< sample pairs for a pair whose first rays disagree
    std::uint64_t seed = 1;     ///< seed of every pair's random stream
    BvhOptions bvh{};           ///< build settings of the acceleration structure
};

namespace detail {

/// The exchange integral A_outer F_outer->inner without visibility, by the sample points xs on
/// the outer patch with the inner integral taken analytically (Lambert's contour integral).
inline double sampled_mean(const PatchTable& t, std::size_t outer, std::size_t inner,
                           const std::vector<Vec3>& xs) {
    double sum = 0.0;
    for (const Vec3& x : xs) sum += point_to_polygon(x, t.normal(outer), t.polygon(inner));
    return t.area(outer) * sum / static_cast<double>(xs.size());
}

}  // namespace detail

/// Ray-cast form factors over a BVH (see the file comment). Every pair (i, j) has its own
/// random stream, seeded from both indices, and is integrated over the smaller patch of the
/// two: so A_i F_ij = A_j F_ji exactly, and rows do not depend on thread count or order.
/// Cost per pair: k^2 contour integrals and k^2 rays (O(log n) each); a row is O(n log n).
/// Near-field pairs (touching bounding spheres) take the outer integral by the analytic
/// method's adaptive quadrature, and still k^2 rays for their visible fraction.
class RayCast {
  public:
    /// A method with the given settings; throws Error for samples outside [1, 65536].
    explicit RayCast(RayCastOptions options = {}) : options_(options) {
        if (options_.samples < 1 || options_.samples > 65536 || options_.penumbra_samples < 0 ||
            options_.penumbra_samples > 65536)
            throw Error("ray-cast form factors: samples must be in [1, 65536], not " +
                        std::to_string(options_.samples));
    }

    /// Keeps a reference to the table and builds the BVH over its patches.
    void prepare(const PatchTable& patches) {
        patches_ = &patches;
        bvh_ = std::make_shared<const Bvh>(patches, options_.bvh);
        radius_.assign(patches.size(), 0.0);
        for (std::size_t i = 0; i < patches.size(); ++i)
            for (const Vec3& v : patches.polygon(i))
                radius_[i] = std::max(radius_[i], glm::distance(v, patches.centroid(i)));
    }

    /// F_ij for one pair (0 for i == j).
    double pair(std::size_t i, std::size_t j) const { return exchange(i, j) / table().area(i); }

    double area(std::size_t i) const { return table().area(i); }  ///< A_i

    /// The exchange A_i F_ij = A_j F_ji: the same number both ways (ReciprocalFormFactor).
    double exchange(std::size_t i, std::size_t j) const {
        if (i == j) return 0.0;
        const PatchTable& t = table();
        const bool outer_is_i = t.area(i) < t.area(j) || (t.area(i) == t.area(j) && i < j);
        const std::size_t outer = outer_is_i ? i : j, inner = outer_is_i ? j : i;
        if (!detail::facing(t, outer, inner)) return 0.0;
        Rng rng(pair_seed(options_.seed, outer, inner));
        const int k = static_cast<int>(std::ceil(std::sqrt(double(options_.samples))));
        std::vector<Vec3> xs, ys;
        jittered_pairs(t.polygon(outer), t.polygon(inner), k, rng, xs, ys);
        double exchange =
            near_field(outer, inner)
                ? exchange_integral(t.polygon(outer), t.normal(outer), t.polygon(inner))
                : detail::sampled_mean(t, outer, inner, xs);
        if (exchange > 0.0 && may_be_blocked(outer, inner))
            exchange *= pair_visible_fraction(*bvh_, t, outer, inner, xs, ys,
                                              options_.penumbra_samples, rng);
        return exchange;
    }

    /// Row i: F_ij for every patch j (RowSource).
    void row(std::size_t i, std::span<float> out) const {
        for (std::size_t j = 0; j < out.size(); ++j) out[j] = static_cast<float>(pair(i, j));
    }

    const RayCastOptions& options() const { return options_; }  ///< the settings
    const Bvh& bvh() const { return *bvh_; }                    ///< the BVH (after prepare)

  private:
    /// False when nothing but walls around them can be between the two patches (Bvh::may_block
    /// on their joint bounding box): then V = 1 exactly and no ray is cast.
    bool may_be_blocked(std::size_t a, std::size_t b) const {
        const PatchTable& t = table();
        Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (std::size_t p : {a, b})
            for (const Vec3& v : t.polygon(p)) {
                lo = glm::min(lo, v);
                hi = glm::max(hi, v);
            }
        const double eps = 1e-9 * glm::length(hi - lo);
        return bvh_->may_block(lo, hi, static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                               {t.centroid(a), t.normal(a)}, {t.centroid(b), t.normal(b)}, eps);
    }

    /// Near field: the bounding spheres of the two patches touch (always so for neighbours).
    /// There F_dA->j changes fast across patch i (a logarithmic singularity of its derivative at
    /// a shared edge), and a few jittered points would miss it by several per cent; the adaptive
    /// quadrature of the analytic method takes the outer integral instead.
    bool near_field(std::size_t a, std::size_t b) const {
        return glm::distance(table().centroid(a), table().centroid(b)) <=
               2.0 * (radius_[a] + radius_[b]);
    }

    const PatchTable& table() const {
        if (patches_ == nullptr) throw Error("ray-cast form factors: prepare() was not called");
        return *patches_;
    }

    RayCastOptions options_;
    const PatchTable* patches_ = nullptr;
    std::shared_ptr<const Bvh> bvh_;
    std::vector<double> radius_;  // distance from each centroid to its farthest vertex
};

static_assert(ReciprocalFormFactor<RayCast>);

}  // namespace radiosity
