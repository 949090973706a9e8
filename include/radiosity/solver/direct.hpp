#pragma once
/// @file direct.hpp  The direct solve B = (I - M)^-1 E with M_ij = R_i F_ij: LU factorisation
/// with partial pivoting (Golub & Van Loan 2013, alg. 3.4.1), in double, one factorisation per
/// distinct reflectance band. O(n^3) time and 8 n^2 bytes: the reference for small systems,
/// against which the iterative solvers are checked.

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>
#include <radiosity/solver/session.hpp>

#include <cmath>
#include <cstdint>
#include <utility>

namespace radiosity {

/// Settings of the direct solver.
struct DirectOptions {
    std::size_t max_patches = 8000;  ///< refuse larger systems (8000 patches: 512 MB, minutes)
};

/// Direct LU solve (see the file comment). The report gives the relative residual of the
/// computed B, which is at rounding level for the well-conditioned matrices of radiosity
/// (I - R F is diagonally dominant by rows: R_i sum_j F_ij < 1), and the bound it gives on the
/// relative error of B in the max norm, ||r|| / (1 - q) over ||B*|| with q = ||R F||_inf
/// (detail::bound_from_residual; one more pass over F). The solve is converged unless cancelled.
class Direct : public detail::SolverBase<Direct, DirectOptions> {
  public:
    using SolverBase::SolverBase;
    static constexpr const char* name = "direct";  ///< Report::solver

    /// The solve of solve() (detail::SolverBase): LU per distinct reflectance band, then the
    /// residual of the result; returns B. Throws Error for a system larger than max_patches.
    template <SpectrumType S, AssembledMatrix Mx>
    std::vector<double> iterate(detail::SolveSession<S>& session, const Mx& F) const {
        constexpr std::size_t K = band_count<S>;
        const std::size_t n = session.system.size();
        if (n > options_.max_patches)
            throw Error("direct solver: " + std::to_string(n) + " patches exceed max_patches = " +
                        std::to_string(options_.max_patches) + " (use an iterative solver)");
        const std::vector<double>& E = session.E;
        const std::vector<double>& R = session.R;
        std::vector<double> B(E.size(), 0.0);
        std::vector<double> A;
        std::vector<std::size_t> pivot;
        std::size_t factored = K;  // the band whose LU is in A (none yet)
        for (std::size_t k = 0; k < K; ++k) {
            if (factored < K && same_reflectance(R, k, factored, K)) {  // grey: reuse the LU
                substitute(A, pivot, E, B, k, K, n);
                continue;
            }
            if (!session.proceed(double(k) / double(K))) break;
            assemble(F, R, k, K, n, A);
            factor(A, pivot, n);
            factored = k;
            substitute(A, pivot, E, B, k, K, n);
        }
        Report& report = session.report;
        report.iterations = 1;
        report.residual = detail::relative_residual<K>(F, E, R, B);
        report.error_bound = detail::relative_bound(
            detail::bound_from_residual(detail::contraction_bound<K>(F, R),
                                        report.residual * detail::emission_scale(E)),
            detail::max_abs(B));
        report.converged = !report.cancelled && std::isfinite(report.residual);
        return B;
    }

  private:
    static bool same_reflectance(const std::vector<double>& R, std::size_t k, std::size_t m,
                                 std::size_t K) {
        for (std::size_t i = 0; i < R.size() / K; ++i)
            if (R[i * K + k] != R[i * K + m]) return false;
        return true;
    }

    /// A = I - R F for band k, row-major.
    template <AssembledMatrix Mx>
    static void assemble(const Mx& F, const std::vector<double>& R, std::size_t k, std::size_t K,
                         std::size_t n, std::vector<double>& A) {
        A.assign(n * n, 0.0);
        for (std::size_t i = 0; i < n; ++i) {
            F.for_each_in_row(i, [&](std::size_t j, float f) { A[i * n + j] = -R[i * K + k] * f; });
            A[i * n + i] += 1.0;
        }
    }

    /// In-place LU with partial pivoting: P A = L U, L unit lower (below the diagonal).
    static void factor(std::vector<double>& A, std::vector<std::size_t>& pivot, std::size_t n) {
        pivot.resize(n);
        for (std::size_t c = 0; c < n; ++c) {
            std::size_t p = c;
            for (std::size_t r = c + 1; r < n; ++r)
                if (std::abs(A[r * n + c]) > std::abs(A[p * n + c])) p = r;
            pivot[c] = p;
            if (p != c)
                for (std::size_t j = 0; j < n; ++j) std::swap(A[c * n + j], A[p * n + j]);
            const double d = A[c * n + c];
            if (d == 0.0) throw Error("direct solver: the system I - R F is singular");
            const auto last = static_cast<std::int64_t>(n);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) if (n - c > 256)
#endif
            for (std::int64_t rs = static_cast<std::int64_t>(c) + 1; rs < last; ++rs) {
                const auto r = static_cast<std::size_t>(rs);
                const double l = A[r * n + c] / d;
                A[r * n + c] = l;
                if (l == 0.0) continue;
                double* row = &A[r * n];
                const double* top = &A[c * n];
                for (std::size_t j = c + 1; j < n; ++j) row[j] -= l * top[j];
            }
        }
    }

    /// Solves L U x = P e for band k by forward and back substitution.
    static void substitute(const std::vector<double>& A, const std::vector<std::size_t>& pivot,
                           const std::vector<double>& E, std::vector<double>& B, std::size_t k,
                           std::size_t K, std::size_t n) {
        std::vector<double> x(n);
        for (std::size_t i = 0; i < n; ++i) x[i] = E[i * K + k];
        for (std::size_t c = 0; c < n; ++c) std::swap(x[c], x[pivot[c]]);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < i; ++j) x[i] -= A[i * n + j] * x[j];
        for (std::size_t i = n; i-- > 0;) {
            for (std::size_t j = i + 1; j < n; ++j) x[i] -= A[i * n + j] * x[j];
            x[i] /= A[i * n + i];
        }
        for (std::size_t i = 0; i < n; ++i) B[i * K + k] = x[i];
    }
};

// The solver contract (concepts.hpp): the LU solve reads any assembled matrix.
static_assert(Solver<Direct, float, DenseMatrix> && Solver<Direct, Rgb, SparseMatrix>);

}  // namespace radiosity
