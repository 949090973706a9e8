#pragma once
/// @file common.hpp  The arithmetic the solvers share: patch values as doubles (K bands per
/// patch, interleaved), the gather sum_j F_ij B_j over an assembled row, a parallel pass
/// gathering every row, the relative residual of B = E + R F B, and the contraction bound
/// q = ||R F||_inf on which the solvers' error bounds rest. The opening and closing of
/// a solve, and its stopping rule, are in session.hpp.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/dense_dot.hpp>
#include <radiosity/detail/parallel.hpp>
#include <radiosity/solver/system.hpp>
#include <radiosity/spectrum.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace radiosity {

namespace detail {

/// The most bands a solver handles (the per-row accumulators live on the stack).
inline constexpr std::size_t max_bands = 16;

/// Values of all patches as doubles, band_count<S> bands per patch, patch after patch: the
/// solvers accumulate in double so that a tolerance of 1e-7 is meaningful with float colours.
template <SpectrumType S>
std::vector<double> to_doubles(std::span<const S> v) {
    constexpr std::size_t K = band_count<S>;
    static_assert(K <= max_bands, "the solvers handle at most 16 bands");
    std::vector<double> out(v.size() * K);
    for (std::size_t i = 0; i < v.size(); ++i)
        for (std::size_t k = 0; k < K; ++k) out[i * K + k] = band(v[i], k);
    return out;
}

/// The inverse of to_doubles.
template <SpectrumType S>
std::vector<S> from_doubles(const std::vector<double>& v) {
    constexpr std::size_t K = band_count<S>;
    std::vector<S> out(v.size() / K);
    for (std::size_t i = 0; i < out.size(); ++i)
        for (std::size_t k = 0; k < K; ++k) set_band(out[i], k, static_cast<float>(v[i * K + k]));
    return out;
}

/// acc[k] = sum_j F_ij B_j[k] over the entries of row i (the "gather" of the course). K, the
/// number of bands, is a compile-time constant so that the band loop unrolls (with K known only
/// at run time, a grey gather over dense rows ran about 3x slower).
template <std::size_t K, AssembledMatrix Mx>
void gather(const Mx& F, std::size_t i, const std::vector<double>& B, double* acc) {
    std::fill(acc, acc + K, 0.0);
    // No test for F_ij = 0 (as in Gauss-Seidel's sweep): adding 0 * B_j changes nothing, and on
    // dense rows, half zeros in no pattern, the branch costs more than the product it saves.
    F.for_each_in_row(i, [&](std::size_t j, float f) {
        for (std::size_t k = 0; k < K; ++k) acc[k] += f * B[j * K + k];
    });
}

/// max_i |v_i|: the max norm of patch values (every band). Cost: O(n K).
inline double max_abs(std::span<const double> v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
}

/// max over patches and bands of |E|: the scale of the relative residual (1 if E = 0, so that
/// the residual is then the absolute one).
inline double emission_scale(const std::vector<double>& E) {
    const double m = max_abs(E);
    return m > 0.0 ? m : 1.0;
}

/// q = max_i (max_k R_i[k]) sum_j |F_ij| = ||M||_inf for M = R F (per band; the largest band):
/// the contraction bound of the stopping rule (session.hpp). It bounds the spectral radius of M,
/// and with it the error of every sweeping solver; below 1 whenever R < 1 and rows sum to at
/// most 1 (exactly so for analytic and ray-cast rows, up to the hemicube's pixel error for its
/// rows). Rows in parallel, each summed in a fixed order, max exact: the same q for any thread
/// count. Cost: one pass over F (about a sweep).
template <std::size_t K, AssembledMatrix Mx>
double contraction_bound(const Mx& F, const std::vector<double>& R) {
    const auto count = static_cast<std::int64_t>(F.size());
    double q = 0.0;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) reduction(max : q) if (worth_threads(F.size(), 1))
#endif
    for (std::int64_t s = 0; s < count; ++s) {
        const auto i = static_cast<std::size_t>(s);
        double sum = 0.0;
        if constexpr (DenseRowMatrix<Mx>)
            sum = dense_abs_sum(F.row(i));
        else
            F.for_each_in_row(i, [&](std::size_t, float f) { sum += std::abs(double(f)); });
        double r = 0.0;
        for (std::size_t k = 0; k < K; ++k) r = std::max(r, R[i * K + k]);
        q = std::max(q, r * sum);
    }
    return q;
}

/// max over rows i of value(i, acc), where acc[k] = sum_j F_ij B_j[k] is row i's gather over B
/// (interleaved, as to_doubles gives it). Rows run in parallel, so value must be safe to call
/// for different rows at once; each row's sum is made by one thread in a fixed order and max is
/// exact, so the result does not depend on the thread count. Dense rows take the vectorised
/// kernel of dense_dot.hpp. Cost: one pass over F.
template <std::size_t K, AssembledMatrix Mx, class Value>
double max_over_rows(const Mx& F, const std::vector<double>& B, Value&& value) {
    const std::size_t n = F.size();
    const auto count = static_cast<std::int64_t>(n);
    // Dense rows gather over a band-major copy of B; other matrices entry by entry.
    std::optional<BandMajor<K>> band_major;
    if constexpr (DenseRowMatrix<Mx>) band_major.emplace(B);
    auto gather_row = [&](std::size_t i, double* acc) {
        if constexpr (DenseRowMatrix<Mx>)
            dense_dot<K>(F.row(i).data(), band_major->data(), band_major->stride(), 0, n, acc);
        else
            gather<K>(F, i, B, acc);
    };
    double worst = 0.0;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) reduction(max : worst) if (worth_threads(n, K))
#endif
    for (std::int64_t s = 0; s < count; ++s) {
        const auto i = static_cast<std::size_t>(s);
        std::array<double, K> acc;
        gather_row(i, acc.data());
        worst = std::max(worst, value(i, acc.data()));
    }
    return worst;
}

/// The relative residual ||E + R F B - B||_inf / ||E||_inf of the radiosity equation at B.
/// Cost: one pass over the matrix, rows in parallel (max_over_rows).
template <std::size_t K, AssembledMatrix Mx>
double relative_residual(const Mx& F, const std::vector<double>& E, const std::vector<double>& R,
                         const std::vector<double>& B) {
    const double worst = max_over_rows<K>(F, B, [&](std::size_t i, const double* acc) {
        double w = 0.0;
        for (std::size_t k = 0; k < K; ++k) {
            const std::size_t ik = i * K + k;
            w = std::max(w, std::abs(E[ik] + R[ik] * acc[k] - B[ik]));
        }
        return w;
    });
    return worst / emission_scale(E);
}

}  // namespace detail
}  // namespace radiosity
