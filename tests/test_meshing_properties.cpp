// Property tests of the meshing: random simple polygons (convex, star-shaped, histograms with
// collinear corners, extra points along edges, seeded), placed at random in space and meshed at
// random settings. Each time: the patches cover the polygon's area (to 1e-9 of it), no patch
// reaches outside it, every patch is convex and faces its way, neighbours conform (every patch
// edge is shared by matching vertices or lies on the polygon's boundary), patches stay within
// 2 x 2 grid cells, and no patch is a sliver beyond the bound stated below. Closed prisms of
// such polygons and quads stay closed (polygons and quads conform along shared edges).
//
// Quality (measured; the bound is what these polygons meet): a patch's thinness is its
// diameter^2 / area (2 for a square, 2.31 for an equilateral triangle). A polygon's own corners
// limit it: a patch in a corner of angle a has thinness at least about 2 / sin a. Bound: 24 /
// sin(min(sharpest corner, 90 degrees)). Every patch of convex polygons, histograms and
// polygons with collinear runs meets it. Of star-shaped polygons (edges in every direction next
// to reflex corners) a few patches do not: wedges where an edge leaves a reflex corner that a
// grid line passes through, at a small angle to the line (no convex union with a neighbour
// exists there); they are asserted to be rare (under 0.5 % of the patches), small (under a
// quarter of a cell each), together under 2 % of the polygon's area, and within 4 times the
// bound (the thinnest measured: 3.4 times; every patch of every polygon meets that).
#include "support/polygons.hpp"

#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

using namespace radiosity;
using namespace test_polygons;

namespace {

/// The polygon in its own plane, and distances on it.
struct Outline {
    std::vector<Vec2> p;
    double size = 0.0;  // diagonal of its box

    explicit Outline(std::vector<Vec2> q) : p(std::move(q)) {
        Vec2 lo(p[0]), hi(p[0]);
        for (const Vec2& x : p) {
            lo = glm::min(lo, x);
            hi = glm::max(hi, x);
        }
        size = glm::length(hi - lo);
    }
    /// Distance from x to the segment of edge k.
    double to_edge(const Vec2& x, std::size_t k) const {
        const Vec2 a = p[k], b = p[(k + 1) % p.size()], d = b - a;
        const double t = std::clamp(glm::dot(x - a, d) / glm::dot(d, d), 0.0, 1.0);
        return glm::length(x - (a + t * d));
    }
    double to_boundary(const Vec2& x) const {
        double d = std::numeric_limits<double>::max();
        for (std::size_t k = 0; k < p.size(); ++k) d = std::min(d, to_edge(x, k));
        return d;
    }
    /// Winding number, in plain floating point (the test does not use the library's).
    bool inside(const Vec2& x) const {
        int w = 0;
        for (std::size_t k = 0; k < p.size(); ++k) {
            const Vec2 a = p[k], b = p[(k + 1) % p.size()];
            const double side = cross2(b - a, x - a);
            if (a.y <= x.y && b.y > x.y && side > 0) ++w;
            if (a.y > x.y && b.y <= x.y && side < 0) --w;
        }
        return w != 0;
    }
};

struct Measured {
    double area = 0.0, worst_aspect = 0.0, longest = 0.0, largest = 0.0;
    std::size_t patches = 0;
    std::vector<std::pair<double, double>> thin;  // thinness and area of each patch
};

/// The sharpest corner of a polygon (its smallest interior angle), in radians.
double sharpest_corner(const std::vector<Vec2>& p) {
    double a = std::numbers::pi;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec2 u = p[k] - p[(k + p.size() - 1) % p.size()], v = p[(k + 1) % p.size()] - p[k];
        a = std::min(a, std::numbers::pi - std::atan2(cross2(u, v), glm::dot(u, v)));
    }
    return a;
}

/// Checks one meshed polygon (see the file comment) and measures it.
Measured check_patches(const Mesh<float>& sub, const Outline& poly, const Placement& at) {
    Measured m;
    const double tol = 1e-9 * poly.size;
    auto flat = [&](const Mesh<float>::Point& x) {
        const Vec3 d = Vec3(x[0], x[1], x[2]) - at.origin;
        CHECK(std::abs(glm::dot(d, glm::cross(at.u, at.v))) <= tol);  // in the plane
        return Vec2(glm::dot(d, at.u), glm::dot(d, at.v));
    };
    for (auto f : sub.faces()) {
        std::vector<Vec2> q;
        for (auto v : sub.fv_range(f)) q.push_back(flat(sub.point(v)));
        const double a = 0.5 * area2(q);
        REQUIRE(a > 0.0);  // faces the polygon's way
        m.area += a;
        ++m.patches;
        Vec2 c(0.0);
        double d = 0.0;
        for (std::size_t k = 0; k < q.size(); ++k) {
            const Vec2 prev = q[(k + q.size() - 1) % q.size()], next = q[(k + 1) % q.size()];
            // Convex: no corner turns right by more than rounding.
            CHECK(cross2(q[k] - prev, next - q[k]) >=
                  -1e-9 * glm::length(q[k] - prev) * glm::length(next - q[k]));
            // No corner outside the polygon.
            CHECK((poly.inside(q[k]) || poly.to_boundary(q[k]) <= tol));
            for (const Vec2& r : q) d = std::max(d, glm::length(r - q[k]));
            m.longest = std::max(m.longest, glm::length(next - q[k]));
        }
        for (std::size_t k = 1; k + 1 < q.size(); ++k)
            c += cross2(q[k] - q[0], q[k + 1] - q[0]) * (q[0] + q[k] + q[k + 1]) / 3.0;
        c /= 2.0 * a;
        CHECK(poly.inside(c));  // the centroid inside: not in a notch
        m.worst_aspect = std::max(m.worst_aspect, d * d / a);
        m.largest = std::max(m.largest, a);
        m.thin.push_back({d * d / a, a});
    }
    // Conforming: an edge of only one patch lies on the polygon's boundary (both its ends on
    // one edge of the polygon); a T-junction inside would leave such an edge off it.
    for (auto e : sub.edges()) {
        if (!sub.is_boundary(e)) continue;
        const auto h = sub.halfedge_handle(e, 0);
        const Vec2 a = flat(sub.point(sub.from_vertex_handle(h))),
                   b = flat(sub.point(sub.to_vertex_handle(h)));
        bool on = false;
        for (std::size_t k = 0; k < poly.p.size() && !on; ++k)
            on = poly.to_edge(a, k) <= tol && poly.to_edge(b, k) <= tol;
        CHECK(on);
    }
    return m;
}

std::vector<Vec2> random_polygon(Rng& rng, int family) {
    switch (family) {
        case 0:
            return convex(rng, 3 + static_cast<int>(60 * rng.uniform()));
        case 1:
            return star(rng, 5 + static_cast<int>(60 * rng.uniform()), 0.3);
        case 2:
            return histogram(rng, 2 + static_cast<int>(8 * rng.uniform()));
        default:
            return with_runs(rng, rng.uniform() < 0.5 ? convex(rng, 6) : histogram(rng, 4),
                             1 + static_cast<int>(10 * rng.uniform()),
                             rng.uniform() < 0.5 ? 0.0 : 1e-10);
    }
}

const char* family_name(int family) {
    static const char* names[] = {"convex", "star-shaped", "histogram", "collinear runs"};
    return names[family];
}

}  // namespace

TEST_CASE("random polygons at random settings: area kept, nothing outside, convex, conforming") {
    Rng rng(20240612);
    std::size_t patches[4] = {}, beyond[4] = {};
    double worst[4] = {};
    for (int trial = 0; trial < 400; ++trial) {
        const int family = trial % 4;
        const Outline poly(random_polygon(rng, family));
        const Placement at = random_placement(rng);
        SubdivisionOptions o;
        const double r = rng.uniform();
        if (r < 0.1) {
            // none: convex pieces only
        } else if (r < 0.8) {
            o.max_edge = poly.size * (0.03 + 0.4 * rng.uniform());
        } else {
            o.max_area = poly.size * poly.size * (0.001 + 0.05 * rng.uniform());
        }
        o.conforming = rng.uniform() < 0.8;
        CAPTURE(trial);
        const std::string family_text = family_name(family);
        CAPTURE(family_text);
        CAPTURE(poly.p.size());
        CAPTURE(o.max_edge);
        CAPTURE(o.max_area);
        const Subdivided<float> sub = subdivide_with_report(build_mesh(one_face(poly.p, at)), o);
        const Measured m = check_patches(sub.mesh, poly, at);
        const double area = 0.5 * area2(poly.p);
        CHECK(std::abs(m.area - area) <= 1e-9 * area);
        CHECK(sub.report.dropped_faces.empty());
        // Within 2 x 2 cells of the grid (its inner lines moved by at most a tenth of a cell
        // onto corners): cells no wider than max_edge, of no more than max_area.
        if (o.max_edge > 0.0) CHECK(m.longest <= 2.2 * std::sqrt(2.0) * o.max_edge * (1 + 1e-9));
        if (o.max_area > 0.0) CHECK(m.largest <= 2.2 * 2.2 * o.max_area * (1 + 1e-9));
        const double bound =
            24.0 / std::sin(std::min(sharpest_corner(poly.p), std::numbers::pi / 2));
        const double cell = o.max_edge > 0.0   ? o.max_edge * o.max_edge
                            : o.max_area > 0.0 ? o.max_area
                                               : area;
        double thin_area = 0.0;
        for (const auto& [thinness, a] : m.thin) {
            worst[family] = std::max(worst[family], thinness / bound);
            if (thinness <= bound) continue;
            ++beyond[family];
            thin_area += a;
            CHECK(family == 1);  // stars only (see the file comment)
            CHECK(a < 0.25 * cell);
            CHECK(thinness <= 4.0 * bound);  // no patch of any polygon beyond this
        }
        CHECK(thin_area < 0.02 * area);
        patches[family] += m.patches;
    }
    for (int f = 0; f < 4; ++f)
        MESSAGE(std::string(family_name(f))
                << ": " << patches[f] << " patches, " << beyond[f]
                << " beyond the thinness bound; the thinnest at " << worst[f] << " of it");
    CHECK(double(beyond[1]) < 0.005 * double(patches[1]));
}

TEST_CASE("closed prisms of random polygons stay closed: polygons and quads conform") {
    Rng rng(7);
    for (int trial = 0; trial < 60; ++trial) {
        const int family = trial % 4;
        const std::vector<Vec2> p = random_polygon(rng, family);
        const double height = 0.2 + rng.uniform();
        SubdivisionOptions o;
        o.max_edge = 0.05 + 0.3 * rng.uniform();
        CAPTURE(trial);
        const std::string family_text = family_name(family);
        CAPTURE(family_text);
        const Subdivided<float> sub = subdivide_with_report(build_mesh(prism(p, height)), o);
        std::size_t open = 0;
        for (auto e : sub.mesh.edges()) open += sub.mesh.is_boundary(e);
        CHECK(open == 0);  // no crack, no T-junction
        const auto V = static_cast<long>(sub.mesh.n_vertices()),
                   E = static_cast<long>(sub.mesh.n_edges()),
                   F = static_cast<long>(sub.mesh.n_faces());
        CHECK(V - E + F == 2);
        double perimeter = 0.0, total = 0.0;
        for (std::size_t k = 0; k < p.size(); ++k)
            perimeter += glm::length(p[(k + 1) % p.size()] - p[k]);
        for (auto f : sub.mesh.faces()) total += polygon_area(face_polygon(sub.mesh, f));
        const double expected = area2(p) + perimeter * height;
        CHECK(std::abs(total - expected) <= 1e-9 * expected);
    }
}
