// Occlusion rays per second, one thread, in a cluttered room of about 100k triangles: the
// library's BVH and (when configured with RADIOSITY_WITH_EMBREE) Embree 3 on the same rays.
// Also the BVH's build time. Rays join random points on random patches, as form factors do.
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/sampling.hpp>
#if defined(RADIOSITY_WITH_EMBREE)
#include <radiosity/geometry/embree.hpp>
#endif

#include "support/rooms.hpp"

#include <benchmark/benchmark.h>

#include <vector>

using namespace radiosity;

namespace {

/// 18 x 18 blocks of 5 x 5 patches per face plus 40 x 40 walls: about 107k triangles.
const PatchTable& scene() {
    static const PatchTable t = bench::cluttered_room(18, 5, 40);
    return t;
}

struct Segment {
    Vec3 p, q;
    std::uint32_t a, b;
};

/// 65536 segments between the centroids (jittered) of random patch pairs, seeded.
const std::vector<Segment>& segments() {
    static const std::vector<Segment> s = [] {
        const PatchTable& t = scene();
        Rng rng(42);
        std::vector<Segment> out;
        std::vector<Vec3> xs, ys;
        while (out.size() < 65536) {
            const auto a = static_cast<std::size_t>(rng.uniform() * double(t.size()));
            const auto b = static_cast<std::size_t>(rng.uniform() * double(t.size()));
            if (a == b) continue;
            jittered_pairs(t.polygon(a), t.polygon(b), 1, rng, xs, ys);
            out.push_back({xs[0], ys[0], std::uint32_t(a), std::uint32_t(b)});
        }
        return out;
    }();
    return s;
}

template <class V>
void occlusion_rays(benchmark::State& state, const V& visibility) {
    const auto& rays = segments();
    std::size_t k = 0, blocked = 0;
    for (auto _ : state) {
        const Segment& s = rays[k++ & (rays.size() - 1)];
        blocked += visibility.occluded(s.p, s.q, s.a, s.b);
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["triangles"] = 0.0;
    state.counters["blocked_share"] = double(blocked) / double(state.iterations());
}

void bvh_occlusion(benchmark::State& state) {
    static const Bvh bvh(scene());
    occlusion_rays(state, bvh);
    state.counters["triangles"] = static_cast<double>(bvh.triangle_count());
}

void bvh_build(benchmark::State& state) {
    for (auto _ : state) {
        Bvh bvh(scene());
        benchmark::DoNotOptimize(bvh.node_count());
    }
}

#if defined(RADIOSITY_WITH_EMBREE)
void embree_occlusion(benchmark::State& state) {
    static const EmbreeVisibility embree(scene());
    occlusion_rays(state, embree);
}
BENCHMARK(embree_occlusion);
#endif

BENCHMARK(bvh_occlusion);
BENCHMARK(bvh_build)->Unit(benchmark::kMillisecond);

}  // namespace
