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
/// B^(m+1) - B^(m), so the stopping test costs nothing extra. Cost: O(non-zeros of F) a sweep.
class Jacobi : public detail::SolverBase<Jacobi, JacobiOptions> {
  public:
    using SolverBase::SolverBase;
    static constexpr const char* name = "jacobi";  ///< Report::solver

    /// The iteration of solve() (detail::SolverBase): sweeps from B = E until the stopping rule
    /// holds; returns B.
    template <SpectrumType S, AssembledMatrix Mx>
    std::vector<double> iterate(detail::SolveSession<S>& session, const Mx& F) const {
        const std::vector<double>& E = session.E;
        std::vector<double> B = E, next(B.size());
        // The residual at a sweep's input is exactly the change the sweep makes.
        detail::sweep_until(
            session, {options_.tolerance, options_.max_iterations}, detail::emission_scale(E),
            [&] {
                const double change = sweep<band_count<S>>(F, E, session.R, B, next);
                B.swap(next);
                return change;
            },
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
