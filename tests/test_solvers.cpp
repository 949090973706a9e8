// The four solvers against the exact solutions of ../shared/refdata/cases.json: the furnace
// (B = E / (1 - rho) in a closed box), a sphere of 8 patches that see themselves (F_ii != 0),
// infinite parallel plates, and a cube with one emitting face. Also the iteration guard,
// cancellation and bad input.
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include "support/refdata.hpp"

#include <doctest/doctest.h>

#include <cmath>

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
            return Jacobi({1e-7, 10000}).solve(s, F);
        });
        check_case<S>(name, [](const System<S>& s, const DenseMatrix& F) {
            return GaussSeidel({1e-7, 10000}).solve(s, F);
        });
        check_case<S>(name, [](const System<S>& s, const DenseMatrix& F) {
            return Progressive({1e-7, 0, 1 << 20, false}).solve(s, F);
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
            CHECK(band(reference.radiosity[i], b) ==
                  doctest::Approx(grey.radiosity[i]).epsilon(1e-6));
    }
    for (auto s :
         {Jacobi({1e-7, 10000}).solve(system, k.F), GaussSeidel({1e-7, 10000}).solve(system, k.F),
          Progressive({1e-7, 0, 1 << 20, false}).solve(system, k.F)})
        for (std::size_t i = 0; i < k.E.size(); ++i)
            for (int b = 0; b < 3; ++b)
                CHECK(band(s.radiosity[i], b) ==
                      doctest::Approx(band(reference.radiosity[i], b)).epsilon(1e-5));
}

TEST_CASE("the report is honest: residual, iteration guard, cancellation") {
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    const auto capped = Jacobi({1e-9, 3}).solve(system, k.F);
    CHECK(capped.report.iterations == 3);
    CHECK(!capped.report.converged);
    CHECK(capped.report.residual > 1e-9);
    const auto gs = GaussSeidel({1e-6, 1000}).solve(system, k.F);
    CHECK(gs.report.converged);
    CHECK(gs.report.residual <= 1e-6);
    int calls = 0;
    const ProgressCallback stop = [&](const Progress& p) {
        CHECK(p.phase == "solve");
        return ++calls < 2;
    };
    const auto cancelled = Jacobi({1e-9, 1000}).solve(system, k.F, stop);
    CHECK(cancelled.report.cancelled);
    CHECK(!cancelled.report.converged);
    CHECK(cancelled.report.iterations == 2);
    const auto shots = Progressive({1e-9, 4, 0, false}).solve(system, k.F);
    CHECK(shots.report.iterations == 4);
    CHECK(!shots.report.converged);
}

TEST_CASE("the ambient term: exact for uniform unshot light, and it helps an early stop") {
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    // Before any shot, B = E and all of E is unshot and uniform: the ambient term then gives
    // the furnace's exact answer E / (1 - rho) = 10.
    for (float b : with_ambient<float>(system, E, E)) CHECK(b == doctest::Approx(10.0));
    // After 6 shots the unshot light is no longer uniform; with the term the picture is still
    // much closer to the answer than without it.
    const auto plain = Progressive({1e-9, 6, 0, false}).solve(system, k.F);
    const auto ambient = Progressive({1e-9, 6, 0, true}).solve(system, k.F);
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
    CHECK_THROWS_AS(Direct({4}).solve(System<float>{E, R, k.area}, k.F), Error);
}

TEST_CASE("every solver stops when the progress callback says so") {
    const Case k = load("furnace_cube_rho0.9");
    const std::vector<float> E(k.E.begin(), k.E.end()), R(k.R.begin(), k.R.end());
    const System<float> system{E, R, k.area};
    const ProgressCallback stop = [](const Progress&) { return false; };
    for (const auto& s : {GaussSeidel({1e-9, 1000}).solve(system, k.F, stop),
                          Progressive({1e-9, 0, 0, false}).solve(system, k.F, stop),
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
