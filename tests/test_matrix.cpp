// Assembly of the form-factor matrix: sparse rows with a threshold against the dense matrix,
// what dropping entries costs in the row sums, and a solve over sparse rows.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/gauss_seidel.hpp>

#include "support/approx.hpp"
#include "support/refdata.hpp"

#include <doctest/doctest.h>

using namespace radiosity;

TEST_CASE("sparse rows: threshold 0 keeps the dense matrix, a threshold drops what it says") {
    const PatchTable t = refdata::table(refdata::find_case("closed_box_1x1x1"));
    Analytic method;
    method.prepare(t);
    const DenseMatrix dense = assemble_dense(method, t.size());
    const SparseMatrix all = assemble_sparse(method, t.size(), 0.0f);
    CHECK(all.non_zeros() == 30);  // every off-diagonal entry of the box
    for (std::size_t i = 0; i < t.size(); ++i) {
        std::vector<float> row(t.size());
        all.row(i, row);
        for (std::size_t j = 0; j < t.size(); ++j) CHECK(row[j] == dense(i, j));
    }
    // Opposite faces see each other with 0.19982, adjacent ones with 0.20004: a threshold in
    // between keeps only the 24 adjacent pairs, and each row then misses one opposite face.
    const SparseMatrix adjacent = assemble_sparse(method, t.size(), 0.2f);
    CHECK(adjacent.non_zeros() == 24);
    const MatrixCheck check = check_matrix(adjacent, t.areas());
    CHECK(check.max_row_sum == test::approx(1.0 - 0.199824895698).epsilon(1e-6));
}

TEST_CASE("a solver over sparse rows gives the dense result") {
    const PatchTable t = refdata::table(refdata::find_case("closed_box_1x1x1"));
    Analytic method;
    method.prepare(t);
    const std::vector<float> E{1, 0, 0, 0, 0, 0}, R(6, 0.5f);
    const System<float> system{E, R, t.areas()};
    const auto dense = GaussSeidel({.tolerance = 1e-8, .max_iterations = 1000})
                           .solve(system, assemble_dense(method, t.size()));
    const auto sparse = GaussSeidel({.tolerance = 1e-8, .max_iterations = 1000})
                            .solve(system, assemble_sparse(method, t.size(), 0.0f));
    for (std::size_t i = 0; i < 6; ++i)
        CHECK(sparse.radiosity[i] == test::approx(dense.radiosity[i]).epsilon(1e-7));
}

TEST_CASE("a dense matrix starts at zero, small or mapped from the kernel, and copies") {
    // 4,200 patches: 70 MB, above the size taken from an anonymous mapping; 300: the heap.
    for (const std::size_t n : {std::size_t{300}, std::size_t{4200}}) {
        CAPTURE(n);
        DenseMatrix F(n);
        REQUIRE(F.size() == n);
        std::size_t nonzero = 0;
        for (std::size_t i = 0; i < n; i += 7)
            for (const float f : F.row(i)) nonzero += f != 0.0f;
        CHECK(nonzero == 0);
        F.row(n - 1)[n - 1] = 0.25f;
        F.row(0)[n / 2] = 0.5f;
        const DenseMatrix G = F;
        CHECK(G(n - 1, n - 1) == 0.25f);
        CHECK(G(0, n / 2) == 0.5f);
        CHECK(G(n / 2, 0) == 0.0f);
    }
}
