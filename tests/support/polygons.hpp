// Seeded random simple polygons for the meshing tests: convex ones, star-shaped ones, histograms
// (concave, with collinear runs where neighbouring bars are as high), extra points along edges
// (exactly or nearly collinear runs), and ways to put them into space.
#pragma once

#include <radiosity/geometry/sampling.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace test_polygons {

using radiosity::Rng;
using radiosity::Vec2;
using radiosity::Vec3;

/// n points on an ellipse at sorted random angles: strictly convex.
inline std::vector<Vec2> convex(Rng& rng, int n) {
    std::vector<double> angle(static_cast<std::size_t>(n));
    for (double& a : angle) a = 2.0 * std::numbers::pi * rng.uniform();
    std::sort(angle.begin(), angle.end());
    const double a = 0.5 + rng.uniform(), b = 0.5 + rng.uniform();
    std::vector<Vec2> p;
    for (double t : angle) p.emplace_back(a * std::cos(t), b * std::sin(t));
    return p;
}

/// n points at random angles, one in each of n equal sectors (so no gap reaches 180 degrees),
/// and random radii in [r_min, 1]: star-shaped about 0 (n >= 5).
inline std::vector<Vec2> star(Rng& rng, int n, double r_min) {
    std::vector<double> angle(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < angle.size(); ++k)
        angle[k] = 2.0 * std::numbers::pi * (double(k) + rng.uniform()) / double(n);
    std::vector<Vec2> p;
    for (double t : angle) {
        const double r = r_min + (1.0 - r_min) * rng.uniform();
        p.emplace_back(r * std::cos(t), r * std::sin(t));
    }
    return p;
}

/// A histogram of `bars` bars of width 1 and heights 1..4 (whole numbers, so neighbouring bars
/// are often as high: their shared corner is a straight one): concave, axis-aligned.
inline std::vector<Vec2> histogram(Rng& rng, int bars) {
    std::vector<double> h(static_cast<std::size_t>(bars));
    for (double& x : h) x = 1.0 + std::floor(4.0 * rng.uniform());
    std::vector<Vec2> p{{0.0, 0.0}, {double(bars), 0.0}};
    auto add = [&](double x, double y) {  // equal neighbours share a corner: a straight one
        if (p.back() != Vec2(x, y)) p.emplace_back(x, y);
    };
    for (int i = bars - 1; i >= 0; --i) {
        add(double(i + 1), h[static_cast<std::size_t>(i)]);
        add(double(i), h[static_cast<std::size_t>(i)]);
    }
    return p;
}

/// Adds `extra` points along random edges, at random fractions, moved off the edge by at most
/// `wobble` of its length (0: on it, up to rounding): runs of (nearly) collinear corners.
inline std::vector<Vec2> with_runs(Rng& rng, std::vector<Vec2> p, int extra, double wobble) {
    for (int k = 0; k < extra; ++k) {
        const auto i = static_cast<std::size_t>(rng.uniform() * double(p.size()));
        const Vec2 a = p[i], b = p[(i + 1) % p.size()], d = b - a;
        const Vec2 normal(-d.y, d.x);
        const double t = 0.2 + 0.6 * rng.uniform(), s = wobble * (2.0 * rng.uniform() - 1.0);
        p.insert(p.begin() + static_cast<std::ptrdiff_t>(i + 1), a + t * d + s * normal);
    }
    return p;
}

/// The regular n-gon of radius 1 (a disk of area close to pi).
inline std::vector<Vec2> disk(int n) {
    std::vector<Vec2> p;
    for (int k = 0; k < n; ++k) {
        const double t = 2.0 * std::numbers::pi * k / n;
        p.emplace_back(std::cos(t), std::sin(t));
    }
    return p;
}

/// Twice the signed area of a 2-D polygon.
inline double area2(const std::vector<Vec2>& p) {
    double a = 0.0;
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
        a += radiosity::cross2(p[k] - p[0], p[k + 1] - p[0]);
    return a;
}

/// A placement in space: point (x, y) goes to origin + x u + y v.
struct Placement {
    Vec3 origin, u, v;
    Vec3 at(const Vec2& q) const { return origin + q.x * u + q.y * v; }
};

/// A random rotation and offset (the plane is no coordinate plane).
inline Placement random_placement(Rng& rng) {
    const double a = 2.0 * std::numbers::pi * rng.uniform(), b = std::acos(2.0 * rng.uniform() - 1);
    const Vec3 n(std::sin(b) * std::cos(a), std::sin(b) * std::sin(a), std::cos(b));
    Vec3 u, v;
    radiosity::orthonormal_basis(n, u, v);
    return {Vec3(10.0 * rng.uniform() - 5.0, 10.0 * rng.uniform() - 5.0, 3.0 * rng.uniform()), u,
            v};
}

/// A scene of one polygon.
inline radiosity::Scene<float> one_face(const std::vector<Vec2>& p, const Placement& at) {
    radiosity::Scene<float> s;
    std::vector<std::uint32_t> f;
    for (const Vec2& q : p) {
        f.push_back(static_cast<std::uint32_t>(s.positions.size()));
        s.positions.push_back(at.at(q));
    }
    s.faces = {f};
    s.face_material = {0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    return s;
}

/// A closed prism: the polygon as its bottom (facing down), the polygon raised by `height` as its
/// top, and one quad per edge as its sides; faces share no vertex indices (welding joins them).
inline radiosity::Scene<float> prism(const std::vector<Vec2>& p, double height) {
    radiosity::Scene<float> s;
    auto add = [&](const Vec3& x) {
        s.positions.push_back(x);
        return static_cast<std::uint32_t>(s.positions.size() - 1);
    };
    std::vector<std::uint32_t> bottom, top;
    for (std::size_t k = p.size(); k-- > 0;) bottom.push_back(add({p[k].x, p[k].y, 0.0}));
    for (const Vec2& q : p) top.push_back(add({q.x, q.y, height}));
    s.faces = {bottom, top};
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec2 a = p[k], b = p[(k + 1) % p.size()];
        s.faces.push_back({add({a.x, a.y, 0.0}), add({b.x, b.y, 0.0}), add({b.x, b.y, height}),
                           add({a.x, a.y, height})});
    }
    s.face_material.assign(s.faces.size(), 0);
    s.materials = {{0.0f, 0.5f, "grey"}};
    return s;
}

}  // namespace test_polygons
