#pragma once
// Benchmark scenes made directly as patch tables: a closed room whose walls are k x k grids,
// optionally with blocks standing in it (occluders), so every form-factor method and the BVH can
// be timed at any patch count without the rest of the pipeline.
#include <radiosity/geometry/patch_table.hpp>

#include <algorithm>
#include <vector>

namespace bench {

using radiosity::Vec3;

/// Adds the six faces of the box [lo, hi], each a g x g grid, facing inwards (a room) or
/// outwards (a block).
inline void add_box(radiosity::PatchTable& t, const Vec3& lo, const Vec3& hi, int g, bool inwards) {
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            for (int u = 0; u < g; ++u)
                for (int v = 0; v < g; ++v) {
                    auto at = [&](double s, double r) {
                        Vec3 p;
                        p[axis] = side ? hi[axis] : lo[axis];
                        p[a1] = lo[a1] + (hi[a1] - lo[a1]) * s / g;
                        p[a2] = lo[a2] + (hi[a2] - lo[a2]) * r / g;
                        return p;
                    };
                    std::vector<Vec3> q{at(u, v), at(u + 1, v), at(u + 1, v + 1), at(u, v + 1)};
                    if ((side == 0) != inwards) std::reverse(q.begin(), q.end());
                    t.add(q);
                }
        }
}

/// A unit room (walls k x k) with one block in it (faces k/2 x k/2): 6 k^2 + 6 (k/2)^2 patches.
inline radiosity::PatchTable room_with_block(int k) {
    radiosity::PatchTable t;
    add_box(t, Vec3(0.0), Vec3(1.0), k, true);
    add_box(t, Vec3(0.3, 0.0, 0.35), Vec3(0.6, 0.55, 0.65), std::max(1, k / 2), false);
    return t;
}

/// A room cluttered with an n x n array of blocks on the floor, each face a g x g grid: about
/// 12 (g^2 n^2 + k^2) triangles. Used to time rays in a scene of realistic depth complexity.
inline radiosity::PatchTable cluttered_room(int n, int g, int k) {
    radiosity::PatchTable t;
    add_box(t, Vec3(0.0), Vec3(1.0), k, true);
    const double cell = 1.0 / n;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const double h = 0.1 + 0.5 * ((a * 7 + b * 13) % 10) / 10.0;  // varied heights
            add_box(t, Vec3(a * cell + 0.2 * cell, 0.0, b * cell + 0.2 * cell),
                    Vec3(a * cell + 0.8 * cell, h, b * cell + 0.8 * cell), g, false);
        }
    return t;
}

}  // namespace bench
