#pragma once
/// @file visibility.hpp  The visibility term V_ij of the form factor, estimated by rays: the
/// kernel-weighted fraction of sample pairs whose connecting segment is unblocked. Shared by the
/// ray-cast method and the analytic method's optional visibility.

#include <radiosity/concepts.hpp>
#include <radiosity/config.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/geometry/vec.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace radiosity {

/// The point-to-point form-factor kernel cos(phi_x) cos(phi_y) / (pi r^2) between x (normal nx)
/// and y (normal ny); 0 when either faces away. F_dA->A = integral over A of kernel dA.
inline double form_factor_kernel(const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny) {
    const Vec3 d = y - x;
    const double r2 = glm::dot(d, d);
    const double cx = glm::dot(nx, d), cy = -glm::dot(ny, d);
    if (cx <= 0.0 || cy <= 0.0 || r2 == 0.0) return 0.0;
    return cx * cy / (std::numbers::pi * r2 * r2);
}

/// Kernel-weighted visibility of sample pairs: seen = sum_s V_s k_s and total = sum_s k_s, with
/// V_s = 1 if the segment of pair s is unblocked (one ray each) and k_s the kernel above.
struct VisibilitySums {
    double seen = 0.0;   ///< kernel carried by unblocked pairs
    double total = 0.0;  ///< kernel of all pairs
    /// The visible fraction seen / total: a ratio estimator (consistent, bias O(1/N)) that
    /// weights each ray by how much its direction carries; exactly 1 when nothing is in the
    /// way; 1 if no pair carries anything.
    double fraction() const { return total > 0.0 ? seen / total : 1.0; }
    /// True if some rays were blocked and some not: the pair is in penumbra.
    bool mixed() const { return seen > 0.0 && seen < total; }
};

/// Casts one ray per sample pair (xs[s], ys[s]) between patches a and b (normals nx, ny) and
/// adds up the kernel-weighted visibility.
template <Visibility V>
VisibilitySums visibility_sums(const V& visibility, std::span<const Vec3> xs, const Vec3& nx,
                               std::span<const Vec3> ys, const Vec3& ny, std::uint32_t a,
                               std::uint32_t b) {
    RADIOSITY_ASSERT(xs.size() == ys.size());
    VisibilitySums sums;
    for (std::size_t s = 0; s < xs.size(); ++s) {
        const double k = form_factor_kernel(xs[s], nx, ys[s], ny);
        if (k == 0.0) continue;
        sums.total += k;
        if (!visibility.occluded(xs[s], ys[s], a, b)) sums.seen += k;
    }
    return sums;
}

/// Kernel-weighted visible fraction of patch pair (a, b) from n stratified, jittered sample
/// pairs (k x k with k^2 >= n, jittered_pairs) drawn from rng: one stage, one ray each. No
/// decision is taken on the first rays, so the estimate is unbiased up to the ratio's O(1/N):
/// a refinement only where the first rays disagree (below) trusts pairs whose first rays all
/// agree, and its estimate of a pair partly hidden by a small occluder is then 1 (or 0 behind
/// a large one), every time. Cost: k^2 rays.
template <Visibility V>
double stratified_visible_fraction(const V& visibility, const PatchTable& t, std::size_t a,
                                   std::size_t b, int n, Rng& rng) {
    const int k = static_cast<int>(std::ceil(std::sqrt(double(n))));
    std::vector<Vec3> xs, ys;
    jittered_pairs(t.polygon(a), t.polygon(b), k, rng, xs, ys);
    return visibility_sums(visibility, xs, t.normal(a), ys, t.normal(b),
                           static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b))
        .fraction();
}

/// Kernel-weighted visible fraction of patch pair (a, b) from the sample pairs (xs on a, ys on
/// b); where their rays disagree (penumbra: the pair is partly hidden), k x k more jittered
/// pairs with k^2 >= penumbra_samples are drawn from rng and added, so that rays go where the
/// visibility term varies rather than where it is plainly 0 or 1. xs and ys are overwritten
/// in that case.
template <Visibility V>
double pair_visible_fraction(const V& visibility, const PatchTable& t, std::size_t a, std::size_t b,
                             std::vector<Vec3>& xs, std::vector<Vec3>& ys, int penumbra_samples,
                             Rng& rng) {
    const auto ia = static_cast<std::uint32_t>(a), ib = static_cast<std::uint32_t>(b);
    VisibilitySums sums = visibility_sums(visibility, xs, t.normal(a), ys, t.normal(b), ia, ib);
    if (sums.mixed() && penumbra_samples > static_cast<int>(xs.size())) {
        const int k = static_cast<int>(std::ceil(std::sqrt(double(penumbra_samples))));
        jittered_pairs(t.polygon(a), t.polygon(b), k, rng, xs, ys);
        const VisibilitySums more =
            visibility_sums(visibility, xs, t.normal(a), ys, t.normal(b), ia, ib);
        sums.seen += more.seen;
        sums.total += more.total;
    }
    return sums.fraction();
}

}  // namespace radiosity
