#pragma once
/// @file matrix.hpp  The form-factor matrix F (F_ij = fraction of the energy leaving patch i that
/// arrives at patch j): dense storage, sparse rows with a threshold, assembly from any
/// FormFactorMethod (rows in parallel with OpenMP when available), and the checks of the two
/// identities every F must satisfy: reciprocity A_i F_ij = A_j F_ji and, in a closed scene,
/// row sums sum_j F_ij = 1.

#include <radiosity/concepts.hpp>
#include <radiosity/error.hpp>
#include <radiosity/progress.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <string>
#include <span>
#include <utility>
#include <vector>

#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace radiosity {

namespace detail {

/// Faults in the pages of a fresh mapping with all threads at once, 16 MiB at a time:
/// MADV_POPULATE_WRITE (Linux 5.14) where the kernel has it, else a write to each page.
inline void fault_in(std::byte* p, std::size_t bytes) {
    constexpr std::size_t chunk = std::size_t{16} << 20, page = 4096;
    const auto chunks = static_cast<std::int64_t>((bytes + chunk - 1) / chunk);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static)
#endif
    for (std::int64_t c = 0; c < chunks; ++c) {
        std::byte* const a = p + static_cast<std::size_t>(c) * chunk;
        const std::size_t size = std::min(chunk, bytes - static_cast<std::size_t>(c) * chunk);
#if defined(MADV_POPULATE_WRITE)
        if (madvise(a, size, MADV_POPULATE_WRITE) == 0) continue;
#endif
        for (std::size_t k = 0; k < size; k += page)
            *static_cast<volatile std::byte*>(a + k) = std::byte{0};
    }
}

/// The allocator of a dense matrix: memory that reads as zero, without one thread writing
/// hundreds of megabytes of zeros. Large blocks come from the kernel (an anonymous mapping, whose
/// pages are zero) and are faulted in by all threads at once: 0.07 s for 10,448 patches on two
/// cores, against 0.24 s for clearing the same bytes on one. Small ones are cleared as usual.
template <class T>
struct ZeroedAllocator {
    using value_type = T;
    static constexpr std::size_t mapped = std::size_t{64} << 20;  // from 64 MiB on

    ZeroedAllocator() = default;
    template <class U>
    ZeroedAllocator(const ZeroedAllocator<U>&) {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
#if defined(__linux__)
        if (bytes >= mapped) {
            void* p =
                mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
            if (p == MAP_FAILED) throw std::bad_alloc();
            fault_in(static_cast<std::byte*>(p), bytes);
            return static_cast<T*>(p);
        }
#endif
        void* p = ::operator new(bytes);
        std::memset(p, 0, bytes);
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) {
#if defined(__linux__)
        if (n * sizeof(T) >= mapped) {
            munmap(p, n * sizeof(T));
            return;
        }
#endif
        ::operator delete(p);
    }
    /// Elements made without a value keep the zero bytes the memory came with.
    template <class U>
    void construct(U*) {}
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
    template <class U>
    bool operator==(const ZeroedAllocator<U>&) const {
        return true;
    }
};

}  // namespace detail

/// Dense n x n form-factor matrix stored row-major in float (4 n^2 bytes).
class DenseMatrix {
  public:
    DenseMatrix() = default;
    /// An n x n matrix of zeros. Throws Error (not std::bad_alloc) when it cannot be allocated,
    /// naming its size and what to do instead.
    explicit DenseMatrix(std::size_t n) : n_(n) {
        const std::string advice =
            "; use fewer patches (a longer max edge) or the progressive "
            "solver, which needs no matrix";
        if (n != 0 && n > f_.max_size() / n)
            throw Error("form factors: " + std::to_string(n) +
                        " patches are too many for a dense matrix" + advice);
        try {
            f_.resize(n * n);  // zeros: see ZeroedAllocator
        } catch (const std::bad_alloc&) {
            throw Error("form factors: " + std::to_string(n) + " patches need a dense matrix of " +
                        std::to_string(double(n) * double(n) * sizeof(float) / double(1 << 30)) +
                        " GiB, more than can be allocated" + advice);
        }
    }

    std::size_t size() const { return n_; }  ///< number of patches n
    /// Row i, F_i0 .. F_i(n-1).
    std::span<float> row(std::size_t i) { return {f_.data() + i * n_, n_}; }
    std::span<const float> row(std::size_t i) const { return {f_.data() + i * n_, n_}; }
    float operator()(std::size_t i, std::size_t j) const { return f_[i * n_ + j]; }  ///< F_ij
    /// RowSource: copies row i into out, so a matrix can stand in for a method.
    void row(std::size_t i, std::span<float> out) const {
        std::copy_n(f_.begin() + static_cast<std::ptrdiff_t>(i * n_), n_, out.begin());
    }
    /// Visits every entry of row i (zeros included) as f(j, F_ij).
    template <class F>
    void for_each_in_row(std::size_t i, F&& f) const {
        const float* r = f_.data() + i * n_;
        for (std::size_t j = 0; j < n_; ++j) f(j, r[j]);
    }

  private:
    std::size_t n_ = 0;
    std::vector<float, detail::ZeroedAllocator<float>> f_;
};

/// An assembled matrix whose rows are stored as contiguous floats: `m.row(i)` views the n
/// entries F_i0 .. F_i(n-1). The sweeping solvers then gather with the vectorised dense kernel
/// (detail/dense_dot.hpp) instead of visiting entries one at a time.
template <class Mx>
concept DenseRowMatrix = AssembledMatrix<Mx> && requires(const Mx& m, std::size_t i) {
    { m.row(i) } -> std::convertible_to<std::span<const float>>;
};

/// Sparse rows (compressed sparse row): only entries above a threshold are kept. Dropping small
/// entries loses energy, which check_matrix reports as row sums below 1.
class SparseMatrix {
  public:
    SparseMatrix() = default;
    explicit SparseMatrix(std::size_t n) : n_(n), first_(n + 1, 0) {}

    std::size_t size() const { return n_; }                  ///< number of patches n
    std::size_t non_zeros() const { return value_.size(); }  ///< stored entries
    /// Visits the stored entries of row i as f(j, F_ij).
    template <class F>
    void for_each_in_row(std::size_t i, F&& f) const {
        for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) f(column_[k], value_[k]);
    }
    /// RowSource: writes row i (zeros where nothing is stored) into out.
    void row(std::size_t i, std::span<float> out) const {
        std::fill(out.begin(), out.end(), 0.0f);
        for_each_in_row(i, [&](std::size_t j, float v) { out[j] = v; });
    }

    /// Builds the matrix from per-row lists of (j, F_ij).
    static SparseMatrix from_rows(
        const std::vector<std::vector<std::pair<std::uint32_t, float>>>& rows) {
        SparseMatrix S(rows.size());
        for (std::size_t i = 0; i < rows.size(); ++i) {
            S.first_[i + 1] = S.first_[i] + rows[i].size();
            for (auto [j, v] : rows[i]) {
                S.column_.push_back(j);
                S.value_.push_back(v);
            }
        }
        return S;
    }

  private:
    std::size_t n_ = 0;
    std::vector<std::size_t> first_;
    std::vector<std::uint32_t> column_;
    std::vector<float> value_;
};

static_assert(DenseRowMatrix<DenseMatrix> && !DenseRowMatrix<SparseMatrix>);

namespace detail {
/// This thread's index in its OpenMP team (0 outside a parallel region or without OpenMP).
inline int thread_index() {
#if defined(RADIOSITY_WITH_OPENMP)
    return omp_get_thread_num();
#else
    return 0;
#endif
}

/// Runs body(i) for every row i, in parallel with OpenMP when available, reporting progress from
/// the first thread only (the callback need not be thread-safe) and stopping (by throwing
/// Cancelled) when the callback asks to.
template <class Body>
void for_each_row(std::size_t n, const ProgressCallback& progress, Body&& body) {
    std::atomic<std::size_t> done{0};
    std::atomic<bool> cancel{false};
    const auto count = static_cast<std::int64_t>(n);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 4)
#endif
    for (std::int64_t i = 0; i < count; ++i) {
        if (cancel.load(std::memory_order_relaxed)) continue;
        body(static_cast<std::size_t>(i));
        const std::size_t d = ++done;
        if (thread_index() == 0 && !detail::report(progress, "form factors",
                                                   static_cast<double>(d) / static_cast<double>(n)))
            cancel = true;
    }
    if (cancel) throw Cancelled();
}
}  // namespace detail

/// Assembles the dense n x n matrix, one row per patch. Cost: n rows of the method.
/// A method that is reciprocal by construction (ReciprocalFormFactor) computes each pair once:
/// row i fills F_ij and F_ji for j > i, from the exchange A_i F_ij = A_j F_ji.
template <FormFactorMethod M>
DenseMatrix assemble_dense(const M& method, std::size_t n, const ProgressCallback& progress = {}) {
    DenseMatrix F(n);
    if constexpr (ReciprocalFormFactor<M>) {
        detail::for_each_row(n, progress, [&](std::size_t i) {
            for (std::size_t j = i + 1; j < n; ++j) {
                const double x = method.exchange(i, j);
                F.row(i)[j] = static_cast<float>(x / method.area(i));
                F.row(j)[i] = static_cast<float>(x / method.area(j));
            }
        });
    } else {
        detail::for_each_row(n, progress, [&](std::size_t i) { method.row(i, F.row(i)); });
    }
    return F;
}

/// Assembles sparse rows keeping the entries F_ij > threshold. Memory: only what is kept, plus
/// one dense scratch row per thread.
template <FormFactorMethod M>
SparseMatrix assemble_sparse(const M& method, std::size_t n, float threshold,
                             const ProgressCallback& progress = {}) {
    std::vector<std::vector<std::pair<std::uint32_t, float>>> rows(n);
    detail::for_each_row(n, progress, [&](std::size_t i) {
        std::vector<float> scratch(n);
        method.row(i, scratch);
        for (std::size_t j = 0; j < n; ++j)
            if (scratch[j] > threshold)
                rows[i].emplace_back(static_cast<std::uint32_t>(j), scratch[j]);
    });
    return SparseMatrix::from_rows(rows);
}

/// What check_matrix finds: the reciprocity error and the row sums.
struct MatrixCheck {
    /// max_ij |A_i F_ij - A_j F_ji| / max_ij A_i F_ij: 0 for an exact F.
    double reciprocity_error = 0.0;
    double min_row_sum = 0.0;      ///< min_i sum_j F_ij (1 in a closed scene)
    double max_row_sum = 0.0;      ///< max_i sum_j F_ij (never above 1 for an exact F)
    std::vector<double> row_sums;  ///< sum_j F_ij per row
};

/// Checks reciprocity A_i F_ij = A_j F_ji and the row sums of an assembled matrix. O(n^2).
template <AssembledMatrix Mx>
MatrixCheck check_matrix(const Mx& F, std::span<const double> area) {
    const std::size_t n = F.size();
    if (area.size() != n) throw Error("check_matrix: need one area per patch");
    DenseMatrix dense(n);  // reciprocity needs F_ji next to F_ij
    MatrixCheck c;
    c.row_sums.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        F.for_each_in_row(i, [&](std::size_t j, float v) {
            dense.row(i)[j] = v;
            c.row_sums[i] += v;
        });
    double worst = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            const double aij = area[i] * dense(i, j), aji = area[j] * dense(j, i);
            worst = std::max(worst, std::abs(aij - aji));
            scale = std::max(scale, aij);
        }
    c.reciprocity_error = scale > 0.0 ? worst / scale : 0.0;
    if (n > 0) {
        const auto [lo, hi] = std::minmax_element(c.row_sums.begin(), c.row_sums.end());
        c.min_row_sum = *lo;
        c.max_row_sum = *hi;
    }
    return c;
}

}  // namespace radiosity
