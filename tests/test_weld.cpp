// Vertex welding (mesh/weld.hpp) against its definition: points at most eps apart are one
// group, transitively, named by its smallest index. Hand-built points with known groups (chains,
// exactly eps apart and just beyond it, a ball and not a box, neighbours across the hash grid's
// cell walls and corners, eps = 0), seeded clusters compared with an all-pairs search, and
// weld_mesh's tolerance of 1e-9 of the bounding-box diagonal on a polygon soup.
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/weld.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using namespace radiosity;

namespace {

using Groups = std::vector<std::size_t>;

/// The definition, by brute force: every pair within eps joined, each point named by the
/// smallest index it is joined to (transitively). O(n^2).
Groups all_pairs(const std::vector<Vec3>& p, double eps) {
    Groups g(p.size());
    for (std::size_t v = 0; v < p.size(); ++v) g[v] = v;
    bool changed = true;
    while (changed) {  // relax until every joined pair carries the same, smallest name
        changed = false;
        for (std::size_t u = 0; u < p.size(); ++u)
            for (std::size_t v = u + 1; v < p.size(); ++v)
                if (glm::distance(p[u], p[v]) <= eps && g[u] != g[v]) {
                    g[u] = g[v] = std::min(g[u], g[v]);
                    changed = true;
                }
    }
    return g;
}

}  // namespace

TEST_CASE("weld_points: chains join transitively, exactly eps apart joins, just beyond does not") {
    const double eps = 0.25, beyond = std::ldexp(1.0, -20);  // binary fractions: exact distances
    const std::vector<Vec3> p{{0, 0, 0}, {0.25, 0, 0}, {0.5, 0, 0}, {0.75 + beyond, 0, 0},
                              {5, 0, 0}, {0, 0, 0},    {5, 0.25, 0}};
    // 0 - 1 - 2 a chain (0 and 2 are 2 eps apart); 3 just beyond eps of 2; 5 on 0; 6 eps from 4.
    CHECK(weld_points(p, eps) == Groups{0, 0, 0, 3, 4, 0, 4});
    CHECK(all_pairs(p, eps) == Groups{0, 0, 0, 3, 4, 0, 4});
}

TEST_CASE("weld_points: a group is named by its smallest index, whatever the order of joining") {
    // Point 3 lies between 1 and 2, which are 2 eps apart: it joins them when it comes last.
    const std::vector<Vec3> p{{5, 5, 5}, {0, 0, 0}, {0, 0.5, 0}, {0, 0.25, 0}};
    CHECK(weld_points(p, 0.25) == Groups{0, 1, 1, 1});
    // Reversed, the same groups under the new indices.
    const std::vector<Vec3> q{p[3], p[2], p[1], p[0]};
    CHECK(weld_points(q, 0.25) == Groups{0, 0, 0, 3});
}

TEST_CASE("weld_points: within eps means within a ball, not a box") {
    const double eps = 0.25;
    // Within eps on every axis, but sqrt(3) x 0.2 = 0.35 apart: not joined.
    CHECK(weld_points(std::vector<Vec3>{{0, 0, 0}, {0.2, 0.2, 0.2}}, eps) == Groups{0, 1});
    // sqrt(3) x 0.125 = 0.22 apart: joined.
    CHECK(weld_points(std::vector<Vec3>{{0, 0, 0}, {0.125, 0.125, 0.125}}, eps) == Groups{0, 0});
}

TEST_CASE("weld_points: neighbours across the grid's cell walls and corners are found") {
    const double eps = 0.25, d = std::ldexp(1.0, -10);  // cells are 2 eps = 0.5 wide
    // Either side of the wall x = 0.5, and either side of x = 0 (floor of negative coordinates).
    CHECK(weld_points(std::vector<Vec3>{{0.5 - d, 0, 0}, {0.5 + d, 0, 0}}, eps) == Groups{0, 0});
    CHECK(weld_points(std::vector<Vec3>{{-d, 3, 3}, {d, 3, 3}}, eps) == Groups{0, 0});
    // Eight points around the corner (0.5, 0.5, 0.5), one in each of the eight cells there
    // (each must find the others in the seven cells beside its own), and one far away.
    std::vector<Vec3> p;
    for (int k = 7; k >= 0; --k)
        p.emplace_back(0.5 + (k & 1 ? d : -d), 0.5 + (k & 2 ? d : -d), 0.5 + (k & 4 ? d : -d));
    p.emplace_back(0.5 + 2 * eps, 0.5, 0.5);
    CHECK(weld_points(p, eps) == Groups{0, 0, 0, 0, 0, 0, 0, 0, 8});
    // A point eps - d before a wall and one d beyond it are exactly eps apart, in cells side by
    // side: joined; one eps - d beyond it is 2 (eps - d) away: not.
    CHECK(weld_points(std::vector<Vec3>{{0.5 - eps + d, 0, 0}, {0.5 + eps - d, 0, 0}}, eps) ==
          Groups{0, 1});
    CHECK(weld_points(std::vector<Vec3>{{0.5 - eps + d, 0, 0}, {0.5 + d, 0, 0}}, eps) ==
          Groups{0, 0});
}

TEST_CASE("weld_points: eps = 0 joins equal points only") {
    const double x = 0.1, next = std::nextafter(x, 1.0);
    const std::vector<Vec3> p{{x, x, x}, {x, next, x}, {x, x, x}, {0.0, 0, 0}, {-0.0, 0, 0}};
    CHECK(weld_points(p, 0.0) == Groups{0, 1, 0, 3, 3});
    CHECK(weld_points(std::vector<Vec3>{}, 1.0).empty());
}

TEST_CASE("weld_points: seeded clusters on a regular grid agree with the all-pairs definition") {
    // Cluster centres on a grid of step 0.5 (many points share coordinates, and the hash cells
    // of 2 eps = 0.002 have walls through the centres); each cluster's points spread by 0 to 3
    // eps, so some clusters weld into one, some into chains, some stay apart.
    const double eps = 1e-3;
    std::mt19937 rng(99);  // its raw output is fixed by the standard
    auto uniform = [&] { return double(rng()) / 4294967296.0; };
    std::size_t welded = 0, kept = 0;
    for (int round = 0; round < 20; ++round) {
        std::vector<Vec3> p;
        for (int c = 0; c < 60; ++c) {
            const Vec3 centre(0.5 * double(rng() % 5) - 1.0, 0.5 * double(rng() % 3),
                              0.5 * double(rng() % 2));
            const double spread = eps * std::vector<double>{0.0, 0.3, 0.6, 1.2, 3.0}[rng() % 5];
            for (std::uint32_t k = 0, n = 1 + rng() % 4; k < n; ++k)
                p.push_back(centre +
                            spread * Vec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5));
        }
        const Groups g = weld_points(p, eps);
        CAPTURE(round);
        CHECK(g == all_pairs(p, eps));
        for (std::size_t v = 0; v < g.size(); ++v) (g[v] == v ? kept : welded) += 1;
    }
    MESSAGE(welded << " points welded, " << kept << " kept");
    CHECK(welded > 1000);  // the cases hold both
    CHECK(kept > 300);
}

TEST_CASE("weld_mesh: a polygon soup's vertices within 1e-9 of the diagonal are welded") {
    // Two quads and a triangle in z = 0 with vertices of their own: the second quad's left
    // corners on the first quad's right ones (one exactly, one 1e-9 off), the triangle's first
    // corner 5e-9 from the second quad's, its last exactly on another. The bounding box is 3 x 1:
    // eps = 1e-9 x sqrt(10) = 3.2e-9.
    Scene<float> s;
    s.positions = {{0, 0, 0}, {1, 0, 0},        {1, 1, 0},        {0, 1, 0}, {1, 0, 0}, {2, 0, 0},
                   {2, 1, 0}, {1, 1 + 1e-9, 0}, {2 + 5e-9, 0, 0}, {3, 0, 0}, {2, 1, 0}};
    s.faces = {{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10}};
    s.face_material = {0, 0, 0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    const Mesh<float> mesh = build_mesh(s);
    REQUIRE(mesh.n_vertices() == s.positions.size());  // a soup: nothing for make_manifold
    const MeshWeld w = weld_mesh(mesh);
    CHECK(w.diagonal == glm::length(Vec3(3, 1 + 1e-9, 0)));  // the box (0, 0, 0) - (3, 1 + 1e-9, 0)
    REQUIRE(w.point.size() == s.positions.size());
    for (auto v : mesh.vertices()) {
        const auto& q = mesh.point(v);
        CHECK(w.point[std::size_t(v.idx())] == Vec3(q[0], q[1], q[2]));
    }
    CHECK(w.group == Groups{0, 1, 2, 3, 1, 5, 6, 2, 8, 9, 6});
    const MeshWeld none = weld_mesh(Mesh<float>{});
    CHECK(none.point.empty());
    CHECK(none.group.empty());
    CHECK(none.diagonal == 0.0);
}
