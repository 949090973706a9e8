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
#include <atomic>
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
            std::vector<double> outside(B.size());
            detail::sweep_until(
                report, [&] { return sweep_dense<K>(F, E, R, b, outside); },
                [&] {  // B is band-major during the sweeps: interleave it for the observer
                    b.copy_to(B);
                    return std::span<const double>(B);
                },
                detail::emission_scale(E), options_.tolerance, options_.max_iterations, progress);
            b.copy_to(B);
        } else {
            detail::sweep_until(
                report, [&] { return sweep<K>(F, E, R, B); },
                [&] { return std::span<const double>(B); }, detail::emission_scale(E),
                options_.tolerance, options_.max_iterations, progress);
        }
        report.residual = detail::relative_residual<K>(F, E, R, B);
        report.seconds = clock.seconds();
        return {detail::from_doubles<S>(B), report};
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

    /// Rows per block of sweep_dense. Fixed, not taken from the thread count, so that every sum
    /// is cut, and so B rounded, the same way on any machine. 256 rows leave the one-thread part
    /// of a sweep (the blocks on the diagonal) at 256 / n of it.
    static constexpr std::size_t block_rows = 256;

    /// Rows that a thread takes at a time in sweep_dense (block_rows is a multiple of it).
    static constexpr std::size_t take = 8;

    /// The same sweep as sweep() over dense rows, with B band-major, rows cut into blocks
    /// [r0, r1) of block_rows. While a block is swept, its columns outside [r0, r1) keep their
    /// values (j < r0 already updated this sweep, j >= r1 from the last), so those parts of the
    /// block's rows are gathered first, rows shared among the threads; then every thread sweeps
    /// the block's square on the diagonal in patch order, each on its own copy of B, with the
    /// same operations and so the same values. That costs every thread the diagonal (block_rows
    /// / n of the sweep) but spares all barriers: a thread needs no other's writes to B. Nor
    /// does it wait long for the rows others have taken: after a moment it gathers them itself,
    /// to the same bits, since the thread that holds them may have been put aside by a busy
    /// machine for a time slice. (Barriers, OpenMP's spinning ones even once a block, made a
    /// 10k-patch solve on two busy cores take 2 s against 0.7 s on one thread.)
    template <std::size_t K, class Mx>
    static double sweep_dense(const Mx& F, const std::vector<double>& E,
                              const std::vector<double>& R, detail::BandMajor<K>& B,
                              std::vector<double>& outside) {
        const std::size_t n = F.size();
        SharedRows shared(n);
        double change = 0.0;
        std::optional<detail::BandMajor<K>> result;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel if (detail::worth_threads(n, K))
#endif
        {
            detail::BandMajor<K> mine = B;  // read and written by this thread only
            std::vector<double> sums(block_rows * K);
            double my_change = 0.0;
            for (std::size_t r0 = 0; r0 < n; r0 += block_rows) {
                const std::size_t r1 = std::min(n, r0 + block_rows);
                share_gather<K>(F, mine, r0, r1, shared, outside);
                collect_gather<K>(F, mine, r0, r1, shared, outside, sums);
                my_change = std::max(my_change, sweep_block<K>(F, E, R, mine, r0, r1, sums));
            }
            if (detail::thread_index() == 0) {  // every thread holds the same B
                result.emplace(std::move(mine));
                change = my_change;
            }
        }
        B = std::move(*result);
        return change;
    }

    /// The state that sweep_dense's threads share: per block, the next rows to hand out; per
    /// `take` rows, whether their gathered sums are written.
    struct SharedRows {
        std::vector<std::atomic<std::size_t>> taken;  ///< rows of each block handed out
        std::vector<std::atomic<bool>> gathered;      ///< sums of each `take` rows written
        explicit SharedRows(std::size_t n)
            : taken((n + block_rows - 1) / block_rows), gathered((n + take - 1) / take) {}
    };

    /// out[(i - a) K + k] = sum_{j < r0 or j >= r1} F_ij B_j[k] for the rows i in [a, e) of the
    /// block [r0, r1): the gather outside the block.
    template <std::size_t K, class Mx>
    static void gather_outside(const Mx& F, const detail::BandMajor<K>& B, std::size_t r0,
                               std::size_t r1, std::size_t a, std::size_t e, double* out) {
        for (std::size_t i = a; i < e; ++i) {
            const float* row = F.row(i).data();
            std::array<double, K> before, after;
            detail::dense_dot<K>(row, B.data(), B.stride(), 0, r0, before.data());
            detail::dense_dot<K>(row, B.data(), B.stride(), r1, F.size(), after.data());
            for (std::size_t k = 0; k < K; ++k) out[(i - a) * K + k] = before[k] + after[k];
        }
    }

    /// Takes rows of the block, `take` at a time, until none are left, and writes their gathered
    /// sums to outside[i K + k] for all threads.
    template <std::size_t K, class Mx>
    static void share_gather(const Mx& F, const detail::BandMajor<K>& B, std::size_t r0,
                             std::size_t r1, SharedRows& shared, std::vector<double>& outside) {
        std::atomic<std::size_t>& taken = shared.taken[r0 / block_rows];
        for (std::size_t a = r0 + taken.fetch_add(take); a < r1; a = r0 + taken.fetch_add(take)) {
            gather_outside<K>(F, B, r0, r1, a, std::min(r1, a + take), outside.data() + a * K);
            shared.gathered[a / take].store(true, std::memory_order_release);
        }
    }

    /// sums = the block's gathered sums: those written by now, and, for rows still in another
    /// thread's hands after a short spin, sums gathered here (the same bits).
    template <std::size_t K, class Mx>
    static void collect_gather(const Mx& F, const detail::BandMajor<K>& B, std::size_t r0,
                               std::size_t r1, const SharedRows& shared,
                               const std::vector<double>& outside, std::vector<double>& sums) {
        for (std::size_t a = r0; a < r1; a += take) {
            const std::size_t e = std::min(r1, a + take);
            const std::atomic<bool>& done = shared.gathered[a / take];
            // About a row's gather (tens of microseconds): long enough for a running thread to
            // finish, short next to a time slice of a thread that the machine put aside.
            for (int spin = 0; spin < 2048 && !done.load(std::memory_order_acquire); ++spin)
                detail::spin_pause();
            if (done.load(std::memory_order_acquire))
                std::copy(outside.begin() + static_cast<std::ptrdiff_t>(a * K),
                          outside.begin() + static_cast<std::ptrdiff_t>(e * K),
                          sums.begin() + static_cast<std::ptrdiff_t>((a - r0) * K));
            else
                gather_outside<K>(F, B, r0, r1, a, e, sums.data() + (a - r0) * K);
        }
    }

    /// Gauss-Seidel over the rows of one block, in order, adding the block's own columns to the
    /// gathered rest (sums, row r0 first); returns the largest change. The self term is left out of
    /// the sum by setting B_i to 0 while row i is gathered (F_ii times 0 adds nothing), then solved
    /// for exactly.
    template <std::size_t K, class Mx>
    static double sweep_block(const Mx& F, const std::vector<double>& E,
                              const std::vector<double>& R, detail::BandMajor<K>& B, std::size_t r0,
                              std::size_t r1, const std::vector<double>& sums) {
        double change = 0.0;
        for (std::size_t i = r0; i < r1; ++i) {
            const float* row = F.row(i).data();
            std::array<double, K> old, inside;
            for (std::size_t k = 0; k < K; ++k) old[k] = std::exchange(B.at(k, i), 0.0);
            detail::dense_dot<K>(row, B.data(), B.stride(), r0, r1, inside.data());
            const double self = row[i];  // F_ii
            for (std::size_t k = 0; k < K; ++k) {
                const std::size_t ik = i * K + k;
                const double b = updated(E[ik], R[ik], sums[(i - r0) * K + k] + inside[k], self);
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
