#pragma once
/// @file jacobi.hpp  Jacobi iteration for B = E + R F B: every sweep computes all patches from the
/// previous sweep's values, B^(m+1) = E + R F B^(m) (Cohen & Wallace 1993, ch. 5). It converges
/// because R F has spectral radius below 1 (R < 1 and rows of F sum to at most 1). Rows are
/// independent, so sweeps run in parallel, with results independent of the thread count.

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>

#include <array>
#include <cstdint>

namespace radiosity {

/// Settings of the Jacobi solver.
struct JacobiOptions {
    double tolerance = 1e-4;            ///< stop when the relative residual is this small
    std::size_t max_iterations = 1000;  ///< guard on the number of sweeps
};

/// Jacobi iteration (see the file comment). The residual of the equation at B^(m) is exactly
/// B^(m+1) - B^(m), so the stopping test costs nothing extra. Cost: O(non-zeros of F) a sweep.
class Jacobi {
  public:
    /// A solver with the given settings.
    explicit Jacobi(JacobiOptions options = {}) : options_(options) {}

    /// Solves the system over an assembled matrix. Throws Error for bad input.
    template <SpectrumType S, AssembledMatrix Mx>
    Solution<S> solve(const System<S>& system, const Mx& F,
                      const ProgressCallback& progress = {}) const {
        detail::check_system(system, F.size(), "jacobi");
        const detail::Stopwatch clock;
        constexpr std::size_t K = band_count<S>;
        const std::vector<double> E = detail::to_doubles(system.emission),
                                  R = detail::to_doubles(system.reflectance);
        std::vector<double> B = E, next(B.size());
        Report report{"jacobi"};
        // The residual at a sweep's input is exactly the change the sweep makes.
        detail::sweep_until(
            report,
            [&] {
                const double change = sweep<K>(F, E, R, B, next);
                B.swap(next);
                return change;
            },
            [&] { return std::span<const double>(B); }, detail::emission_scale(E),
            options_.tolerance, options_.max_iterations, progress);
        report.seconds = clock.seconds();
        return {detail::from_doubles<S>(B), report};
    }

  private:
    /// next = E + R F B, in parallel over rows; returns max |next - B|.
    template <std::size_t K, AssembledMatrix Mx>
    static double sweep(const Mx& F, const std::vector<double>& E, const std::vector<double>& R,
                        const std::vector<double>& B, std::vector<double>& next) {
        return detail::max_over_rows<K>(F, B, [&](std::size_t i, const double* acc) {
            double change = 0.0;
            for (std::size_t k = 0; k < K; ++k) {
                const std::size_t ik = i * K + k;
                next[ik] = E[ik] + R[ik] * acc[k];
                change = std::max(change, std::abs(next[ik] - B[ik]));
            }
            return change;
        });
    }

    JacobiOptions options_;
};

// The solver contract (common.hpp): the sweeping solvers work on dense and sparse assembled
// matrices.
static_assert(Solver<Jacobi, float, DenseMatrix> && Solver<Jacobi, Rgb, SparseMatrix>);

}  // namespace radiosity
