// Conforming subdivision against identities: area is preserved, no edge exceeds the limit,
// faces meeting along an edge share its new vertices (closed surfaces stay closed, Euler's
// formula holds), children keep their parent's data and normal.
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

using namespace radiosity;

namespace {

/// The unit cube as 6 quads that share NO vertex indices (24 vertices), faces pointing out.
Scene<float> separate_cube() {
    Scene<float> s;
    const std::vector<std::vector<Vec3>> faces{
        {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
        {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
    for (std::size_t f = 0; f < faces.size(); ++f) {
        std::vector<std::uint32_t> idx;
        for (const Vec3& p : faces[f]) {
            idx.push_back(static_cast<std::uint32_t>(s.positions.size()));
            s.positions.push_back(p);
        }
        s.faces.push_back(idx);
        s.face_material.push_back(static_cast<std::uint32_t>(f % 2));
    }
    s.materials = {{0.0f, 0.5f, "grey"}, {2.0f, 0.25f, "lamp"}};
    return s;
}

double total_area(const Mesh<float>& m) {
    double a = 0.0;
    for (auto f : m.faces()) a += polygon_area(face_polygon(m, f));
    return a;
}

double longest_edge(const Mesh<float>& m) {
    double e = 0.0;
    for (auto h : m.edges()) {
        const auto v = m.calc_edge_vector(h);
        e = std::max(e, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    }
    return e;
}

std::size_t boundary_edges(const Mesh<float>& m) {
    std::size_t n = 0;
    for (auto e : m.edges()) n += m.is_boundary(e);
    return n;
}

}  // namespace

TEST_CASE("a cube of separate faces stays closed: shared vertices, Euler's formula") {
    const auto mesh = build_mesh(separate_cube());
    CHECK(boundary_edges(mesh) == 24);  // as built: every face on its own
    for (double max_edge : {1.0, 0.5, 0.3, 0.1}) {
        CAPTURE(max_edge);
        const auto sub = subdivide(mesh, {max_edge});
        CHECK(boundary_edges(sub) == 0);  // no cracks, no T-junctions
        const auto V = static_cast<long>(sub.n_vertices()), E = static_cast<long>(sub.n_edges()),
                   F = static_cast<long>(sub.n_faces());
        CHECK(V - E + F == 2);
        CHECK(total_area(sub) == test::approx(6.0).epsilon(1e-12));
        CHECK(longest_edge(sub) <= max_edge + 1e-12);
        const long k = static_cast<long>(std::ceil(1.0 / max_edge - 1e-9));
        CHECK(F == 6 * k * k);
    }
}

TEST_CASE("children keep their parent's material, emission, reflectance and normal") {
    const auto mesh = build_mesh(separate_cube());
    const auto sub = subdivide(mesh, {0.25});
    for (auto f : sub.faces()) {
        const auto& d = sub.data(f);
        const auto parent = Mesh<float>::FaceHandle(static_cast<int>(d.surface));
        CHECK(d.material == mesh.data(parent).material);
        CHECK(d.emission == mesh.data(parent).emission);
        CHECK(d.reflectance == mesh.data(parent).reflectance);
        const Vec3 n = polygon_normal(face_polygon(sub, f));
        const Vec3 np = polygon_normal(face_polygon(mesh, parent));
        CHECK(glm::dot(n, np) == test::approx(1.0).epsilon(1e-12));
    }
}

TEST_CASE("a long quad becomes a k1 x k2 grid and its neighbour follows") {
    // A 4 x 1 strip next to a 1 x 1 square (separately indexed): the shared side is cut as
    // often as both need, and opposite sides of each quad alike.
    Scene<float> s;
    s.positions = {{0, 0, 0}, {4, 0, 0}, {4, 1, 0}, {0, 1, 0},
                   {0, 1, 0}, {4, 1, 0}, {4, 2, 0}, {0, 2, 0}};
    s.faces = {{0, 1, 2, 3}, {4, 5, 6, 7}};
    s.face_material = {0, 0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    const auto sub = subdivide(build_mesh(s), {1.0});
    CHECK(sub.n_faces() == 8);                    // 4 x 1 each
    CHECK(boundary_edges(sub) == 4 + 4 + 2 + 2);  // the outer rim only: bottom, top, sides
    CHECK(total_area(sub) == test::approx(8.0));
}

TEST_CASE("triangles split into k^2 triangles, conforming with their neighbours") {
    Scene<float> s;  // a square as two triangles with separate vertices along the diagonal
    s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.faces = {{0, 1, 2}, {3, 4, 5}};
    s.face_material = {0, 0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    const auto sub = subdivide(build_mesh(s), {0.3});
    const std::size_t k = 5;  // the diagonal (1.41) needs 5 segments, so all sides get 5
    CHECK(sub.n_faces() == 2 * k * k);
    CHECK(boundary_edges(sub) == 4 * k);
    CHECK(total_area(sub) == test::approx(1.0).epsilon(1e-12));
    CHECK(longest_edge(sub) <= 0.3 + 1e-12);
}

double largest_area(const Mesh<float>& m) {
    double a = 0.0;
    for (auto f : m.faces()) a = std::max(a, polygon_area(face_polygon(m, f)));
    return a;
}

TEST_CASE("max_area: RRV's rule of 1 -> 4 splits at edge midpoints until small enough") {
    Scene<float> s;  // a square as two triangles of area 0.5 with separate diagonal vertices
    s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.faces = {{0, 1, 2}, {3, 4, 5}};
    s.face_material = {0, 0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    const auto mesh = build_mesh(s);
    // 0.5 -> 0.125 -> 0.03125: two rounds for 0.1, so 4 segments a side and 16 children each.
    SubdivisionOptions o;
    o.max_area = 0.1;
    const auto sub = subdivide(mesh, o);
    CHECK(sub.n_faces() == 2 * 16);
    CHECK(subdivided_face_count(mesh, o) == sub.n_faces());
    CHECK(boundary_edges(sub) == 4 * 4);  // conforming along the diagonal
    CHECK(total_area(sub) == test::approx(1.0).epsilon(1e-12));
    CHECK(largest_area(sub) == test::approx(0.03125).epsilon(1e-12));
    o.max_area = 0.125;  // exactly reached after one round: no second
    CHECK(subdivide(mesh, o).n_faces() == 2 * 4);
    // Both limits: the edge rule asks for 5 segments (the diagonal), more than the area's 4.
    o.max_area = 0.1;
    o.max_edge = 0.3;
    CHECK(subdivide(mesh, o).n_faces() == 2 * 25);
    // A quad is split 1 -> 4 the same way.
    const auto cube = build_mesh(separate_cube());  // faces of area 1
    o = {};
    o.max_area = 0.3;
    const auto q = subdivide(cube, o);
    CHECK(q.n_faces() == 6 * 4);
    CHECK(largest_area(q) == test::approx(0.25).epsilon(1e-12));
    o.max_area = -1.0;
    CHECK_THROWS_AS(subdivide(cube, o), Error);
    o.max_area = std::nan("");
    CHECK_THROWS_AS(subdivide(cube, o), Error);
}

TEST_CASE("max_area without conforming: each face split by itself, as RRV does") {
    Scene<float> s;  // triangles of area 0.5 and 2.5 sharing the edge (1, 0) - (0, 1)
    s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {3, 3, 0}};
    s.faces = {{0, 1, 2}, {1, 3, 2}};
    s.face_material = {0, 0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    const auto mesh = build_mesh(s);
    SubdivisionOptions o;
    o.max_area = 0.6;  // the small one stays whole, the large one needs 2 rounds: 16 children
    o.conforming = false;
    const auto alone = subdivide(mesh, o);
    CHECK(alone.n_faces() == 1 + 16);
    CHECK(subdivided_face_count(mesh, o) == alone.n_faces());
    CHECK(total_area(alone) == test::approx(3.0).epsilon(1e-12));
    CHECK(largest_area(alone) <= 0.6);
    // The shared edge is a T-junction: one edge on the small side, four on the large side, none
    // of them shared; the outer edges are 2 + 8.
    CHECK(boundary_edges(alone) == 2 + 8 + 1 + 4);
    o.conforming = true;  // the small one is split along with its neighbour
    const auto joined = subdivide(mesh, o);
    CHECK(joined.n_faces() == 16 + 16);
    CHECK(boundary_edges(joined) == 8 + 8);
}

TEST_CASE("max_edge 0 keeps the mesh, bad values and explosions are refused") {
    const auto mesh = build_mesh(separate_cube());
    CHECK(subdivide(mesh, {0.0}).n_faces() == 6);
    CHECK_THROWS_AS(subdivide(mesh, {-1.0}), Error);
    CHECK_THROWS_AS(subdivide(mesh, {std::nan("")}), Error);
    CHECK_THROWS_AS(subdivide(mesh, {1e-5}), Error);  // 6e10 patches: refused, not attempted
}

// --- polygons: more than four corners, or concave -----------------------------------------

namespace {

Scene<float> polygon_scene(const std::vector<Vec2>& p) {
    Scene<float> s;
    std::vector<std::uint32_t> f;
    for (const Vec2& q : p) {
        f.push_back(static_cast<std::uint32_t>(s.positions.size()));
        s.positions.push_back({q.x, q.y, 0.0});
    }
    s.faces = {f};
    s.face_material = {0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    return s;
}

std::vector<Vec2> regular_polygon(int n) {
    std::vector<Vec2> p;
    for (int k = 0; k < n; ++k) {
        const double t = 2.0 * std::numbers::pi * k / n;
        p.emplace_back(std::cos(t), std::sin(t));
    }
    return p;
}

}  // namespace

TEST_CASE("an L-shaped hexagon subdivided covers area 3 and leaves its notch empty") {
    // The first corner sees the notch's corner: a fan from it, as the mesh used to be cut,
    // covers area 4 and puts patches in the notch.
    const auto mesh = build_mesh(polygon_scene({{2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}}));
    const Subdivided<float> sub = subdivide_with_report(mesh, {.max_edge = 0.1});
    double area = 0.0;
    std::size_t in_notch = 0;
    for (auto f : sub.mesh.faces()) {
        const auto p = face_polygon(sub.mesh, f);
        area += polygon_area(p);
        CHECK(polygon_normal(p).z == test::approx(1.0));
        const Vec3 c = polygon_centroid(p);
        in_notch += c.x > 1.0 && c.y > 1.0;
        for (const Vec3& v : p) CHECK(!(v.x > 1.0 + 1e-12 && v.y > 1.0 + 1e-12));
    }
    CHECK(area == test::approx(3.0).epsilon(1e-12));
    CHECK(in_notch == 0);
    CHECK(sub.mesh.n_faces() == 300);  // 0.1 x 0.1 squares, the notch's corner on grid lines
    CHECK(sub.report.polygons == 1);
    CHECK(sub.report.lines().empty());
}

TEST_CASE("disks of 500 and 10,000 corners mesh to their area with about a square's patches") {
    const double h = 0.1;
    const std::size_t k = static_cast<std::size_t>(std::ceil(std::sqrt(std::numbers::pi) / h));
    for (int n : {500, 10000}) {
        CAPTURE(n);
        const auto mesh = build_mesh(polygon_scene(regular_polygon(n)));
        const double own = polygon_area(face_polygon(mesh, *mesh.faces().begin()));
        const Mesh<float> sub = subdivide(mesh, {.max_edge = h});
        double area = 0.0;
        for (auto f : sub.faces()) area += polygon_area(face_polygon(sub, f));
        CHECK(std::abs(area - own) <= 1e-9 * own);  // the polygon's own area, near pi
        CHECK(own == test::approx(std::numbers::pi).epsilon(1e-4));
        // A square of the same area at the same edge: k x k patches.
        const double ratio = double(sub.n_faces()) / double(k * k);
        MESSAGE(n << "-gon: " << sub.n_faces() << " patches, a square of its area " << k * k
                  << ": ratio " << ratio);
        CHECK(ratio > 0.9);
        CHECK(ratio < 1.1);
    }
}

TEST_CASE("a concave quad is cut as a polygon, not as a bilinear grid") {
    // A dart: its bilinear grid would fold over itself.
    const auto mesh = build_mesh(polygon_scene({{0, 0}, {2, 1}, {0, 2}, {0.7, 1}}));
    const Mesh<float> sub = subdivide(mesh, {.max_edge = 0.2});
    double area = 0.0;
    for (auto f : sub.faces()) {
        const auto p = face_polygon(sub, f);
        area += polygon_area(p);
        CHECK(polygon_normal(p).z == test::approx(1.0));
    }
    CHECK(area == test::approx(1.3).epsilon(1e-12));
    CHECK(boundary_edges(sub) > 0);
}

TEST_CASE("a slightly non-planar polygon is cut as its projection, with a warning") {
    Scene<float> s = polygon_scene(regular_polygon(7));
    s.positions[3].z = 1e-3;  // off the plane by 1e-3 of a polygon of size 2
    const Subdivided<float> sub = subdivide_with_report(build_mesh(s), {.max_edge = 0.3});
    CHECK(sub.report.non_planar_faces == 1);
    CHECK(sub.report.worst_non_planar_face == 0);
    CHECK(sub.report.worst_non_planarity > 1e-4);
    REQUIRE(sub.report.lines().size() == 1);
    CHECK(sub.report.lines()[0].find("not planar") != std::string::npos);
    // The patches' projections cover the polygon's projection.
    std::vector<Vec3> p(s.positions.begin(), s.positions.end());
    const Vec3 n = glm::normalize(newell_vector(p));
    double projected = 0.0;
    for (auto f : sub.mesh.faces())
        projected += 0.5 * glm::dot(newell_vector(face_polygon(sub.mesh, f)), n);
    CHECK(projected == test::approx(polygon_area(p)).epsilon(1e-9));
    // Within the tolerance: no warning.
    s.positions[3].z = 1e-7;
    CHECK(subdivide_with_report(build_mesh(s), {.max_edge = 0.3}).report.non_planar_faces == 0);
}

TEST_CASE("a self-intersecting polygon is refused, naming the file, line and face") {
    Scene<float> s = polygon_scene({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, -1}, {0, 1}});
    s.source = "room.obj";
    s.face_lines = {17};
    CHECK_THROWS_WITH_AS(build_mesh(s), doctest::Contains("room.obj:17: face 0"), Error);
    CHECK_THROWS_WITH_AS(build_mesh(s), doctest::Contains("intersects itself"), Error);
    // A quad with two corners at one point (a sphere's pole) is a triangle, not a pinch.
    Scene<float> pole = polygon_scene({{0, 0}, {1, 0}, {1, 0}, {0, 1}});
    CHECK(build_mesh(pole).n_faces() == 1);
}

TEST_CASE("a face that welding leaves without area is left out and reported") {
    Scene<float> s = polygon_scene({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    const auto a = static_cast<std::uint32_t>(s.positions.size());
    s.positions.push_back({0.5, 0.5, 0.0});
    s.positions.push_back({0.5 + 1e-12, 0.5, 0.0});  // within 1e-9 of the scene's size
    s.positions.push_back({0.5, 0.5 + 1e-12, 1e-12});
    s.faces.push_back({a, a + 1, a + 2});
    s.face_material.push_back(0);
    const Subdivided<float> sub = subdivide_with_report(build_mesh(s), {.max_edge = 0.5});
    REQUIRE(sub.report.dropped_faces.size() == 1);
    CHECK(sub.report.dropped_faces[0] == 1);
    CHECK(sub.mesh.n_faces() == 4);
    REQUIRE(!sub.report.lines().empty());
    CHECK(sub.report.lines()[0].find("left out 1 face") != std::string::npos);
}

TEST_CASE("lightmap UVs follow a polygon's patches") {
    // UVs an affine function of position: every patch corner must get that function's value.
    Scene<float> s = polygon_scene({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 2}, {0, 2}});
    auto uv_at = [](double x, double y) {
        return glm::vec2(static_cast<float>(0.05 + 0.3 * x), static_cast<float>(0.1 + 0.4 * y));
    };
    s.face_uvs = {{}};
    for (const Vec3& p : s.positions) s.face_uvs[0].push_back(uv_at(p.x, p.y));
    const Mesh<float> sub = subdivide(build_mesh(s), {.max_edge = 0.35});
    REQUIRE(has_corner_uvs(sub));
    for (auto f : sub.faces())
        for (auto v : sub.fv_range(f)) {
            const auto& p = sub.point(v);
            const glm::vec2 t = corner_uv(sub, f, v), want = uv_at(p[0], p[1]);
            CHECK(t.x == test::approx(want.x).epsilon(1e-5));
            CHECK(t.y == test::approx(want.y).epsilon(1e-5));
        }
}

TEST_CASE("a polygon beside a quad: each takes the other's points along their shared edge") {
    // A pentagon reaching past the quad's side shares the edge (0, 1) - (4, 1) with a 4 x 1 quad
    // above it: its grid (over x in [-1, 4]) cuts that edge elsewhere than the quad's 14 equal
    // segments do, so each inserts the other's points; no edge is left open along it.
    Scene<float> s;
    s.positions = {{-1, 0.5, 0}, {0, 0, 0}, {4, 0, 0}, {4, 1, 0}, {0, 1, 0},
                   {0, 1, 0},    {4, 1, 0}, {4, 2, 0}, {0, 2, 0}};
    s.faces = {{0, 1, 2, 3, 4}, {5, 6, 7, 8}};
    s.face_material = {0, 0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    const Subdivided<float> sub = subdivide_with_report(build_mesh(s), {.max_edge = 0.3});
    CHECK(sub.report.conforming_points > 0);
    for (auto e : sub.mesh.edges()) {
        if (!sub.mesh.is_boundary(e)) continue;
        const auto h = sub.mesh.halfedge_handle(e, 0);
        const auto a = sub.mesh.point(sub.mesh.from_vertex_handle(h)),
                   b = sub.mesh.point(sub.mesh.to_vertex_handle(h));
        const bool on_shared = a[1] == 1.0 && b[1] == 1.0 && a[0] > 0.0 && a[0] < 4.0;
        CHECK(!on_shared);
    }
    CHECK(total_area(sub.mesh) == test::approx(4.5 + 4.0).epsilon(1e-12));
}

TEST_CASE("polygons too finely cut are refused before any work") {
    const auto mesh = build_mesh(polygon_scene(regular_polygon(500)));
    CHECK_THROWS_WITH_AS(subdivide(mesh, {.max_edge = 1e-5}), doctest::Contains("patches"), Error);
    CHECK(subdivided_face_count(mesh, {.max_edge = 1e-5}) > 4'000'000);
    CHECK(subdivided_face_count(mesh, {.max_edge = 0.1}) ==
          subdivide(mesh, {.max_edge = 0.1}).n_faces());
}
