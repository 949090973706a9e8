#pragma once
/// @file gauss_seidel.hpp  Gauss-Seidel iteration for B = E + R F B: like Jacobi, but each patch
/// uses the values already updated in the same sweep, which about halves the sweeps needed
/// (Cohen & Wallace 1993, ch. 5). A patch that sees itself (F_ii != 0, curved or non-planar
/// patches) is solved for exactly: B_i = (E_i + R_i sum_{j != i} F_ij B_j) / (1 - R_i F_ii).

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>

#include <array>

namespace radiosity {

/// Settings of the Gauss-Seidel solver.
struct GaussSeidelOptions {
    double tolerance = 1e-4;            ///< stop when the relative residual is this small
    std::size_t max_iterations = 1000;  ///< guard on the number of sweeps
};

/// Gauss-Seidel iteration (see the file comment). It stops when the largest change of a sweep,
/// relative to max E, is below the tolerance: the residual left after a sweep is
/// r_i = R_i sum_{j > i} F_ij (change of B_j), at most that change since R_i < 1 and rows sum to
/// at most 1. The report gives the true relative residual ||E + R F B - B|| / ||E|| at the
/// returned B (one more pass over F). Sequential by nature.
/// Cost: O(non-zeros of F) a sweep.
class GaussSeidel {
  public:
    /// A solver with the given settings.
    explicit GaussSeidel(GaussSeidelOptions options = {}) : options_(options) {}

    /// Solves the system over an assembled matrix. Throws Error for bad input.
    template <SpectrumType S, AssembledMatrix Mx>
    Solution<S> solve(const System<S>& system, const Mx& F,
                      const ProgressCallback& progress = {}) const {
        detail::check_system(system, F.size(), "gauss-seidel");
        const detail::Stopwatch clock;
        constexpr std::size_t K = band_count<S>;
        const std::vector<double> E = detail::to_doubles(system.emission),
                                  R = detail::to_doubles(system.reflectance);
        std::vector<double> B = E;
        Report report{"gauss-seidel"};
        detail::sweep_until(
            report, [&] { return sweep<K>(F, E, R, B); }, detail::emission_scale(E),
            options_.tolerance, options_.max_iterations, progress);
        report.residual = detail::relative_residual<K>(F, E, R, B);
        report.seconds = clock.seconds();
        return {detail::from_doubles<S>(B), report};
    }

  private:
    /// One sweep in patch order, in place; returns the largest change.
    template <std::size_t K, AssembledMatrix Mx>
    static double sweep(const Mx& F, const std::vector<double>& E, const std::vector<double>& R,
                        std::vector<double>& B) {
        double change = 0.0;
        std::array<double, K> acc;
        for (std::size_t i = 0; i < F.size(); ++i) {
            acc.fill(0.0);
            double self = 0.0;  // F_ii
            F.for_each_in_row(i, [&](std::size_t j, float f) {
                if (j == i) {
                    self = f;
                    return;
                }
                // No test for F_ij = 0: adding 0 * B_j changes nothing, and on dense rows, half
                // zeros in no pattern, the branch costs more than the multiplication it saves.
                for (std::size_t k = 0; k < K; ++k) acc[k] += f * B[j * K + k];
            });
            for (std::size_t k = 0; k < K; ++k) {
                const std::size_t ik = i * K + k;
                const double b = (E[ik] + R[ik] * acc[k]) / (1.0 - R[ik] * self);
                change = std::max(change, std::abs(b - B[ik]));
                B[ik] = b;
            }
        }
        return change;
    }

    GaussSeidelOptions options_;
};

// The solver contract (common.hpp): the sweeping solvers work on dense and sparse assembled
// matrices.
static_assert(Solver<GaussSeidel, float, DenseMatrix> && Solver<GaussSeidel, Rgb, SparseMatrix>);

}  // namespace radiosity
