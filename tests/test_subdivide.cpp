// Conforming subdivision against identities: area is preserved, no edge exceeds the limit,
// faces meeting along an edge share its new vertices (closed surfaces stay closed, Euler's
// formula holds), children keep their parent's data and normal.
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include <doctest/doctest.h>

#include <cmath>

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
        CHECK(total_area(sub) == doctest::Approx(6.0).epsilon(1e-12));
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
        CHECK(glm::dot(n, np) == doctest::Approx(1.0).epsilon(1e-12));
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
    CHECK(total_area(sub) == doctest::Approx(8.0));
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
    CHECK(total_area(sub) == doctest::Approx(1.0).epsilon(1e-12));
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
    CHECK(total_area(sub) == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(largest_area(sub) == doctest::Approx(0.03125).epsilon(1e-12));
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
    CHECK(largest_area(q) == doctest::Approx(0.25).epsilon(1e-12));
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
    CHECK(total_area(alone) == doctest::Approx(3.0).epsilon(1e-12));
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
