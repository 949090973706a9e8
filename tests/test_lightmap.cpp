// Lightmap baking end to end on the Cornell box and a sphere: the lightmap drawn through its UVs
// gives the picture of the vertex-interpolated radiosity away from edges; no texel of a chart is
// black; the gutter holds only its own chart's light; texels on both sides of a UV seam agree
// within a texel's change; and the whole bake is bit-identical on 1 and 2 threads.
#include <radiosity/io/gltf.hpp>
#include <radiosity/io/gltf_read.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/lightmap/lightmap.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/shading/tonemap.hpp>

#include <doctest/doctest.h>
#include "support/approx.hpp"
#include "support/threads.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <numbers>

using namespace radiosity;

namespace {

/// The Cornell box baked once into a 256^2 lightmap (shared by the tests: the solve is the
/// expensive part).
const BakeResult<Rgb>& cornell() {
    static const BakeResult<Rgb> baked = [] {
        LightmapOptions o;
        o.unwrap.size = 256;
        return bake(build_mesh(cornell_box<Rgb>()), SolveOptions{}, o);
    }();
    return baked;
}

const Camera cornell_camera{{278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3};

/// Per pixel, the lightmap texel the camera sees there (x, y) and 1, or 0 where it sees nothing.
Image texel_image(const ShadedMesh& m, const Camera& camera, const RenderOptions& o, int size) {
    return render_with(m, camera, o, [&](std::size_t i, const glm::dvec3& w) {
        return glm::vec3(interpolate_uv(m, i, w) * float(size), 1.0f);
    });
}

}  // namespace

TEST_CASE("Cornell box: the lightmap drawn through its UVs matches the direct picture") {
    const auto& b = cornell();
    const int size = b.atlas.width;
    const RenderOptions o{.width = 256, .height = 256, .cull_back_faces = true};
    const Image direct = render(b.shaded, cornell_camera, o);
    const Image textured = render_lightmapped(b.shaded, b.lightmap.image, cornell_camera, o);
    const Image where = texel_image(b.shaded, cornell_camera, o, size);
    // A pixel is away from edges if every pixel within 2 of it sees the same chart (island).
    auto island = [&](int x, int y) {
        const glm::vec3 t = where.at(x, y);
        if (t.z != 1.0f) return Lightmap::no_island;
        return b.lightmap.island[b.lightmap.index(std::clamp(int(t.x), 0, size - 1),
                                                  std::clamp(int(t.y), 0, size - 1))];
    };
    std::vector<double> error;
    double sum = 0.0;
    for (int y = 2; y < o.height - 2; ++y)
        for (int x = 2; x < o.width - 2; ++x) {
            const std::uint32_t here = island(x, y);
            bool interior = here != Lightmap::no_island;
            for (int dy = -2; dy <= 2 && interior; ++dy)
                for (int dx = -2; dx <= 2 && interior; ++dx)
                    interior = island(x + dx, y + dy) == here;
            if (!interior) continue;
            const double d = luminance(direct.at(x, y)), t = luminance(textured.at(x, y));
            REQUIRE(d > 0.0);
            error.push_back(std::abs(t - d) / d);
            sum += error.back();
        }
    REQUIRE(error.size() > 20000);  // most of the picture is away from edges
    std::sort(error.begin(), error.end());
    const double mean = sum / double(error.size()), p99 = error[error.size() * 99 / 100];
    MESSAGE("relative difference away from edges: mean " << mean << ", 99th percentile " << p99
                                                         << ", max " << error.back());
    CHECK(mean < 0.002);
    CHECK(p99 < 0.02);
}

TEST_CASE(
    "Cornell box: no texel of a chart is black, and the texels under the blocks are refilled") {
    const auto& lm = cornell().lightmap;
    std::size_t covered = 0;
    for (std::size_t i = 0; i < lm.state.size(); ++i) {
        if (lm.state[i] != TexelState::surface && lm.state[i] != TexelState::inside) continue;
        ++covered;
        CHECK(luminance(lm.image.pixels[i]) > 0.0f);  // every surface of the box is lit
    }
    CHECK(covered > 256 * 256 / 3);
    // The blocks stand on the floor: the floor under them is inside geometry.
    CHECK(lm.count(TexelState::inside) > 100);
    CHECK(lm.count(TexelState::dilated) > 0);  // the charts' gutters took their light
}

TEST_CASE("Cornell box: the gutter holds only the light of its own chart") {
    const auto& lm = cornell().lightmap;
    // The range of each chart's own texels, per channel.
    std::map<std::uint32_t, std::pair<glm::vec3, glm::vec3>> range;
    for (std::size_t i = 0; i < lm.state.size(); ++i) {
        if (lm.state[i] != TexelState::surface && lm.state[i] != TexelState::inside) continue;
        auto [it, fresh] = range.try_emplace(lm.island[i], lm.image.pixels[i], lm.image.pixels[i]);
        it->second.first = glm::min(it->second.first, lm.image.pixels[i]);
        it->second.second = glm::max(it->second.second, lm.image.pixels[i]);
    }
    REQUIRE(range.size() >= 10);  // walls, ceiling, floor, light, two blocks' sides
    std::size_t gutter = 0;
    const int w = lm.image.width;
    for (std::size_t i = 0; i < lm.state.size(); ++i) {
        if (lm.state[i] != TexelState::dilated) continue;
        ++gutter;
        const auto& [lo, hi] = range.at(lm.island[i]);
        const glm::vec3 v = lm.image.pixels[i];
        for (int k = 0; k < 3; ++k) {
            CHECK(v[k] >= lo[k] * (1.0f - 1e-6f));
            CHECK(v[k] <= hi[k] * (1.0f + 1e-6f));
        }
        // Its nearest chart texel (8-neighbourhood, growing) is of its own chart.
        const int x = int(i % w), y = int(i / w);
        bool own = false, other = false;
        for (int r = 1; r <= 2 && !own && !other; ++r)
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= w || ny >= lm.image.height) continue;
                    const std::size_t j = lm.index(nx, ny);
                    if (lm.state[j] != TexelState::surface && lm.state[j] != TexelState::inside)
                        continue;
                    (lm.island[j] == lm.island[i] ? own : other) = true;
                }
        CHECK(own);
    }
    CHECK(gutter > 1000);
}

TEST_CASE("a sphere cut into charts: texels on both sides of each seam agree") {
    // An icosphere with B a linear function of position, smooth across every edge.
    Scene<float> s;
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    s.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    s.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
               {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    s.face_material.assign(s.faces.size(), 0);
    s.materials = {{0.0f, 0.5f, "grey"}};
    Mesh<float> mesh = subdivide(build_mesh(s), {.max_edge = 0.5});
    // Push the vertices onto the sphere (faces stay planar triangles).
    for (auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v).normalized());
    for (auto f : mesh.faces()) {
        const Vec3 c = polygon_centroid(face_polygon(mesh, f));
        mesh.data(f).radiosity = float(2.0 + c.x + 0.5 * c.y);
    }
    UnwrapOptions uo;
    uo.size = 256;
    const Atlas atlas = make_lightmap_uvs(mesh, uo);
    REQUIRE(atlas.charts > 2);
    SmoothShadingOptions so;
    so.crease_angle_degrees = 60.0;  // the whole sphere is one smooth surface
    const ShadedMesh shaded = smooth_shading(mesh, so);
    BakeOptions bo;
    bo.inside_rays = 0;  // a closed sphere seen from outside: nothing is inside
    const Lightmap lm = bake_lightmap(shaded, atlas.width, atlas.height, bo);
    // The interpolation error: the largest change between neighbouring chart texels.
    float step = 0.0f;
    for (int y = 0; y < lm.image.height; ++y)
        for (int x = 0; x + 1 < lm.image.width; ++x)
            if (lm.state[lm.index(x, y)] == TexelState::surface &&
                lm.state[lm.index(x + 1, y)] == TexelState::surface &&
                lm.island[lm.index(x, y)] == lm.island[lm.index(x + 1, y)])
                step = std::max(step, std::abs(lm.image.pixels[lm.index(x, y)].x -
                                               lm.image.pixels[lm.index(x + 1, y)].x));
    REQUIRE(step > 0.0f);
    // Every edge between faces of different charts is a seam: sample points along it from both.
    std::size_t seams = 0;
    float worst = 0.0f;
    for (auto e : mesh.edges()) {
        const auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
        const auto f0 = mesh.face_handle(h0), f1 = mesh.face_handle(h1);
        if (!f0.is_valid() || !f1.is_valid()) continue;
        if (atlas.face_chart[f0.idx()] == atlas.face_chart[f1.idx()]) continue;
        ++seams;
        const auto a = mesh.from_vertex_handle(h0), b = mesh.to_vertex_handle(h0);
        for (double u : {0.25, 0.5, 0.75}) {
            const glm::vec2 in0 =
                (1.0f - float(u)) * corner_uv(mesh, f0, a) + float(u) * corner_uv(mesh, f0, b);
            const glm::vec2 in1 =
                (1.0f - float(u)) * corner_uv(mesh, f1, a) + float(u) * corner_uv(mesh, f1, b);
            worst = std::max(worst, std::abs(sample_bilinear(lm.image, in0).x -
                                             sample_bilinear(lm.image, in1).x));
        }
    }
    MESSAGE(seams << " seam edges; worst difference " << worst << ", largest texel step " << step);
    REQUIRE(seams > 10);
    CHECK(worst <= step);
}

TEST_CASE("the same scene bakes into bit-identical lightmaps on 1 and 2 threads" *
          doctest::skip(test::threads::without_openmp) *
          doctest::description("needs OpenMP: without it every run is on one thread")) {
    const auto scene = build_mesh(cornell_box<Rgb>());
    LightmapOptions o;
    o.unwrap.size = 128;
    std::vector<BakeResult<Rgb>> runs;
    for (int threads : {1, 2}) {
        const test::threads::Forced forced(threads);
        REQUIRE(test::threads::team_size() == threads);  // else nothing would be compared
        runs.push_back(bake(scene, SolveOptions{}, o));
    }
    const auto &one = runs[0], &two = runs[1];
    // Form factors, the solve, the texels and the inside test (rays seeded per texel, under
    // the blocks) all went into these lightmaps.
    REQUIRE(one.lightmap.count(TexelState::inside) > 0);
    REQUIRE(one.lightmap.image.pixels.size() == two.lightmap.image.pixels.size());
    CHECK(std::memcmp(one.lightmap.image.pixels.data(), two.lightmap.image.pixels.data(),
                      one.lightmap.image.pixels.size() * sizeof(glm::vec3)) == 0);
    CHECK(one.lightmap.state == two.lightmap.state);
    CHECK(one.shaded.uvs == two.shaded.uvs);
}

TEST_CASE("a scene's own UVs are used as they are, and the patches follow the texel size") {
    Scene<float> s;
    s.positions = {{0, 0, 0}, {4, 0, 0}, {4, 2, 0}, {0, 2, 0}, {0, 0, 1}, {4, 0, 1}};
    s.faces = {{0, 1, 2, 3}, {0, 4, 5, 1}};  // a floor and, along one edge, a glowing wall
    s.face_material = {0, 1};
    s.materials = {{0.0f, 0.5f, "floor"}, {10.0f, 0.0f, "light"}};
    s.face_uvs = {{{0.0f, 0.5f}, {1.0f, 0.5f}, {1.0f, 1.0f}, {0.0f, 1.0f}},
                  {{0.0f, 0.25f}, {0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 0.25f}}};
    LightmapOptions o;
    o.unwrap.size = 64;  // 16 texels per unit
    o.texels_per_patch = 4.0;
    const auto r = bake(build_mesh(s), SolveOptions{}, o);
    CHECK_FALSE(r.generated_uvs);
    CHECK(r.atlas.texel_density == test::approx(16.0));
    CHECK(r.solution.patches.size() == 16 * 8 + 16 * 4);  // 0.25-unit patches: 4 texels each
    // The floor's texels hold light that falls off away from the glowing wall (y = 0).
    const auto& lm = r.lightmap;
    for (int y = 19; y <= 28; ++y)    // rows 16..31 are unused: a conservative row and a
        for (int x = 0; x < 64; ++x)  // 2-texel gutter on each side, the rest stays empty
            CHECK(lm.state[lm.index(x, y)] == TexelState::empty);
    const float near = lm.image.at(32, 33).x, far = lm.image.at(32, 62).x;
    CHECK(near > far);
    CHECK(far > 0.0f);
}

TEST_CASE("bad lightmap options are refused") {
    const auto scene = build_mesh(cornell_box<Rgb>());
    LightmapOptions o;
    o.texels_per_patch = -1.0;
    CHECK_THROWS_AS(bake(scene, SolveOptions{}, o), Error);
    o = LightmapOptions{};
    o.unwrap.size = 4;
    CHECK_THROWS_AS(bake(scene, SolveOptions{}, o), Error);
}

TEST_CASE("a baked glTF read back keeps its lightmap UVs, and a second bake uses them") {
    const auto& b = cornell();
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / "radiosity_lightmap_roundtrip.glb";
    write_gltf_lightmapped(b.shaded, b.lightmap.image, path.string(), 1.0);
    const Scene<Rgb> scene = read_gltf<Rgb>(path.string());
    std::filesystem::remove(path);
    REQUIRE(scene.face_uvs.size() == b.shaded.triangles.size());
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k)
            CHECK(scene.face_uvs[f][k] == b.shaded.uvs[b.shaded.triangles[f][k]]);
    LightmapOptions o;
    o.unwrap.size = b.atlas.width;
    o.texels_per_patch = 0.0;  // keep the triangles as patches
    o.bake.inside_rays = 0;
    const auto again = bake(build_mesh(scene), SolveOptions{}, o);
    CHECK_FALSE(again.generated_uvs);
    CHECK(again.atlas.texel_density == test::approx(b.atlas.texel_density).epsilon(0.01));
    // The same texels are covered as in the first bake (the same triangles in the same places).
    std::size_t same = 0, covered = 0;
    for (std::size_t i = 0; i < b.lightmap.state.size(); ++i) {
        const bool first =
            b.lightmap.state[i] == TexelState::surface || b.lightmap.state[i] == TexelState::inside;
        covered += first;
        same += first && again.lightmap.state[i] == TexelState::surface;
    }
    REQUIRE(covered > b.lightmap.state.size() / 3);
    CHECK(same == covered);
}

TEST_CASE("the texel rule never makes more patches than max_patches") {
    const auto scene = build_mesh(cornell_box<Rgb>());
    LightmapOptions o;
    o.unwrap.size = 256;
    o.max_patches = 600;
    o.bake.inside_rays = 0;
    const auto r = bake(scene, SolveOptions{}, o);
    CHECK(r.solution.patches.size() <= 600);
    CHECK(r.solution.patches.size() > 300);  // the edge grows no more than it must
    CHECK(r.patch_edge > o.texels_per_patch / r.atlas.texel_density);
    CHECK(subdivided_face_count(scene, SubdivisionOptions{.max_edge = r.patch_edge}) ==
          r.solution.patches.size());
}
