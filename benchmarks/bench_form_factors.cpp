// Form-factor rows per second: the analytic method and the hemicube at 64, 128 and 256, on a
// closed room (the unit cube, each face a k x k grid of patches) of about 1k patches. Rows are
// what every solver consumes, so rows per second is the method's throughput; items_per_second
// in the output is rows per second on one thread.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

using namespace radiosity;

namespace {

/// The unit cube, faces pointing inwards, each face a k x k grid: 6 k^2 patches.
PatchTable gridded_cube(int k) {
    PatchTable t;
    const double h = 1.0 / k;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (int a = 0; a < k; ++a)
                for (int b = 0; b < k; ++b) {
                    auto point = [&](double s, double r) {
                        Vec3 p(0.0);
                        p[axis] = side;
                        p[(axis + 1) % 3] = s;
                        p[(axis + 2) % 3] = r;
                        return p;
                    };
                    std::vector<Vec3> q{point(a * h, b * h), point((a + 1) * h, b * h),
                                        point((a + 1) * h, (b + 1) * h), point(a * h, (b + 1) * h)};
                    if (side == 1) std::reverse(q.begin(), q.end());  // keep normals inwards
                    t.add(q);
                }
    return t;
}

const PatchTable& room() {
    static const PatchTable t = gridded_cube(13);  // 1014 patches
    return t;
}

template <class Method>
void rows(benchmark::State& state, Method method) {
    const PatchTable& t = room();
    method.prepare(t);
    std::vector<float> out(t.size());
    std::size_t i = 0;
    for (auto _ : state) {
        method.row(i, out);
        benchmark::DoNotOptimize(out.data());
        i = (i + 97) % t.size();  // visit rows all over the room
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["patches"] = static_cast<double>(t.size());
}

void analytic_rows(benchmark::State& state) {
    rows(state, Analytic());
}
void hemicube_rows(benchmark::State& state) {
    rows(state, Hemicube({static_cast<int>(state.range(0)), true}));
}

}  // namespace

BENCHMARK(analytic_rows)->Unit(benchmark::kMillisecond);
BENCHMARK(hemicube_rows)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
