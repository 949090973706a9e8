// The exact predicates against integer arithmetic, and the constrained Delaunay triangulation
// and its convex pieces against their definitions: triangles that cover the polygon exactly,
// every boundary edge an edge, every free edge locally Delaunay; convex pieces, at most 2r + 1
// of them for r reflex corners (Hertel & Mehlhorn's bound); crossing boundaries refused.
#include "support/approx.hpp"
#include "support/polygons.hpp"

#include <radiosity/geometry/convex_partition.hpp>
#include <radiosity/geometry/predicates.hpp>
#include <radiosity/geometry/triangulate.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>

using namespace radiosity;
using namespace test_polygons;

namespace {

__extension__ typedef __int128 i128;  // GCC and clang; __extension__: not ISO C++

/// An integer of at most `bits` bits, as a double (exact).
double integer(Rng& rng, int bits) {
    const auto span = std::uint64_t{1} << bits;
    return static_cast<double>(static_cast<std::int64_t>(rng.next() % span) -
                               static_cast<std::int64_t>(span / 2));
}

int sign(i128 x) {
    return (x > 0) - (x < 0);
}

int orient_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
    auto I = [](double x) { return static_cast<i128>(x); };
    return sign((I(a.x) - I(c.x)) * (I(b.y) - I(c.y)) - (I(a.y) - I(c.y)) * (I(b.x) - I(c.x)));
}

int incircle_exact(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    auto I = [](double x) { return static_cast<i128>(x); };
    const i128 adx = I(a.x) - I(d.x), ady = I(a.y) - I(d.y), bdx = I(b.x) - I(d.x),
               bdy = I(b.y) - I(d.y), cdx = I(c.x) - I(d.x), cdy = I(c.y) - I(d.y);
    return sign((adx * adx + ady * ady) * (bdx * cdy - bdy * cdx) +
                (bdx * bdx + bdy * bdy) * (cdx * ady - cdy * adx) +
                (cdx * cdx + cdy * cdy) * (adx * bdy - ady * bdx));
}

TriangulationInput loop_of(const std::vector<Vec2>& p) {
    TriangulationInput in;
    in.points = p;
    in.loops.emplace_back();
    for (std::uint32_t k = 0; k < p.size(); ++k) in.loops[0].push_back(k);
    return in;
}

double triangle_area2(const Triangulation& t, std::size_t k) {
    const auto& v = t.triangles[k];
    return cross2(t.points[v[1]] - t.points[v[0]], t.points[v[2]] - t.points[v[0]]);
}

/// Checks a triangulation of one loop p: covers its area, positive triangles, each boundary edge
/// present once, free edges locally Delaunay (exactly), neighbours consistent.
void check_triangulation(const Triangulation& t, const std::vector<Vec2>& p) {
    double area = 0.0;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> edge;
    for (std::size_t k = 0; k < t.triangles.size(); ++k) {
        const auto& v = t.triangles[k];
        CHECK(orient2d(t.points[v[0]], t.points[v[1]], t.points[v[2]]) > 0);
        area += triangle_area2(t, k);
        for (int j = 0; j < 3; ++j) ++edge[{v[j], v[(j + 1) % 3]}];
    }
    CHECK(area == test::approx(area2(p)).epsilon(1e-12));
    for (std::uint32_t k = 0; k < p.size(); ++k)
        CHECK(edge[{k, static_cast<std::uint32_t>((k + 1) % p.size())}] == 1);
    for (std::size_t k = 0; k < t.triangles.size(); ++k)
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t u = t.neighbours[k][j];
            const auto& v = t.triangles[k];
            if (u == Triangulation::none) {
                CHECK(t.kinds[k][j] == EdgeKind::boundary);
                continue;
            }
            const auto& w = t.triangles[u];
            std::uint32_t far = Triangulation::none;  // w's corner off the shared edge
            for (std::uint32_t x : w)
                if (x != v[j] && x != v[(j + 1) % 3]) far = x;
            REQUIRE(far != Triangulation::none);
            if (t.kinds[k][j] != EdgeKind::free) continue;
            const Vec2 &a = t.points[v[0]], &b = t.points[v[1]], &c = t.points[v[2]],
                       &d = t.points[far];
            CHECK(incircle(a, b, c, d) <= 0);
        }
}

int reflex_corners(const std::vector<Vec2>& p) {
    int r = 0;
    for (std::size_t k = 0; k < p.size(); ++k)
        r += orient2d(p[(k + p.size() - 1) % p.size()], p[k], p[(k + 1) % p.size()]) < 0;
    return r;
}

}  // namespace

TEST_CASE("orient2d and incircle are exact: integer cases checked in 128-bit arithmetic") {
    Rng rng(5);
    int zero_orient = 0, zero_circle = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        // Near-collinear: c on the line a b (rounded to integers), moved by at most one unit.
        const Vec2 a(integer(rng, 40), integer(rng, 40)), d(integer(rng, 20), integer(rng, 20));
        const double t = std::floor(8.0 * rng.uniform());
        const Vec2 c =
            a + t * d + Vec2(std::floor(3 * rng.uniform()) - 1, std::floor(3 * rng.uniform()) - 1);
        const Vec2 b = a + d;
        CHECK(orient2d(a, b, c) == orient_exact(a, b, c));
        zero_orient += orient_exact(a, b, c) == 0;
        // Near-cocircular: four points of a circle of radius 5 m (3-4-5 triangles), one moved by
        // at most one unit.
        const double m = std::floor(1e5 * rng.uniform()) + 1.0;
        const Vec2 o(integer(rng, 20), integer(rng, 20));
        const Vec2 p = o + Vec2(3 * m, 4 * m), q = o + Vec2(-4 * m, 3 * m), r = o + Vec2(-5 * m, 0),
                   s = o + Vec2(0, -5 * m) +
                       Vec2(std::floor(3 * rng.uniform()) - 1, std::floor(3 * rng.uniform()) - 1);
        CHECK(incircle(p, q, r, s) == incircle_exact(p, q, r, s));
        zero_circle += incircle_exact(p, q, r, s) == 0;
    }
    CHECK(zero_orient > 1000);  // the degenerate cases were really reached
    CHECK(zero_circle > 1000);
    // Off the line through a and b by one unit in the last place of c.y: the sign is still right.
    const Vec2 a(0.5, 0.5), b(12.0, 12.0), c(24.0, 24.0 + 0x1p-48);
    CHECK(orient2d(a, b, c) == 1);
    CHECK(orient2d(a, c, b) == -1);
}

TEST_CASE("constrained Delaunay triangulation of random polygons: exact cover, Delaunay edges") {
    Rng rng(11);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Vec2> p;
        switch (trial % 4) {
            case 0:
                p = convex(rng, 3 + static_cast<int>(100 * rng.uniform()));
                break;
            case 1:
                p = star(rng, 5 + static_cast<int>(100 * rng.uniform()), 0.2);
                break;
            case 2:
                p = histogram(rng, 2 + static_cast<int>(12 * rng.uniform()));
                break;
            default:
                p = with_runs(rng, histogram(rng, 5), 20, trial % 8 == 3 ? 0.0 : 1e-11);
        }
        CAPTURE(trial);
        const Triangulation t = triangulate(loop_of(p));
        CHECK(t.triangles.size() == p.size() - 2);
        CHECK(t.points.size() == p.size());
        check_triangulation(t, p);
    }
}

TEST_CASE("a 10,000-gon: 9,998 triangles covering it, every free edge Delaunay") {
    const std::vector<Vec2> p = disk(10000);
    const Triangulation t = triangulate(loop_of(p));
    CHECK(t.triangles.size() == 9998);
    check_triangulation(t, p);
}

TEST_CASE("holes and cuts: holes left out, cuts become edges, crossing cuts split") {
    TriangulationInput in;
    in.points = {{0, 0},     {4, 0},     {4, 4},     {0, 4},     {1, 1},     {1, 3},
                 {3, 3},     {3, 1},  // hole: clockwise
                 {0.5, 0.5}, {3.5, 3.5}, {3.5, 0.5}, {0.5, 3.5}, {0.2, 2.0}, {0.8, 2.0}};
    in.loops = {{0, 1, 2, 3}, {4, 5, 6, 7}};
    in.cuts = {{8, 10}, {10, 9}, {12, 13}, {8, 11}};
    const Triangulation t = triangulate(in, "test");
    double area = 0.0;
    for (std::size_t k = 0; k < t.triangles.size(); ++k) area += 0.5 * triangle_area2(t, k);
    CHECK(area == test::approx(16.0 - 4.0).epsilon(1e-14));
    // Cut 8 - 11 (x = 0.5) crosses cut 12 - 13 (y = 2): one new point, where they cross.
    REQUIRE(t.points.size() == in.points.size() + 1);
    CHECK(t.points.back().x == test::approx(0.5));
    CHECK(t.points.back().y == test::approx(2.0));
    const auto x = static_cast<std::uint32_t>(t.points.size() - 1);
    std::set<std::pair<std::uint32_t, std::uint32_t>> cut;
    for (std::size_t k = 0; k < t.triangles.size(); ++k)
        for (int j = 0; j < 3; ++j)
            if (t.kinds[k][j] == EdgeKind::cut)
                cut.insert(std::minmax(t.triangles[k][j], t.triangles[k][(j + 1) % 3]));
    for (auto e : std::vector<std::pair<std::uint32_t, std::uint32_t>>{
             {8, 10}, {9, 10}, {8, x}, {11, x}, {12, x}, {13, x}})
        CHECK(cut.count(e) == 1);
}

TEST_CASE("polygons that cross, touch or overlap themselves are refused, naming the edges") {
    auto refused = [](std::vector<Vec2> p, const char* why) {
        CAPTURE(why);
        std::string message;
        try {
            triangulate(loop_of(p), "scene.obj:7: face 3");
        } catch (const Error& e) {
            message = e.what();
        }
        CHECK(message.rfind("scene.obj:7: face 3: ", 0) == 0);
        CHECK(message.find(why) != std::string::npos);
    };
    refused({{0, 0}, {1, 0}, {0, 1}, {1, 1}}, "intersects itself");       // bow-tie
    refused({{0, 0}, {2, 0}, {1, 0}, {1, 1}}, "touches itself");          // spike back
    refused({{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}, "touches itself");  // corner on an edge
    refused({{0, 0}, {2, 0}, {1, 1}, {2, 2}, {0, 2}, {1, 1}}, "touches itself");  // pinched
    refused({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, -1}, {2, -1}, {2, 2}, {0, 2}},
            "intersects itself");  // a loop through itself
}

TEST_CASE("Hertel-Mehlhorn pieces: convex, covering, at most 2r + 1 for r reflex corners") {
    Rng rng(3);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Vec2> p;
        switch (trial % 3) {
            case 0:
                p = convex(rng, 3 + static_cast<int>(60 * rng.uniform()));
                break;
            case 1:
                p = star(rng, 5 + static_cast<int>(60 * rng.uniform()), 0.2);
                break;
            default:
                p = with_runs(rng, histogram(rng, 2 + static_cast<int>(10 * rng.uniform())), 5,
                              0.0);
        }
        CAPTURE(trial);
        const Triangulation t = triangulate(loop_of(p));
        const ConvexPartition c = convex_partition(t);
        double area = 0.0;
        std::vector<int> used(t.triangles.size(), 0);
        for (std::size_t k = 0; k < c.pieces.size(); ++k) {
            const auto& q = c.pieces[k];
            for (std::size_t j = 0; j < q.size(); ++j) {
                const Vec2 &a = t.points[q[(j + q.size() - 1) % q.size()]], &x = t.points[q[j]],
                           &b = t.points[q[(j + 1) % q.size()]];
                CHECK(orient2d(a, x, b) >= 0);  // convex (straight corners allowed)
                area += cross2(x - t.points[q[0]], b - t.points[q[0]]);
            }
            for (std::uint32_t tri : c.triangles[k]) ++used[tri];
        }
        CHECK(area == test::approx(area2(p)).epsilon(1e-12));
        for (int u : used) CHECK(u == 1);
        CHECK(c.pieces.size() <= static_cast<std::size_t>(2 * reflex_corners(p) + 1));
        if (trial % 3 == 0) CHECK(c.pieces.size() == 1);
    }
}
