#pragma once
/// @file ray_cast.hpp  Ray-cast form factors: F_ij = (1/A_i) integral over A_i integral over A_j
/// of V cos(phi_i) cos(phi_j) / (pi r^2), estimated with stratified, jittered sample points on
/// both patches and one visibility ray per sample pair (Wallace, Elmquist & Haines 1989; Cook
/// 1986 for jittering), through any Visibility model: the BVH by default.
///
/// The inner integral over patch j is taken analytically at each sample point (Lambert's contour
/// integral), and the rays give the kernel-weighted visible fraction. This removes the 1/r^2
/// blow-up of the plain estimator for adjacent patches (near field): a shared edge costs no more
/// samples than any other pair, and unoccluded pairs are exact up to the outer quadrature.

#include <radiosity/concepts.hpp>
#include <radiosity/config.hpp>
#include <radiosity/error.hpp>
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/pair_culling.hpp>
#include <radiosity/form_factor/visibility.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/sampling.hpp>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace radiosity {

/// Settings of the ray-cast method.
struct RayCastOptions {
    int samples = 16;           ///< sample pairs per patch pair (rounded up to a square, k x k)
    int penumbra_samples = 64;  ///< sample pairs for a pair whose first rays disagree
    std::uint64_t seed = 1;     ///< seed of every pair's random stream
    BvhOptions bvh{};           ///< build settings of the BVH (when the visibility is Bvh)
};

namespace detail {

/// The exchange integral A_outer F_outer->inner without visibility, by the sample points xs on
/// the outer patch with the inner integral taken analytically (Lambert's contour integral).
inline double sampled_mean(const PatchTable& t, std::size_t outer, std::size_t inner,
                           const std::vector<Vec3>& xs) {
    RADIOSITY_ASSERT(!xs.empty());
    double sum = 0.0;
    for (const Vec3& x : xs) sum += point_to_polygon(x, t.normal(outer), t.polygon(inner));
    return t.area(outer) * sum / static_cast<double>(xs.size());
}

/// The visibility model V over the patches: with the BVH's build settings where V takes them
/// (Bvh), else V(table).
template <class V>
std::shared_ptr<const V> build_visibility(const PatchTable& patches, const BvhOptions& bvh) {
    if constexpr (std::constructible_from<V, const PatchTable&, const BvhOptions&>)
        return std::make_shared<const V>(patches, bvh);
    else
        return std::make_shared<const V>(patches);
}

}  // namespace detail

/// Ray-cast form factors (see the file comment) with visibility from V: the BVH by default
/// (`RayCast method(options)` is RayCast<Bvh>), or any Visibility built over the patch table
/// (BruteForceVisibility, EmbreeVisibility). Every pair (i, j) has its own random stream,
/// seeded from both indices, and is integrated over the smaller patch of the two: so A_i F_ij =
/// A_j F_ji exactly, and rows do not depend on thread count or order. Cost per pair: k^2
/// contour integrals and k^2 rays (O(log n) each through the BVH); a row is O(n log n).
/// Near-field pairs (touching bounding spheres) take the outer integral by the analytic
/// method's adaptive quadrature, and still k^2 rays for their visible fraction. Where V offers
/// pair culling (PairCulling), a pair that nothing can stand between casts no ray.
template <class V = Bvh>
requires Visibility<V> && std::constructible_from<V, const PatchTable&>
class RayCast {
  public:
    /// A method with the given settings; throws Error for samples outside [1, 65536].
    explicit RayCast(RayCastOptions options = {}) : options_(options) {
        if (options_.samples < 1 || options_.samples > 65536 || options_.penumbra_samples < 0 ||
            options_.penumbra_samples > 65536)
            throw Error("ray-cast form factors: samples must be in [1, 65536], not " +
                        std::to_string(options_.samples));
    }

    /// Keeps a reference to the table and builds the visibility model over its patches.
    void prepare(const PatchTable& patches) {
        patches_ = &patches;
        visibility_ = detail::build_visibility<V>(patches, options_.bvh);
        radius_.assign(patches.size(), 0.0);
        for (std::size_t i = 0; i < patches.size(); ++i)
            for (const Vec3& v : patches.polygon(i))
                radius_[i] = std::max(radius_[i], glm::distance(v, patches.centroid(i)));
    }

    /// F_ij for one pair (0 for i == j).
    double pair(std::size_t i, std::size_t j) const { return exchange(i, j) / table().area(i); }

    double area(std::size_t i) const { return table().area(i); }  ///< A_i

    /// The exchange A_i F_ij = A_j F_ji: the same number both ways (ReciprocalFormFactor).
    /// Steps: integrate over the smaller patch (outer); skip pairs that do not face each other;
    /// draw the pair's jittered sample pairs; the unoccluded exchange; times the visible
    /// fraction of the rays, unless nothing can be in the way.
    double exchange(std::size_t i, std::size_t j) const {
        if (i == j) return 0.0;
        const PatchTable& t = table();
        RADIOSITY_ASSERT(i < t.size() && j < t.size());
        const auto [outer, inner] = detail::integration_order(t, i, j);
        if (!detail::facing(t, outer, inner)) return 0.0;
        Rng rng(pair_seed(options_.seed, outer, inner));
        std::vector<Vec3> xs, ys;
        jittered_pairs(t.polygon(outer), t.polygon(inner), sample_grid(), rng, xs, ys);
        double exchange = unoccluded_exchange(outer, inner, xs);
        if (exchange > 0.0 && may_be_blocked(outer, inner))
            exchange *= pair_visible_fraction(*visibility_, t, outer, inner, xs, ys,
                                              options_.penumbra_samples, rng);
        return exchange;
    }

    /// Row i: F_ij for every patch j (RowSource).
    void row(std::size_t i, std::span<float> out) const {
        RADIOSITY_ASSERT(out.size() == table().size());
        for (std::size_t j = 0; j < out.size(); ++j) out[j] = static_cast<float>(pair(i, j));
    }

    const RayCastOptions& options() const { return options_; }  ///< the settings
    const V& visibility() const { return *visibility_; }        ///< the model (after prepare)

  private:
    /// k, for k x k sample pairs: the square root of the samples asked for, rounded up.
    int sample_grid() const {
        return static_cast<int>(std::ceil(std::sqrt(double(options_.samples))));
    }

    /// A_outer F_outer->inner without visibility: by the analytic method's adaptive quadrature
    /// in the near field, else by the mean over the sample points xs on the outer patch.
    double unoccluded_exchange(std::size_t outer, std::size_t inner,
                               const std::vector<Vec3>& xs) const {
        const PatchTable& t = table();
        return near_field(outer, inner)
                   ? exchange_integral(t.polygon(outer), t.normal(outer), t.polygon(inner))
                   : detail::sampled_mean(t, outer, inner, xs);
    }

    /// False when nothing but walls around them can be between the two patches (pair culling,
    /// pair_may_be_blocked): then V = 1 exactly and no ray is cast. Always true for a model
    /// without pair culling, whose rays then give V = 1 where nothing is in the way.
    bool may_be_blocked(std::size_t a, std::size_t b) const {
        if constexpr (PairCulling<V>)
            return pair_may_be_blocked(*visibility_, table(), a, b);
        else
            return true;
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
    std::shared_ptr<const V> visibility_;
    std::vector<double> radius_;  // distance from each centroid to its farthest vertex
};

static_assert(ReciprocalFormFactor<RayCast<>>);

}  // namespace radiosity
