#pragma once
/// @file gauss_seidel.hpp  Gauss-Seidel iteration for B = E + R F B: like Jacobi, but each patch
/// uses the values already updated in the same sweep, which about halves the sweeps needed
/// (Cohen & Wallace 1993, ch. 5). A patch that sees itself (F_ii != 0, curved or non-planar
/// patches) is solved for exactly: B_i = (E_i + R_i sum_{j != i} F_ij B_j) / (1 - R_i F_ii).
/// Over dense rows the sweep is vectorised and, on large systems, shared among threads without
/// changing its meaning or its result (see sweep_dense).

#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/common.hpp>

#include <algorithm>
#include <array>
#include <barrier>
#include <cstdint>
#include <optional>
#include <utility>

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
/// returned B (one more pass over F, rows in parallel). Each row depends on the rows before it;
/// over dense rows most of each row's gather still runs in parallel (sweep_dense), with B
/// bit-identical for any number of threads. Cost: O(non-zeros of F) a sweep.
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
        if constexpr (DenseRowMatrix<Mx>) {
            detail::BandMajor<K> b(B);
            std::vector<double> outside(2 * block_rows * K);
            detail::sweep_until(
                report, [&] { return sweep_dense<K>(F, E, R, b, outside); },
                detail::emission_scale(E), options_.tolerance, options_.max_iterations, progress);
            b.copy_to(B);
        } else {
            detail::sweep_until(
                report, [&] { return sweep<K>(F, E, R, B); }, detail::emission_scale(E),
                options_.tolerance, options_.max_iterations, progress);
        }
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

    /// Rows per block of sweep_dense. Fixed, not taken from the thread count, so that every sum
    /// is cut, and so B rounded, the same way on any machine. 256 rows leave the one-thread part
    /// of a sweep (the blocks on the diagonal) at 256 / n of it.
    static constexpr std::size_t block_rows = 256;

    /// The same sweep as sweep() over dense rows, with B band-major, rows cut into blocks
    /// [r0, r1) of block_rows. While a block is swept, its columns outside [r0, r1) keep their
    /// values (j < r0 already updated this sweep, j >= r1 from the last), so those parts of the
    /// block's rows are gathered first, rows shared among the threads; then every thread sweeps
    /// the block's square on the diagonal in patch order, each on its own copy of B, with the
    /// same operations and so the same values. That costs every thread the diagonal (block_rows
    /// / n of the sweep) but leaves one barrier a block: a thread needs no other's writes to B.
    /// The gathered sums alternate between two buffers, as a thread may start the next block's
    /// gather while another still reads this one's. The barrier sleeps after a short spin
    /// (std::barrier): OpenMP's spinning barriers, on a machine with other work, took CPU from
    /// the very thread they waited for (10k patches, with another program running: 2 s a solve
    /// against 0.7 s on one thread).
    template <std::size_t K, class Mx>
    static double sweep_dense(const Mx& F, const std::vector<double>& E,
                              const std::vector<double>& R, detail::BandMajor<K>& B,
                              std::vector<double>& outside) {
        const std::size_t n = F.size();
        double change = 0.0;
        std::optional<std::barrier<>> gathered;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel if (n >= detail::parallel_rows)
#endif
        {
            const auto [thread, threads] = detail::thread_in_team();
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp single
#endif
            gathered.emplace(static_cast<std::ptrdiff_t>(threads));
            detail::BandMajor<K> mine = B;  // read and written by this thread only
            double my_change = 0.0;
            for (std::size_t r0 = 0; r0 < n; r0 += block_rows) {
                const std::size_t r1 = std::min(n, r0 + block_rows);
                double* sums = outside.data() + (r0 / block_rows % 2) * block_rows * K;
                gather_outside<K>(F, mine, r0, r1, sums);
                gathered->arrive_and_wait();
                my_change = std::max(my_change, sweep_block<K>(F, E, R, mine, r0, r1, sums));
            }
            // After the last barrier: every thread has long finished copying B.
            if (thread == 0) {
                B = std::move(mine);
                change = my_change;
            }
        }
        return change;
    }

    /// sums[(i - r0) K + k] = sum_{j < r0 or j >= r1} F_ij B_j[k] for the rows i of the block,
    /// each row by one thread (an orphaned worksharing loop, run by sweep_dense's team, without
    /// the loop's own barrier). Dynamic, so that a thread slowed by other work takes fewer rows.
    template <std::size_t K, class Mx>
    static void gather_outside(const Mx& F, const detail::BandMajor<K>& B, std::size_t r0,
                               std::size_t r1, double* sums) {
        const std::size_t n = F.size();
        const auto first = static_cast<std::int64_t>(r0), last = static_cast<std::int64_t>(r1);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp for schedule(dynamic, 8) nowait
#endif
        for (std::int64_t s = first; s < last; ++s) {
            const auto i = static_cast<std::size_t>(s);
            const float* row = F.row(i).data();
            std::array<double, K> before, after;
            detail::dense_dot<K>(row, B.data(), B.stride(), 0, r0, before.data());
            detail::dense_dot<K>(row, B.data(), B.stride(), r1, n, after.data());
            for (std::size_t k = 0; k < K; ++k) sums[(i - r0) * K + k] = before[k] + after[k];
        }
    }

    /// Gauss-Seidel over the rows of one block, in order, adding the block's own columns to the
    /// gathered rest; returns the largest change. The self term is left out of the sum by
    /// setting B_i to 0 while row i is gathered (F_ii times 0 adds nothing), then solved for
    /// exactly.
    template <std::size_t K, class Mx>
    static double sweep_block(const Mx& F, const std::vector<double>& E,
                              const std::vector<double>& R, detail::BandMajor<K>& B, std::size_t r0,
                              std::size_t r1, const double* outside) {
        double change = 0.0;
        for (std::size_t i = r0; i < r1; ++i) {
            const float* row = F.row(i).data();
            std::array<double, K> old, inside;
            for (std::size_t k = 0; k < K; ++k) old[k] = std::exchange(B.at(k, i), 0.0);
            detail::dense_dot<K>(row, B.data(), B.stride(), r0, r1, inside.data());
            const double self = row[i];  // F_ii
            for (std::size_t k = 0; k < K; ++k) {
                const std::size_t ik = i * K + k;
                const double acc = outside[(i - r0) * K + k] + inside[k];
                const double b = (E[ik] + R[ik] * acc) / (1.0 - R[ik] * self);
                change = std::max(change, std::abs(b - old[k]));
                B.at(k, i) = b;
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
