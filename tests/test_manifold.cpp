// make_manifold (mesh/manifold.hpp) on hand-built face lists with known answers: a manifold
// left as it is; a third face on an edge, a face running along an edge the same way as another,
// and a duplicate face each moved onto copies of their vertices; bow-tie vertices split into one
// copy per fan; seeded polygon soups over a few shared vertices, whose results OpenMesh must
// take face by face with every vertex manifold; and the same output, face for face and copy for
// copy, as the plain version of the method kept here (a std::set and std::map of edges, a
// std::map of neighbours per ring).
#include <radiosity/mesh/manifold.hpp>

#include <doctest/doctest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace radiosity;

namespace {

using Faces = std::vector<std::vector<std::uint32_t>>;

std::vector<std::uint32_t> identity(std::size_t n) {
    std::vector<std::uint32_t> v(n);
    std::iota(v.begin(), v.end(), std::uint32_t{0});
    return v;
}

/// The invariants of the file comment: input order kept, every output corner standing for its
/// input corner, each directed edge once, each undirected edge at most twice.
void check_invariants(const Faces& in, std::size_t vertices, const ManifoldFaces& out) {
    REQUIRE(out.faces.size() == in.size());
    REQUIRE(out.origin.size() >= vertices);
    for (std::uint32_t v = 0; v < vertices; ++v) CHECK(out.origin[v] == v);
    std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t f = 0; f < in.size(); ++f) {
        REQUIRE(out.faces[f].size() == in[f].size());
        for (std::size_t k = 0; k < in[f].size(); ++k) {
            const std::uint32_t a = out.faces[f][k], b = out.faces[f][(k + 1) % in[f].size()];
            REQUIRE(a < out.origin.size());
            CHECK(out.origin[a] == in[f][k]);
            CHECK(directed.insert({a, b}).second);
            CHECK(++uses[std::minmax(a, b)] <= 2);
        }
    }
}

/// make_manifold's plain version, its two steps as the file comment of manifold.hpp has them:
/// (1) a std::set of the directed edges and a std::map of the undirected edges' uses over the
/// faces kept so far; (2) around each vertex, a std::map from each neighbour to the first ring
/// entry that named it, uniting the entries that share one, and a std::map from each fan's root
/// to its vertex. The library's version keeps flat rows per vertex instead.
ManifoldFaces plain_make_manifold(const Faces& faces, std::size_t vertex_count) {
    ManifoldFaces out;
    out.origin = identity(vertex_count);
    auto copy_of = [&](std::uint32_t v) {
        out.origin.push_back(out.origin[v]);
        return static_cast<std::uint32_t>(out.origin.size() - 1);
    };
    std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& f : faces) {
        bool fits = true;
        for (std::size_t k = 0; k < f.size() && fits; ++k) {
            const std::uint32_t a = f[k], b = f[(k + 1) % f.size()];
            const auto key = std::minmax(a, b);
            fits = !directed.count({a, b}) && uses[{key.first, key.second}] < 2;
        }
        std::vector<std::uint32_t> g = f;
        if (fits) {
            for (std::size_t k = 0; k < f.size(); ++k) {
                const std::uint32_t a = f[k], b = f[(k + 1) % f.size()];
                directed.insert({a, b});
                const auto key = std::minmax(a, b);
                ++uses[{key.first, key.second}];
            }
        } else {
            for (auto& v : g) v = copy_of(v);
        }
        out.faces.push_back(std::move(g));
    }
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> around(out.origin.size());
    for (std::size_t f = 0; f < out.faces.size(); ++f)
        for (std::size_t k = 0; k < out.faces[f].size(); ++k)
            around[out.faces[f][k]].push_back({f, k});
    for (std::uint32_t v = 0; v < around.size(); ++v) {
        const auto& ring = around[v];
        if (ring.size() < 2) continue;
        std::vector<std::size_t> group(ring.size());
        std::iota(group.begin(), group.end(), std::size_t{0});
        auto find = [&](std::size_t x) {
            while (group[x] != x) x = group[x] = group[group[x]];
            return x;
        };
        std::map<std::uint32_t, std::size_t> by_neighbour;
        for (std::size_t r = 0; r < ring.size(); ++r) {
            const auto& f = out.faces[ring[r].first];
            const std::size_t k = ring[r].second, n = f.size();
            for (std::uint32_t w : {f[(k + 1) % n], f[(k + n - 1) % n]}) {
                auto [it, fresh] = by_neighbour.try_emplace(w, r);
                if (!fresh) group[find(r)] = find(it->second);
            }
        }
        std::map<std::size_t, std::uint32_t> vertex_of;
        for (std::size_t r = 0; r < ring.size(); ++r) {
            auto [it, fresh] = vertex_of.try_emplace(find(r), v);
            if (fresh && vertex_of.size() > 1) it->second = copy_of(v);
            out.faces[ring[r].first][ring[r].second] = it->second;
        }
    }
    return out;
}

/// OpenMesh's verdict: every face added, and every vertex manifold (at most one boundary fan).
void check_openmesh_takes(const ManifoldFaces& m) {
    OpenMesh::PolyMesh_ArrayKernelT<> mesh;
    std::vector<OpenMesh::VertexHandle> vh;
    for (std::size_t v = 0; v < m.origin.size(); ++v)
        vh.push_back(mesh.add_vertex({float(v), float(v * v % 7), float(v % 3)}));
    std::size_t added = 0;
    for (const auto& f : m.faces) {
        std::vector<OpenMesh::VertexHandle> corners;
        for (std::uint32_t v : f) corners.push_back(vh[v]);
        added += mesh.add_face(corners).is_valid();
    }
    CHECK(added == m.faces.size());
    std::size_t complex = 0;
    for (auto v : mesh.vertices()) complex += !mesh.is_manifold(v);
    CHECK(complex == 0);
}

}  // namespace

TEST_CASE("make_manifold leaves a manifold alone: a closed cube and an open fan") {
    const Faces cube{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                     {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    const Faces fan{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}};  // open: vertex 0 on the boundary
    for (const auto& [faces, n] :
         {std::pair{cube, std::size_t{8}}, std::pair{fan, std::size_t{5}}}) {
        const ManifoldFaces m = make_manifold(faces, n);
        CHECK(m.faces == faces);
        CHECK(m.origin == identity(n));
        check_openmesh_takes(m);
    }
}

TEST_CASE("make_manifold moves a third face on an edge onto copies of its vertices") {
    // Three triangles on the edge 0-1 (pages of a book): the first two agree (0->1, 1->0), the
    // third would be the edge's third face.
    const Faces book{{0, 1, 2}, {1, 0, 3}, {0, 4, 1}};
    const ManifoldFaces m = make_manifold(book, 5);
    CHECK(m.faces == Faces{{0, 1, 2}, {1, 0, 3}, {5, 6, 7}});
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 0, 4, 1});
    check_invariants(book, 5, m);
    check_openmesh_takes(m);
}

TEST_CASE("make_manifold moves a face running along an edge the same way, and a duplicate") {
    // Two triangles on 0-1 that both run 0 -> 1 (one of them faces the wrong way): only two
    // faces on the edge, yet a half-edge mesh cannot hold them.
    const Faces same_way{{0, 1, 2}, {0, 1, 3}};
    ManifoldFaces m = make_manifold(same_way, 4);
    CHECK(m.faces == Faces{{0, 1, 2}, {4, 5, 6}});
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 0, 1, 3});
    check_invariants(same_way, 4, m);
    check_openmesh_takes(m);
    // The same quad twice, and once more turned about (its vertices in another starting place).
    const Faces twice{{0, 1, 2, 3}, {0, 1, 2, 3}, {2, 3, 0, 1}};
    m = make_manifold(twice, 4);
    CHECK(m.faces == Faces{{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}});
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 0, 1, 2, 3, 2, 3, 0, 1});
    check_invariants(twice, 4, m);
    check_openmesh_takes(m);
    // The quad and its back face (reversed): each edge once each way, which is manifold.
    const Faces two_sided{{0, 1, 2, 3}, {3, 2, 1, 0}};
    m = make_manifold(two_sided, 4);
    CHECK(m.faces == two_sided);
    CHECK(m.origin == identity(4));
    check_openmesh_takes(m);
}

TEST_CASE("make_manifold gives each fan at a bow-tie vertex after the first its own copy") {
    // Two triangles meeting only at vertex 0.
    const Faces bow_tie{{0, 1, 2}, {0, 3, 4}};
    ManifoldFaces m = make_manifold(bow_tie, 5);
    CHECK(m.faces == Faces{{0, 1, 2}, {5, 3, 4}});
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 0});
    check_invariants(bow_tie, 5, m);
    check_openmesh_takes(m);
    // Three fans of two triangles each at vertex 0, listed interleaved: the faces of a fan,
    // joined through the edge they share at 0, take the same copy; fans are numbered in the
    // order their first face comes.
    const Faces fans{{0, 1, 2}, {0, 3, 4}, {0, 5, 6}, {0, 2, 7}, {0, 8, 3}, {0, 6, 9}};
    m = make_manifold(fans, 10);
    CHECK(m.faces == Faces{{0, 1, 2}, {10, 3, 4}, {11, 5, 6}, {0, 2, 7}, {10, 8, 3}, {11, 6, 9}});
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0});
    check_invariants(fans, 10, m);
    check_openmesh_takes(m);
    // Two closed cones (octahedron halves) touching at their apex 0: two fans, each closed.
    const Faces cones{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1},
                      {0, 5, 6}, {0, 6, 7}, {0, 7, 8}, {0, 8, 5}};
    m = make_manifold(cones, 9);
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 0});
    for (std::size_t f = 0; f < cones.size(); ++f) CHECK(m.faces[f][0] == (f < 4 ? 0u : 9u));
    check_openmesh_takes(m);
}

TEST_CASE("make_manifold: an edge repair and a bow-tie in one input") {
    // Face 2 would be a third face on the edge 0-1 and moves to copies (leaving vertex 4 with
    // no face); face 3 meets faces 0 and 1 only at vertex 0, a bow-tie, and takes a copy of it.
    const Faces faces{{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {0, 5, 6}};
    const ManifoldFaces m = make_manifold(faces, 7);
    CHECK(m.faces[2] == std::vector<std::uint32_t>{7, 8, 9});
    CHECK(m.faces[3] == std::vector<std::uint32_t>{10, 5, 6});
    CHECK(m.origin == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 0, 1, 4, 0});
    check_invariants(faces, 7, m);
    check_openmesh_takes(m);
}

TEST_CASE("make_manifold: seeded soups over a few vertices all go into OpenMesh") {
    // Triangles and quads over 9 shared vertices: edges of many faces, both orientations,
    // duplicates and bow-ties everywhere.
    std::mt19937 rng(1234);  // its raw output is fixed by the standard
    std::size_t copies = 0;
    for (int round = 0; round < 200; ++round) {
        const std::size_t n = 9;
        Faces faces(1 + rng() % 12);
        for (auto& f : faces) {
            const std::size_t corners = 3 + rng() % 2;
            while (f.size() < corners) {
                const auto v = static_cast<std::uint32_t>(rng() % n);
                if (std::find(f.begin(), f.end(), v) == f.end()) f.push_back(v);
            }
        }
        CAPTURE(round);
        const ManifoldFaces m = make_manifold(faces, n);
        check_invariants(faces, n, m);
        check_openmesh_takes(m);
        copies += m.origin.size() - n;
    }
    MESSAGE(copies << " vertex copies in 200 soups");
    CHECK(copies > 200);  // the soups did need repairs
}

TEST_CASE("make_manifold gives the plain version's faces and copies on seeded soups") {
    // Soups of every density, from a few shared vertices (every repair at once) to many (mostly
    // manifold, a few bow-ties): the flat rows must give the same faces, in the same order,
    // with the same copies numbered the same way.
    std::mt19937 rng(99);  // its raw output is fixed by the standard
    std::size_t copies = 0;
    for (int round = 0; round < 300; ++round) {
        const std::size_t n = 4 + rng() % 60;
        Faces faces(1 + rng() % 80);
        for (auto& f : faces) {
            const std::size_t corners = 3 + rng() % 3;
            while (f.size() < std::min(corners, n)) {
                const auto v = static_cast<std::uint32_t>(rng() % n);
                if (std::find(f.begin(), f.end(), v) == f.end()) f.push_back(v);
            }
        }
        CAPTURE(round);
        const ManifoldFaces fast = make_manifold(faces, n), plain = plain_make_manifold(faces, n);
        CHECK(fast.faces == plain.faces);
        CHECK(fast.origin == plain.origin);
        copies += plain.origin.size() - n;
    }
    MESSAGE(copies << " vertex copies in 300 soups");
    CHECK(copies > 300);
}
