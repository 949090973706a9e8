// The four solvers against the exact solutions of ../shared/refdata/cases.json: the furnace
// (B = E / (1 - rho) in a closed box), a sphere of 8 patches that see themselves (F_ii != 0),
// infinite parallel plates, and a cube with one emitting face. Also the iteration guard, an
// iteration that diverges, cancellation and bad input; the dense gather kernel, and the sweeps
// over dense rows against the generic ones and across thread counts.
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include "support/approx.hpp"
#include "support/refdata.hpp"
#include "support/threads.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

using namespace radiosity;

namespace {

DenseMatrix dense(const std::vector<std::vector<double>>& rows) {
    DenseMatrix F(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t j = 0; j < rows.size(); ++j) F.row(i)[j] = static_cast<float>(rows[i][j]);
    return F;
}

/// A solution case: its matrix (its own, or the closed box's exact one), E, R, areas, B.
struct Case {
    DenseMatrix F;
    std::vector<double> E, R, area, expected;
};

Case load(const std::string& name) {
    const auto& c = refdata::find_case(name);
    Case k;
    if (c.contains("form_factor_matrix")) {
        k.F = dense(refdata::matrix(c["form_factor_matrix"]));
    } else {  // the unit cube cases use the exact matrix of the closed box
        k.F = dense(refdata::matrix(refdata::find_case("closed_box_1x1x1")["expected"]));
    }
    k.E = c["emission"].get<std::vector<double>>();
    k.R = c["reflectance"].get<std::vector<double>>();
    k.expected = c["expected"].get<std::vector<double>>();
    k.area.assign(k.E.size(), 1.0);  // equal areas in every case (sphere: area fractions 1/8)
    return k;
}

template <SpectrumType S>
std::vector<S> colours(const std::vector<double>& v, float tint = 1.0f) {
    std::vector<S> out;
    for (double x : v) {
        S s{};
        for (std::size_t k = 0; k < band_count<S>; ++k)
            set_band(s, k, static_cast<float>(x) * (k == 1 ? tint : 1.0f));
        out.push_back(s);
    }
    return out;
}

template <SpectrumType S, class Solve>
void check_case(const std::string& name, Solve&& solve) {
    CAPTURE(name);
    const Case k = load(name);
    const std::vector<S> E = colours<S>(k.E), R = colours<S>(k.R);
    const System<S> system{E, R, k.area};
    const Solution<S> s = solve(system, k.F);
    CHECK(s.report.converged);
    CHECK(!s.report.cancelled);
    REQUIRE(s.radiosity.size() == k.expected.size());
    for (std::size_t i = 0; i < k.expected.size(); ++i)
        for (std::size_t b = 0; b < band_count<S>; ++b)
            CHECK(std::abs(band(s.radiosity[i], b) - k.expected[i]) <= 1e-4 * k.expected[i]);
}

const std::vector<std::string> cases{
    "furnace_cube_rho0.5", "furnace_cube_rho0.9", "sphere_one_emitter_f0.125_rho0.5",
    "infinite_parallel_plates_E1_0_rho0.5_0.5", "cube_one_emitter_rho0.5"};

template <SpectrumType S>
void every_solver_on_every_case() {
    for (const auto& name : cases) {
        check_case<S>(name, [](const System<S>& s, const DenseMatrix& F) {
            return Jacobi({.tolerance = 1e-7, .max_iterations = 10000}).solve(s, F);
        });
        check_case<S>(name, [](const System<S>& s, const DenseMatrix& F) {
            return GaussSeidel({.tolerance = 1e-7, .max_iterations = 10000}).solve(s, F);
        });
        check_case<S>(name, [](const System<S>& s, const DenseMatrix& F) {
            return Progressive({.tolerance = 1e-7, .row_cache_bytes = 1 << 20}).solve(s, F);
        });
        check_case<S>(
            name, [](const System<S>& s, const DenseMatrix& F) { return Direct().solve(s, F); });
    }
}

}  // namespace

TEST_CASE("every solver reaches the exact solutions to 1e-4 (grey)") {
    every_solver_on_every_case<float>();
}

TEST_CASE("every solver reaches the exact solutions to 1e-4 (RGB)") {
    every_solver_on_every_case<Rgb>();
}

TEST_CASE("the solvers agree per band when the bands differ") {
    // Cube with one emitter, reflectance 0.5 / 0.2 / 0.8 in the three bands: each band is its own
    // grey problem, so each must match the direct solve of that band alone.
    const Case k = load("cube_one_emitter_rho0.5");
    std::vector<Rgb> E = colours<Rgb>(k.E), R(k.E.size(), Rgb(0.5f, 0.2f, 0.8f));
    const System<Rgb> system{E, R, k.area};
    const auto reference = Direct().solve(system, k.F);
    for (int b = 0; b < 3; ++b) {
        const std::vector<float> Eg(k.E.begin(), k.E.end());
        const std::vector<float> Rg(k.E.size(), band(R[0], b));
        const auto grey = Direct().solve(System<float>{Eg, Rg, k.area}, k.F);
        for (std::size_t i = 0; i < k.E.size(); ++i)
            CHECK(band(reference.radiosity[i], b) == test::approx(grey.radiosity[i]).epsilon(1e-6));
    }
    for (auto s : {Jacobi({.tolerance = 1e-7, .max_iterations = 10000}).solve(system, k.F),
                   GaussSeidel({.tolerance = 1e-7, .max_iterations = 10000}).solve(system, k.F),
                   Progressive({.tolerance = 1e-7, .row_cache_bytes = 1 << 20}).solve(system, k.F)})
        for (std::size_t i = 0; i < k.E.size(); ++i)
            for (int b = 0; b < 3; ++b)
                CHECK(band(s.radiosity[i], b) ==
                      test::approx(band(reference.radiosity[i], b)).epsilon(1e-5));
}

TEST_CASE("the report is honest: residual, iteration guard, cancellation") {
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    const auto capped = Jacobi({.tolerance = 1e-9, .max_iterations = 3}).solve(system, k.F);
    CHECK(capped.report.iterations == 3);
    CHECK(!capped.report.converged);
    CHECK(capped.report.residual > 1e-9);
    const auto gs = GaussSeidel({.tolerance = 1e-6, .max_iterations = 1000}).solve(system, k.F);
    CHECK(gs.report.converged);
    CHECK(gs.report.residual <= 1e-6);
    int calls = 0;
    const ProgressCallback stop = [&](const Progress& p) {
        CHECK(p.phase == "solve");
        return ++calls < 2;
    };
    const auto cancelled =
        Jacobi({.tolerance = 1e-9, .max_iterations = 1000}).solve(system, k.F, stop);
    CHECK(cancelled.report.cancelled);
    CHECK(!cancelled.report.converged);
    CHECK(cancelled.report.iterations == 2);
    const auto shots = Progressive({.tolerance = 1e-9, .max_iterations = 4, .row_cache_bytes = 0})
                           .solve(system, k.F);
    CHECK(shots.report.iterations == 4);
    CHECK(!shots.report.converged);
}

TEST_CASE("an iteration that diverges stops with an error naming its rows, not with infinities") {
    // The closed cube's exact matrix with every form factor 1.2 times too large (as form factors
    // without visibility come out where surfaces hide one another): rows sum to 1.2, times
    // rho 0.9 a contraction bound of 1.08, and light grows at every bounce. Unscaled, the same
    // system converges (the tests above).
    const Case k = load("furnace_cube_rho0.9");
    DenseMatrix F(6);
    for (std::size_t i = 0; i < 6; ++i)
        for (std::size_t j = 0; j < 6; ++j) F.row(i)[j] = 1.2f * k.F.row(i)[j];
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    const auto message = [&](auto&& solve) {
        try {
            solve();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string jacobi = message([&] { Jacobi({.tolerance = 1e-6}).solve(system, F); });
    const std::string gs = message([&] { GaussSeidel({.tolerance = 1e-6}).solve(system, F); });
    const std::string shots =
        message([&] { Progressive({.tolerance = 1e-6, .row_cache_bytes = 0}).solve(system, F); });
    for (const std::string& m : {jacobi, gs, shots}) {
        INFO(m);
        CHECK(m.find("diverged after") != std::string::npos);
        CHECK(m.find("sum to up to 1.08") != std::string::npos);
    }
    CHECK(jacobi.rfind("jacobi:", 0) == 0);
    CHECK(gs.rfind("gauss-seidel:", 0) == 0);
    CHECK(shots.rfind("progressive:", 0) == 0);
}

TEST_CASE("the ambient term: exact for uniform unshot light, and it helps an early stop") {
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    // Before any shot, B = E and all of E is unshot and uniform: the ambient term then gives
    // the furnace's exact answer E / (1 - rho) = 10.
    for (float b : with_ambient<float>(system, E, E)) CHECK(b == test::approx(10.0));
    // After 6 shots the unshot light is no longer uniform; with the term the picture is still
    // much closer to the answer than without it.
    const auto plain = Progressive({.tolerance = 1e-9, .max_iterations = 6, .row_cache_bytes = 0})
                           .solve(system, k.F);
    const auto ambient =
        Progressive({.tolerance = 1e-9, .max_iterations = 6, .row_cache_bytes = 0, .ambient = true})
            .solve(system, k.F);
    for (std::size_t i = 0; i < 6; ++i)
        CHECK(std::abs(ambient.radiosity[i] - 10.0) < 0.2 * std::abs(plain.radiosity[i] - 10.0));
}

TEST_CASE("bad input is refused") {
    const Case k = load("furnace_cube_rho0.5");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const std::vector<double> two_areas{1.0, 1.0};
    CHECK_THROWS_AS(Jacobi().solve(System<float>{E, R, two_areas}, k.F), Error);
    const std::vector<float> bad_R(6, 1.0f);
    CHECK_THROWS_AS(GaussSeidel().solve(System<float>{E, bad_R, k.area}, k.F), Error);
    DenseMatrix small(2);
    CHECK_THROWS_AS(Direct().solve(System<float>{E, R, k.area}, small), Error);
    CHECK_THROWS_AS(Direct({.max_patches = 4}).solve(System<float>{E, R, k.area}, k.F), Error);
}

TEST_CASE("every solver stops when the progress callback says so") {
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    const ProgressCallback stop = [](const Progress&) { return false; };
    for (const auto& s :
         {GaussSeidel({.tolerance = 1e-9, .max_iterations = 1000}).solve(system, k.F, stop),
          Progressive({.tolerance = 1e-9, .row_cache_bytes = 0}).solve(system, k.F, stop),
          Direct().solve(system, k.F, stop)}) {
        CAPTURE(s.report.solver);
        CHECK(s.report.cancelled);
        CHECK(!s.report.converged);
        CHECK(s.radiosity.size() == E.size());  // the values so far
    }
}

TEST_CASE("no emission: B = 0 at once, with residual 0") {
    const Case k = load("cube_one_emitter_rho0.5");
    const std::vector<float> E(k.E.size(), 0.0f), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    for (const auto& s : {Jacobi().solve(system, k.F), GaussSeidel().solve(system, k.F),
                          Progressive().solve(system, k.F), Direct().solve(system, k.F)}) {
        CAPTURE(s.report.solver);
        CHECK(s.report.converged);
        CHECK(s.report.residual == 0.0);
        for (float b : s.radiosity) CHECK(b == 0.0f);
    }
}

namespace {

/// A random system of n patches in the shape of radiosity's: rows half zeros, F_ij up to 1.8 / n
/// (row sums about 0.45), every seventh patch seeing itself (F_ii = 0.3), reflectance below 0.9
/// per band and one emitter in fifty. Diagonally dominant, so every sweep converges.
struct RandomSystem {
    DenseMatrix F;
    std::vector<Rgb> E, R;
    std::vector<double> area;
};

RandomSystem random_system(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    RandomSystem s{DenseMatrix(n), {}, {}, std::vector<double>(n, 1.0)};
    for (std::size_t i = 0; i < n; ++i) {
        for (float& f : s.F.row(i)) {
            const float x = u(rng);
            f = x < 0.5f ? 0.0f : (x - 0.5f) * 3.6f / static_cast<float>(n);
        }
        s.F.row(i)[i] = i % 7 == 0 ? 0.3f : 0.0f;
        s.R.emplace_back(0.9f * u(rng), 0.9f * u(rng), 0.9f * u(rng));
        s.E.push_back(i % 50 == 0 ? Rgb(u(rng), 2.0f * u(rng), 3.0f * u(rng)) : Rgb());
    }
    return s;
}

/// The same matrix with every entry stored sparse: the solvers' generic, entry-by-entry path.
SparseMatrix all_entries(const DenseMatrix& F) {
    std::vector<std::vector<std::pair<std::uint32_t, float>>> rows(F.size());
    for (std::size_t i = 0; i < F.size(); ++i)
        for (std::size_t j = 0; j < F.size(); ++j)
            rows[i].emplace_back(static_cast<std::uint32_t>(j), F(i, j));
    return SparseMatrix::from_rows(rows);
}

}  // namespace

TEST_CASE("the dense gather is accurate to double rounding") {
    const std::size_t n = 1003;  // not a multiple of 8: the last terms take the scalar tail
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<float> f(n);
    std::vector<double> B(3 * n);
    for (float& x : f) x = static_cast<float>(u(rng));
    for (double& x : B) x = u(rng);
    for (std::size_t begin : {std::size_t(0), std::size_t(5)}) {
        double out[3];
        detail::dense_dot<3>(f.data(), B.data(), n, begin, n, out);
        for (std::size_t k = 0; k < 3; ++k) {
            long double exact = 0.0L;
            for (std::size_t j = begin; j < n; ++j)
                exact += static_cast<long double>(f[j]) * B[k * n + j];
            CHECK(std::abs(out[k] - static_cast<double>(exact)) <= 1e-14 * out[k]);
        }
    }
}

namespace {

/// dense_dot's summation order, written out plainly (detail/dense_dot.hpp): term j goes to lane
/// (j - begin) % 8, each lane adds its terms in order of j, and the lanes are summed as
/// ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)).
double in_fixed_order(const float* f, const double* b, std::size_t begin, std::size_t end) {
    double lane[8] = {};
    for (std::size_t j = begin; j < end; ++j) lane[(j - begin) % 8] += double(f[j]) * b[j];
    return ((lane[0] + lane[1]) + (lane[2] + lane[3])) +
           ((lane[4] + lane[5]) + (lane[6] + lane[7]));
}

}  // namespace

TEST_CASE("the dense gather adds in its fixed order, bit for bit, on the path this build takes") {
    // The order is what makes the sums, and so B, the same on every thread and on either path
    // (SSE2 or plain C++). Whichever path this build compiled is checked against the order
    // written out above. Magnitudes spread over 16 decades, so that another order rounds
    // differently: the sequential sum must differ somewhere, or the comparison could not fail.
    const std::size_t n = 1003;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0), decade(-8.0, 8.0);
    std::vector<float> f(n);
    std::vector<double> B(3 * n);
    for (float& x : f) x = static_cast<float>(u(rng));
    for (double& x : B) x = u(rng) * std::pow(10.0, decade(rng));
    std::size_t cases = 0, unlike_sequential = 0;
    for (std::size_t begin : {0, 1, 5, 8})
        for (std::size_t end : {begin, begin + 3, begin + 8, begin + 13, n - 7, n}) {
            CAPTURE(begin);
            CAPTURE(end);
            double grey, rgb[3];
            detail::dense_dot<1>(f.data(), B.data(), n, begin, end, &grey);
            detail::dense_dot<3>(f.data(), B.data(), n, begin, end, rgb);
            CHECK(grey == in_fixed_order(f.data(), B.data(), begin, end));
            for (std::size_t k = 0; k < 3; ++k) {
                const double expected = in_fixed_order(f.data(), B.data() + k * n, begin, end);
                CHECK(rgb[k] == expected);
                double sequential = 0.0;
                for (std::size_t j = begin; j < end; ++j) sequential += double(f[j]) * B[k * n + j];
                unlike_sequential += sequential != expected;
                ++cases;
            }
        }
    CHECK(unlike_sequential > cases / 4);
}

TEST_CASE("over dense rows the sweeps give the generic path's B") {
    // 2500 patches: enough to share the passes among threads (detail::worth_threads), and
    // neither a multiple of the blocks (256) nor of the 8 rows taken at a time. A fixed number of
    // sweeps, so both do the same work; they add in different orders, so B agrees to double
    // rounding, well inside one float.
    const RandomSystem s = random_system(2500, 1);
    const SparseMatrix generic = all_entries(s.F);
    const System<Rgb> system{s.E, s.R, s.area};
    const auto check_same = [](const Solution<Rgb>& dense, const Solution<Rgb>& sparse) {
        CAPTURE(dense.report.solver);
        CHECK(dense.report.iterations == sparse.report.iterations);
        // The residuals are at double rounding (1e-16), in different orders: they agree as
        // changes of B, which is of order 1, not digit for digit.
        CHECK(std::abs(dense.report.residual - sparse.report.residual) < 1e-9);
        for (std::size_t i = 0; i < dense.radiosity.size(); ++i)
            for (std::size_t k = 0; k < 3; ++k) {
                const double a = band(dense.radiosity[i], k), b = band(sparse.radiosity[i], k);
                CHECK(std::abs(a - b) <= 1e-12 * std::abs(b));
            }
    };
    check_same(GaussSeidel({.tolerance = 0.0, .max_iterations = 12}).solve(system, s.F),
               GaussSeidel({.tolerance = 0.0, .max_iterations = 12}).solve(system, generic));
    check_same(Jacobi({.tolerance = 0.0, .max_iterations = 12}).solve(system, s.F),
               Jacobi({.tolerance = 0.0, .max_iterations = 12}).solve(system, generic));
}

TEST_CASE("the sweeps give bit-identical B for 1, 2 and 3 threads" *
          doctest::skip(test::threads::without_openmp) *
          doctest::description("needs OpenMP: without it every run is on one thread")) {
    const RandomSystem s = random_system(2500, 2);
    REQUIRE(detail::worth_threads(2500, 3));  // the sweeps and the residual pass are shared
    const System<Rgb> system{s.E, s.R, s.area};
    std::vector<Solution<Rgb>> gs, jacobi;
    for (int threads : {1, 2, 3}) {
        const test::threads::Forced forced(threads);
        REQUIRE(test::threads::team_size() == threads);  // else the runs would compare nothing
        gs.push_back(GaussSeidel({.tolerance = 1e-9, .max_iterations = 1000}).solve(system, s.F));
        jacobi.push_back(Jacobi({.tolerance = 1e-9, .max_iterations = 1000}).solve(system, s.F));
    }
    for (const auto* runs : {&gs, &jacobi})
        for (std::size_t t = 1; t < 3; ++t) {
            const auto &one = (*runs)[0], &other = (*runs)[t];
            CAPTURE(one.report.solver);
            CAPTURE(t + 1);
            CHECK(one.report.converged);
            CHECK(other.report.iterations == one.report.iterations);
            CHECK(other.report.residual == one.report.residual);
            CHECK(std::memcmp(other.radiosity.data(), one.radiosity.data(),
                              one.radiosity.size() * sizeof(Rgb)) == 0);
        }
}

TEST_CASE("the stopping rule: a sweep from B = E meets the tolerance within sweeps_needed") {
    // The exact closed box at rho = 0.9: rows sum to 1, so q = 0.9, and the error of Jacobi
    // shrinks by exactly 0.9 a sweep (B and E are uniform), the worst case that sweeps_needed
    // provides for. Gauss-Seidel contracts at least as fast.
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    const double q = detail::contraction_bound<1>(k.F, k.R);
    CHECK(q == test::approx(0.9).epsilon(1e-6));
    for (double tolerance : {1e-2, 1e-4, 1e-6, 1e-8}) {
        CAPTURE(tolerance);
        const double needed = detail::StoppingRule::sweeps_needed(tolerance, q);
        const auto rule = detail::StoppingRule::sweeps(tolerance, q, 0);
        CHECK(rule.max_iterations == static_cast<std::size_t>(2 * needed + 10));
        const auto jacobi = Jacobi({.tolerance = tolerance}).solve(system, k.F);
        const auto gs = GaussSeidel({.tolerance = tolerance}).solve(system, k.F);
        CHECK(jacobi.report.converged);
        CHECK(gs.report.converged);
        CHECK(static_cast<double>(jacobi.report.iterations) <= needed);
        // and no looser than its worst case: it takes the change of a sweep as (1 + q) q^m ||B*||,
        // here it is (1 - q) q^m ||B*||
        const double slack = std::ceil(std::log((1 + q) / (1 - q)) / -std::log(q));
        CHECK(needed <= static_cast<double>(jacobi.report.iterations) + slack + 1);
        CHECK(gs.report.iterations <= jacobi.report.iterations);
        for (const auto* s : {&jacobi, &gs})
            for (float b : s->radiosity)
                CHECK(std::abs(b - 10.0) <= s->report.error_bound * 10.0 * (1 + 1e-6));
    }
    // No bound without a contraction below 1, and no guard from it.
    CHECK(std::isinf(detail::StoppingRule::sweeps_needed(1e-4, 1.0)));
    CHECK(detail::StoppingRule::sweeps(1e-4, 1.0, 0).max_iterations == 1000);
    CHECK(std::isinf(detail::bound_from_residual(1.0, 1e-3)));
    CHECK(detail::bound_from_change(0.5, 1e-3) == test::approx(1e-3));
    CHECK(detail::relative_bound(1.0, 3.0) == test::approx(0.5));
}

TEST_CASE("progressive shooting goes down the columns: dense copy, strided, sparse alike") {
    // The columns of an assembled matrix come from a transposed copy where it fits in the row
    // cache's budget, else from strided reads of F; of sparse rows, from a sparse transpose.
    // The same numbers in the same order: the same shots and bit-identical B.
    const RandomSystem s = random_system(300, 3);
    const SparseMatrix sparse = all_entries(s.F);
    const System<Rgb> system{s.E, s.R, s.area};
    const auto copied = Progressive({.tolerance = 1e-6}).solve(system, s.F);
    const auto strided =
        Progressive({.tolerance = 1e-6, .row_cache_bytes = 1000}).solve(system, s.F);
    const auto from_sparse = Progressive({.tolerance = 1e-6}).solve(system, sparse);
    CHECK(copied.report.converged);
    for (const auto* other : {&strided, &from_sparse}) {
        CHECK(other->report.iterations == copied.report.iterations);
        CHECK(std::memcmp(other->radiosity.data(), copied.radiosity.data(),
                          copied.radiosity.size() * sizeof(Rgb)) == 0);
    }
    // and it is the gathering solvers' system: the direct solve's B within the tolerance
    const auto direct = Direct().solve(system, s.F);
    double diff = 0.0, size = 0.0;
    for (std::size_t i = 0; i < s.E.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) {
            diff = std::max<double>(
                diff, std::abs(band(copied.radiosity[i], k) - band(direct.radiosity[i], k)));
            size = std::max<double>(size, std::abs(band(direct.radiosity[i], k)));
        }
    CHECK(diff / size <= copied.report.error_bound);
    CHECK(copied.report.error_bound <= 1e-6);
}

TEST_CASE("progressive shooting refuses a relaxation outside (0, 2)") {
    const Case k = load("furnace_cube_rho0.5");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    for (double omega : {2.0, -0.5, std::nan("")}) {
        CAPTURE(omega);
        CHECK_THROWS_AS(Progressive({.relaxation = omega}).solve(system, k.F), Error);
    }
    CHECK(Progressive({.tolerance = 1e-6, .relaxation = 1.5}).solve(system, k.F).report.converged);
}
