#pragma once
/// @file triangle.hpp  The ray-triangle tests of the BVH: the watertight test in double
/// precision (Woop, Benthin & Wald 2013), the exact answer; and a single-precision filter that
/// tests four triangles at once with a proven error bound, so that only the triangles it cannot
/// decide go to the exact test and answers stay exactly the exact test's. Also the exact skip of
/// triangles lying in an axis plane that contains the ray.

#include <radiosity/detail/float4.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

namespace radiosity {

/// The part of a segment at each end, relative to its length, that occlusion queries leave out
/// (an open segment): a ray between two patches leaves them rather than crossing them, and a
/// hit within this of an end is the patch itself or its edge.
inline constexpr double segment_margin = 1e-9;

/// A ray direction prepared for the watertight ray-triangle test (Woop, Benthin & Wald 2013):
/// the axis kz along which the direction is largest, and the shear (sx, sy, sz) that maps the
/// ray onto the z axis of a frame (kx, ky, kz) with the winding kept. O(1), once per ray.
struct ShearedRay {
    int kx, ky, kz;
    double sx, sy, sz;
    explicit ShearedRay(const Vec3& dir) {
        const Vec3 a = glm::abs(dir);
        const double* d = glm::value_ptr(dir);
        kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (d[kz] < 0.0) std::swap(kx, ky);  // keep the winding
        sx = d[kx] / d[kz];
        sy = d[ky] / d[kz];
        sz = 1.0 / d[kz];
    }
};

/// The watertight ray-triangle test (Woop, Benthin & Wald 2013) in double precision: shear the
/// triangle into the ray's frame, where the ray is the z axis, and test the signs of the 2-D edge
/// functions U, V, W. Edges shared by two triangles give the same edge function with opposite
/// sign, so a ray through an edge hits at least one of them: rays never slip through a mesh.
/// On a hit with t0 < t < t1 (hit point o + t d), sets t and the barycentrics u, v of vertices 1
/// and 2. Cost: O(1), about 30 multiplications.
inline bool hit_triangle(const PatchTriangle& tri, const Vec3& o, const ShearedRay& r, double t0,
                         double t1, double& t, double& u, double& v) {
    const Vec3 dA = tri.v[0] - o, dB = tri.v[1] - o, dC = tri.v[2] - o;
    const double *A = glm::value_ptr(dA), *B = glm::value_ptr(dB), *C = glm::value_ptr(dC);
    const double ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
    const double bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
    const double cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
    const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
    const double det = U + V + W;
    if (det == 0.0) return false;
    const double T = r.sz * (U * A[r.kz] + V * B[r.kz] + W * C[r.kz]);
    t = T / det;
    if (!(t > t0 && t < t1)) return false;
    u = V / det;
    v = W / det;
    return true;
}

namespace detail {

/// The plane x_axis = at in which a triangle lies, if it lies in one (all three vertices
/// with exactly that coordinate; axis 3 if none). A ray with d_axis = 0 and o_axis = at
/// lies in that plane, and the watertight test then surely misses: in its sheared frame
/// every vertex projects to exactly 0 (or NaN) along the axis, so U, V and W are all zero
/// (det = 0) or NaN (t = NaN). Lets the search skip these without the double test.
struct AxisPlane {
    double at = 0.0;
    std::uint32_t axis = 3;
    static AxisPlane of(const PatchTriangle& t) {
        for (std::uint32_t a = 0; a < 3; ++a)
            if (t.v[0][a] == t.v[1][a] && t.v[0][a] == t.v[2][a]) return {t.v[0][a], a};
        return {};
    }
    /// Whether the ray from o lies in this plane; bit a of `flat` is set where the ray's
    /// direction has d_a = 0.
    bool contains_ray(const Vec3& o, unsigned flat) const {
        return axis < 3 && ((flat >> axis) & 1u) != 0 && at == glm::value_ptr(o)[axis];
    }
};

/// Four consecutive triangles in single precision, lane by lane (v[4 * (3 * vertex + axis) +
/// lane]) with their patches: what the SIMD filter of the triangle test reads. One flat
/// array, so that the filter reaches a vertex's row from its axis's row by a constant
/// offset (12 floats), which frees registers. 160 bytes.
struct alignas(16) TriangleBlock {
    std::array<float, 36> v{};
    std::array<std::uint32_t, 4> patch{};
    void set(std::size_t lane, const PatchTriangle& t) {
        for (std::size_t i = 0; i < 3; ++i)
            for (std::size_t a = 0; a < 3; ++a)
                v[4 * (3 * i + a) + lane] = static_cast<float>(glm::value_ptr(t.v[i])[a]);
        patch[lane] = t.patch;
    }
};

/// What the SIMD filter of the triangle test needs of a ray, in single precision: the
/// origin, the shear of ShearedRay, the error bound, and the range of t in which every
/// vertex must lie for a sure hit (see candidates).
struct FilterRay {
    // The origin's coordinates along the sheared frame's axes kx, ky, kz, and those axes'
    // offsets into TriangleBlock::v.
    Float4 ox, oy, oz, sx, sy, sz, bound_scale, bound_floor, t_low, t_high;
    std::size_t fx, fy, fz;
    /// R is scene scale + |origin|.
    FilterRay(const Vec3& o, const ShearedRay& r, double R, double t0, double t1)
        : fx(4 * static_cast<std::size_t>(r.kx)),
          fy(4 * static_cast<std::size_t>(r.ky)),
          fz(4 * static_cast<std::size_t>(r.kz)) {
        ox = Float4::splat(static_cast<float>(glm::value_ptr(o)[r.kx]));
        oy = Float4::splat(static_cast<float>(glm::value_ptr(o)[r.ky]));
        oz = Float4::splat(static_cast<float>(glm::value_ptr(o)[r.kz]));
        sx = Float4::splat(static_cast<float>(r.sx));
        sy = Float4::splat(static_cast<float>(r.sy));
        // R bounds every coordinate of vertices and origin. Far outside float's comfortable
        // range the bound below could fail (overflow, subnormals, NaN): then reject nothing
        // and prove nothing. Within it, every value in candidates is finite.
        const bool sane =
            R > 1e-15 && R < 1e15 && std::abs(r.sz) < 1e30 && std::isfinite(r.sx + r.sy);
        const double inf = std::numeric_limits<double>::infinity();
        bound_scale = Float4::splat(static_cast<float>(sane ? 0x1p-18 * R : inf));
        bound_floor = Float4::splat(static_cast<float>(0x1p-16 * R));
        sz = Float4::splat(static_cast<float>(r.sz));
        const double margin = 0x1p-20 * (R * std::abs(r.sz) + 1.0);
        t_low = Float4::splat(static_cast<float>(sane ? t0 + margin : inf));
        t_high = Float4::splat(static_cast<float>(t1 - margin));
    }
};

/// Lanes of a block: those the exact test might hit, and those it surely hits.
struct Lanes {
    unsigned maybe, sure;
};

/// Which triangles of a block the exact (double) test might hit, and which it surely hits:
/// Woop's sheared edge functions U, V, W for four triangles at once in single precision.
/// A triangle is rejected only when one edge function is surely negative and another surely
/// positive, i.e. beyond the rounding error; it is surely hit when all three are surely of
/// one sign and the t of each vertex (the hit's t is their convex combination) lies surely
/// inside (t0, t1). With u = 2^-24 and R a bound on every coordinate of vertices and
/// origin, each sheared coordinate (ax ... cy) is off by at most 16 u R after rounding
/// vertices, origin, shear and arithmetic, and is at most 4R; so U is off by at most
/// 24 u R M + 512 u^2 R^2, where M is the sum of the six magnitudes. The bound used,
/// 64 u R (M + 2^-16 R), is more than twice that even with M taken from the rounded values.
/// A vertex's t is off by at most 4 u R |sz| + 2.1 u; the margin used is 16 u (R |sz| + 1).
/// So the filter never contradicts the double test, and answers are exactly its answers.
inline Lanes candidates(const TriangleBlock& b, const FilterRay& r) {
    std::array<Float4, 3> px, py, t;
    const float *row_x = b.v.data() + r.fx, *row_y = b.v.data() + r.fy, *row_z = b.v.data() + r.fz;
    for (std::size_t i = 0; i < 3; ++i) {
        const Float4 x = Float4::load(row_x + 12 * i) - r.ox;
        const Float4 y = Float4::load(row_y + 12 * i) - r.oy;
        const Float4 z = Float4::load(row_z + 12 * i) - r.oz;
        px[i] = x - r.sx * z;
        py[i] = y - r.sy * z;
        t[i] = z * r.sz;
    }
    const Float4 U = px[2] * py[1] - py[2] * px[1];
    const Float4 V = px[0] * py[2] - py[0] * px[2];
    const Float4 W = px[1] * py[0] - py[1] * px[0];
    const Float4 M =
        vabs(px[0]) + vabs(py[0]) + vabs(px[1]) + vabs(py[1]) + vabs(px[2]) + vabs(py[2]);
    const Float4 bound = r.bound_scale * (M + r.bound_floor);
    const Float4 minus = Float4::splat(0.0f) - bound;
    // Only the smallest and largest of U, V, W matter (and of the vertices' t). No NaN can
    // arise while the filter is on (see FilterRay), so min / max drop none; while it is off,
    // the bound is +inf or NaN and every lane is a candidate, none sure.
    const Float4 low = vmin(vmin(U, V), W), high = vmax(vmax(U, V), W);
    const int some_negative = less_mask(low, minus), some_positive = less_mask(bound, high);
    const int all_one_sign = less_mask(bound, low) | less_mask(high, minus);
    const int inside = less_mask(r.t_low, vmin(vmin(t[0], t[1]), t[2])) &
                       less_mask(vmax(vmax(t[0], t[1]), t[2]), r.t_high);
    return {static_cast<unsigned>(~(some_negative & some_positive)) & 15u,
            static_cast<unsigned>(all_one_sign & inside)};
}

}  // namespace detail

}  // namespace radiosity
