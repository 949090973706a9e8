// The solvers' progress reports as an observer sees them (progress.hpp): each report of an
// iterative solver carries the values it holds at that moment, so that a viewer can draw the
// solve as it goes. The values after m sweeps (or shots) must be exactly those that the same
// solver returns when its iteration guard stops it at m; the unshot radiosity of shooting must
// account for the residual it reports; cancelling still stops at once.
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include "support/approx.hpp"
#include "support/refdata.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace radiosity;

namespace {

/// The closed unit cube with one emitting face (cases.json: cube_one_emitter_rho0.5), over the
/// exact matrix of the closed box, in RGB with a different reflectance per band.
struct Cube {
    DenseMatrix F{6};
    std::vector<Rgb> E, R;
    std::vector<double> area = std::vector<double>(6, 1.0);
    Cube() {
        const auto& c = refdata::find_case("cube_one_emitter_rho0.5");
        const auto rows = refdata::matrix(refdata::find_case("closed_box_1x1x1")["expected"]);
        for (std::size_t i = 0; i < 6; ++i)
            for (std::size_t j = 0; j < 6; ++j) F.row(i)[j] = static_cast<float>(rows[i][j]);
        const auto e = c["emission"].get<std::vector<double>>();
        const auto r = c["reflectance"].get<std::vector<double>>();
        for (std::size_t i = 0; i < 6; ++i) {
            const auto ei = static_cast<float>(e[i]), ri = static_cast<float>(r[i]);
            E.push_back(Rgb{ei, ei, ei});
            R.push_back(Rgb{ri, 0.8f * ri, 0.5f * ri});
        }
    }
    System<Rgb> system() const { return {E, R, area}; }
};

/// One report as the observer copied it.
struct Seen {
    std::size_t iteration = 0;
    double residual = 0.0;
    std::vector<double> radiosity, unshot;
};

/// A callback that copies every "solve" report into `seen`.
ProgressCallback recorder(std::vector<Seen>& seen) {
    return [&seen](const Progress& p) {
        if (p.phase == "solve")
            seen.push_back({p.iteration,
                            p.residual,
                            {p.radiosity.begin(), p.radiosity.end()},
                            {p.unshot.begin(), p.unshot.end()}});
        return true;
    };
}

/// The values a report carried, as the solver returns them (floats).
std::vector<Rgb> as_colours(const std::vector<double>& v) {
    std::vector<Rgb> out(v.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) set_band(out[i], k, static_cast<float>(v[i * 3 + k]));
    return out;
}

void check_same(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) CHECK(band(a[i], k) == band(b[i], k));
}

/// Every report of a sweeping solver: iterations 1, 2, ..., and the values those of the same
/// solver stopped by its guard after that many sweeps.
template <class Solver, class Options, class Mx>
void check_sweeps(const Mx& F) {
    const Cube cube;
    std::vector<Seen> seen;
    const auto full = Solver(Options{.tolerance = 1e-6}).solve(cube.system(), F, recorder(seen));
    REQUIRE(full.report.converged);
    REQUIRE(seen.size() >= 3);
    for (std::size_t m = 0; m < seen.size(); ++m) {
        CAPTURE(m);
        CHECK(seen[m].iteration == m + 1);
        CHECK(seen[m].unshot.empty());
        REQUIRE(seen[m].radiosity.size() == 18);
        const auto capped =
            Solver(Options{.tolerance = 1e-6, .max_iterations = m + 1}).solve(cube.system(), F);
        check_same(as_colours(seen[m].radiosity), capped.radiosity);
    }
}

}  // namespace

TEST_CASE("Jacobi reports the values of each sweep") {
    check_sweeps<Jacobi, JacobiOptions>(Cube().F);
}

TEST_CASE("Gauss-Seidel reports the values of each sweep, over dense and sparse rows") {
    const Cube cube;
    check_sweeps<GaussSeidel, GaussSeidelOptions>(cube.F);
    std::vector<std::vector<std::pair<std::uint32_t, float>>> rows(6);
    for (std::uint32_t i = 0; i < 6; ++i)
        for (std::uint32_t j = 0; j < 6; ++j)
            if (cube.F(i, j) != 0.0f) rows[i].emplace_back(j, cube.F(i, j));
    check_sweeps<GaussSeidel, GaussSeidelOptions>(SparseMatrix::from_rows(rows));
}

TEST_CASE("progressive shooting reports B and the unshot radiosity after every shot") {
    const Cube cube;
    const System<Rgb> system = cube.system();
    std::vector<Seen> seen;
    const ProgressiveOptions every_shot{.tolerance = 1e-6, .report_every = 1};
    const auto full = Progressive(every_shot).solve(system, cube.F, recorder(seen));
    REQUIRE(full.report.converged);
    REQUIRE(seen.size() == full.report.iterations);
    double emitted = 0.0;
    for (std::size_t i = 0; i < 6; ++i) emitted += 3.0 * band(cube.E[i], 0) * cube.area[i];
    for (std::size_t k = 0; k < seen.size(); ++k) {
        CAPTURE(k);
        CHECK(seen[k].iteration == k + 1);
        REQUIRE(seen[k].unshot.size() == 18);
        // The residual is the unshot power over the emitted power, re-summed at every report.
        double unshot = 0.0;
        for (std::size_t i = 0; i < 18; ++i) unshot += std::abs(seen[k].unshot[i]) * 1.0;
        CHECK(seen[k].residual == test::approx(unshot / emitted).epsilon(1e-12));
        // The values after k + 1 shots are what shooting returns when stopped there.
        ProgressiveOptions capped = every_shot;
        capped.max_iterations = k + 1;
        check_same(as_colours(seen[k].radiosity),
                   Progressive(capped).solve(system, cube.F).radiosity);
    }
    // The residual of shooting never grows: every shot moves power out of the unshot pool, and a
    // receiver keeps only the fraction R < 1 of what it receives.
    for (std::size_t k = 1; k < seen.size(); ++k) CHECK(seen[k].residual <= seen[k - 1].residual);
}

TEST_CASE("reports come every report_every shots, n / 100 (at least 1) by default") {
    const Cube cube;
    std::vector<Seen> seen;
    Progressive(ProgressiveOptions{.tolerance = 1e-6, .report_every = 4})
        .solve(cube.system(), cube.F, recorder(seen));
    REQUIRE(!seen.empty());
    for (std::size_t k = 0; k < seen.size(); ++k) CHECK(seen[k].iteration == 4 * (k + 1));
    seen.clear();
    const auto r = Progressive(ProgressiveOptions{.tolerance = 1e-6})
                       .solve(cube.system(), cube.F, recorder(seen));
    CHECK(seen.size() == r.report.iterations);  // 6 patches: every shot
}

TEST_CASE("an observer that cancels stops the solve at that report") {
    const Cube cube;
    std::size_t calls = 0;
    auto stop_at_3 = [&calls](const Progress& p) { return p.phase != "solve" || ++calls < 3; };
    const auto j = Jacobi(JacobiOptions{.tolerance = 1e-9}).solve(cube.system(), cube.F, stop_at_3);
    CHECK(j.report.cancelled);
    CHECK(j.report.iterations == 3);
    calls = 0;
    const auto p = Progressive(ProgressiveOptions{.tolerance = 1e-9, .report_every = 1})
                       .solve(cube.system(), cube.F, stop_at_3);
    CHECK(p.report.cancelled);
    CHECK(p.report.iterations == 3);
}
