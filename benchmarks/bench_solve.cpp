// End-to-end time of radiosity::solve on the built-in Cornell box at about 1k, 4k and 16k
// patches, per form-factor method: subdivision, form factors (all cores), Gauss-Seidel to the
// default tolerance. The patch count is reported as a counter. The analytic and ray-cast runs
// stop at 4k patches (their cost grows as n^2 pairs; see bench_form_factors for rows at 64k).
// And RRV's room3 as `radiosity room3.xml --divide 1 --tolerance 0.01` solves it (RRV's own
// 9,680 patches, hemicube, Gauss-Seidel to 1%), skipped when the shared scenes are missing.
#include <radiosity/radiosity.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

namespace {

// Max edge lengths (mm) that give 1014, 3988 and 15290 patches on the Cornell box.
constexpr double edge_1k = 48.0, edge_4k = 23.0, edge_16k = 11.5;

/// Times radiosity::solve of the scene; reports the patches and the form factors' seconds.
template <class Mesh>
void time_solves(benchmark::State& state, const Mesh& scene,
                 const radiosity::SolveOptions& options) {
    std::size_t patches = 0;
    double form_factor_seconds = 0.0;
    for (auto _ : state) {
        const auto result = radiosity::solve(scene, options);
        patches = result.patches.size();
        form_factor_seconds = result.form_factor_seconds;
        benchmark::DoNotOptimize(result.report.residual);
    }
    state.counters["patches"] = static_cast<double>(patches);
    state.counters["form_factor_s"] = form_factor_seconds;
}

void solve_cornell(benchmark::State& state, double max_edge, radiosity::FormFactorKind method) {
    const auto scene = radiosity::build_mesh(radiosity::cornell_box<radiosity::Rgb>());
    radiosity::SolveOptions options;
    options.subdivision.max_edge = max_edge;
    options.form_factor = method;
    time_solves(state, scene, options);
}

void solve_room3(benchmark::State& state, bool conforming) {
    const std::string path = std::string(RADIOSITY_SHARED_DIR) + "/rrv/room3.xml";
    if (!std::filesystem::exists(path)) {
        state.SkipWithError((path + " is missing").c_str());
        return;
    }
    const auto scene = radiosity::build_mesh(radiosity::read_rrv<radiosity::Rgb>(path));
    radiosity::SolveOptions options;
    options.subdivision.max_area = 1.0;  // RRV's default divide
    options.subdivision.conforming = conforming;
    options.tolerance = 0.01;
    time_solves(state, scene, options);
}

using radiosity::FormFactorKind;

}  // namespace

BENCHMARK_CAPTURE(solve_room3, rrv_divide, false)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3);
BENCHMARK_CAPTURE(solve_room3, conforming, true)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3);

BENCHMARK_CAPTURE(solve_cornell, hemicube_1k, edge_1k, FormFactorKind::hemicube)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, hemicube_4k, edge_4k, FormFactorKind::hemicube)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, hemicube_16k, edge_16k, FormFactorKind::hemicube)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, analytic_1k, edge_1k, FormFactorKind::analytic)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, analytic_4k, edge_4k, FormFactorKind::analytic)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, ray_cast_1k, edge_1k, FormFactorKind::ray_cast)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, ray_cast_4k, edge_4k, FormFactorKind::ray_cast)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
