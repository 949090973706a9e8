// Flat and smooth shading against hand-computed values and identities (a uniform B stays
// uniform; no averaging across creases or materials), and the PLY writer read back by OpenMesh.
#include <radiosity/io/ply.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/shading/vertex_shading.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>
#include <support/scenes.hpp>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace radiosity;

namespace {

/// The mesh of a scene with B set per face.
Mesh<float> mesh_with(const Scene<float>& s, const std::vector<float>& B) {
    Mesh<float> m = build_mesh(s);
    set_face_radiosity<float>(m, B);
    return m;
}

using test::two_squares;

/// The colour of the output vertex at position p that belongs to a triangle touching face f
/// (identified by a point strictly inside it).
glm::vec3 colour_at(const ShadedMesh& m, const Vec3& p, const Vec3& inside) {
    for (const auto& t : m.triangles) {
        Vec3 c(0.0);
        for (auto v : t) c += m.positions[v] / 3.0;
        for (auto v : t)
            if (glm::distance(m.positions[v], p) < 1e-12 && glm::distance(c, inside) < 0.5)
                return m.colours[v];
    }
    FAIL("no such vertex");
    return {};
}

}  // namespace

TEST_CASE("flat shading gives every patch its own colour at its own vertices") {
    const auto m = mesh_with(two_squares(), {1.0f, 3.0f});
    const ShadedMesh s = flat_shading(m);
    CHECK(s.positions.size() == 8);
    CHECK(s.triangles.size() == 4);
    CHECK(colour_at(s, {1, 0, 0}, {0.5, 0.5, 0}) == glm::vec3(1.0f));
    CHECK(colour_at(s, {1, 0, 0}, {1.5, 0.5, 0}) == glm::vec3(3.0f));
}

TEST_CASE("smooth shading: area-weighted means at shared vertices, none across creases") {
    // Flat neighbours: the shared vertices get (1 * 1 + 1 * 3) / 2 = 2; the outer ones keep B.
    const ShadedMesh flat = smooth_shading(mesh_with(two_squares(), {1.0f, 3.0f}));
    CHECK(flat.positions.size() == 6);  // one output vertex per mesh vertex
    CHECK(colour_at(flat, {1, 0, 0}, {0.5, 0.5, 0}).r == test::approx(2.0));
    CHECK(colour_at(flat, {0, 0, 0}, {0.5, 0.5, 0}).r == test::approx(1.0));
    CHECK(colour_at(flat, {2, 0, 0}, {1.5, 0.5, 0}).r == test::approx(3.0));

    // Unequal areas: a 1 x 1 and a 2 x 1 patch give (1 * 1 + 2 * 4) / 3 = 3 at the shared edge.
    Scene<float> s = two_squares();
    s.positions[4] = {3, 0, 0};
    s.positions[5] = {3, 1, 0};
    const ShadedMesh weighted = smooth_shading(mesh_with(s, {1.0f, 4.0f}));
    CHECK(colour_at(weighted, {1, 1, 0}, {0.5, 0.5, 0}).r == test::approx(3.0));

    // A 90-degree fold (sharper than the 30-degree crease angle) and a material change both
    // keep the two patches apart: each side keeps its own B.
    for (const ShadedMesh& apart :
         {smooth_shading(mesh_with(two_squares(true, 90.0), {1.0f, 3.0f})),
          smooth_shading(mesh_with(two_squares(false), {1.0f, 3.0f}))}) {
        CHECK(apart.positions.size() == 8);
        CHECK(colour_at(apart, {1, 0, 0}, {0.5, 0.5, 0}).r == test::approx(1.0));
    }
    // A gentle 20-degree fold is smoothed over.
    const ShadedMesh gentle = smooth_shading(mesh_with(two_squares(true, 20.0), {1.0f, 3.0f}));
    CHECK(gentle.positions.size() == 6);
}

TEST_CASE("smooth shading of a flat grid with a linear B: area-weighted means, by hand") {
    // Columns at x = 0, 1, 3, 4 and rows at y = 0, 2, 3 (unequal cells); each cell's B is the
    // linear function 1 + x + 2y at its centre. At an interior vertex the area-weighted mean of
    // a linear B is its value at the centroid of the four cells around it.
    const std::vector<double> xs{0, 1, 3, 4}, ys{0, 2, 3};
    Scene<float> s;
    for (double y : ys)
        for (double x : xs) s.positions.emplace_back(x, y, 0.0);
    std::vector<float> B;
    for (std::uint32_t j = 0; j < 2; ++j)
        for (std::uint32_t i = 0; i < 3; ++i) {
            s.faces.push_back({j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i});
            const double cx = 0.5 * (xs[i] + xs[i + 1]), cy = 0.5 * (ys[j] + ys[j + 1]);
            B.push_back(static_cast<float>(1.0 + cx + 2.0 * cy));
        }
    s.face_material.assign(6, 0);
    s.materials = {{0.0f, 0.5f, "grey"}};
    const ShadedMesh m = smooth_shading(mesh_with(s, B));
    CHECK(m.positions.size() == 12);
    // Vertex (1, 2): cells of area 2, 4, 1, 2 with B 3.5, 5, 6.5, 8 -> 49.5 / 9 = 5.5.
    CHECK(colour_at(m, {1, 2, 0}, {0.5, 1, 0}).r == test::approx(5.5));
    // Vertex (3, 2): cells of area 4, 2, 2, 1 with B 5, 6.5, 8, 9.5 -> 58.5 / 9 = 6.5.
    CHECK(colour_at(m, {3, 2, 0}, {3.5, 2.5, 0}).g == test::approx(6.5));
    // A corner keeps its one cell's B; an edge vertex (1, 0) averages two: (2 * 3.5 + 4 * 5) / 6.
    CHECK(colour_at(m, {0, 0, 0}, {0.5, 1, 0}).b == test::approx(3.5));
    CHECK(colour_at(m, {1, 0, 0}, {2, 1, 0}).r == test::approx(4.5));
}

TEST_CASE("smooth shading keeps a uniform radiosity uniform") {
    Scene<float> s;  // a 3 x 3 grid of quads
    for (int y = 0; y <= 3; ++y)
        for (int x = 0; x <= 3; ++x) s.positions.emplace_back(x * 0.7, y * 1.3, 0.0);
    for (std::uint32_t y = 0; y < 3; ++y)
        for (std::uint32_t x = 0; x < 3; ++x)
            s.faces.push_back({y * 4 + x, y * 4 + x + 1, (y + 1) * 4 + x + 1, (y + 1) * 4 + x});
    s.face_material.assign(9, 0);
    s.materials = {{0.0f, 0.5f, "grey"}};
    const ShadedMesh m = smooth_shading(mesh_with(s, std::vector<float>(9, 2.5f)));
    CHECK(m.positions.size() == 16);
    REQUIRE(m.colours.size() == m.positions.size());
    for (const auto& c : m.colours) CHECK(c == glm::vec3(2.5f));
}

TEST_CASE("PLY: written through OpenMesh, read back with clamped sRGB colours") {
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.colours = {glm::vec3(0.0f), glm::vec3(0.5f), glm::vec3(4.0f)};  // the last one too bright
    m.triangles = {{0, 1, 2}};
    const auto path = std::filesystem::temp_directory_path() /
                      ("radiosity_ply_test_" + std::to_string(::getpid()) + ".ply");
    write_ply(m, path.string(), 1.0);
    OpenMesh::TriMesh_ArrayKernelT<> back;
    back.request_vertex_colors();
    OpenMesh::IO::Options o(OpenMesh::IO::Options::VertexColor);
    REQUIRE(OpenMesh::IO::read_mesh(back, path.string(), o));
    std::filesystem::remove(path);
    REQUIRE(back.n_vertices() == 3);
    REQUIRE(back.n_faces() == 1);
    const auto c0 = back.color(back.vertex_handle(0)), c1 = back.color(back.vertex_handle(1)),
               c2 = back.color(back.vertex_handle(2));
    CHECK(int(c0[0]) == 0);
    CHECK(int(c1[0]) == srgb8(0.5f));  // 188: the sRGB code of linear 0.5
    CHECK(int(c1[0]) == 188);
    CHECK(int(c2[0]) == 255);  // clamped, not wrapped round
    CHECK_THROWS_AS(write_ply(m, "/no/such/folder/x.ply", 1.0), Error);
}

TEST_CASE("PLY with linear float colours: unclamped values, read back by hand") {
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.colours = {glm::vec3(0.0f), glm::vec3(0.5f, 0.25f, 0.125f), glm::vec3(4.0f)};
    m.triangles = {{0, 1, 2}};
    const auto path = std::filesystem::temp_directory_path() /
                      ("radiosity_plyf_test_" + std::to_string(::getpid()) + ".ply");
    write_ply(m, path.string(), 2.0, PlyColours::linear_float);
    // OpenMesh's reader rounds float colours to 8 bits, so read the binary PLY directly: a
    // header, then per vertex x y z red green blue as little-endian floats.
    std::ifstream in(path, std::ios::binary);
    std::string line, header;
    while (std::getline(in, line) && line != "end_header") header += line + "\n";
    CHECK(header.find("format binary_little_endian") != std::string::npos);
    CHECK(header.find("element vertex 3") != std::string::npos);
    CHECK(header.find("property float red") != std::string::npos);
    float v[3][6];
    in.read(reinterpret_cast<char*>(v), sizeof v);
    REQUIRE(in);
    std::filesystem::remove(path);
    CHECK(v[1][3] == test::approx(1.0));  // 2 x 0.5
    CHECK(v[1][5] == test::approx(0.25));
    CHECK(v[2][4] == test::approx(8.0));  // not clamped
}
