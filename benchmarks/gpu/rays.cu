// What a GPU does with the visibility rays that dominate the hierarchical solve and the ray-cast
// form factors: occlusion queries (any hit) of segments between random points of the scene's
// triangles, through a plain binary BVH, one CUDA thread a ray. Not built by CMake (CI has no
// GPU and Debian no CUDA); build and run it where nvcc and a GPU are:
//
//   nvcc -O3 -std=c++17 -arch=native benchmarks/gpu/rays.cu -o rays
//   ./rays TRIANGLES.bin [RAYS]
//
// TRIANGLES.bin: 9 floats per triangle (what bench_rays_cpu --write writes). The segments are
// drawn from a seeded hash of the ray's index, the same way as bench_rays_cpu draws them, so the
// two count the same blocked rays. Prints the build time, and the median of 5 timed launches.
#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "segments.hpp"

namespace {

struct Node {  // 32 bytes: box, then first child (inner) or first triangle (leaf)
    float lo[3];
    int left_or_first;
    float hi[3];
    int count;  // 0: inner node (children left_or_first, left_or_first + 1)
};

struct Builder {
    const std::vector<float>& tri;
    std::vector<int> order;
    std::vector<Node> nodes;
    float centre(int t, int axis) const {
        const float* v = &tri[size_t(t) * 9];
        return (v[axis] + v[3 + axis] + v[6 + axis]) / 3.0f;
    }
    // Node id over order[b, e): median split along the longest axis of the centroids' box
    // (two children side by side), leaves of at most 4.
    void build(int id, int b, int e) {
        Node n{};
        for (int k = 0; k < 3; ++k) n.lo[k] = 1e30f, n.hi[k] = -1e30f;
        float clo[3] = {1e30f, 1e30f, 1e30f}, chi[3] = {-1e30f, -1e30f, -1e30f};
        for (int i = b; i < e; ++i) {
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) {
                    const float x = tri[size_t(order[i]) * 9 + c * 3 + k];
                    n.lo[k] = std::min(n.lo[k], x), n.hi[k] = std::max(n.hi[k], x);
                }
            for (int k = 0; k < 3; ++k)
                clo[k] = std::min(clo[k], centre(order[i], k)),
                chi[k] = std::max(chi[k], centre(order[i], k));
        }
        if (e - b <= 4) {
            n.left_or_first = b, n.count = e - b;
            nodes[id] = n;
            return;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
        const int mid = (b + e) / 2;
        std::nth_element(order.begin() + b, order.begin() + mid, order.begin() + e,
                         [&](int x, int y) { return centre(x, axis) < centre(y, axis); });
        const int left = int(nodes.size());
        nodes.resize(nodes.size() + 2);
        n.left_or_first = left, n.count = 0;
        nodes[id] = n;
        build(left, b, mid);
        build(left + 1, mid, e);
    }
};

__device__ bool slab(const Node& n, const float3 o, const float3 inv, float tmax) {
    float t0 = 0.0f, t1 = tmax;
    const float lo[3] = {n.lo[0], n.lo[1], n.lo[2]}, hi[3] = {n.hi[0], n.hi[1], n.hi[2]};
    const float oo[3] = {o.x, o.y, o.z}, ii[3] = {inv.x, inv.y, inv.z};
#pragma unroll
    for (int k = 0; k < 3; ++k) {
        float a = (lo[k] - oo[k]) * ii[k], b = (hi[k] - oo[k]) * ii[k];
        t0 = fmaxf(t0, fminf(a, b));
        t1 = fminf(t1, fmaxf(a, b));
    }
    return t0 <= t1;
}

// Moller & Trumbore 1997, t in (t0, t1) along the segment's direction d (t = 1 at its end).
__device__ bool hit(const float* v, const float3 o, const float3 d, float t0, float t1) {
    const float3 e1 = make_float3(v[3] - v[0], v[4] - v[1], v[5] - v[2]);
    const float3 e2 = make_float3(v[6] - v[0], v[7] - v[1], v[8] - v[2]);
    const float3 p =
        make_float3(d.y * e2.z - d.z * e2.y, d.z * e2.x - d.x * e2.z, d.x * e2.y - d.y * e2.x);
    const float det = e1.x * p.x + e1.y * p.y + e1.z * p.z;
    if (fabsf(det) < 1e-20f) return false;
    const float inv = 1.0f / det;
    const float3 s = make_float3(o.x - v[0], o.y - v[1], o.z - v[2]);
    const float u = (s.x * p.x + s.y * p.y + s.z * p.z) * inv;
    if (u < 0.0f || u > 1.0f) return false;
    const float3 q =
        make_float3(s.y * e1.z - s.z * e1.y, s.z * e1.x - s.x * e1.z, s.x * e1.y - s.y * e1.x);
    const float w = (d.x * q.x + d.y * q.y + d.z * q.z) * inv;
    if (w < 0.0f || u + w > 1.0f) return false;
    const float t = (e2.x * q.x + e2.y * q.y + e2.z * q.z) * inv;
    return t > t0 && t < t1;
}

__global__ void occlusion(const Node* nodes, const float* tri, const int* order, int triangles,
                          long rays, std::uint64_t seed, unsigned* blocked) {
    const long i = long(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= rays) return;
    float p[3], q[3];
    int a, b;
    segment(tri, triangles, seed, std::uint64_t(i), p, q, a, b);
    const float3 o = make_float3(p[0], p[1], p[2]);
    const float3 d = make_float3(q[0] - p[0], q[1] - p[1], q[2] - p[2]);
    const float3 inv = make_float3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
    int stack[64], top = 0;
    stack[top++] = 0;
    bool any = false;
    while (top > 0 && !any) {
        const Node n = nodes[stack[--top]];
        if (!slab(n, o, inv, 1.0f)) continue;
        if (n.count > 0) {
            for (int k = 0; k < n.count && !any; ++k) {
                const int t = order[n.left_or_first + k];
                if (t != a && t != b) any = hit(&tri[size_t(t) * 9], o, d, 1e-4f, 1.0f - 1e-4f);
            }
        } else {
            stack[top++] = n.left_or_first;
            stack[top++] = n.left_or_first + 1;
        }
    }
    if (any) atomicAdd(blocked, 1u);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: rays TRIANGLES.bin [RAYS]\n");
        return 2;
    }
    const long rays = argc > 2 ? std::atol(argv[2]) : 16L << 20;
    std::vector<float> tri = read_triangles(argv[1]);
    const int n = int(tri.size() / 9);
    const auto t0 = std::chrono::steady_clock::now();
    Builder b{tri, std::vector<int>(n), {}};
    for (int i = 0; i < n; ++i) b.order[i] = i;
    b.nodes.reserve(size_t(n) * 2);
    b.nodes.resize(1);
    b.build(0, 0, n);
    const double build_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Node* d_nodes;
    float* d_tri;
    int* d_order;
    unsigned* d_blocked;
    cudaMalloc(&d_nodes, b.nodes.size() * sizeof(Node));
    cudaMalloc(&d_tri, tri.size() * sizeof(float));
    cudaMalloc(&d_order, b.order.size() * sizeof(int));
    cudaMalloc(&d_blocked, sizeof(unsigned));
    cudaMemcpy(d_nodes, b.nodes.data(), b.nodes.size() * sizeof(Node), cudaMemcpyHostToDevice);
    cudaMemcpy(d_tri, tri.data(), tri.size() * sizeof(float), cudaMemcpyHostToDevice);
    cudaMemcpy(d_order, b.order.data(), b.order.size() * sizeof(int), cudaMemcpyHostToDevice);
    std::vector<float> ms;
    unsigned blocked = 0;
    for (int run = 0; run < 6; ++run) {  // the first warms up
        cudaMemset(d_blocked, 0, sizeof(unsigned));
        cudaEvent_t start, stop;
        cudaEventCreate(&start), cudaEventCreate(&stop);
        cudaEventRecord(start);
        occlusion<<<unsigned((rays + 255) / 256), 256>>>(d_nodes, d_tri, d_order, n, rays, 1,
                                                         d_blocked);
        cudaEventRecord(stop);
        cudaEventSynchronize(stop);
        float t = 0.0f;
        cudaEventElapsedTime(&t, start, stop);
        if (run > 0) ms.push_back(t);
        cudaMemcpy(&blocked, d_blocked, sizeof(unsigned), cudaMemcpyDeviceToHost);
    }
    const cudaError_t err = cudaGetLastError();
    if (err != cudaSuccess) {
        std::fprintf(stderr, "CUDA: %s\n", cudaGetErrorString(err));
        return 1;
    }
    std::sort(ms.begin(), ms.end());
    cudaDeviceProp prop;
    cudaGetDeviceProperties(&prop, 0);
    std::printf("%s: %d triangles, BVH of %zu nodes built in %.2f s (host, one thread)\n",
                prop.name, n, b.nodes.size(), build_s);
    std::printf("%ld rays, %u blocked (%.2f%%): median %.2f ms, %.0f million rays/s\n", rays,
                blocked, 100.0 * blocked / double(rays), ms[ms.size() / 2],
                rays / (ms[ms.size() / 2] * 1e-3) / 1e6);
    return 0;
}
