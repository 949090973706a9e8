#pragma once
/// @file dense_dot.hpp  The gather sum_j F_ij B_j over a stretch of a dense float row, for K
/// bands at once (and a row's sum of |F_ij|), accumulated in double: SSE2 where the compiler
/// targets it (every x86-64 build), plain C++ otherwise. B is held band-major (all patches' band 0,
/// then band 1, ...) so that consecutive j are consecutive doubles. Every path adds in the same
/// fixed order (dense_dot), so the sums are bit-identical across paths and do not depend on which
/// thread computes them. (Off x86-64, a compiler that fuses the plain path's multiply and add
/// rounds differently, yet still alike on every thread.)

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace radiosity::detail {

/// Patch values band-major: band k of patch j at `at(k, j)`. Converted from and to the solvers'
/// interleaved layout (K values per patch) in O(n K), nothing next to an O(n^2) sweep.
template <std::size_t K>
class BandMajor {
  public:
    /// The band-major copy of interleaved values v (v[j K + k]).
    explicit BandMajor(std::span<const double> v) : n_(v.size() / K), v_(v.size()) {
        for (std::size_t j = 0; j < n_; ++j)
            for (std::size_t k = 0; k < K; ++k) v_[k * n_ + j] = v[j * K + k];
    }
    /// Writes the values back, interleaved, into v.
    void copy_to(std::span<double> v) const {
        for (std::size_t j = 0; j < n_; ++j)
            for (std::size_t k = 0; k < K; ++k) v[j * K + k] = v_[k * n_ + j];
    }
    double& at(std::size_t k, std::size_t j) { return v_[k * n_ + j]; }  ///< band k of patch j
    const double* data() const { return v_.data(); }  ///< band k starts at data() + k stride()
    std::size_t stride() const { return n_; }         ///< distance between bands

  private:
    std::size_t n_;
    std::vector<double> v_;
};

/// Lanes of the fixed summation order of dense_dot: term j goes to lane (j - begin) % 8.
inline constexpr std::size_t dot_lanes = 8;

/// Asks for the row 1 KiB ahead of p. The hardware prefetcher alone left a one-core gather at
/// 6 GB/s of F against 14 GB/s for a plain read of memory; this brought it to about 10. The
/// address is made as an integer: it may lie past the row's end, which a prefetch may touch
/// but pointer arithmetic may not name.
inline void prefetch_ahead(const float* p) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(p) + 1024));
#else
    (void)p;
#endif
}

/// Adds the terms of dense_dot over [begin, body) to their lanes, body - begin a multiple of 8
/// and begin where term 0 of lane 0 lies: SSE2 (two doubles an instruction) or plain C++, in the
/// same order. Wider vectors (AVX, chosen at run time) gained only about 6%: with the prefetch
/// the gather is bound by memory, not by arithmetic.
template <std::size_t K>
void dense_lanes(const float* f, const double* B, std::size_t stride, std::size_t begin,
                 std::size_t body, double (*lane)[dot_lanes]) {
#if defined(__SSE2__)
    // Lanes 0-1, 2-3, 4-5, 6-7 of band k in acc[k][0..3]: 4 K chains of adds.
    __m128d acc[K][4];
    for (std::size_t k = 0; k < K; ++k)
        for (std::size_t q = 0; q < 4; ++q) acc[k][q] = _mm_loadu_pd(lane[k] + 2 * q);
    const auto step = [&](std::size_t j, std::size_t half) {  // terms j .. j + 3
        const __m128 x = _mm_loadu_ps(f + j);
        const __m128d x01 = _mm_cvtps_pd(x), x23 = _mm_cvtps_pd(_mm_movehl_ps(x, x));
        for (std::size_t k = 0; k < K; ++k) {
            const double* b = B + k * stride + j;
            acc[k][half] = _mm_add_pd(acc[k][half], _mm_mul_pd(x01, _mm_loadu_pd(b)));
            acc[k][half + 1] = _mm_add_pd(acc[k][half + 1], _mm_mul_pd(x23, _mm_loadu_pd(b + 2)));
        }
    };
    for (std::size_t j = begin; j < body; j += dot_lanes) {
        prefetch_ahead(f + j);
        step(j, 0);
        step(j + 4, 2);
    }
    for (std::size_t k = 0; k < K; ++k)
        for (std::size_t q = 0; q < 4; ++q) _mm_storeu_pd(lane[k] + 2 * q, acc[k][q]);
#else
    for (std::size_t j = begin; j < body; j += dot_lanes)
        for (std::size_t k = 0; k < K; ++k)
            for (std::size_t q = 0; q < dot_lanes; ++q)
                lane[k][q] += static_cast<double>(f[j + q]) * B[k * stride + j + q];
#endif
}

/// The sum of the lanes in their fixed order ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)).
inline double sum_lanes(const double* l) {
    return ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]));
}

/// sum_j |f[j]| over a dense row, in double, term j in lane j % 8 and the lanes summed as in
/// sum_lanes: a fixed order, so the same bits on every thread. Eight chains of adds, which the
/// compiler may pack two to an SSE2 instruction: as fast as the gather, bound by memory.
/// Cost: f.size() additions.
inline double dense_abs_sum(std::span<const float> f) {
    double lane[dot_lanes] = {};
    const std::size_t body = f.size() / dot_lanes * dot_lanes;
    for (std::size_t j = 0; j < body; j += dot_lanes) {
        prefetch_ahead(f.data() + j);
        for (std::size_t q = 0; q < dot_lanes; ++q)
            lane[q] += std::abs(static_cast<double>(f[j + q]));
    }
    for (std::size_t j = body; j < f.size(); ++j)
        lane[j - body] += std::abs(static_cast<double>(f[j]));
    return sum_lanes(lane);
}

/// out[k] = sum_{j in [begin, end)} double(f[j]) B[k stride + j] for k < K: the part of the gather
/// over one stretch of a dense row (Cohen & Wallace 1993, ch. 5). Floats widen to double exactly
/// and every product and sum is in double, so the only rounding is that of a double sum: a
/// relative error of a few 1e-16 times the row's length at worst, far below float's 6e-8.
/// Term j goes to lane (j - begin) % 8, each lane adds its terms in order of j, and
/// out[k] = sum_lanes, on both paths (SSE2, plain C++): the same bits whichever thread
/// computes it. Cost: (end - begin) K multiply-adds.
template <std::size_t K>
void dense_dot(const float* f, const double* B, std::size_t stride, std::size_t begin,
               std::size_t end, double* out) {
    double lane[K][dot_lanes] = {};
    const std::size_t body = begin + (end - begin) / dot_lanes * dot_lanes;
    dense_lanes<K>(f, B, stride, begin, body, lane);
    for (std::size_t j = body; j < end; ++j)  // the last few terms, in their lanes
        for (std::size_t k = 0; k < K; ++k)
            lane[k][j - body] += static_cast<double>(f[j]) * B[k * stride + j];
    for (std::size_t k = 0; k < K; ++k) out[k] = sum_lanes(lane[k]);
}

}  // namespace radiosity::detail
