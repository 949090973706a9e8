#pragma once
/// @file predicates.hpp  Exact geometric predicates on double-precision points: the orientation
/// of three points and whether a point lies inside the circle through three others. Each is
/// evaluated in floating point first and trusted when the result is larger than a bound on its
/// rounding error (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
/// geometric predicates", the A-stage bounds); only then is the determinant computed exactly, as
/// a floating-point expansion (a sum of non-overlapping doubles, Priest 1991, Shewchuk 1997).
/// Exact for any finite inputs whose products neither overflow nor underflow.

#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace radiosity {

namespace detail::exact {

/// x + y = a + b exactly, with x = fl(a + b) (Knuth 1969, "Two-Sum").
inline void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a, av = x - bv;
    y = (a - av) + (b - bv);
}

/// x + y = a * b exactly, with x = fl(a * b): by a fused multiply-add where the target has one,
/// else by Dekker's splitting of each factor into two 26-bit halves (Dekker 1971). (Where a
/// compiler could fuse the splitting's products, the target has an FMA, so the first is used.)
inline void two_product(double a, double b, double& x, double& y) {
    x = a * b;
#if defined(__FMA__) || defined(__aarch64__) || defined(__ARM_FEATURE_FMA)
    y = std::fma(a, b, -x);
#else
    auto split = [](double v, double& hi, double& lo) {
        const double c = 134217729.0 * v;  // 2^27 + 1
        hi = c - (c - v);
        lo = v - hi;
    };
    double ahi, alo, bhi, blo;
    split(a, ahi, alo);
    split(b, bhi, blo);
    y = alo * blo - (((x - ahi * bhi) - alo * bhi) - ahi * blo);
#endif
}

/// A number as a sum of at most N doubles, non-overlapping and in increasing magnitude, zeros
/// left out: its sign is the sign of its last (largest) component. On the stack, so that the
/// exact stage allocates nothing.
template <std::size_t N>
struct Expansion {
    std::array<double, N> c;
    std::size_t n = 0;
    void push(double x) {
        if (x != 0.0) c[n++] = x;
    }
    int sign() const { return n == 0 ? 0 : (c[n - 1] > 0.0) - (c[n - 1] < 0.0); }
};

/// e + f, exactly: the components of both merged by magnitude and summed with Two-Sum, each
/// rounding error kept as a component (Shewchuk 1997, Fast-Expansion-Sum with zero
/// elimination; it needs round-to-nearest-even arithmetic, as IEEE 754 doubles have).
template <std::size_t N, std::size_t M>
Expansion<N + M> sum(const Expansion<N>& e, const Expansion<M>& f) {
    Expansion<N + M> h;
    std::size_t i = 0, j = 0;
    auto take = [&] {
        return j == f.n || (i < e.n && std::abs(e.c[i]) < std::abs(f.c[j])) ? e.c[i++] : f.c[j++];
    };
    if (e.n + f.n == 0) return h;
    double q = take();
    while (i < e.n || j < f.n) {
        double r;
        two_sum(q, take(), q, r);
        h.push(r);
    }
    h.push(q);
    return h;
}

/// e * b, exactly (Shewchuk 1997, Scale-Expansion with zero elimination).
template <std::size_t N>
Expansion<2 * N> scale(const Expansion<N>& e, double b) {
    Expansion<2 * N> h;
    if (e.n == 0 || b == 0.0) return h;
    double q, r;
    two_product(e.c[0], b, q, r);
    h.push(r);
    for (std::size_t i = 1; i < e.n; ++i) {
        double t_hi, t_lo, s;
        two_product(e.c[i], b, t_hi, t_lo);
        two_sum(q, t_lo, s, r);
        h.push(r);
        q = t_hi + s;  // Fast-Two-Sum: |t_hi| >= |s|
        h.push(s - (q - t_hi));
    }
    h.push(q);
    return h;
}

/// e * f, exactly: the sum of e scaled by each component of f (at most 2 N M components).
template <std::size_t N, std::size_t M>
Expansion<2 * N * M> product(const Expansion<N>& e, const Expansion<M>& f) {
    Expansion<2 * N * M> p;
    for (std::size_t j = 0; j < f.n; ++j) {
        const Expansion<2 * N> s = scale(e, f.c[j]);
        const Expansion<2 * N* M + 2 * N> t = sum(p, s);
        std::copy(t.c.begin(), t.c.begin() + static_cast<std::ptrdiff_t>(t.n), p.c.begin());
        p.n = t.n;  // a product of N and M components never needs more than 2 N M
    }
    return p;
}

/// -e.
template <std::size_t N>
Expansion<N> negate(Expansion<N> e) {
    for (std::size_t i = 0; i < e.n; ++i) e.c[i] = -e.c[i];
    return e;
}

/// a - b as an expansion of at most two components.
inline Expansion<2> difference(double a, double b) {
    double x, y;
    two_sum(a, -b, x, y);
    Expansion<2> e;
    e.push(y);
    e.push(x);
    return e;
}

/// The orientation determinant computed exactly: the sum of its six products (the c_x c_y terms
/// cancel), each product exact as two doubles.
inline int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
    auto term = [](double u, double v) {
        double x, y;
        two_product(u, v, x, y);
        Expansion<2> p;
        p.push(y);
        p.push(x);
        return p;
    };
    const auto s1 = sum(term(a.x, b.y), term(-a.x, c.y));
    const auto s2 = sum(term(-c.x, b.y), term(-a.y, b.x));
    const auto s3 = sum(term(a.y, c.x), term(c.y, b.x));
    return sum(sum(s1, s2), s3).sign();
}

/// The in-circle determinant computed exactly, from the exact differences to d.
inline int incircle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const auto adx = difference(a.x, d.x), ady = difference(a.y, d.y);
    const auto bdx = difference(b.x, d.x), bdy = difference(b.y, d.y);
    const auto cdx = difference(c.x, d.x), cdy = difference(c.y, d.y);
    auto cross = [](const Expansion<2>& ux, const Expansion<2>& uy, const Expansion<2>& vx,
                    const Expansion<2>& vy) {
        return sum(product(ux, vy), negate(product(uy, vx)));
    };
    auto lift = [](const Expansion<2>& x, const Expansion<2>& y) {
        return sum(product(x, x), product(y, y));
    };
    const auto det = sum(sum(product(lift(adx, ady), cross(bdx, bdy, cdx, cdy)),
                             product(lift(bdx, bdy), cross(cdx, cdy, adx, ady))),
                         product(lift(cdx, cdy), cross(adx, ady, bdx, bdy)));
    return det.sign();
}

inline constexpr double epsilon = 0x1.0p-53;  // half an ulp of 1: the unit roundoff
/// Shewchuk's (1997) first-stage error bounds of the two determinants, relative to the
/// permanents (the same sums with every product taken in absolute value).
inline constexpr double orient_bound = (3.0 + 16.0 * epsilon) * epsilon;
inline constexpr double incircle_bound = (10.0 + 96.0 * epsilon) * epsilon;

}  // namespace detail::exact

/// Orientation of c against the directed line a -> b: +1 when a, b, c turn counter-clockwise
/// (c on the left), -1 clockwise, 0 when collinear; exact (see the file comment). Cost: a few
/// flops, an exact expansion only when the points are within rounding of collinear.
inline int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
    const double left = (a.x - c.x) * (b.y - c.y), right = (a.y - c.y) * (b.x - c.x);
    const double det = left - right;
    const double bound = detail::exact::orient_bound * (std::abs(left) + std::abs(right));
    if (det > bound) return 1;
    if (-det > bound) return -1;
    if (left == 0.0 && right == 0.0) return 0;  // both products exactly zero: so is det
    return detail::exact::orient2d(a, b, c);
}

namespace detail {
/// The in-circle determinant in floating point, with Shewchuk's bound on its error: +1 or -1
/// when its sign is certain, 0 when d is within rounding of the circle.
inline int incircle_filtered(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y;
    const double cdx = c.x - d.x, cdy = c.y - d.y;
    const double bc = bdx * cdy, cb = cdx * bdy, ca = cdx * ady, ac = adx * cdy;
    const double ab = adx * bdy, ba = bdx * ady;
    const double alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy;
    const double clift = cdx * cdx + cdy * cdy;
    const double det = alift * (bc - cb) + blift * (ca - ac) + clift * (ab - ba);
    const double permanent = (std::abs(bc) + std::abs(cb)) * alift +
                             (std::abs(ca) + std::abs(ac)) * blift +
                             (std::abs(ab) + std::abs(ba)) * clift;
    const double bound = exact::incircle_bound * permanent;
    return det > bound ? 1 : -det > bound ? -1 : 0;
}

/// The in-circle sign where floating point settles it from any of the four points as the origin
/// of the differences (the even permutations (a b c d), (b a d c), (c d a b), (d c b a) have one
/// determinant; their rounding bounds differ, most when one point lies far from the others);
/// 0 when none does.
inline int incircle_certain(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    if (const int s = incircle_filtered(a, b, c, d)) return s;
    if (const int s = incircle_filtered(b, a, d, c)) return s;
    if (const int s = incircle_filtered(c, d, a, b)) return s;
    return incircle_filtered(d, c, b, a);
}
}  // namespace detail

/// Whether d lies inside (+1), on (0) or outside (-1) the circle through a, b, c, which must be
/// counter-clockwise (Guibas & Stolfi 1985's InCircle); exact. Cost: a few dozen flops, an exact
/// expansion (some microseconds) only when d is within rounding of the circle.
inline int incircle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const int s = detail::incircle_certain(a, b, c, d);
    return s != 0 ? s : detail::exact::incircle(a, b, c, d);
}

}  // namespace radiosity
