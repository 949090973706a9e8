// Lightmap plumbing and baking on hand-made meshes whose answers are known exactly: lightmap UVs
// through build_mesh, OBJ and subdivision (an affine UV map stays affine); conservative
// rasterisation (thin triangles get texels); a linear radiosity baked exactly (edge texels at
// the nearest point); texels inside a closed box detected and refilled; dilation that never
// crosses from one chart into another; seams that agree; thread independence; the lightmap
// rendered back through its UVs; EXR and the lightmapped glTF read back.
#include <radiosity/io/gltf.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/lightmap/bake.hpp>
#include <radiosity/mesh/subdivide.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/shading/vertex_shading.hpp>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "support/approx.hpp"
#include "support/threads.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

using namespace radiosity;
namespace fs = std::filesystem;

namespace {

fs::path temp(const std::string& name) {
    return fs::temp_directory_path() / ("radiosity_bake_" + std::to_string(::getpid()) + name);
}

/// A 2 x 1 rectangle in the plane z = 0 as one quad, with UVs an affine image of x and y.
glm::vec2 affine_uv(const Vec3& p) {
    return {float(0.05 + 0.25 * p.x + 0.05 * p.y), float(0.1 + 0.1 * p.x + 0.6 * p.y)};
}

Scene<float> rectangle_scene() {
    Scene<float> s;
    s.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    s.faces = {{0, 1, 2, 3}};
    s.face_material = {0};
    s.materials = {{0.0f, 0.5f, "grey"}};
    s.face_uvs = {{affine_uv(s.positions[0]), affine_uv(s.positions[1]), affine_uv(s.positions[2]),
                   affine_uv(s.positions[3])}};
    return s;
}

/// A linear function of position, for exact interpolation checks.
glm::vec3 linear_light(const Vec3& p) {
    return glm::vec3(float(1.0 + 0.5 * p.x), float(2.0 - 0.25 * p.y), float(0.5 + 0.1 * p.x));
}

/// A unit square (z = 0) of two triangles, coloured with linear_light, its UVs mapping it onto
/// the texel rectangle [x0, x0 + w] x [y0, y0 + w] of a size x size lightmap.
ShadedMesh square(double x0, double y0, double w, int size, Vec3 offset = Vec3(0.0)) {
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (auto& p : m.positions) {
        m.uvs.emplace_back(float((x0 + w * p.x) / size), float((y0 + w * p.y) / size));
        p += offset;
        m.colours.push_back(linear_light(p));
    }
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

void append(ShadedMesh& to, const ShadedMesh& from) {
    const auto base = static_cast<std::uint32_t>(to.positions.size());
    to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
    to.colours.insert(to.colours.end(), from.colours.begin(), from.colours.end());
    to.uvs.insert(to.uvs.end(), from.uvs.begin(), from.uvs.end());
    for (auto t : from.triangles) to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

BakeOptions no_inside_test() {
    BakeOptions o;
    o.inside_rays = 0;
    return o;
}

}  // namespace

TEST_CASE("lightmap UVs go onto the mesh's corners, survive a copy and are validated") {
    const Scene<float> s = rectangle_scene();
    const Mesh<float> mesh = build_mesh(s);
    REQUIRE(has_corner_uvs(mesh));
    const Mesh<float> copy = mesh;
    REQUIRE(has_corner_uvs(copy));
    for (auto f : copy.faces()) {
        const auto uv = corner_uvs(copy, f);
        const auto poly = face_polygon(copy, f);
        REQUIRE(uv.size() == poly.size());
        for (std::size_t k = 0; k < uv.size(); ++k) {
            CHECK(uv[k].x == test::approx(affine_uv(poly[k]).x));
            CHECK(uv[k].y == test::approx(affine_uv(poly[k]).y));
        }
    }
    Scene<float> bad = s;
    bad.face_uvs[0][2] = {1.5f, 0.0f};
    CHECK_THROWS_WITH_AS(build_mesh(bad), doctest::Contains("face 0"), Error);
    bad = s;
    bad.face_uvs[0].pop_back();
    CHECK_THROWS_WITH_AS(build_mesh(bad), doctest::Contains("3 UVs for 4 corners"), Error);
}

TEST_CASE("subdivision interpolates the UVs: an affine UV map stays exact on every child") {
    Scene<float> s = rectangle_scene();
    // A triangle beside the rectangle (sharing its right edge) with the same affine map.
    s.positions.push_back({3, 0.5, 0});
    s.faces.push_back({1, 4, 2});
    s.face_material.push_back(0);
    s.face_uvs.push_back(
        {affine_uv(s.positions[1]), affine_uv(s.positions[4]), affine_uv(s.positions[2])});
    const Mesh<float> fine = subdivide(build_mesh(s), {.max_edge = 0.3});
    REQUIRE(fine.n_faces() > 40);
    REQUIRE(has_corner_uvs(fine));
    for (auto f : fine.faces()) {
        const auto uv = corner_uvs(fine, f);
        const auto poly = face_polygon(fine, f);
        for (std::size_t k = 0; k < uv.size(); ++k) {
            CHECK(uv[k].x == test::approx(affine_uv(poly[k]).x).epsilon(1e-6));
            CHECK(uv[k].y == test::approx(affine_uv(poly[k]).y).epsilon(1e-6));
        }
    }
    // Smooth shading keeps them, one per output vertex.
    const ShadedMesh shaded = smooth_shading(fine);
    REQUIRE(shaded.uvs.size() == shaded.positions.size());
    for (std::size_t v = 0; v < shaded.uvs.size(); ++v) {
        CHECK(shaded.uvs[v].x == test::approx(affine_uv(shaded.positions[v]).x).epsilon(1e-6));
        CHECK(shaded.uvs[v].y == test::approx(affine_uv(shaded.positions[v]).y).epsilon(1e-6));
    }
}

TEST_CASE("OBJ texture coordinates become lightmap UVs, v flipped to rows from the top") {
    const fs::path path = temp("uv.obj");
    {
        std::ofstream o(path);
        o << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.25 0.25\nvt 0.75 0.25\nvt 0.75 0.75\n"
             "vt 0.25 1\nf 1/1 2/2 3/3 4/4\n";
    }
    const Mesh<float> mesh = build_mesh(read_obj<float>(path.string()));
    REQUIRE(has_corner_uvs(mesh));
    const auto uv = corner_uvs(mesh, *mesh.faces().begin());
    const auto poly = face_polygon(mesh, *mesh.faces().begin());
    std::size_t corners = 0;
    for (std::size_t k = 0; k < 4; ++k)
        if (poly[k] == Vec3(0, 1, 0)) {
            CHECK(uv[k] == glm::vec2(0.25f, 0.0f));
            ++corners;
        }
    CHECK(corners == 1);
    // A file whose vt lie outside [0, 1] (a tiled texture) simply has no lightmap UVs.
    {
        std::ofstream o(path);
        o << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 4 0\nvt 0 4\nf 1/1 2/2 3/3\n";
    }
    CHECK_FALSE(has_corner_uvs(build_mesh(read_obj<float>(path.string()))));
    fs::remove(path);
}

TEST_CASE("a linear radiosity is baked exactly: at covered texel centres, else the nearest point") {
    const int size = 32;
    const ShadedMesh m = square(4.0, 6.0, 20.0, size);  // texels [4, 24] x [6, 26]
    const Lightmap lm = bake_lightmap(m, size, size, no_inside_test());
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            CAPTURE(x);
            CAPTURE(y);
            const std::size_t i = lm.index(x, y);
            // Conservatively, every texel whose square touches the chart: the 20 x 20 whose
            // centres it covers and the ring around them.
            const bool touches = x >= 3 && x <= 24 && y >= 5 && y <= 26;
            CHECK((lm.state[i] == TexelState::surface) == touches);
            if (!touches) continue;
            // The light at the texel centre, or (in the ring) at the chart's point nearest to it.
            const Vec3 p((std::clamp(x + 0.5, 4.0, 24.0) - 4.0) / 20.0,
                         (std::clamp(y + 0.5, 6.0, 26.0) - 6.0) / 20.0, 0.0);
            for (int k = 0; k < 3; ++k)
                CHECK(lm.image.pixels[i][k] == test::approx(linear_light(p)[k]).epsilon(1e-5));
        }
}

TEST_CASE("conservative rasterisation: a triangle thinner than a texel still gets its texels") {
    const int size = 16;
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0.01, 0}};
    m.colours = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f)};
    // A sliver a tenth of a texel high, between texel centres, 10 texels long.
    m.uvs = {
        {2.0f / size, 5.05f / size}, {12.0f / size, 5.05f / size}, {12.0f / size, 5.15f / size}};
    m.triangles = {{0, 1, 2}};
    const Lightmap lm = bake_lightmap(m, size, size, no_inside_test());
    for (int x = 2; x < 12; ++x) {
        CHECK(lm.state[lm.index(x, 5)] == TexelState::surface);
        CHECK(lm.image.pixels[lm.index(x, 5)].x == test::approx(1.0f));
    }
}

namespace {
/// A 4 x 4 floor (z = 0, facing up) as 3 x 3 quads cut at 1.5 and 2.5, each with its own
/// vertices, mapped onto the whole 64 x 64 lightmap (no texel centre on a cut); the middle quad is
/// black (as a solve leaves the floor under a box), the others have B = 2. On it stands a closed
/// box over [1.5, 2.5]^2, faces outward, whose faces take no texels (their UVs sit in one corner
/// texel).
ShadedMesh floor_and_box(double box_height) {
    ShadedMesh m;
    const double cut[4] = {0.0, 1.5, 2.5, 4.0};
    auto quad = [&](const std::array<Vec3, 4>& c, glm::vec3 colour, bool texels) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const Vec3& p : c) {
            m.positions.push_back(p);
            m.colours.push_back(colour);
            m.uvs.push_back(texels ? glm::vec2(float(p.x / 4.0), float(p.y / 4.0))
                                   : glm::vec2(0.5f / 64.0f));
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
    };
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            quad({Vec3(cut[i], cut[j], 0), Vec3(cut[i + 1], cut[j], 0),
                  Vec3(cut[i + 1], cut[j + 1], 0), Vec3(cut[i], cut[j + 1], 0)},
                 glm::vec3(i == 1 && j == 1 ? 0.0f : 2.0f), true);
    const double h = box_height;
    const std::vector<Vec3> c{{1.5, 1.5, 0}, {2.5, 1.5, 0}, {2.5, 2.5, 0}, {1.5, 2.5, 0},
                              {1.5, 1.5, h}, {2.5, 1.5, h}, {2.5, 2.5, h}, {1.5, 2.5, h}};
    for (const auto& f : std::vector<std::array<int, 4>>{
             {0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}})
        quad({c[f[0]], c[f[1]], c[f[2]], c[f[3]]}, glm::vec3(1.0f), false);
    return m;
}
}  // namespace

TEST_CASE("texels inside a closed box standing on a floor are detected") {
    const int size = 64;
    const ShadedMesh m = floor_and_box(1.0);
    const Lightmap lm = bake_lightmap(m, size, size);
    // Texel x covers floor x in [x, x + 1] / 16; the box covers [1.5, 2.5].
    std::size_t inside = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double px = (x + 0.5) / 16.0, py = (y + 0.5) / 16.0;
            const bool under = px > 1.55 && px < 2.45 && py > 1.55 && py < 2.45;
            const bool clear = px < 1.4 || px > 2.6 || py < 1.4 || py > 2.6;
            const TexelState s = lm.state[lm.index(x, y)];
            if (under) CHECK(s == TexelState::inside);
            if (clear) CHECK(s == TexelState::surface);
            inside += s == TexelState::inside;
        }
    CHECK(inside == 16 * 16);
    CHECK(bake_lightmap(m, size, size, no_inside_test()).count(TexelState::inside) == 0);
}

TEST_CASE("inside texels take their valid neighbours' light instead of staying black") {
    const int size = 64;
    const ShadedMesh m = floor_and_box(2.0);
    const Lightmap raw = bake_lightmap(m, size, size, no_inside_test());
    const Lightmap lm = bake_lightmap(m, size, size);
    REQUIRE(lm.count(TexelState::inside) > 100);
    std::size_t were_black = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::size_t i = lm.index(x, y);
            were_black += raw.image.pixels[i].x == 0.0f;
            CHECK(lm.image.pixels[i].x == test::approx(2.0f));
        }
    CHECK(were_black == 16 * 16);
}

TEST_CASE("dilation fills each chart's gutter from that chart only, never over a valid texel") {
    const int size = 32;
    ShadedMesh m = square(2.0, 2.0, 10.0, size);
    ShadedMesh green = square(16.0, 2.0, 10.0, size, Vec3(5, 0, 0));  // 4 texels to the right
    for (auto& col : m.colours) col = glm::vec3(1.0f, 0.0f, 0.0f);
    for (auto& col : green.colours) col = glm::vec3(0.0f, 1.0f, 0.0f);
    append(m, green);
    BakeOptions o = no_inside_test();
    o.dilation = 3;  // more than the 2 texels of gutter each side: the charts' fronts meet
    const Lightmap lm = bake_lightmap(m, size, size, o);
    const Lightmap undilated = bake_lightmap(m, size, size, [] {
        BakeOptions u = no_inside_test();
        u.dilation = 0;
        return u;
    }());
    std::size_t dilated = 0;
    for (std::size_t i = 0; i < lm.state.size(); ++i) {
        if (undilated.state[i] == TexelState::surface) {  // valid texels are untouched
            CHECK(lm.state[i] == TexelState::surface);
            CHECK(lm.image.pixels[i] == undilated.image.pixels[i]);
        }
        if (lm.state[i] != TexelState::dilated) continue;
        ++dilated;
        const glm::vec3 v = lm.image.pixels[i];
        CHECK(((v.x == 1.0f && v.y == 0.0f) || (v.x == 0.0f && v.y == 1.0f)));  // never a mix
        const int x = int(i % size), y = int(i / size);
        if (y >= 1 && y <= 12 && x <= 13) CHECK(v.x == 1.0f);  // the red chart's side of the gap
        if (y >= 1 && y <= 12 && x >= 14) CHECK(v.y == 1.0f);  // and the green one's
    }
    CHECK(dilated > 100);
}

TEST_CASE("a seam: texels of two charts at the same surface point agree within a texel's change") {
    // One 2 x 1 strip cut into two unit squares, placed apart in the atlas; the light is linear
    // across the strip, continuous over the seam x = 1.
    const int size = 64;
    ShadedMesh m = square(4.0, 4.0, 24.0, size);
    append(m, square(36.0, 4.0, 24.0, size, Vec3(1, 0, 0)));
    const Lightmap lm = bake_lightmap(m, size, size, no_inside_test());
    const double gradient = 0.5, texel = 1.0 / 24.0;  // |dB/dx| of linear_light, texel in units
    for (int k = 0; k <= 20; ++k) {
        const double y = (k + 0.5) / 21.0;
        const glm::vec3 a =
            sample_bilinear(lm.image, {float(28.0 / size), float((4 + 24 * y) / size)});
        const glm::vec3 b =
            sample_bilinear(lm.image, {float(36.0 / size), float((4 + 24 * y) / size)});
        CHECK(std::abs(a.x - b.x) <= gradient * texel * 1.01);
        CHECK(std::abs(a.x - linear_light(Vec3(1, y, 0)).x) <= gradient * texel);
    }
}

TEST_CASE("the lightmap rendered back through its UVs matches the vertex-interpolated picture") {
    const int size = 128;
    ShadedMesh m = square(4.0, 4.0, 120.0, size);
    const Camera cam{{0.5, 0.5, 2.0}, {0.5, 0.5, 0.0}, {0, 1, 0}, 30.0};
    const RenderOptions ro{.width = 96, .height = 96};
    const Image direct = render(m, cam, ro);
    const Image baked =
        render_lightmapped(m, bake_lightmap(m, size, size, no_inside_test()).image, cam, ro);
    // Where each pixel looks in the lightmap (z = 1 marks the square's pixels).
    const Image where = render_with(m, cam, ro, [&](std::size_t i, const glm::dvec3& w) {
        return glm::vec3(interpolate_uv(m, i, w) * float(size), 1.0f);
    });
    const double gradient = 0.5, texel = 1.0 / 120.0;  // largest |dB/dx|; a texel in units
    double interior = 0.0, border = 0.0;
    std::size_t pixels = 0;
    for (std::size_t i = 0; i < direct.pixels.size(); ++i) {
        if (where.pixels[i].z != 1.0f) continue;
        ++pixels;
        const glm::vec2 t(where.pixels[i]);  // texel coordinates; the chart spans [4, 124]
        const bool inner = t.x > 5.0f && t.x < 123.0f && t.y > 5.0f && t.y < 123.0f;
        for (int k = 0; k < 3; ++k) {
            const double e = std::abs(direct.pixels[i][k] - baked.pixels[i][k]);
            (inner ? interior : border) = std::max(inner ? interior : border, e);
        }
    }
    REQUIRE(pixels > 5000);
    CHECK(interior < 2e-5);             // bilinear filtering reproduces a linear function exactly
    CHECK(border <= gradient * texel);  // at the border, within one texel's change
}

TEST_CASE("the bake is bit-identical on 1 and 2 threads" *
          doctest::skip(test::threads::without_openmp) *
          doctest::description("needs OpenMP: without it every run is on one thread")) {
    // The floor and box: texels inside the box are found by rays seeded per texel, so a
    // thread-dependent stream would change which texels are inside, and so the light they take.
    const int size = 64;
    const ShadedMesh m = floor_and_box(1.0);
    std::vector<Lightmap> runs;
    for (int threads : {1, 2}) {
        const test::threads::Forced forced(threads);
        REQUIRE(test::threads::team_size() == threads);  // else nothing would be compared
        runs.push_back(bake_lightmap(m, size, size));
    }
    const Lightmap &one = runs[0], &two = runs[1];
    REQUIRE(one.count(TexelState::inside) > 0);
    REQUIRE(one.count(TexelState::surface) > 0);
    CHECK(std::memcmp(one.image.pixels.data(), two.image.pixels.data(),
                      one.image.pixels.size() * sizeof(glm::vec3)) == 0);
    CHECK(one.state == two.state);
    CHECK(one.island == two.island);
}

TEST_CASE("bad bake input is refused with a clear error") {
    ShadedMesh m = square(0, 0, 4, 8);
    CHECK_THROWS_WITH_AS(bake_lightmap(m, 0, 8), doctest::Contains("size"), Error);
    m.uvs.pop_back();
    CHECK_THROWS_WITH_AS(bake_lightmap(m, 8, 8), doctest::Contains("no lightmap UVs"), Error);
    m = square(0, 0, 4, 8);
    m.uvs[1].x = std::nanf("");
    CHECK_THROWS_WITH_AS(bake_lightmap(m, 8, 8), doctest::Contains("vertex 1"), Error);
}

TEST_CASE("EXR lightmaps hold linear radiance B / pi in 32-bit floats") {
    const ShadedMesh m = square(1.0, 1.0, 6.0, 8);
    const Lightmap lm = bake_lightmap(m, 8, 8, no_inside_test());
    const fs::path path = temp("lm.exr");
    write_image(lm.image, path.string());
    float* rgba = nullptr;
    int w = 0, h = 0;
    const char* err = nullptr;
    REQUIRE(LoadEXR(&rgba, &w, &h, path.string().c_str(), &err) == 0);
    REQUIRE(w == 8);
    REQUIRE(h == 8);
    for (int i = 0; i < 64; ++i)
        for (int k = 0; k < 3; ++k)
            CHECK(rgba[4 * i + k] ==
                  test::approx(lm.image.pixels[i][k] / std::numbers::pi_v<float>));
    std::free(rgba);
    fs::remove(path);
    CHECK_THROWS_WITH_AS(write_image(lm.image, temp("lm.tga").string()),
                         doctest::Contains("unknown picture format"), Error);
}

TEST_CASE("the lightmapped glTF carries the UVs and the lightmap as an embedded PNG texture") {
    const ShadedMesh m = square(1.0, 1.0, 6.0, 8);
    const Lightmap lm = bake_lightmap(m, 8, 8, no_inside_test());
    const fs::path path = temp("lm.gltf");
    write_gltf_lightmapped(m, lm.image, path.string(), 0.25);
    std::ifstream in(path);
    const auto doc = nlohmann::json::parse(in);
    std::ifstream b(fs::path(path).replace_extension(".bin"), std::ios::binary);
    const std::vector<std::uint8_t> bin{std::istreambuf_iterator<char>(b), {}};
    REQUIRE(doc["buffers"][0]["byteLength"].get<std::size_t>() == bin.size());
    const auto& prim = doc["meshes"][0]["primitives"][0];
    CHECK_FALSE(prim["attributes"].contains("COLOR_0"));  // the texture holds the light
    const auto& acc = doc["accessors"][prim["attributes"]["TEXCOORD_0"].get<int>()];
    CHECK(prim["attributes"]["TEXCOORD_1"] == prim["attributes"]["TEXCOORD_0"]);
    CHECK(acc["type"] == "VEC2");
    const auto& view = doc["bufferViews"][acc["bufferView"].get<int>()];
    std::vector<float> uv(m.uvs.size() * 2);
    REQUIRE(view["byteLength"].get<std::size_t>() == uv.size() * 4);
    std::memcpy(uv.data(), bin.data() + view["byteOffset"].get<std::size_t>(), uv.size() * 4);
    for (std::size_t v = 0; v < m.uvs.size(); ++v) CHECK(uv[2 * v] == m.uvs[v].x);
    const auto& material = doc["materials"][0];
    CHECK(material["pbrMetallicRoughness"]["baseColorTexture"]["index"] == 0);
    const auto& image = doc["images"][doc["textures"][0]["source"].get<int>()];
    CHECK(image["mimeType"] == "image/png");
    const auto& iv = doc["bufferViews"][image["bufferView"].get<int>()];
    const std::uint8_t* png = bin.data() + iv["byteOffset"].get<std::size_t>();
    const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    CHECK(std::memcmp(png, signature, 8) == 0);
    ShadedMesh no_uvs = m;
    no_uvs.uvs.clear();
    CHECK_THROWS_AS(write_gltf_lightmapped(no_uvs, lm.image, path.string(), 1.0), Error);
    fs::remove(path);
    fs::remove(fs::path(path).replace_extension(".bin"));
}
