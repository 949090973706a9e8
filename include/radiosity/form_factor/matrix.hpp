#pragma once
/// @file matrix.hpp  The form-factor matrix F (F_ij = fraction of the energy leaving patch i that
/// arrives at patch j): dense storage, sparse rows with a threshold, assembly from any
/// FormFactorMethod (rows in parallel with OpenMP when available), and the checks of the two
/// identities every F must satisfy: reciprocity A_i F_ij = A_j F_ji and, in a closed scene,
/// row sums sum_j F_ij = 1.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/parallel.hpp>
#include <radiosity/detail/zeroed_memory.hpp>
#include <radiosity/error.hpp>
#include <radiosity/progress.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <span>
#include <utility>
#include <vector>

namespace radiosity {

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
