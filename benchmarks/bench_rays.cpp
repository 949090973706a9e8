// Occlusion rays through the library's BVH, the CPU side of benchmarks/gpu/rays.cu: the same
// triangles and the same segments (gpu/segments.hpp), so the two can be compared ray for ray.
//
//   bench_rays --write SCENE FILE   the faces of SCENE (an RRV .xml, an OBJ or a built-in scene,
//                                   cut as the program cuts them), fan-triangulated, written as
//                                   9 floats per triangle
//   bench_rays FILE [RAYS]          RAYS segments (default 4 Mi) through radiosity::Bvh with
//                                   OpenMP's threads: the median of 5 timed passes, rays per s
#include <radiosity/radiosity.hpp>

#include "gpu/segments.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

using radiosity::Rgb;
using radiosity::Vec3;

int write(const std::string& scene, const char* path) {
    const auto ends = [&](const char* x) {
        const std::string s(x);
        return scene.size() >= s.size() && scene.compare(scene.size() - s.size(), s.size(), s) == 0;
    };
    const auto mesh = ends(".xml")   ? radiosity::build_mesh(radiosity::read_rrv<Rgb>(scene))
                      : ends(".obj") ? radiosity::build_mesh(radiosity::read_obj<Rgb>(scene))
                                     : radiosity::build_mesh(radiosity::builtin_scene<Rgb>(scene));
    const auto meshed = radiosity::subdivide_with_report(mesh, radiosity::SubdivisionOptions{});
    const radiosity::PatchTable faces = radiosity::make_patch_table(meshed.mesh);
    FILE* f = std::fopen(path, "wb");
    if (!f) return 1;
    std::size_t count = 0;
    for (std::size_t p = 0; p < faces.size(); ++p) {
        const auto poly = faces.polygon(p);
        for (std::size_t k = 1; k + 1 < poly.size(); ++k, ++count)
            for (const Vec3& v : {poly[0], poly[k], poly[k + 1]}) {
                const float x[3] = {float(v.x), float(v.y), float(v.z)};
                std::fwrite(x, sizeof x, 1, f);
            }
    }
    std::fclose(f);
    std::printf("%zu triangles written to %s\n", count, path);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 4 && std::strcmp(argv[1], "--write") == 0) return write(argv[2], argv[3]);
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_rays --write SCENE FILE | bench_rays FILE [RAYS]\n");
        return 2;
    }
    const long rays = argc > 2 ? std::atol(argv[2]) : 4L << 20;
    const std::vector<float> tri = read_triangles(argv[1]);
    const int n = int(tri.size() / 9);
    radiosity::PatchTable table;
    for (int t = 0; t < n; ++t) {
        std::vector<Vec3> p;
        for (int c = 0; c < 3; ++c)
            p.emplace_back(tri[std::size_t(t) * 9 + c * 3], tri[std::size_t(t) * 9 + c * 3 + 1],
                           tri[std::size_t(t) * 9 + c * 3 + 2]);
        table.add(p, "triangle " + std::to_string(t));
    }
    const auto t0 = std::chrono::steady_clock::now();
    const radiosity::Bvh bvh(table);
    const double build_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<double> seconds;
    long blocked = 0;
    for (int run = 0; run < 6; ++run) {  // the first warms up
        long count = 0;
        const auto start = std::chrono::steady_clock::now();
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for reduction(+ : count) schedule(dynamic, 4096)
#endif
        for (long i = 0; i < rays; ++i) {
            float p[3], q[3];
            int a, b;
            segment(tri.data(), n, 1, std::uint64_t(i), p, q, a, b);
            count += bvh.occluded(Vec3(p[0], p[1], p[2]), Vec3(q[0], q[1], q[2]), std::uint32_t(a),
                                  std::uint32_t(b))
                         ? 1
                         : 0;
        }
        if (run > 0)
            seconds.push_back(
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        blocked = count;
    }
    std::sort(seconds.begin(), seconds.end());
    const double median = seconds[seconds.size() / 2];
    std::printf(
        "%d triangles, BVH built in %.2f s; %ld rays, %ld blocked (%.2f%%): median "
        "%.1f ms, %.1f million rays/s\n",
        n, build_s, rays, blocked, 100.0 * double(blocked) / double(rays), median * 1e3,
        double(rays) / median / 1e6);
    return 0;
}
