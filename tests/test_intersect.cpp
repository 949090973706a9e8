// Cutting intersecting faces (mesh/intersect.hpp) and leaving out what lies inside closed
// solids (mesh/solid.hpp): boxes pushed into a wall, a room's floor and a solid block; faces
// that only touch; the lit side against the same scene modelled without intersections; and
// RRV's room3, whose lamp barrels run through their globes.
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/intersect.hpp>
#include <radiosity/mesh/orientation.hpp>
#include <radiosity/mesh/subdivide.hpp>
#include <radiosity/solve.hpp>

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

using namespace radiosity;

namespace {

const std::string rrv_dir = std::string(RADIOSITY_REFDATA_DIR) + "/../rrv";

/// Adds the six faces of box [lo, hi] with material m, pointing out (or in, for a room).
template <SpectrumType S>
void add_box(Scene<S>& s, const Vec3& lo, const Vec3& hi, std::uint32_t m, bool inward = false) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (int k = 0; k < 8; ++k)
        s.positions.push_back({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
    const std::array<std::array<std::uint32_t, 4>, 6> quads{
        {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}};
    for (auto q : quads) {
        if (inward) std::swap(q[1], q[3]);
        s.faces.push_back({base + q[0], base + q[1], base + q[2], base + q[3]});
        s.face_material.push_back(m);
    }
}

/// Adds a quad with corners a, b, c, d (counter-clockwise seen from its front).
template <SpectrumType S>
void add_quad(Scene<S>& s, std::array<Vec3, 4> p, std::uint32_t m) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (const Vec3& x : p) s.positions.push_back(x);
    s.faces.push_back({base, base + 1, base + 2, base + 3});
    s.face_material.push_back(m);
}

template <SpectrumType S>
Scene<S> with_materials(int n) {
    Scene<S> s;
    for (int k = 0; k < n; ++k) s.materials.push_back(Material<S>::unnamed());
    return s;
}

double mesh_area(const Mesh<float>& m) {
    double a = 0.0;
    for (auto f : m.faces()) a += polygon_area(face_polygon(m, f));
    return a;
}

/// Whether some patch has corners strictly on both sides of the plane x[axis] = at.
template <class M>
bool straddles(const M& mesh, int axis, double at, double tol = 1e-9) {
    for (auto f : mesh.faces()) {
        bool below = false, above = false;
        for (const Vec3& p : face_polygon(mesh, f)) {
            below = below || p[axis] < at - tol;
            above = above || p[axis] > at + tol;
        }
        if (below && above) return true;
    }
    return false;
}

// The wall is the plane x = 0, facing +x; the box reaches 0.4 behind it and 0.6 in front.
const Vec3 box_lo(-0.4, -0.3, -0.45), box_hi(0.6, 0.5, 0.35);

Scene<float> box_in_wall() {
    Scene<float> s = with_materials<float>(2);
    add_quad(s, {Vec3(0, -2, -2), Vec3(0, 2, -2), Vec3(0, 2, 2), Vec3(0, -2, 2)}, 0);
    add_box(s, box_lo, box_hi, 1);
    return s;
}

}  // namespace

TEST_CASE("a box pushed halfway into a wall: no patch straddles the wall, the areas add up") {
    const Mesh<float> mesh = build_mesh(box_in_wall());
    const double before = mesh_area(mesh);
    SubdivisionOptions o;
    o.max_edge = 0.3;
    REQUIRE(straddles(subdivide(mesh, {.max_edge = 0.3, .cut_intersections = false}), 0, 0.0));
    const Subdivided<float> cut = subdivide_with_report(mesh, o);
    const IntersectionReport& r = cut.report.intersections;
    CHECK(r.crossing_pairs == 4);  // the wall and each of the four sides that pass through it
    CHECK(r.cut_faces == 5);
    CHECK_FALSE(straddles(cut.mesh, 0, 0.0));
    // A single wall is not a closed object: the box behind it stays. The part of the wall
    // inside the closed box, its 0.8 x 0.8 cross-section, is left out.
    CHECK(r.left_out == 1);
    CHECK(r.left_out_area == doctest::Approx(0.8 * 0.8).epsilon(1e-12));
    CHECK(mesh_area(cut.mesh) + r.left_out_area == doctest::Approx(before).epsilon(1e-12));
    double behind = 0.0;
    for (auto f : cut.mesh.faces()) {
        const auto p = face_polygon(cut.mesh, f);
        const Vec3 c = polygon_centroid(p);
        if (cut.mesh.data(f).surface == 0)
            CHECK_FALSE((c.y > box_lo.y && c.y < box_hi.y && c.z > box_lo.z && c.z < box_hi.z));
        else if (c.x < 0.0)
            behind += polygon_area(p);
    }
    CHECK(behind == doctest::Approx(0.4 * 2 * (0.8 + 0.8) + 0.8 * 0.8).epsilon(1e-12));
    REQUIRE(cut.report.lines().size() == 1);
    CHECK(cut.report.lines()[0] ==
          "meshing: cut 5 face(s) where other faces cross them; left out 1 piece(s) inside "
          "closed objects (area 0.64)");
}

TEST_CASE("a box pushed into a closed room's floor: the floor under it is left out, not the box") {
    Scene<float> s = with_materials<float>(2);
    add_box(s, Vec3(-2.0), Vec3(2.0), 0, true);  // a room: faces point in
    add_box(s, Vec3(-0.5, -2.3, -0.4), Vec3(0.4, -1.5, 0.5), 1);
    const Mesh<float> mesh = build_mesh(s);
    const Subdivided<float> cut = subdivide_with_report(mesh, {.max_edge = 0.35});
    const IntersectionReport& r = cut.report.intersections;
    CHECK(r.cut_faces == 5);  // the floor and the box's four sides
    CHECK_FALSE(straddles(cut.mesh, 1, -2.0));
    // The room faces in: what lies outside it is in no solid, so the box's foot stays (its
    // patches see only backs and get no light); the floor inside the box goes.
    CHECK(r.left_out == 1);
    CHECK(r.left_out_area == doctest::Approx(0.9 * 0.9).epsilon(1e-12));
    CHECK(mesh_area(cut.mesh) + r.left_out_area == doctest::Approx(mesh_area(mesh)).epsilon(1e-12));
}

TEST_CASE("a box pushed into a solid block: what lies inside the other is left out on both") {
    Scene<float> s = with_materials<float>(2);
    add_box(s, Vec3(-1.0), Vec3(1.0, 0.0, 1.0), 0);  // a solid block, top at y = 0
    add_box(s, Vec3(-0.3, -0.4, -0.2), Vec3(0.5, 0.6, 0.3), 1);
    const Mesh<float> mesh = build_mesh(s);
    const Subdivided<float> cut = subdivide_with_report(mesh, {.max_edge = 0.25});
    const IntersectionReport& r = cut.report.intersections;
    CHECK(r.cut_faces == 5);
    CHECK_FALSE(straddles(cut.mesh, 1, 0.0));
    // The box's bottom (0.8 x 0.5) and the lower 0.4 of its sides (perimeter 2.6) lie in the
    // block; the block's top under the box (0.8 x 0.5) lies in the box.
    CHECK(r.left_out == 1 + 4 + 1);
    CHECK(r.left_out_area == doctest::Approx(0.4 + 0.4 * 2.6 + 0.4).epsilon(1e-12));
    for (auto f : cut.mesh.faces()) {
        const Vec3 c = polygon_centroid(face_polygon(cut.mesh, f));
        if (cut.mesh.data(f).surface >= 6) CHECK(c.y > 0.0);  // the box: only above the block
    }
    CHECK(mesh_area(cut.mesh) + r.left_out_area == doctest::Approx(mesh_area(mesh)).epsilon(1e-12));
}

TEST_CASE("faces that only touch are not cut: blocks on a floor, against a wall, the Cornell box") {
    Scene<float> s = with_materials<float>(2);
    add_box(s, Vec3(-2.0), Vec3(2.0), 0, true);
    add_box(s, Vec3(-0.5, -2.0, -0.5), Vec3(0.5, -1.0, 0.5), 1);  // standing on the floor
    add_box(s, Vec3(-2.0, 0.0, 0.0), Vec3(-1.0, 1.0, 1.0), 1);    // flush against a wall
    add_box(s, Vec3(-0.5, -1.0, -0.5), Vec3(0.0, 0.0, 0.0), 1);   // on the first, sharing a face
    for (const auto& [scene, edge] : {std::pair{s, 0.5}, std::pair{cornell_box<float>(), 100.0}}) {
        Scene<float> twins = scene;
        make_two_sided(twins);
        for (const Scene<float>& x : {scene, twins}) {
            const Mesh<float> mesh = build_mesh(x);
            const CutMesh<float> cut = cut_intersections(mesh);
            CHECK(cut.report.crossing_pairs == 0);
            CHECK_FALSE(cut.changed());
            const Mesh<float> a = subdivide(mesh, {.max_edge = edge});
            const Mesh<float> b = subdivide(mesh, {.max_edge = edge, .cut_intersections = false});
            REQUIRE(a.n_faces() == b.n_faces());
            bool same = a.n_vertices() == b.n_vertices();
            for (auto v : a.vertices()) same = same && a.point(v) == b.point(v);
            CHECK(same);
        }
    }
}
