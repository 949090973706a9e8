// The triangles and the segments that benchmarks/gpu/rays.cu (on a GPU) and bench_rays_cpu (on
// the CPUs, through the library's BVH) cast alike: segment i joins a uniform point of one
// triangle to a uniform point of another, both picked and placed by a hash of (seed, i).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#if defined(__CUDACC__)
#define RAYS_HD __host__ __device__
#else
#define RAYS_HD
#endif

/// splitmix64 (Steele, Lea & Flood 2014): the hash behind every random number here.
RAYS_HD inline std::uint64_t rays_mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// A uniform float in [0, 1) from a hash.
RAYS_HD inline float rays_unit(std::uint64_t h) {
    return float(h >> 40) * (1.0f / 16777216.0f);
}

/// Segment i: from a point of triangle a to a point of triangle b (9 floats per triangle).
RAYS_HD inline void segment(const float* tri, int triangles, std::uint64_t seed, std::uint64_t i,
                            float p[3], float q[3], int& a, int& b) {
    std::uint64_t h = rays_mix(seed * 0x100000001b3ull ^ i);
    a = int((h >> 16) % std::uint64_t(triangles));
    h = rays_mix(h);
    b = int((h >> 16) % std::uint64_t(triangles));
    for (int end = 0; end < 2; ++end) {
        const float* v = &tri[std::size_t(end ? b : a) * 9];
        h = rays_mix(h);
        const float s = std::sqrt(rays_unit(h));
        h = rays_mix(h);
        const float t = rays_unit(h);
        float* x = end ? q : p;
        for (int k = 0; k < 3; ++k)
            x[k] = (1.0f - s) * v[k] + s * (1.0f - t) * v[3 + k] + s * t * v[6 + k];
    }
}

/// The triangles of a file of 9 floats each.
inline std::vector<float> read_triangles(const char* path) {
    std::vector<float> tri;
    if (FILE* f = std::fopen(path, "rb")) {
        float buf[9];
        while (std::fread(buf, sizeof buf, 1, f) == 1) tri.insert(tri.end(), buf, buf + 9);
        std::fclose(f);
    }
    if (tri.empty()) {
        std::fprintf(stderr, "%s: no triangles\n", path);
        std::exit(1);
    }
    return tri;
}
