#pragma once
/// @file gauss_seidel.hpp  Gauss-Seidel iteration for B = E + R F B: like Jacobi, but each patch
/// uses the values already updated in the same sweep, which about halves the sweeps needed
/// (Cohen & Wallace 1993, ch. 5). A patch that sees itself (F_ii != 0, curved or non-planar
/// patches) is solved for exactly: B_i = (E_i + R_i sum_{j != i} F_ij B_j) / (1 - R_i F_ii).
/// The sweep below is the plain one; over dense rows the same sweep runs vectorised and, on
/// large systems, shared among threads, with the same update and a bit-identical result for any
/// number of threads (detail/gauss_seidel_dense.hpp).

#include <radiosity/concepts.hpp>
#include <radiosity/detail/gauss_seidel_dense.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/session.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace radiosity {

/// Settings of the Gauss-Seidel solver: those of every sweeping solver (session.hpp).
using GaussSeidelOptions = SweepOptions;

/// Gauss-Seidel iteration (see the file comment). A sweep contracts the error in the max norm by
/// q = ||R F||_inf at least as Jacobi does (row i's update takes each B_j, old or new, with the
/// weight R_i F_ij, which sum to at most q; with the self term solved for, the weights
/// R_i F_ij / (1 - R_i F_ii), j != i, sum to at most q as well), so the error after a sweep is
/// at most q / (1 - q) times its change: the tolerance bounds the relative error of B in the max
/// norm (detail::StoppingRule). The report gives the true relative residual
/// ||E + R F B - B|| / ||E|| at the returned B (one more pass over F, rows in parallel), and the
/// smaller of the two bounds, from the last change and from that residual. q costs one pass over
/// F. Each row depends on the rows before it;
/// over dense rows most of each row's gather still runs in parallel (DenseGaussSeidel), with B
/// bit-identical for any number of threads. Cost: O(non-zeros of F) a sweep.
class GaussSeidel : public detail::SolverBase<GaussSeidel, GaussSeidelOptions> {
  public:
    using SolverBase::SolverBase;
    static constexpr const char* name = "gauss-seidel";  ///< Report::solver

    /// The iteration of solve() (detail::SolverBase): sweeps from B = E until the stopping rule
    /// holds, then measures the true residual; returns B.
    template <SpectrumType S, AssembledMatrix Mx>
    std::vector<double> iterate(detail::SolveSession<S>& session, const Mx& F) const {
        constexpr std::size_t K = band_count<S>;
        const std::vector<double>& E = session.E;
        const std::vector<double>& R = session.R;
        std::vector<double> B = E;
        const auto rule = detail::StoppingRule::sweeps(
            options_.tolerance, detail::contraction_bound<K>(F, R), options_.max_iterations);
        const double scale = detail::emission_scale(E);
        if constexpr (!DenseRowMatrix<Mx>) {
            detail::sweep_until(
                session, rule, scale, [&] { return sweep<K>(F, E, R, B); },
                [&] { return detail::max_abs(B); }, [&] { return std::span<const double>(B); });
        } else {  // the fast path over dense rows: the same sweep with the same update
            const auto update = [](double e, double r, double gathered, double self) {
                return updated(e, r, gathered, self);
            };
            detail::DenseGaussSeidel<K> dense(B);
            detail::sweep_until(
                session, rule, scale, [&] { return dense.sweep(F, E, R, update); },
                [&] { return dense.max_abs(); },
                [&] {  // B is band-major during the sweeps: interleave it for the observer
                    dense.copy_to(B);
                    return std::span<const double>(B);
                });
            dense.copy_to(B);
        }
        Report& report = session.report;
        report.residual = detail::relative_residual<K>(F, E, R, B);
        const double from_residual = detail::relative_bound(
            detail::bound_from_residual(rule.contraction, report.residual * scale),
            detail::max_abs(B));
        report.error_bound = std::min(report.error_bound, from_residual);
        report.converged = !report.cancelled && rule.met(report.error_bound);
        return B;
    }

  private:
    /// The Gauss-Seidel update of one band of patch i with the self term solved for:
    /// B_i = (E_i + R_i sum_{j != i} F_ij B_j) / (1 - R_i F_ii), from gathered = sum_{j != i}.
    static double updated(double E, double R, double gathered, double self) {
        return (E + R * gathered) / (1.0 - R * self);
    }

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
                const double b = updated(E[ik], R[ik], acc[k], self);
                change = std::max(change, std::abs(b - B[ik]));
                B[ik] = b;
            }
        }
        return change;
    }
};

// The solver contract (concepts.hpp): the sweeping solvers work on dense and sparse assembled
// matrices.
static_assert(Solver<GaussSeidel, float, DenseMatrix> && Solver<GaussSeidel, Rgb, SparseMatrix>);

}  // namespace radiosity
