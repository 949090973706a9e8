#pragma once
/// @file sampling.hpp  Repeatable randomness for Monte Carlo form factors: a counter-free hash
/// and a small generator seeded from it (so each patch pair has its own stream, independent of
/// threads and order), and stratified, jittered points on a polygon (Cook 1986; Shirley 1991).

#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace radiosity {

/// SplitMix64 finaliser (Steele, Lea & Flood 2014): a well-mixed 64-bit hash. Used to derive
/// per-patch and per-pair seeds, so results never depend on thread count or scheduling.
inline std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

/// A small pseudo-random generator: SplitMix64 as a sequence (Steele et al. 2014), good enough
/// for jittering and cheap to seed per patch pair. Not for cryptography.
class Rng {
  public:
    /// A generator whose stream is fixed by the seed.
    explicit Rng(std::uint64_t seed) : state_(splitmix64(seed)) {}
    /// The next 64 random bits.
    std::uint64_t next() {
        state_ += 0x9e3779b97f4a7c15ULL;
        std::uint64_t z = state_;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    /// A uniform double in [0, 1) (53 random bits).
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

  private:
    std::uint64_t state_;
};

/// k x k stratified, jittered points on a convex polygon, uniform in area (Shirley 1991): the
/// unit square is cut into k x k cells, one random point per cell; u picks the fan triangle by
/// its share of the area and, rescaled, the position in it by the area-preserving map
/// (u, v) -> (1 - sqrt(u), sqrt(u) (1 - v), sqrt(u) v), so strata stay compact. Appends k^2
/// points to out. Cost: O(k^2 + polygon size).
inline void stratified_points(std::span<const Vec3> poly, int k, Rng& rng, std::vector<Vec3>& out) {
    const std::size_t fan = poly.size() - 2;
    std::vector<double> cdf(fan + 1, 0.0);  // area share of the fan triangles, accumulated
    for (std::size_t t = 0; t < fan; ++t)
        cdf[t + 1] = cdf[t] + glm::length(glm::cross(poly[t + 1] - poly[0], poly[t + 2] - poly[0]));
    for (double& c : cdf) c /= cdf[fan];
    for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
            double u = (a + rng.uniform()) / k;
            const double v = (b + rng.uniform()) / k;
            std::size_t t = 0;
            while (t + 1 < fan && u >= cdf[t + 1]) ++t;
            u = (u - cdf[t]) / (cdf[t + 1] - cdf[t]);
            const double s = std::sqrt(std::clamp(u, 0.0, 1.0));
            out.push_back((1.0 - s) * poly[0] + s * (1.0 - v) * poly[t + 1] + s * v * poly[t + 2]);
        }
}

/// The seed of the random stream of patch pair (a, b): a hash of a base seed and both indices,
/// so a pair's estimate is the same whichever row, thread or order asks for it.
inline std::uint64_t pair_seed(std::uint64_t seed, std::size_t a, std::size_t b) {
    return splitmix64(splitmix64(seed) ^ ((static_cast<std::uint64_t>(a) << 32) ^ b));
}

/// The side k of the square grid of strata for `samples` samples: round(sqrt(samples)), 1 to
/// 16 (shuffled_strata's limit).
inline int strata_side(int samples) {
    return std::clamp(static_cast<int>(std::lround(std::sqrt(double(samples)))), 1, 16);
}

/// The strata 0 .. k^2 - 1 of a k x k grid (k at most 16) in random order (Fisher-Yates; Knuth
/// 1969), so that stratum i of one grid meets stratum order[i] of another, as jittered_pairs
/// pairs its points. No allocation.
inline std::array<std::uint16_t, 256> shuffled_strata(int k, Rng& rng) {
    std::array<std::uint16_t, 256> order;
    for (int i = 0; i < k * k; ++i) order[std::size_t(i)] = static_cast<std::uint16_t>(i);
    for (int m = k * k; m > 1; --m)
        std::swap(order[std::size_t(m - 1)],
                  order[static_cast<std::size_t>(rng.uniform() * double(m))]);
    return order;
}

/// k x k stratified, jittered sample pairs: xs on polygon a, ys on polygon b, the strata of b
/// shuffled (Fisher-Yates; Knuth 1969) so that cell (u, v) of a meets a random cell of b.
/// Replaces the contents of xs and ys. Cost: O(k^2).
inline void jittered_pairs(std::span<const Vec3> a, std::span<const Vec3> b, int k, Rng& rng,
                           std::vector<Vec3>& xs, std::vector<Vec3>& ys) {
    xs.clear();
    ys.clear();
    stratified_points(a, k, rng, xs);
    stratified_points(b, k, rng, ys);
    for (std::size_t m = ys.size(); m > 1; --m)
        std::swap(ys[m - 1], ys[static_cast<std::size_t>(rng.uniform() * static_cast<double>(m))]);
}

}  // namespace radiosity
