// radiosity-view end to end, headless (run under Xvfb with Mesa's software OpenGL): its
// pictures against the library's own CPU renderer of the same solution and camera, its picks
// against the patch that the library's renderer sees at that pixel, its row numbers against the
// library's form factors, and the live solve's pictures against what physics says the first shot
// or sweep can light. Every run of the program is bounded by `timeout`.
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/subdivide.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/shading/tonemap.hpp>
#include <radiosity/shading/vertex_shading.hpp>
#include <radiosity/solve.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace radiosity;

namespace {

namespace fs = std::filesystem;

constexpr int W = 512, H = 512;
/// The meshing of every run: coarse enough for quick solves, fine enough for a wireframe.
constexpr double max_edge = 60.0;
/// The published Cornell camera's field of view: 25 mm film behind a 35 mm lens.
const double cornell_fov = 2.0 * std::atan(12.5 / 35.0) * 180.0 / std::numbers::pi;
/// The runs on the default camera (whatever the `radiosity` program's default is).
const std::string defaults = " cornell --max-edge 60 --quiet";
/// The runs whose pixels are compared with the library's renderer: the published Cornell camera
/// (cornell_camera), named on the command line so that they do not hang on the default one.
const std::string common = [] {
    char fov[64];
    std::snprintf(fov, sizeof fov, "%.17g", cornell_fov);
    return defaults + " --camera 278,273,-800,278,273,0,0,1,0 --fov " + fov;
}();

struct Run {
    int status = -1;
    std::string out, err;
};

const fs::path& work_dir() {
    static const fs::path dir = [] {
        fs::path d =
            fs::temp_directory_path() / ("radiosity_view_test_" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

std::string path(const std::string& name) {
    return (work_dir() / name).string();
}

std::string slurp(const std::string& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs the viewer with the arguments, stopped after `seconds` (status 124 then); env:
/// variables to set or unset first (`env -u DISPLAY`). In sanitizer builds, leaks are not
/// looked for in the viewer: a GLFW program that only opens and closes a window leaks 128 bytes
/// allocated inside the OpenGL libraries, which glfwTerminate unloads, so that no suppression
/// can name them.
Run run(const std::string& args, const std::string& env = "", int seconds = 120) {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 " + env +
                            " timeout " + std::to_string(seconds) + " '" +
                            std::string(RADIOSITY_VIEW) + "' " + args + " > '" + out + "' 2> '" +
                            err + "'";
    const int raw = std::system(cmd.c_str());
    Run r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

/// An 8-bit RGB picture.
struct Picture {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
    const unsigned char* at(int x, int y) const {
        return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
    }
    bool black(int x, int y) const { return at(x, y)[0] + at(x, y)[1] + at(x, y)[2] == 0; }
};

Picture read_png(const std::string& file) {
    Picture p;
    int channels = 0;
    unsigned char* data = stbi_load(file.c_str(), &p.width, &p.height, &channels, 3);
    REQUIRE_MESSAGE(data != nullptr, file);
    p.rgb.assign(data, data + 3 * p.width * p.height);
    stbi_image_free(data);
    return p;
}

/// A screenshot of the Cornell box by the viewer with the given extra arguments (after `base`:
/// the pinned camera unless told otherwise).
Picture screenshot(const std::string& name, const std::string& args,
                   const std::string& base = common) {
    const std::string file = path(name + ".png");
    const Run r = run(base + " --screenshot '" + file + "' " + args);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const Picture p = read_png(file);
    REQUIRE(p.width == W);
    REQUIRE(p.height == H);
    return p;
}

/// The published Cornell camera (the Cornell Program of Computer Graphics' box data), which
/// `common` names on the viewer's command line.
Camera cornell_camera() {
    return {{278.0, 273.0, -800.0}, {278.0, 273.0, 0.0}, {0.0, 1.0, 0.0}, cornell_fov};
}

/// The library's side: the same patches as the viewer's, the patch each pixel sees (by the
/// library's CPU renderer, shading/camera.hpp), and pictures of a solution.
struct Reference {
    Mesh<Rgb> scene = build_mesh(cornell_box<Rgb>());
    Mesh<Rgb> mesh = subdivide(scene, SubdivisionOptions{.max_edge = max_edge});
    PatchTable patches = make_patch_table(mesh);
    std::vector<int> id;  // patch seen at each pixel, -1 for none

    Reference() {
        const ShadedMesh flat = flat_shading(mesh);
        std::vector<int> owner;  // flat shading fans each patch, patch after patch
        for (std::size_t i = 0; i < patches.size(); ++i)
            owner.insert(owner.end(), patches.polygon(i).size() - 2, static_cast<int>(i));
        REQUIRE(owner.size() == flat.triangles.size());
        const Image ids = render_with(
            flat, cornell_camera(), {.width = W, .height = H, .cull_back_faces = true},
            [&](std::size_t t, const glm::dvec3&) { return glm::vec3(float(owner[t] + 1)); });
        for (const auto& v : ids.pixels) id.push_back(static_cast<int>(v.x) - 1);
    }
    int at(int x, int y) const { return id[static_cast<std::size_t>(y) * W + x]; }
    /// Whether every pixel within r of (x, y) sees the same patch.
    bool inside(int x, int y, int r) const {
        for (int v = y - r; v <= y + r; ++v)
            for (int u = x - r; u <= x + r; ++u)
                if (u < 0 || v < 0 || u >= W || v >= H || at(u, v) != at(x, y)) return false;
        return true;
    }
    /// The library's picture of a solution (back faces culled, as the program's), as write_png
    /// encodes it: exposure from the picture, sRGB in 8 bits.
    Picture picture(const ShadedMesh& shaded) const {
        const Image image =
            render(shaded, cornell_camera(), {.width = W, .height = H, .cull_back_faces = true});
        const double scale = exposure_scale(image.pixels, {});
        Picture p{W, H, {}};
        for (const auto& c : image.pixels)
            for (int k = 0; k < 3; ++k) p.rgb.push_back(srgb8(static_cast<float>(scale * c[k])));
        return p;
    }
};

const Reference& reference() {
    static const Reference r;
    return r;
}

/// The mean colour of a rectangle of pixels.
glm::dvec3 mean(const Picture& p, int x0, int y0, int x1, int y1) {
    glm::dvec3 sum(0.0);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            sum += glm::dvec3(p.at(x, y)[0], p.at(x, y)[1], p.at(x, y)[2]);
    return sum / double((x1 - x0) * (y1 - y0));
}

int largest_difference(const Picture& a, const Picture& b, int x, int y) {
    int d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a.at(x, y)[k]) - int(b.at(x, y)[k])));
    return d;
}

/// The pixels that see the ceiling (not its lamp), well inside their patches.
std::vector<std::pair<int, int>> ceiling_pixels() {
    const Reference& ref = reference();
    std::vector<std::pair<int, int>> out;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int i = ref.at(x, y);
            if (i < 0 || !ref.inside(x, y, 2)) continue;
            const auto& d = ref.mesh.data(Mesh<Rgb>::FaceHandle(i));
            if (ref.patches.normal(std::size_t(i)).y < -0.99 && band(d.emission, 0) == 0.0f)
                out.emplace_back(x, y);
        }
    return out;
}

}  // namespace

TEST_CASE("every mode draws the Cornell box: lit, coloured and covering the picture") {
    const Reference& ref = reference();
    std::size_t seen = 0;
    for (int v : ref.id) seen += v >= 0;
    REQUIRE(seen > std::size_t(W * H * 3 / 4));  // the box fills most of the picture
    auto material = [&](int i) -> const auto& {
        return ref.mesh.data(Mesh<Rgb>::FaceHandle(i));
    };
    for (const std::string mode : {"wireframe", "flat", "smooth", "reflectance", "emission"}) {
        CAPTURE(mode);
        const Picture p = screenshot(mode, "--mode " + mode);
        std::size_t lit = 0, colours_off = 0, lamp = 0, lamp_lit = 0, dark_lit = 0;
        std::map<int, std::set<int>> colours;  // per patch, the colours of its inner pixels
        std::set<int> all;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const auto* c = p.at(x, y);
                const int i = ref.at(x, y);
                if (i < 0) continue;
                lit += !p.black(x, y);
                if (!ref.inside(x, y, 1)) continue;
                colours[i].insert((c[0] << 16) | (c[1] << 8) | c[2]);
                all.insert((c[0] << 16) | (c[1] << 8) | c[2]);
                const bool emits = band(material(i).emission, 0) > 0.0f;
                lamp += emits;
                lamp_lit += emits && !p.black(x, y);
                dark_lit += !emits && !p.black(x, y);
                // The reflectance is shown as it is: sRGB of R, no exposure.
                const Rgb& R = material(i).reflectance;
                for (std::size_t k = 0; k < 3; ++k)
                    colours_off += std::abs(int(c[k]) - int(srgb8(band(R, k)))) > 1;
            }
        if (mode == "emission") {
            // Only the lamp emits: lit pixels are the lamp's, and the lamp is in view.
            CHECK(lamp > 100);
            CHECK(lamp_lit == lamp);
            CHECK(dark_lit == 0);
        } else if (mode == "reflectance") {
            CHECK(lit == seen);
            CHECK(colours_off == 0);
        } else {
            // Every pixel that sees a patch is lit, but for the wireframe's black lines (at 60 mm
            // patches, about one pixel in ten); the light differs from patch to patch; flat
            // shading gives each patch one colour, smooth shading varies it across most patches.
            CHECK(double(lit) >= (mode == "wireframe" ? 0.8 : 0.999) * double(seen));
            CHECK(all.size() > colours.size() / 4);
            std::size_t one = 0;
            for (const auto& [i, cs] : colours) one += cs.size() == 1;
            if (mode == "flat") CHECK(one == colours.size());
            if (mode == "smooth") CHECK(one < colours.size() / 4);
        }
    }
}

TEST_CASE("the red wall is on the left and the green wall on the right, in every lit mode") {
    // Lit by the warm lamp (E = pi (17, 12, 4)), the red wall (R = 0.63, 0.065, 0.05) sends out
    // red at 14 times green, the green wall (0.14, 0.45, 0.09) green at 2.3 times red and 15
    // times blue; through the sRGB curve (about a power of 1/2.4) those are code ratios of about
    // 3 and 1.4 (or 1.6 for the reflectance alone).
    for (const std::string mode : {"flat", "smooth", "reflectance"}) {
        CAPTURE(mode);
        const Picture p = screenshot("walls_" + mode, "--mode " + mode, defaults);
        const glm::dvec3 left = mean(p, W / 25, 3 * H / 10, 4 * W / 25, 7 * H / 10);
        const glm::dvec3 right = mean(p, 21 * W / 25, 3 * H / 10, 24 * W / 25, 7 * H / 10);
        CAPTURE(left);
        CAPTURE(right);
        CHECK(left.r > 1.5 * left.g);
        CHECK(left.r > 1.5 * left.b);
        CHECK(right.g > 1.25 * right.r);
        CHECK(right.g > 1.5 * right.b);
    }
}

TEST_CASE("smooth and flat pictures are the library's pictures of the same solution") {
    // Gauss-Seidel over the hemicube matrix, as radiosity::solve runs it: the same B bit for bit.
    const Reference& ref = reference();
    SolveOptions o;
    o.subdivision.max_edge = max_edge;
    o.tolerance = 1e-6;
    const SolveResult<Rgb> solved = solve(ref.scene, o);
    REQUIRE(solved.patches.size() == ref.patches.size());
    for (const bool smooth : {true, false}) {
        CAPTURE(smooth);
        const Picture mine =
            screenshot(smooth ? "library_smooth" : "library_flat",
                       std::string("--solver gauss-seidel --tolerance 1e-6 --mode ") +
                           (smooth ? "smooth" : "flat"));
        const Picture theirs =
            ref.picture(smooth ? smooth_shading(solved.mesh) : flat_shading(solved.mesh));
        // Inside the patches the GPU's float arithmetic may round an 8-bit code the other way;
        // along the patches' edges the two rasterisers may give a pixel to different patches.
        std::size_t inside = 0, inside_off = 0, off = 0;
        double sum = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int d = largest_difference(mine, theirs, x, y);
                sum += d;
                off += d > 1;
                if (ref.at(x, y) >= 0 && ref.inside(x, y, 1)) {
                    ++inside;
                    inside_off += d > 1;
                }
            }
        CAPTURE(inside_off);
        CAPTURE(off);
        CHECK(inside > std::size_t(W * H / 2));
        CHECK(double(inside_off) <= 1e-3 * double(inside));
        CHECK(double(off) <= 0.02 * W * H);
        CHECK(sum / (W * H) < 0.5);
    }
}

TEST_CASE("the default camera is the radiosity program's") {
    // The same solve (Gauss-Seidel over the hemicube matrix, the program's default), the same
    // flat shading: where neither is told where to stand, both pictures are taken from one place.
    const std::string file = path("program_flat.png");
    const std::string cmd = "'" + std::string(RADIOSITY_CLI) + "'" + defaults +
                            " --flat --image '" + file + "' > /dev/null 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const Picture program = read_png(file);
    const Picture mine =
        screenshot("default_camera", "--solver gauss-seidel --mode flat", defaults);
    REQUIRE(program.width == W);
    std::size_t off = 0, lit = 0;
    double sum = 0.0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int d = largest_difference(mine, program, x, y);
            sum += d;
            off += d > 1;
            lit += !program.black(x, y);
        }
    CAPTURE(off);
    CHECK(lit > std::size_t(W * H / 2));  // the scene is in view, not just a black picture
    // Along the patches' edges the two rasterisers may give a pixel to different patches; a
    // camera moved or turned by a pixel would change the colour along every edge of the picture.
    CHECK(double(off) <= 0.02 * W * H);
    CHECK(sum / (W * H) < 0.5);
}

TEST_CASE("the wireframe draws the edges of every patch in view, and nothing inside them") {
    const Reference& ref = reference();
    const Picture flat = screenshot("edges_flat", "--mode flat");
    const Picture wire = screenshot("edges_wire", "--mode wireframe");
    std::size_t edges = 0, drawn = 0, inside = 0, inside_same = 0;
    for (int y = 1; y + 1 < H; ++y)
        for (int x = 1; x + 1 < W; ++x) {
            const int i = ref.at(x, y);
            if (i < 0) continue;
            if (ref.inside(x, y, 3)) {  // a line of one pixel cannot reach here
                ++inside;
                inside_same += largest_difference(flat, wire, x, y) == 0;
            }
            // An edge between two patches of the picture: it is drawn (dark) within one pixel.
            const bool edge = (ref.at(x + 1, y) >= 0 && ref.at(x + 1, y) != i) ||
                              (ref.at(x, y + 1) >= 0 && ref.at(x, y + 1) != i);
            if (!edge) continue;
            ++edges;
            bool line = false;
            for (int v = y - 1; v <= y + 1 && !line; ++v)
                for (int u = x - 1; u <= x + 1 && !line; ++u)
                    line = wire.black(u, v) && !flat.black(u, v);
            drawn += line;
        }
    CAPTURE(edges);
    CAPTURE(drawn);
    CHECK(edges > 5000);
    CHECK(double(drawn) >= 0.98 * double(edges));
    CHECK(inside > std::size_t(W * H / 4));
    CHECK(inside_same == inside);
}

TEST_CASE("a pick returns the patch that the library's renderer sees at that pixel") {
    const Reference& ref = reference();
    std::mt19937 random(15);
    // The back wall, the red and green walls, the ceiling, the floor, the two blocks; then
    // pixels at random. All away from patch edges, where two rasterisers may differ.
    std::vector<std::pair<int, int>> checked;
    for (const auto& [x, y] : std::vector<std::pair<int, int>>{
             {256, 150}, {50, 250}, {470, 250}, {256, 40}, {256, 480}, {190, 300}, {330, 400}})
        if (ref.inside(x, y, 2)) checked.emplace_back(x, y);
    REQUIRE(checked.size() >= 5);
    while (checked.size() < 40) {
        const int x = int(random() % W), y = int(random() % H);
        if (ref.at(x, y) >= 0 && ref.inside(x, y, 2)) checked.emplace_back(x, y);
    }
    std::string args = common;
    for (const auto& [x, y] : checked)
        args += " --pick " + std::to_string(x) + "," + std::to_string(y);
    const Run r = run(args);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const std::regex line(R"(pick (\d+),(\d+): patch (\d+))");
    std::size_t found = 0;
    for (std::sregex_iterator m(r.out.begin(), r.out.end(), line), end; m != end; ++m) {
        const int x = std::stoi((*m)[1]), y = std::stoi((*m)[2]), i = std::stoi((*m)[3]);
        CAPTURE(x);
        CAPTURE(y);
        CHECK(i == ref.at(x, y));
        ++found;
    }
    CHECK(found == checked.size());
}

TEST_CASE("a pick prints F_ii = 0, the row sum and the reciprocity error of the library's row") {
    const Reference& ref = reference();
    const int x = 470, y = 250;  // the green wall
    REQUIRE(ref.inside(x, y, 2));
    const auto i = static_cast<std::size_t>(ref.at(x, y));
    const Run r = run(common + " --pick " + std::to_string(x) + "," + std::to_string(y));
    INFO(r.err);
    REQUIRE(r.status == 0);
    INFO(r.out);
    std::smatch m;
    REQUIRE(std::regex_search(r.out, m,
                              std::regex(R"(F_ii = (\S+)\s+row sum = (\S+)\s+)"
                                         R"(reciprocity error = (\S+))")));
    // The library's hemicube row and column i of its matrix, the viewer's default method.
    Hemicube method;
    method.prepare(ref.patches);
    const DenseMatrix F = assemble_dense(method, ref.patches.size());
    double sum = 0.0, worst = 0.0, scale = 0.0;
    for (std::size_t j = 0; j < ref.patches.size(); ++j) {
        sum += F(i, j);
        const double a = ref.patches.area(i) * F(i, j), b = ref.patches.area(j) * F(j, i);
        worst = std::max(worst, std::abs(a - b));
        scale = std::max(scale, a);
    }
    CHECK(std::stod(m[1]) == 0.0);  // a flat patch does not see itself
    CHECK(std::stod(m[2]) == test::approx(sum).epsilon(1e-5));
    CHECK(sum > 0.3);  // the wall sees most of the box; the open front takes the rest
    CHECK(sum < 1.0);
    CHECK(std::stod(m[3]) == test::approx(worst / scale).epsilon(1e-5));
}

TEST_CASE("a pick where no patch is seen says so") {
    const Reference& ref = reference();
    REQUIRE(ref.at(2, 2) < 0);
    const Run r = run(common + " --pick 2,2");
    CHECK(r.status == 0);
    CHECK(r.out.find("pick 2,2: no patch") != std::string::npos);
}

TEST_CASE("the live solve: the first shot or sweep cannot light the ceiling, later ones do") {
    // The lamp lies in the ceiling's plane, so the ceiling sees no direct light: after shooting
    // from one lamp patch, or after one Jacobi sweep (B = E + R F E), it is black. The ambient
    // term, standing in for the light not yet shot, lights it; so do further shots or sweeps.
    const auto ceiling = ceiling_pixels();
    REQUIRE(ceiling.size() > 1000);
    auto lit = [&](const Picture& p) {
        std::size_t n = 0;
        for (const auto& [x, y] : ceiling) n += !p.black(x, y);
        return n;
    };
    CHECK(lit(screenshot("shot_1", "--mode flat --solver progressive --stop-after 1")) == 0);
    CHECK(lit(screenshot("sweep_1", "--mode flat --solver jacobi --stop-after 1")) == 0);
    const std::size_t all = ceiling.size();
    CHECK(lit(screenshot("shot_1_ambient",
                         "--mode flat --solver progressive --stop-after 1 --ambient")) == all);
    CHECK(lit(screenshot("sweep_2", "--mode flat --solver jacobi --stop-after 2")) == all);
    CHECK(lit(screenshot("shots_200", "--mode flat --solver progressive --stop-after 200")) == all);
}

TEST_CASE("--ui draws the panels over the picture") {
    const Picture plain = screenshot("plain", "--mode smooth --stop-after 50");
    const Picture ui = screenshot("panels", "--mode smooth --stop-after 50 --ui");
    // The view panel sits in the top-left corner, over the black margin and the red wall.
    std::size_t changed = 0;
    for (int y = 15; y < 100; ++y)
        for (int x = 15; x < 200; ++x) changed += largest_difference(plain, ui, x, y) > 16;
    CHECK(changed > 185 * 85 / 2);
}

TEST_CASE("the window opens and keeps drawing while the solve runs, until it is closed") {
    // Stopped from outside after a few seconds: still running then (status 124), no error.
    const Run r = run(" cornell --max-edge 60", "", 6);
    CHECK(r.status == 124);
    CHECK(r.err.find("patches;") != std::string::npos);
    CHECK(r.err.find("error") == std::string::npos);
}

TEST_CASE("without a display the viewer stops with a one-line error, not a crash") {
    const Run r = run(common + " --screenshot '" + path("none.png") + "'",
                      "env -u DISPLAY -u WAYLAND_DISPLAY");
    CHECK(r.status == 1);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find("DISPLAY") != std::string::npos);
    CHECK(!fs::exists(path("none.png")));
}

TEST_CASE("bad viewer options are one-line errors") {
    for (const char* args :
         {" --mode sideways", " --pick 10", " --pick 600,10", " --screenshot x.jpg", " --ui"}) {
        CAPTURE(args);
        const Run r = run(common + args);
        CHECK(r.status == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    const Run missing = run(" no_such_scene.obj --screenshot x.png");
    CHECK(missing.status == 1);
    CHECK(missing.err.find("no_such_scene.obj") != std::string::npos);
}
