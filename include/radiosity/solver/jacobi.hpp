#pragma once
/// @file jacobi.hpp  Jacobi iteration for B = E + R F B: every sweep computes all patches from the
/// previous sweep's values, B^(m+1) = E + R F B^(m) (Cohen & Wallace 1993, ch. 5). It converges
/// because R F has spectral radius below 1 (R < 1 and rows of F sum to at most 1). Rows are
/// independent, so sweeps run in parallel, with results independent of the thread count.

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/session.hpp>

#include <array>
#include <cstdint>

namespace radiosity {

/// Settings of the Jacobi solver: those of every sweeping solver (session.hpp).
using JacobiOptions = SweepOptions;

/// Jacobi iteration (see the file comment). The residual of the equation at B^(m) is exactly
/// the sweep's change B^(m+1) - B^(m), and a sweep contracts the error by q = ||R F||_inf, so
/// ||B^(m+1) - B*||_inf <= q / (1 - q) ||B^(m+1) - B^(m)||_inf: the tolerance bounds the
/// relative error of B in the max norm (detail::StoppingRule), at the cost of one pass over F
/// for q. The report's residual is the last change relative to max E. Cost: O(non-zeros of F) a
/// sweep.
class Jacobi : public detail::SolverBase<Jacobi, JacobiOptions> {
  public:
    using SolverBase::SolverBase;
    static constexpr const char* name = "jacobi";  ///< Report::solver

    /// The iteration of solve() (detail::SolverBase): sweeps from B = E until the stopping rule
    /// holds; returns B.
    template <SpectrumType S, AssembledMatrix Mx>
    std::vector<double> iterate(detail::SolveSession<S>& session, const Mx& F) const {
        constexpr std::size_t K = band_count<S>;
        const std::vector<double>& E = session.E;
        std::vector<double> B = E, next(B.size());
        const auto rule = detail::StoppingRule::sweeps(options_.tolerance,
                                                       detail::contraction_bound<K>(F, session.R),
                                                       options_.max_iterations);
        // The residual at a sweep's input is exactly the change the sweep makes.
        const auto step = [&] {
            const double change = sweep<K>(F, E, session.R, B, next);
            B.swap(next);
            return change;
        };
        detail::sweep_until(
            session, rule, detail::emission_scale(E), step, [&] { return detail::max_abs(B); },
            [&] { return std::span<const double>(B); });
        return B;
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
};

// The solver contract (concepts.hpp): the sweeping solvers work on dense and sparse assembled
// matrices.
static_assert(Solver<Jacobi, float, DenseMatrix> && Solver<Jacobi, Rgb, SparseMatrix>);

}  // namespace radiosity
