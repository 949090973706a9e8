#pragma once
/// @file float4.hpp  Four floats processed together, for the BVH's four-at-once slab and
/// triangle tests: SSE2 where the compiler targets it (every x86-64 build), a plain array
/// otherwise. Both paths give bit-identical results, so answers do not depend on the build.

#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#else
#include <array>
#endif

namespace radiosity::detail {

/// Four floats with the few lane-wise operations the BVH needs (SSE2 or scalar).
/// vmin and vmax return their second argument where either argument is NaN, exactly as SSE's
/// minps / maxps do: the slab test relies on it to ignore a NaN slab distance.
struct Float4 {
#if defined(__SSE2__)
    __m128 v;
    /// Four floats from a 16-byte aligned address.
    static Float4 load(const float* p) {
        return {_mm_load_ps(p)};
    }
    /// One float in every lane.
    static Float4 splat(float x) {
        return {_mm_set1_ps(x)};
    }
    /// Stores the lanes to a 16-byte aligned address.
    void store(float* p) const {
        _mm_store_ps(p, v);
    }
    friend Float4 operator+(Float4 a, Float4 b) {
        return {_mm_add_ps(a.v, b.v)};
    }
    friend Float4 operator-(Float4 a, Float4 b) {
        return {_mm_sub_ps(a.v, b.v)};
    }
    friend Float4 operator*(Float4 a, Float4 b) {
        return {_mm_mul_ps(a.v, b.v)};
    }
    /// Lane-wise a < b ? a : b (b where either is NaN).
    friend Float4 vmin(Float4 a, Float4 b) {
        return {_mm_min_ps(a.v, b.v)};
    }
    /// Lane-wise a > b ? a : b (b where either is NaN).
    friend Float4 vmax(Float4 a, Float4 b) {
        return {_mm_max_ps(a.v, b.v)};
    }
    /// Lane-wise |a| (the sign bit cleared). An and with 0x7fffffff rather than an and-not
    /// with -0.0f: the and can read its mask straight from memory, the and-not overwrites it.
    friend Float4 vabs(Float4 a) {
        return {_mm_and_ps(a.v, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)))};
    }
    /// Lane-wise a <= b ? c : a.
    friend Float4 where_at_most(Float4 a, Float4 b, Float4 c) {
        const __m128 m = _mm_cmple_ps(a.v, b.v);
        return {_mm_or_ps(_mm_and_ps(m, c.v), _mm_andnot_ps(m, a.v))};
    }
    /// Bit k set where a[k] <= b[k] (clear where either is NaN).
    friend int less_equal_mask(Float4 a, Float4 b) {
        return _mm_movemask_ps(_mm_cmple_ps(a.v, b.v));
    }
    /// Bit k set where a[k] < b[k] (clear where either is NaN).
    friend int less_mask(Float4 a, Float4 b) {
        return _mm_movemask_ps(_mm_cmplt_ps(a.v, b.v));
    }
#else
    std::array<float, 4> v;
    /// Four floats from an address.
    static Float4 load(const float* p) {
        return {{p[0], p[1], p[2], p[3]}};
    }
    /// One float in every lane.
    static Float4 splat(float x) {
        return {{x, x, x, x}};
    }
    /// Stores the lanes.
    void store(float* p) const {
        for (int k = 0; k < 4; ++k) p[k] = v[k];
    }
    friend Float4 operator+(Float4 a, Float4 b) {
        return lanes(a, b, [](float x, float y) { return x + y; });
    }
    friend Float4 operator-(Float4 a, Float4 b) {
        return lanes(a, b, [](float x, float y) { return x - y; });
    }
    friend Float4 operator*(Float4 a, Float4 b) {
        return lanes(a, b, [](float x, float y) { return x * y; });
    }
    /// Lane-wise a < b ? a : b (b where either is NaN).
    friend Float4 vmin(Float4 a, Float4 b) {
        return lanes(a, b, [](float x, float y) { return x < y ? x : y; });
    }
    /// Lane-wise a > b ? a : b (b where either is NaN).
    friend Float4 vmax(Float4 a, Float4 b) {
        return lanes(a, b, [](float x, float y) { return x > y ? x : y; });
    }
    /// Lane-wise |a| (the sign bit cleared).
    friend Float4 vabs(Float4 a) {
        return lanes(a, a, [](float x, float) { return std::fabs(x); });
    }
    /// Lane-wise a <= b ? c : a.
    friend Float4 where_at_most(Float4 a, Float4 b, Float4 c) {
        Float4 r = a;
        for (int k = 0; k < 4; ++k) r.v[k] = a.v[k] <= b.v[k] ? c.v[k] : a.v[k];
        return r;
    }
    /// Bit k set where a[k] <= b[k] (clear where either is NaN).
    friend int less_equal_mask(Float4 a, Float4 b) {
        int mask = 0;
        for (int k = 0; k < 4; ++k) mask |= (a.v[k] <= b.v[k] ? 1 : 0) << k;
        return mask;
    }
    /// Bit k set where a[k] < b[k] (clear where either is NaN).
    friend int less_mask(Float4 a, Float4 b) {
        int mask = 0;
        for (int k = 0; k < 4; ++k) mask |= (a.v[k] < b.v[k] ? 1 : 0) << k;
        return mask;
    }

  private:
    template <class Op>
    static Float4 lanes(Float4 a, Float4 b, Op op) {
        return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
    }
#endif
};

}  // namespace radiosity::detail
