// Time per solve of each solver on a physical form-factor matrix: the unit room with a block
// (bench::room_with_block, hemicube form factors) at about 1k and 4k patches, grey reflectance
// 0.7 with one emitting patch, to a relative tolerance of 1e-6. The direct LU solve runs at 1k
// only (O(n^3)). Gauss-Seidel also runs at about 10k patches (a 413 MB matrix: its sweeps are
// bound by memory), on all threads and on one, as the sweep over dense rows is shared among
// threads. Form factors are computed once per size, outside the timing.
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include "support/rooms.hpp"

#include <benchmark/benchmark.h>

#include <map>

#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif

using namespace radiosity;

namespace {

struct Problem {
    PatchTable patches;
    DenseMatrix F;
    std::vector<float> E, R;
};

/// The room of k x k walls with its hemicube matrix, made once per k.
const Problem& problem(int k) {
    static std::map<int, Problem> cache;
    auto it = cache.find(k);
    if (it == cache.end()) {
        Problem p{bench::room_with_block(k), {}, {}, {}};
        Hemicube method;
        method.prepare(p.patches);
        p.F = assemble_dense(method, p.patches.size());
        p.E.assign(p.patches.size(), 0.0f);
        p.E[p.patches.size() / 2] = 100.0f;
        p.R.assign(p.patches.size(), 0.7f);
        it = cache.emplace(k, std::move(p)).first;
    }
    return it->second;
}

template <class Solver>
void solve(benchmark::State& state, const Solver& solver) {
    const Problem& p = problem(static_cast<int>(state.range(0)));
    const System<float> system{p.E, p.R, p.patches.areas()};
    std::size_t iterations = 0;
    for (auto _ : state) {
        const auto s = solver.solve(system, p.F);
        iterations = s.report.iterations;
        benchmark::DoNotOptimize(s.radiosity.data());
    }
    state.counters["patches"] = static_cast<double>(p.patches.size());
    state.counters["iterations"] = static_cast<double>(iterations);
}

void jacobi(benchmark::State& s) {
    solve(s, Jacobi({1e-6, 10000}));
}
void gauss_seidel(benchmark::State& s) {
    solve(s, GaussSeidel({1e-6, 10000}));
}
void gauss_seidel_one_thread(benchmark::State& s) {
#if defined(RADIOSITY_WITH_OPENMP)
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    solve(s, GaussSeidel({1e-6, 10000}));
    omp_set_num_threads(before);
#else
    solve(s, GaussSeidel({1e-6, 10000}));
#endif
}
void progressive(benchmark::State& s) {
    solve(s, Progressive({1e-6, 0, 0, false}));
}
void direct(benchmark::State& s) {
    solve(s, Direct());
}

}  // namespace

// k = 12, 24 and 37: 1134, 4350 and about 10k patches.
BENCHMARK(jacobi)->Arg(12)->Arg(24)->Unit(benchmark::kMillisecond);
BENCHMARK(gauss_seidel)->Arg(12)->Arg(24)->Arg(37)->Unit(benchmark::kMillisecond);
BENCHMARK(gauss_seidel_one_thread)->Arg(37)->Unit(benchmark::kMillisecond);
BENCHMARK(progressive)->Arg(12)->Arg(24)->Unit(benchmark::kMillisecond);
BENCHMARK(direct)->Arg(12)->Unit(benchmark::kMillisecond);
