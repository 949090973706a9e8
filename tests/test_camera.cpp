// The camera renderer and the shared rasteriser: a quad filling the view, the z-buffer, no
// cracks and no double coverage along shared edges (top-left rule), perspective-correct
// interpolation, bad options, and the PNG writer read back.
#include <radiosity/geometry/raster.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/shading/camera.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>

#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <filesystem>
#include <unistd.h>

using namespace radiosity;

namespace {

/// A quad in the plane z = z0 with the given colours at its corners.
void add_quad(ShadedMesh& m, double z0, double half, const std::array<glm::vec3, 4>& c) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    m.positions.insert(
        m.positions.end(),
        {{-half, -half, z0}, {half, -half, z0}, {half, half, z0}, {-half, half, z0}});
    m.colours.insert(m.colours.end(), c.begin(), c.end());
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
}

const Camera looking_down_z{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40.0};

}  // namespace

TEST_CASE("a quad filling the view gives every pixel its colour") {
    ShadedMesh m;
    const glm::vec3 c(0.25f, 0.5f, 1.0f);
    add_quad(m, 0.0, 100.0, {c, c, c, c});
    const Image img =
        render(m, looking_down_z, {.width = 64, .height = 48, .background = glm::vec3(-1.0f)});
    REQUIRE(img.pixels.size() == 64 * 48);
    for (const auto& p : img.pixels) {
        CHECK(p.r == test::approx(c.r));
        CHECK(p.b == test::approx(c.b));
    }
}

TEST_CASE("back faces are culled by default: a camera outside a closed room sees in") {
    // A near quad turned away from the camera (a room's near wall seen from outside) in front
    // of a far one facing it (the far wall seen through it).
    ShadedMesh m;
    const glm::vec3 red(1, 0, 0), blue(0, 0, 1);
    add_quad(m, 1.0, 100.0, {red, red, red, red});
    std::swap(m.triangles[0][1], m.triangles[0][2]);
    std::swap(m.triangles[1][1], m.triangles[1][2]);
    add_quad(m, 0.0, 100.0, {blue, blue, blue, blue});
    CHECK(RenderOptions{}.cull_back_faces);
    CHECK(render(m, looking_down_z, {.width = 9, .height = 9}).at(4, 4) == blue);
    CHECK(render(m, looking_down_z, {.width = 9, .height = 9, .cull_back_faces = false}).at(4, 4) ==
          red);
}

TEST_CASE("the z-buffer keeps the nearest surface, whatever the drawing order") {
    ShadedMesh near_first, far_first;
    const glm::vec3 red(1, 0, 0), blue(0, 0, 1);
    add_quad(near_first, 1.0, 0.5, {red, red, red, red});
    add_quad(near_first, 0.0, 3.0, {blue, blue, blue, blue});
    add_quad(far_first, 0.0, 3.0, {blue, blue, blue, blue});
    add_quad(far_first, 1.0, 0.5, {red, red, red, red});
    for (const ShadedMesh* m : {&near_first, &far_first}) {
        const Image img = render(*m, looking_down_z, {.width = 33, .height = 33});
        CHECK(img.at(16, 16) == red);  // the small near quad in the middle
        CHECK(img.at(1, 1) == blue);   // the big far one around it
    }
}

TEST_CASE("triangles sharing edges cover every pixel exactly once (top-left rule)") {
    // A fan of random triangles around a centre tiles a convex polygon: each pixel inside is
    // visited once, none twice, none missed.
    Rng rng(3);
    const int n = 17, size = 64;
    std::vector<Vec4> rim;
    for (int k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * (k + 0.5 * rng.uniform()) / n;
        rim.emplace_back(0.9 * std::cos(a), 0.9 * std::sin(a), 0.0, 1.0);
    }
    const Vec4 centre(0.013, -0.021, 0.0, 1.0);
    std::vector<int> hits(size * size, 0);
    for (int k = 0; k < n; ++k)
        rasterize_triangle({centre, rim[k], rim[(k + 1) % n]}, size, size,
                           [&](const Fragment& f) { ++hits[f.y * size + f.x]; });
    int twice = 0, inside = 0;
    for (int h : hits) {
        twice += h > 1;
        inside += h == 1;
    }
    CHECK(twice == 0);
    // Every pixel whose centre lies inside the polygon was hit: the count matches the area in
    // pixels to within half a pixel along the rim (pixels the edges cut through).
    double area = 0.0;
    for (int k = 0; k < n; ++k)
        area += 0.5 * (rim[k].x * rim[(k + 1) % n].y - rim[(k + 1) % n].x * rim[k].y);
    const double pixels = area * size * size / 4.0;
    const double rim_pixels = 2.0 * std::numbers::pi * 0.9 * size / 2.0;
    CHECK(std::abs(inside - pixels) < 0.5 * rim_pixels);
}

namespace {

/// Splits a (cells + 1) x (cells + 1) grid of clip-space points into triangles (diagonals
/// alternating) and counts how often each pixel of a size x size raster is visited.
std::vector<int> coverage(const std::vector<Vec4>& grid, int cells, int size) {
    std::vector<int> hits(std::size_t(size) * size, 0);
    auto at = [&](int i, int j) { return grid[std::size_t(j) * (cells + 1) + i]; };
    auto count = [&](const Fragment& f) { ++hits[std::size_t(f.y) * size + f.x]; };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const Vec4 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            if ((i + j) % 2 == 0) {
                rasterize_triangle({a, b, c}, size, size, count);
                rasterize_triangle({a, c, d}, size, size, count);
            } else {
                rasterize_triangle({a, b, d}, size, size, count);
                rasterize_triangle({b, c, d}, size, size, count);
            }
        }
    return hits;
}

}  // namespace

TEST_CASE("a mesh of triangles over the whole raster covers each pixel exactly once") {
    // Both grids reach beyond the raster, so every pixel lies inside their union.
    const int size = 64, cells = 10;
    // Vertices on pixel centres (8 pixels apart): edges pass exactly through pixel centres
    // horizontally, vertically and diagonally, so only the top-left rule decides those pixels.
    std::vector<Vec4> aligned;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i)
            aligned.emplace_back((16.0 * (i - 1) + 1.0) / size - 1.0,
                                 1.0 - (16.0 * (j - 1) + 1.0) / size, 0.0, 1.0);
    // Seeded random jitter of a coarser grid, with random positive w (perspective division).
    // Corners move at most 0.1 of a cell per axis, which cannot fold a triangle over: its
    // doubled area stays above 0.8 * 0.8 - 0.2 * 1.2 > 0 cells.
    Rng rng(11);
    std::vector<Vec4> jittered;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            const double x = -1.3 + 2.6 * (i + 0.2 * (rng.uniform() - 0.5)) / cells;
            const double y = -1.3 + 2.6 * (j + 0.2 * (rng.uniform() - 0.5)) / cells;
            const double w = 0.5 + rng.uniform();
            jittered.emplace_back(x * w, y * w, 0.0, w);
        }
    for (const auto* grid : {&aligned, &jittered}) {
        const std::vector<int> hits = coverage(*grid, cells, size);
        CHECK(std::count(hits.begin(), hits.end(), 1) == size * size);
    }
}

TEST_CASE("interpolation is perspective-correct") {
    // A floor receding from the camera, colour linear in world depth: the pixel that shows the
    // world midpoint of the floor gets the midpoint colour, not the screen-space midpoint's.
    ShadedMesh m;
    m.positions = {{-1, 0, 0}, {1, 0, 0}, {1, 0, -10}, {-1, 0, -10}};
    m.colours = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(1.0f), glm::vec3(1.0f)};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    const Camera cam{{0, 1, 1}, {0, 1, 0}, {0, 1, 0}, 90.0};  // looking along -z, 1 above
    const int size = 401;
    const Image img = render(m, cam, {.width = size, .height = size});
    // The ray through the centre of pixel row `row` leaves the eye (0, 1, 1) downwards with
    // slope t = 1 - 2 (row + 0.5) / size (tan 45 = 1) and meets the floor at z = 1 + 1 / t;
    // the colour there is -z / 10. Screen-space (affine) interpolation would be far off.
    const int row =
        static_cast<int>(std::floor((0.5 + 0.5 * (1.0 / 6.0)) * size));  // z ~ -5, colour ~ 0.5
    const double t = 1.0 - 2.0 * (row + 0.5) / size;
    CHECK(img.at(size / 2, row).r == test::approx(-(1.0 + 1.0 / t) / 10.0).epsilon(1e-5));
    // Near the far end of the floor (z ~ -8.5, colour ~ 0.85), where affine interpolation
    // would err most.
    const int far_row = static_cast<int>(std::floor((1.0 + 1.0 / 9.5) * size / 2.0));
    const double t2 = 1.0 - 2.0 * (far_row + 0.5) / size;
    CHECK(img.at(size / 2, far_row).r == test::approx(-(1.0 + 1.0 / t2) / 10.0).epsilon(1e-5));
}

TEST_CASE("bad camera and image options are refused, naming the option") {
    ShadedMesh m;
    auto message = [&](const Camera& c, const RenderOptions& o) {
        try {
            render(m, c, o);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const Camera ok = looking_down_z;
    CHECK(message(ok, {.width = 0, .height = 10}).find("width") != std::string::npos);
    CHECK(message(ok, {.width = 10, .height = 16385}).find("height") != std::string::npos);
    CHECK(message({{0, 0, 5}, {0, 0, 5}, {0, 1, 0}, 40.0}, {}).find("eye") != std::string::npos);
    CHECK(message({{0, 0, 5}, {0, 0, 0}, {0, 0, 1}, 40.0}, {}).find("up") != std::string::npos);
    CHECK(message({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 180.0}, {}).find("fov") != std::string::npos);
    CHECK(message({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.0}, {}).find("fov") != std::string::npos);
    CHECK(message(ok, {.width = 1, .height = 1}) == "no error");
}

TEST_CASE("PNG: sRGB codes of a known picture, read back, and a bad path is an error") {
    Image img{2, 1, {glm::vec3(0.5f), glm::vec3(0.0f, 0.2f, 1.0f)}};
    const auto path = std::filesystem::temp_directory_path() /
                      ("radiosity_png_test_" + std::to_string(::getpid()) + ".png");
    ToneMapOptions fixed;
    fixed.auto_exposure = false;
    fixed.scale = std::numbers::pi;  // display = B exactly
    write_png(img, path.string(), fixed);
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &channels, 3);
    REQUIRE(data != nullptr);
    std::filesystem::remove(path);
    CHECK(w == 2);
    CHECK(h == 1);
    CHECK(int(data[0]) == 188);  // linear 0.5 in sRGB
    CHECK(int(data[3]) == 0);
    CHECK(int(data[4]) == srgb8(0.2f));
    CHECK(int(data[5]) == 255);
    stbi_image_free(data);
    try {
        write_png(img, "/no/such/folder/x.png");
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("/no/such/folder/x.png") != std::string::npos);
    }
}
