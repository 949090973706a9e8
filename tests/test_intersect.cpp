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

#include "support/approx.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
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
    CHECK(r.left_out_area == test::approx(0.8 * 0.8).epsilon(1e-12));
    CHECK(mesh_area(cut.mesh) + r.left_out_area == test::approx(before).epsilon(1e-12));
    double behind = 0.0;
    for (auto f : cut.mesh.faces()) {
        const auto p = face_polygon(cut.mesh, f);
        const Vec3 c = polygon_centroid(p);
        if (cut.mesh.data(f).surface == 0)
            CHECK_FALSE((c.y > box_lo.y && c.y < box_hi.y && c.z > box_lo.z && c.z < box_hi.z));
        else if (c.x < 0.0)
            behind += polygon_area(p);
    }
    CHECK(behind == test::approx(0.4 * 2 * (0.8 + 0.8) + 0.8 * 0.8).epsilon(1e-12));
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
    CHECK(r.left_out_area == test::approx(0.9 * 0.9).epsilon(1e-12));
    CHECK(mesh_area(cut.mesh) + r.left_out_area == test::approx(mesh_area(mesh)).epsilon(1e-12));
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
    CHECK(r.left_out_area == test::approx(0.4 + 0.4 * 2.6 + 0.4).epsilon(1e-12));
    for (auto f : cut.mesh.faces()) {
        const Vec3 c = polygon_centroid(face_polygon(cut.mesh, f));
        if (cut.mesh.data(f).surface >= 6) CHECK(c.y > 0.0);  // the box: only above the block
    }
    CHECK(mesh_area(cut.mesh) + r.left_out_area == test::approx(mesh_area(mesh)).epsilon(1e-12));
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

TEST_CASE("room3: the lamp barrels are cut where they enter their globes, the parts inside go") {
    const Scene<Rgb> scene = read_rrv<Rgb>(rrv_dir + "/room3.xml");
    const Mesh<Rgb> mesh = build_mesh(scene);
    // RRV's own meshing of its scenes (the program's default, --divide 1): each face split
    // 1 -> 4 by itself until no patch exceeds area 1. The check inside finds every input face
    // covered by its patches and its left-out pieces, to 1e-9.
    const Subdivided<Rgb> sub = subdivide_with_report(mesh, {.max_area = 1.0, .conforming = false});
    const IntersectionReport& r = sub.report.intersections;
    MESSAGE("room3: " << r.crossing_pairs << " crossing pairs, " << r.cut_faces
                      << " faces cut into " << r.pieces << " pieces, " << r.left_out
                      << " pieces left out, area " << r.left_out_area);
    CHECK(r.cut_faces > 0);
    CHECK(r.failed_faces == 0);
    double before = 0.0, after = 0.0;
    for (auto f : mesh.faces()) before += polygon_area(face_polygon(mesh, f));
    for (auto f : sub.mesh.faces()) after += polygon_area(face_polygon(sub.mesh, f));
    CHECK(after + r.left_out_area == test::approx(before).epsilon(1e-9));
    // The two lamps under the ceiling: a globe of radius R = 2.5 centred on the bottom of a
    // barrel of radius 1.25 (a 20-gon prism). Inside the globe lie the barrel's bottom cap and
    // its side up to where a sphere of radius R meets the cylinder, h = sqrt(R^2 - r^2); inside
    // the barrel lies the globe's cap of height R - h, area 2 pi R (R - h). The globe is a
    // polygon mesh inside that sphere, so the areas agree only to within a few per cent.
    const CutMesh<Rgb> cut = cut_intersections(mesh);
    const double R = 2.5, rc = 1.25, pi = std::numbers::pi, h = std::sqrt(R * R - rc * rc);
    const double barrel = 20 * 2 * rc * std::sin(pi / 20) * h + 10 * rc * rc * std::sin(pi / 10);
    const double globe = 2 * pi * R * (R - h);
    double barrels = 0.0, globes = 0.0;
    for (std::size_t k = 0; k < cut.left_out.size(); ++k) {
        if (polygon_centroid(cut.left_out[k]).y < 4.9) continue;  // the lamp on the back wall
        const bool emits =
            band(mesh.data(Mesh<Rgb>::FaceHandle(int(cut.left_out_face[k]))).emission, 0) > 0;
        (emits ? globes : barrels) += polygon_area(cut.left_out[k]);
    }
    MESSAGE("ceiling lamps: barrels " << barrels << " left out (smooth estimate " << 2 * barrel
                                      << "), globes " << globes << " (" << 2 * globe << ")");
    CHECK(barrels == test::approx(2 * barrel).epsilon(0.03));
    CHECK(globes == test::approx(2 * globe).epsilon(0.03));
}

namespace {

// A closed room [-2, 2]^3 facing in, lit by a square lamp under its ceiling, with a box pushed
// halfway through its wall x = -2: intersecting, or modelled by hand as what is seen of it
// (the box cut at the wall, the wall in four quads round the box's footprint).
const Vec3 lamp_lo(-2.45, -1.2, -0.6), lamp_hi(-1.55, -0.3, 0.4);

Scene<float> lit_room(bool by_hand) {
    Scene<float> s;
    s.materials = {Material<float>::unnamed(), {10.0f, 0.0f, "lamp"}};
    add_box(s, Vec3(-2.0), Vec3(2.0), 0, true);
    add_quad(s,
             {Vec3(-0.5, 1.99, -0.5), Vec3(0.5, 1.99, -0.5), Vec3(0.5, 1.99, 0.5),
              Vec3(-0.5, 1.99, 0.5)},
             1);
    if (!by_hand) {
        add_box(s, lamp_lo, lamp_hi, 0);
        return s;
    }
    s.faces.erase(s.faces.begin());  // the wall x = -2, in four quads instead:
    s.face_material.erase(s.face_material.begin());
    auto wall = [&](double y0, double y1, double z0, double z1) {
        add_quad(s, {Vec3(-2, y0, z0), Vec3(-2, y1, z0), Vec3(-2, y1, z1), Vec3(-2, y0, z1)}, 0);
    };
    wall(-2, lamp_lo.y, -2, 2);
    wall(lamp_hi.y, 2, -2, 2);
    wall(lamp_lo.y, lamp_hi.y, -2, lamp_lo.z);
    wall(lamp_lo.y, lamp_hi.y, lamp_hi.z, 2);
    const std::size_t box = s.faces.size();
    add_box(s, Vec3(-2.0, lamp_lo.y, lamp_lo.z), lamp_hi, 0);
    s.faces.erase(s.faces.begin() + std::ptrdiff_t(box));  // its back, x = -2, is not seen
    s.face_material.erase(s.face_material.begin() + std::ptrdiff_t(box));
    return s;
}

/// Mean radiosity (area-weighted) of the patches that `pick` chooses, by centroid and normal.
double mean_b(const SolveResult<float>& r, const std::function<bool(Vec3, Vec3)>& pick) {
    double power = 0.0, area = 0.0;
    for (std::size_t i = 0; i < r.patches.size(); ++i)
        if (pick(r.patches.centroid(i), r.patches.normal(i))) {
            power +=
                r.patches.area(i) * double(r.mesh.data(Mesh<float>::FaceHandle(int(i))).radiosity);
            area += r.patches.area(i);
        }
    return power / area;
}

}  // namespace

TEST_CASE("the lit side of a box pushed into a wall converges to the box modelled cut at it") {
    auto box = [](Vec3 c, Vec3) {
        return c.x > -2 + 1e-9 && c.y > lamp_lo.y - 1e-9 && c.y < lamp_hi.y + 1e-9 &&
               c.z > lamp_lo.z - 1e-9 && c.z < lamp_hi.z + 1e-9 && c.x < lamp_hi.x + 1e-9;
    };
    auto wall = [](Vec3 c, Vec3 n) { return std::abs(c.x + 2) < 1e-9 && n.x > 0.5; };
    auto floor = [](Vec3 c, Vec3 n) { return std::abs(c.y + 2) < 1e-9 && n.y > 0.5; };
    // Both meshings approach the same surfaces, so they agree to within their discretisation
    // (measured: 0.1 to 0.6 per cent at either size). Uncut, the wall's patches under the box
    // count as lit wall (4 to 6 per cent off), and the box's sides straddle the wall unless a
    // grid line happens to fall on it (at max edge 0.5 one does; at 0.35 the box is 5% off).
    for (double edge : {0.5, 0.35}) {
        SolveOptions o;
        o.subdivision.max_edge = edge;
        const SolveResult<float> cut = solve(build_mesh(lit_room(false)), o);
        const SolveResult<float> hand = solve(build_mesh(lit_room(true)), o);
        o.subdivision.cut_intersections = false;
        const SolveResult<float> uncut = solve(build_mesh(lit_room(false)), o);
        using Pick = std::function<bool(Vec3, Vec3)>;
        for (const auto& [name, pick] :
             {std::pair<std::string, Pick>{"box", box}, {"wall", wall}, {"floor", floor}}) {
            const double a = mean_b(cut, pick), b = mean_b(hand, pick), c = mean_b(uncut, pick);
            MESSAGE("max edge " << edge << ", " << name << ": cut " << a << ", by hand " << b
                                << ", uncut " << c);
            CHECK(a == test::approx(b).epsilon(0.01));
            if (name == "wall") CHECK(std::abs(c - b) > 5.0 * std::abs(a - b));
        }
    }
}

TEST_CASE("random crossing triangles and boxes, some on a grid: the meshing's check always holds") {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto unit = [&] { return glm::normalize(Vec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5)); };
    std::size_t cut_faces = 0, left_out = 0, failed = 0, planar_failed = 0;
    for (int trial = 0; trial < 120; ++trial) {
        Scene<float> s = with_materials<float>(1);
        for (int k = 0; k < 2 + trial % 12; ++k) {
            const Vec3 c(U(rng), U(rng), U(rng)), a = unit(),
                                                  b = glm::normalize(glm::cross(a, unit()));
            const double r = 0.2 + 0.3 * U(rng);
            if (k % 3 == 0) {  // a box, turned: corners c +- r a +- r b +- r (a x b), outward
                add_box(s, Vec3(-r), Vec3(r), 0);
                const Vec3 z = glm::cross(a, b);
                for (std::size_t v = s.positions.size() - 8; v < s.positions.size(); ++v) {
                    const Vec3 p = s.positions[v];
                    s.positions[v] = c + p.x * a + p.y * b + p.z * z;
                }
                continue;
            }
            const auto base = static_cast<std::uint32_t>(s.positions.size());
            for (int j = 0; j < 3; ++j) {
                const double t = 2.0 * std::numbers::pi * j / 3 + 0.5 * U(rng);
                s.positions.push_back(c + r * (std::cos(t) * a + std::sin(t) * b));
            }
            s.faces.push_back({base, base + 1, base + 2});
            s.face_material.push_back(0);
        }
        const bool grid = trial % 4 == 1;  // coplanar, touching and T-shaped cases galore
        if (grid)
            for (Vec3& p : s.positions) p = glm::round(p * 4.0) / 4.0;
        Mesh<float> mesh;
        try {
            mesh = build_mesh(s);
        } catch (const Error&) {
            continue;  // snapping made a face without area: refused, as it should be
        }
        Subdivided<float> sub;
        REQUIRE_NOTHROW(sub = subdivide_with_report(mesh, {.max_edge = trial % 2 ? 0.0 : 0.15}));
        const IntersectionReport& r = sub.report.intersections;
        CHECK(mesh_area(sub.mesh) + r.left_out_area == test::approx(mesh_area(mesh)).epsilon(1e-9));
        cut_faces += r.cut_faces;
        left_out += r.left_out;
        failed += r.failed_faces;
        if (!grid) planar_failed += r.failed_faces;
    }
    MESSAGE(cut_faces << " faces cut, " << left_out << " pieces left out, " << failed
                      << " crossed faces kept whole");
    CHECK(cut_faces > 500);
    CHECK(left_out > 100);
    CHECK(planar_failed == 0);  // off the grid every face is planar and in general position
}
