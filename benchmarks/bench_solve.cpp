// End-to-end time of radiosity::solve on the built-in Cornell box at about 1k, 4k and 16k
// patches: subdivision, form factors (hemicube at its default resolution, and analytic at 1k),
// Gauss-Seidel. The patch count is reported as a counter.
#include <radiosity/radiosity.hpp>

#include <benchmark/benchmark.h>

namespace {

// Max edge lengths (mm) that give about 1k, 4k and 16k patches on the Cornell box.
constexpr double edge_1k = 34.0, edge_4k = 17.0, edge_16k = 8.5;

void solve_cornell(benchmark::State& state, double max_edge, radiosity::FormFactorKind method) {
    const auto scene = radiosity::build_mesh(radiosity::cornell_box<radiosity::Rgb>());
    radiosity::SolveOptions options;
    options.subdivision.max_edge = max_edge;
    options.form_factor = method;
    std::size_t patches = 0;
    for (auto _ : state) {
        const auto result = radiosity::solve(scene, options);
        patches = result.patches.size();
        benchmark::DoNotOptimize(result.report.residual);
    }
    state.counters["patches"] = static_cast<double>(patches);
}

}  // namespace

BENCHMARK_CAPTURE(solve_cornell, hemicube_1k, edge_1k, radiosity::FormFactorKind::hemicube)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, hemicube_4k, edge_4k, radiosity::FormFactorKind::hemicube)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, hemicube_16k, edge_16k, radiosity::FormFactorKind::hemicube)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(solve_cornell, analytic_1k, edge_1k, radiosity::FormFactorKind::analytic)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
