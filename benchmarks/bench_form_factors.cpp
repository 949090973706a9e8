// Form-factor rows per second for each method at about 1k, 4k, 16k and 64k patches (a room with
// a block in it), and the hemicube at resolutions 64, 128 and 256 on about 1k patches. Rows are
// what every solver consumes, so rows per second (items_per_second, one thread) is a method's
// throughput; time per row against patch count shows how a row's cost grows with n. Last, the
// hemicube on a cluttered scene, RRV's room3 subdivided by area 1.0 (10,448 patches, many long
// thin triangles near each patch), when ../shared/rrv is there.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include "support/rooms.hpp"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

using namespace radiosity;

namespace {

/// Room of 6 k^2 + 6 (k/2)^2 patches, made once per k.
const PatchTable& room(int k) {
    static std::map<int, PatchTable> rooms;
    auto it = rooms.find(k);
    if (it == rooms.end()) it = rooms.emplace(k, bench::room_with_block(k)).first;
    return it->second;
}

/// Times rows of the method over the patches, from all over the scene.
template <class Method>
void rows_of(benchmark::State& state, Method method, const PatchTable& t) {
    method.prepare(t);
    std::vector<float> out(t.size());
    std::size_t i = 0;
    for (auto _ : state) {
        method.row(i, out);
        benchmark::DoNotOptimize(out.data());
        i = (i + 97) % t.size();  // rows from all over the room
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["patches"] = static_cast<double>(t.size());
}

template <class Method>
void rows(benchmark::State& state, Method method, int k) {
    rows_of(state, method, room(k));
}

void analytic_rows(benchmark::State& state) {
    rows(state, Analytic(), static_cast<int>(state.range(0)));
}
void ray_cast_rows(benchmark::State& state) {
    rows(state, RayCast(), static_cast<int>(state.range(0)));
}
void hemicube_rows(benchmark::State& state) {
    rows(state, Hemicube(), static_cast<int>(state.range(0)));
}
void hemicube_resolution(benchmark::State& state) {
    rows(state, Hemicube({static_cast<int>(state.range(0)), true}), 12);
}

/// RRV's room3 subdivided by area 1.0, as `radiosity room3.xml --divide 1` runs it; skipped
/// when the shared scenes are missing.
void hemicube_room3(benchmark::State& state) {
    const std::string path = std::string(RADIOSITY_SHARED_DIR) + "/rrv/room3.xml";
    if (!std::filesystem::exists(path)) {
        state.SkipWithError((path + " is missing").c_str());
        return;
    }
    static const PatchTable t =
        make_patch_table(subdivide(build_mesh(read_rrv<Rgb>(path)), {.max_area = 1.0}));
    rows_of(state, Hemicube(), t);
}

// k = 12, 24, 46, 92 give about 1.1k, 4.3k, 16k and 63k patches.
BENCHMARK(analytic_rows)->Arg(12)->Arg(24)->Arg(46)->Arg(92)->Unit(benchmark::kMillisecond);
BENCHMARK(ray_cast_rows)->Arg(12)->Arg(24)->Arg(46)->Arg(92)->Unit(benchmark::kMillisecond);
BENCHMARK(hemicube_rows)->Arg(12)->Arg(24)->Arg(46)->Arg(92)->Unit(benchmark::kMillisecond);
BENCHMARK(hemicube_resolution)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(hemicube_room3)->Unit(benchmark::kMillisecond);

}  // namespace
