#pragma once
/// @file common.hpp  What the solvers share: patch values as doubles (K bands per patch,
/// interleaved), the gather sum_j F_ij B_j over an assembled row, a parallel pass gathering every
/// row, the relative residual of B = E + R F B, a stopwatch, and the checks of a system against
/// its matrix.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/dense_dot.hpp>
#include <radiosity/error.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/system.hpp>
#include <radiosity/spectrum.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace radiosity {

/// A solver of the radiosity system: `solver.solve(system, F, progress)` returns B and a Report.
/// F is an assembled matrix (Jacobi, Gauss-Seidel, direct) or, for progressive shooting, any
/// RowSource, so that rows can be computed on demand.
template <class X, class S, class Mx>
concept Solver = SpectrumType<S> &&
    requires(const X& solver, const System<S>& system, const Mx& F, const ProgressCallback& p) {
    { solver.solve(system, F, p) } -> std::same_as<Solution<S>>;
};

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

/// max over patches and bands of |E|: the scale of the relative residual (1 if E = 0, so that
/// the residual is then the absolute one).
inline double emission_scale(const std::vector<double>& E) {
    double m = 0.0;
    for (double e : E) m = std::max(m, std::abs(e));
    return m > 0.0 ? m : 1.0;
}

/// Whether a pass over an n x n system of K bands is worth sharing among threads: from 2^24
/// products on (a few milliseconds), below which starting and waking threads, on a machine
/// with other work, can cost more than the pass. Results do not depend on it: the work is cut
/// the same way either way.
inline bool worth_threads(std::size_t n, std::size_t K) {
    return static_cast<double>(n) * static_cast<double>(n) * static_cast<double>(K) >= 0x1p24;
}

/// A short pause in a spin-wait loop (x86's pause, which frees the core's resources for a
/// sibling hyper-thread; nothing elsewhere).
inline void spin_pause() {
#if defined(__SSE2__)
    _mm_pause();
#endif
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

/// Validates the system and that the matrix has one row per patch.
template <SpectrumType S>
void check_system(const System<S>& system, std::size_t matrix_size, const char* solver) {
    system.validate();
    if (matrix_size != system.size())
        throw Error(std::string(solver) + ": the form-factor matrix has " +
                    std::to_string(matrix_size) + " rows for " + std::to_string(system.size()) +
                    " patches");
}

/// Wall-clock seconds since construction.
class Stopwatch {
  public:
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

  private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Progress through an iterative solve as a fraction: how far the residual has come down from
/// its start towards the tolerance, on a log scale (so that each digit gained counts alike).
inline double convergence_fraction(double first, double now, double tolerance) {
    if (!(now > tolerance) || !(first > tolerance)) return 1.0;
    const double f = std::log(first / now) / std::log(first / tolerance);
    return std::clamp(f, 0.0, 1.0);
}

/// The loop shared by the sweeping solvers: calls sweep() (which returns the largest change of
/// B, absolute) until the change relative to max E is within the tolerance, the iteration cap
/// is reached or the progress callback cancels; fills iterations, residual (the last relative
/// change), converged and cancelled. values() gives the current B (interleaved, as to_doubles)
/// for the callback's Progress::radiosity; it is called only when there is a callback.
template <class Sweep, class Values>
void sweep_until(Report& report, Sweep&& sweep, Values&& values, double scale, double tolerance,
                 std::size_t max_iterations, const ProgressCallback& progress) {
    double first = -1.0;
    while (report.iterations < max_iterations) {
        const double change = sweep() / scale;
        ++report.iterations;
        report.residual = change;
        if (first < 0.0) first = change;
        if (change <= tolerance) {
            report.converged = true;
            return;
        }
        if (progress &&
            !progress(Progress{.phase = "solve",
                               .fraction = convergence_fraction(first, change, tolerance),
                               .residual = change,
                               .iteration = report.iterations,
                               .radiosity = values()})) {
            report.cancelled = true;
            return;
        }
    }
}

}  // namespace detail
}  // namespace radiosity
