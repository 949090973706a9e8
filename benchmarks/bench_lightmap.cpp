// Lightmap baking on the built-in Cornell box. bake_texels: the bake alone (conservative UV
// rasterisation, 16 inside-geometry rays per texel, refill, dilation) of one solved, shaded box
// into 256^2 ... 2048^2 lightmaps; its counter "Mtexels/s" is the rate (1 / that = seconds per
// million texels). bake_pipeline: the whole radiosity::bake (UVs, subdivision to 4 texels per
// patch, hemicube solve, shading, bake) at 256^2 and 512^2, with the time in each phase and the
// solve's share as counters.
#include <radiosity/radiosity.hpp>

#include <benchmark/benchmark.h>

namespace {

using radiosity::Rgb;

/// The Cornell box solved and shaded once, with lightmap UVs (normalised, so they serve every
/// lightmap size).
const radiosity::BakeResult<Rgb>& solved_box() {
    static const radiosity::BakeResult<Rgb> baked = [] {
        radiosity::LightmapOptions o;
        o.unwrap.size = 512;
        return radiosity::bake(radiosity::build_mesh(radiosity::cornell_box<Rgb>()),
                               radiosity::SolveOptions{}, o);
    }();
    return baked;
}

void bake_texels(benchmark::State& state) {
    const auto& box = solved_box();
    const int size = static_cast<int>(state.range(0));
    radiosity::Lightmap lm;
    for (auto _ : state) {
        lm = radiosity::bake_lightmap(box.shaded, size, size);
        benchmark::DoNotOptimize(lm.image.pixels.data());
    }
    // Counted once, outside the timed loop.
    const std::size_t covered =
        lm.count(radiosity::TexelState::surface) + lm.count(radiosity::TexelState::inside);
    const double texels = double(size) * size;
    state.counters["Mtexels/s"] =
        benchmark::Counter(texels * 1e-6 * double(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["covered"] = double(covered);
}

void bake_pipeline(benchmark::State& state) {
    const auto scene = radiosity::build_mesh(radiosity::cornell_box<Rgb>());
    radiosity::LightmapOptions o;
    o.unwrap.size = static_cast<int>(state.range(0));
    double unwrap = 0.0, solve = 0.0, bake = 0.0;
    std::size_t patches = 0;
    for (auto _ : state) {
        const auto r = radiosity::bake(scene, radiosity::SolveOptions{}, o);
        unwrap = r.unwrap_seconds;
        solve = r.solve_seconds;
        bake = r.bake_seconds;
        patches = r.solution.patches.size();
    }
    state.counters["patches"] = double(patches);
    state.counters["unwrap_s"] = unwrap;
    state.counters["solve_s"] = solve;
    state.counters["bake_s"] = bake;
    state.counters["solve_share"] = solve / (unwrap + solve + bake);
}

}  // namespace

BENCHMARK(bake_texels)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK(bake_pipeline)->Arg(256)->Arg(512)->Unit(benchmark::kSecond)->Iterations(1);
