#pragma once
/// @file ray_cast.hpp  Ray-cast form factors: F_ij = (1/A_i) integral over A_i integral over A_j
/// of V cos(phi_i) cos(phi_j) / (pi r^2), as the unoccluded form factor times a visible fraction
/// estimated with stratified, jittered sample points on both patches and one visibility ray per
/// sample pair (Wallace, Elmquist & Haines 1989; Cook 1986 for jittering), through any
/// Visibility model: the BVH by default.
///
/// The unoccluded form factor is taken by quadrature of Lambert's contour integral (the analytic
/// method's: adaptive in the near field, one degree-5 rule in the far field), so unoccluded pairs
/// are exact to the quadrature's 1e-6 and a shared edge costs no more rays than any other pair.
/// The rays give the kernel-weighted visible fraction, in one stage, their number in proportion
/// to the pair's unoccluded form factor (with a floor): the variance a pair leaves in a row is
/// then in proportion to what it carries there, and a row's adds up to at most
/// Var(V) / samples_per_form_factor whatever the patch sizes. At the default every row of a
/// closed room with two blocks sums to 1 within 5.9e-4 (tests/test_row_sums.cpp).

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
    int samples = 16;  ///< fewest rays for a pair that may be blocked (rounded up to a square)
    /// Rays per unit of the pair's unoccluded form factor F_outer,inner (the larger of F_ij and
    /// F_ji): a pair carrying F = 0.01 of its row asks for 2,622 rays (52 x 52) by default.
    double samples_per_form_factor = 262144.0;
    int max_samples = 65536;  ///< most rays for one pair
    std::uint64_t seed = 1;   ///< seed of every pair's random stream
    BvhOptions bvh{};         ///< build settings of the BVH (when the visibility is Bvh)
};

namespace detail {

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
/// A_j F_ji exactly, and rows do not depend on thread count or order. Cost per pair: 14 contour
/// integrals (a quad in the far field; more by the adaptive quadrature in the near field), and
/// for a pair that may be blocked max(samples, F samples_per_form_factor) rays, O(log n) each
/// through the BVH: about samples_per_form_factor times the row's share of such pairs per row.
/// Where V offers pair culling (PairCulling), a pair that nothing can stand between casts no
/// ray.
template <class V = Bvh>
requires Visibility<V> && std::constructible_from<V, const PatchTable&>
class RayCast {
  public:
    /// A method with the given settings; throws Error unless 1 <= samples <= max_samples <=
    /// 65536 and samples_per_form_factor is finite and >= 0.
    explicit RayCast(RayCastOptions options = {}) : options_(options) {
        if (options_.samples < 1 || options_.max_samples < options_.samples ||
            options_.max_samples > 65536)
            throw Error("ray-cast form factors: need 1 <= samples (" +
                        std::to_string(options_.samples) + ") <= max_samples (" +
                        std::to_string(options_.max_samples) + ") <= 65536");
        if (!(options_.samples_per_form_factor >= 0.0) ||
            !std::isfinite(options_.samples_per_form_factor))
            throw Error("ray-cast form factors: samples_per_form_factor must be finite and >= 0");
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
    /// the unoccluded exchange; times the visible fraction of the pair's rays (from its own
    /// random stream), unless nothing can be in the way.
    double exchange(std::size_t i, std::size_t j) const {
        if (i == j) return 0.0;
        const PatchTable& t = table();
        RADIOSITY_ASSERT(i < t.size() && j < t.size());
        const auto [outer, inner] = detail::integration_order(t, i, j);
        if (!detail::facing(t, outer, inner)) return 0.0;
        const double unoccluded = unoccluded_exchange(outer, inner);
        if (!(unoccluded > 0.0) || !may_be_blocked(outer, inner)) return unoccluded;
        Rng rng(pair_seed(options_.seed, outer, inner));
        const int rays = ray_count(unoccluded / t.area(outer));
        return unoccluded * stratified_visible_fraction(*visibility_, t, outer, inner, rays, rng);
    }

    /// Row i: F_ij for every patch j (RowSource).
    void row(std::size_t i, std::span<float> out) const {
        RADIOSITY_ASSERT(out.size() == table().size());
        for (std::size_t j = 0; j < out.size(); ++j) out[j] = static_cast<float>(pair(i, j));
    }

    const RayCastOptions& options() const { return options_; }  ///< the settings
    const V& visibility() const { return *visibility_; }        ///< the model (after prepare)

  private:
    /// Rays for a pair whose unoccluded form factor (from the outer patch) is f: in proportion
    /// to f, so that the pair's variance in a row, f^2 Var(V) / rays, is in proportion to f and
    /// a row's adds up to at most Var(V) / samples_per_form_factor (Neyman's allocation with
    /// the unknown Var(V) taken equal); within [samples, max_samples].
    int ray_count(double f) const {
        const double n = std::ceil(f * options_.samples_per_form_factor);
        return static_cast<int>(
            std::clamp(n, double(options_.samples), double(options_.max_samples)));
    }

    /// A_outer F_outer->inner without visibility: by the analytic method's adaptive quadrature
    /// in the near field, else by its degree-5 rule once (exchange_by_rule), which is as good
    /// where F_dA->inner is smooth over the outer patch. (A mean over 16 jittered points
    /// instead left rows of a closed empty box 2e-3 off 1.)
    double unoccluded_exchange(std::size_t outer, std::size_t inner) const {
        const PatchTable& t = table();
        return near_field(outer, inner)
                   ? exchange_integral(t.polygon(outer), t.normal(outer), t.polygon(inner))
                   : exchange_by_rule(t.polygon(outer), t.normal(outer), t.polygon(inner));
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
