#pragma once
/// @file gauss_seidel_dense.hpp  The fast path of solver/gauss_seidel.hpp: the same Gauss-Seidel
/// sweep over dense rows, vectorised (detail/dense_dot.hpp) and, on large systems, shared among
/// threads without barriers, with B bit-identical for any number of threads. The plain sweep,
/// which this one must match, stays in gauss_seidel.hpp, where the update is also defined.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/dense_dot.hpp>
#include <radiosity/detail/parallel.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace radiosity::detail {

/// Gauss-Seidel sweeps over dense rows, B held band-major between sweeps (see sweep()). Cost of
/// a sweep: n^2 K multiply-adds, plus, per thread, the blocks on the diagonal (block_rows / n
/// of a sweep); memory: 2 n K doubles, and one copy of B per thread while a sweep runs.
template <std::size_t K>
class DenseGaussSeidel {
  public:
    /// Starts from B (interleaved, K values per patch).
    explicit DenseGaussSeidel(std::span<const double> B) : B_(B), outside_(B.size()) {}

    /// Writes the current B back, interleaved.
    void copy_to(std::span<double> B) const { B_.copy_to(B); }

    /// max over patches and bands of |B|. Cost: O(n K).
    double max_abs() const {
        double m = 0.0;
        for (std::size_t i = 0; i < K * B_.stride(); ++i) m = std::max(m, std::abs(B_.data()[i]));
        return m;
    }

    /// One sweep in patch order, in place; returns the largest change of B. update(E_i, R_i,
    /// gathered, F_ii) is the Gauss-Seidel update of one band, gathered = sum_{j != i} F_ij B_j.
    /// Rows are cut into blocks [r0, r1) of block_rows. While a block is swept, its columns
    /// outside [r0, r1) keep their values (j < r0 already updated this sweep, j >= r1 from the
    /// last), so those parts of the block's rows are gathered first, rows shared among the
    /// threads; then every thread sweeps the block's square on the diagonal in patch order, each
    /// on its own copy of B, with the same operations and so the same values. That costs every
    /// thread the diagonal but spares all barriers: a thread needs no other's writes to B. Nor
    /// does it wait long for the rows others have taken: after a moment it gathers them itself,
    /// to the same bits, since the thread that holds them may have been put aside by a busy
    /// machine for a time slice. (Barriers, OpenMP's spinning ones even once a block, made a
    /// 10k-patch solve on two busy cores take 2 s against 0.7 s on one thread.)
    template <DenseRowMatrix Mx, class Update>
    double sweep(const Mx& F, const std::vector<double>& E, const std::vector<double>& R,
                 Update update) {
        const std::size_t n = F.size();
        SharedRows shared(n);
        double change = 0.0;
        std::optional<BandMajor<K>> result;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel if (worth_threads(n, K))
#endif
        {
            BandMajor<K> mine = B_;  // read and written by this thread only
            std::vector<double> sums(block_rows * K);
            double my_change = 0.0;
            for (std::size_t r0 = 0; r0 < n; r0 += block_rows) {
                const std::size_t r1 = std::min(n, r0 + block_rows);
                share_gather(F, mine, r0, r1, shared, outside_);
                collect_gather(F, mine, r0, r1, shared, outside_, sums);
                my_change = std::max(my_change, sweep_block(F, E, R, mine, r0, r1, sums, update));
            }
            if (thread_index() == 0) {  // every thread holds the same B
                result.emplace(std::move(mine));
                change = my_change;
            }
        }
        B_ = std::move(*result);
        return change;
    }

  private:
    /// Rows per block. Fixed, not taken from the thread count, so that every sum is cut, and so
    /// B rounded, the same way on any machine. 256 rows leave the one-thread part of a sweep
    /// (the blocks on the diagonal) at 256 / n of it.
    static constexpr std::size_t block_rows = 256;

    /// Rows that a thread takes at a time (block_rows is a multiple of it).
    static constexpr std::size_t take = 8;

    /// The state that the threads of a sweep share: per block, the next rows to hand out; per
    /// `take` rows, whether their gathered sums are written.
    struct SharedRows {
        std::vector<std::atomic<std::size_t>> taken;  ///< rows of each block handed out
        std::vector<std::atomic<bool>> gathered;      ///< sums of each `take` rows written
        explicit SharedRows(std::size_t n)
            : taken((n + block_rows - 1) / block_rows), gathered((n + take - 1) / take) {}
    };

    /// out[(i - a) K + k] = sum_{j < r0 or j >= r1} F_ij B_j[k] for the rows i in [a, e) of the
    /// block [r0, r1): the gather outside the block.
    template <class Mx>
    static void gather_outside(const Mx& F, const BandMajor<K>& B, std::size_t r0, std::size_t r1,
                               std::size_t a, std::size_t e, double* out) {
        for (std::size_t i = a; i < e; ++i) {
            const float* row = F.row(i).data();
            std::array<double, K> before, after;
            dense_dot<K>(row, B.data(), B.stride(), 0, r0, before.data());
            dense_dot<K>(row, B.data(), B.stride(), r1, F.size(), after.data());
            for (std::size_t k = 0; k < K; ++k) out[(i - a) * K + k] = before[k] + after[k];
        }
    }

    /// Takes rows of the block, `take` at a time, until none are left, and writes their gathered
    /// sums to outside[i K + k] for all threads.
    template <class Mx>
    static void share_gather(const Mx& F, const BandMajor<K>& B, std::size_t r0, std::size_t r1,
                             SharedRows& shared, std::vector<double>& outside) {
        std::atomic<std::size_t>& taken = shared.taken[r0 / block_rows];
        for (std::size_t a = r0 + taken.fetch_add(take); a < r1; a = r0 + taken.fetch_add(take)) {
            gather_outside(F, B, r0, r1, a, std::min(r1, a + take), outside.data() + a * K);
            shared.gathered[a / take].store(true, std::memory_order_release);
        }
    }

    /// sums = the block's gathered sums: those written by now, and, for rows still in another
    /// thread's hands after a short spin, sums gathered here (the same bits).
    template <class Mx>
    static void collect_gather(const Mx& F, const BandMajor<K>& B, std::size_t r0, std::size_t r1,
                               const SharedRows& shared, const std::vector<double>& outside,
                               std::vector<double>& sums) {
        for (std::size_t a = r0; a < r1; a += take) {
            const std::size_t e = std::min(r1, a + take);
            const std::atomic<bool>& done = shared.gathered[a / take];
            // About a row's gather (tens of microseconds): long enough for a running thread to
            // finish, short next to a time slice of a thread that the machine put aside.
            for (int spin = 0; spin < 2048 && !done.load(std::memory_order_acquire); ++spin)
                spin_pause();
            if (done.load(std::memory_order_acquire))
                std::copy(outside.begin() + static_cast<std::ptrdiff_t>(a * K),
                          outside.begin() + static_cast<std::ptrdiff_t>(e * K),
                          sums.begin() + static_cast<std::ptrdiff_t>((a - r0) * K));
            else
                gather_outside(F, B, r0, r1, a, e, sums.data() + (a - r0) * K);
        }
    }

    /// Gauss-Seidel over the rows of one block, in order, adding the block's own columns to the
    /// gathered rest (sums, row r0 first); returns the largest change. The self term is left out
    /// of the sum by setting B_i to 0 while row i is gathered (F_ii times 0 adds nothing), then
    /// handed to update, which solves for it.
    template <class Mx, class Update>
    static double sweep_block(const Mx& F, const std::vector<double>& E,
                              const std::vector<double>& R, BandMajor<K>& B, std::size_t r0,
                              std::size_t r1, const std::vector<double>& sums, Update& update) {
        double change = 0.0;
        for (std::size_t i = r0; i < r1; ++i) {
            const float* row = F.row(i).data();
            std::array<double, K> old, inside;
            for (std::size_t k = 0; k < K; ++k) old[k] = std::exchange(B.at(k, i), 0.0);
            dense_dot<K>(row, B.data(), B.stride(), r0, r1, inside.data());
            const double self = row[i];  // F_ii
            for (std::size_t k = 0; k < K; ++k) {
                const std::size_t ik = i * K + k;
                const double b = update(E[ik], R[ik], sums[(i - r0) * K + k] + inside[k], self);
                change = std::max(change, std::abs(b - old[k]));
                B.at(k, i) = b;
            }
        }
        return change;
    }

    BandMajor<K> B_;
    std::vector<double> outside_;  ///< gathered sums outside the block, rows shared by threads
};

}  // namespace radiosity::detail
