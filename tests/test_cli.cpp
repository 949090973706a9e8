// The radiosity program end to end: the dumps of a two-square OBJ reproduce the closed form
// (Howell C-11), and bad input gives a one-line error and a non-zero exit status.
#include "support/approx.hpp"

#include <doctest/doctest.h>

#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Run {
    int status = -1;
    std::string err;
};

const fs::path& work_dir() {
    static const fs::path dir = [] {
        fs::path d =
            fs::temp_directory_path() / ("radiosity_cli_test_" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

std::string data(const std::string& name) {
    return std::string(RADIOSITY_TEST_DATA_DIR) + "/" + name;
}
std::string out(const std::string& name) {
    return (work_dir() / name).string();
}

/// Runs the program with the arguments; captures stderr and the exit status.
Run run(const std::string& args) {
    const std::string err = out("stderr.txt");
    const std::string cmd =
        std::string("'") + RADIOSITY_CLI + "' " + args + " --quiet 2> '" + err + "' > /dev/null";
    const int raw = std::system(cmd.c_str());
    Run r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    std::ifstream in(err);
    std::stringstream s;
    s << in.rdbuf();
    r.err = s.str();
    return r;
}

std::vector<std::vector<double>> read_csv(const std::string& path, bool skip_header) {
    std::ifstream in(path);
    REQUIRE(in);
    std::vector<std::vector<double>> rows;
    std::string line;
    if (skip_header) std::getline(in, line);
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ',')) row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    return rows;
}

int line_count(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

/// A bad run: non-zero status, exactly one line on stderr, naming `what`.
void check_one_line_error(const std::string& args, const std::string& what) {
    const Run r = run(args);
    CHECK(r.status != 0);
    CHECK(line_count(r.err) == 1);
    CHECK_MESSAGE(r.err.find(what) != std::string::npos, r.err);
}

constexpr double c11_unit = 0.199824895698;  // Howell C-11, a = b = c = 1 (cases.json)

}  // namespace

TEST_CASE("two-square OBJ: the dumped form factors reproduce Howell C-11") {
    const Run r =
        run("'" + data("cli_two_squares.obj") +
            "' --form-factor analytic --solver direct --max-edge 0 --dump-form-factors '" +
            out("ff.csv") + "' --dump-patches '" + out("patches.csv") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto F = read_csv(out("ff.csv"), false);
    REQUIRE(F.size() == 2);
    REQUIRE(F[0].size() == 2);
    CHECK(F[0][0] == 0.0);
    CHECK(F[1][1] == 0.0);
    CHECK(std::abs(F[0][1] - c11_unit) / c11_unit < 1e-5);
    CHECK(std::abs(F[1][0] - c11_unit) / c11_unit < 1e-5);
}

TEST_CASE("two-square OBJ: the dumped radiosities solve the two-patch system exactly") {
    const Run r = run("'" + data("cli_two_squares.obj") +
                      "' --form-factor analytic --solver direct --max-edge 0 --dump-patches '" +
                      out("patches2.csv") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto P = read_csv(out("patches2.csv"), true);
    REQUIRE(P.size() == 2);
    // columns: patch,area,cx,cy,cz,nx,ny,nz,E_rgb(8..10),R_rgb(11..13),B_rgb(14..16)
    CHECK(P[0][1] == radiosity::test::approx(1.0));
    CHECK(P[0][7] == radiosity::test::approx(1.0));   // lower square faces +z
    CHECK(P[1][7] == radiosity::test::approx(-1.0));  // upper square faces -z
    const double E[3] = {1, 2, 3}, R0 = 0.5, R1[3] = {0.5, 0.25, 0.75};
    for (int k = 0; k < 3; ++k) {
        // B0 = E + R0 F B1, B1 = R1 F B0  =>  B0 = E / (1 - R0 R1 F^2)
        const double B0 = E[k] / (1.0 - R0 * R1[k] * c11_unit * c11_unit);
        const double B1 = R1[k] * c11_unit * B0;
        CHECK(std::abs(P[0][14 + k] - B0) / B0 < 1e-5);
        CHECK(std::abs(P[1][14 + k] - B1) / B1 < 1e-5);
    }
}

TEST_CASE("--divide and --max-area split by area, and only one of them is taken") {
    for (const std::string rule : {"--divide", "--max-area"}) {
        CAPTURE(rule);
        // Squares of area 1: one round of 1 -> 4 splits brings them to 0.25 <= 0.3.
        const Run r = run("'" + data("cli_two_squares.obj") + "' " + rule +
                          " 0.3 --quiet --dump-patches '" + out("divided.csv") + "'");
        REQUIRE_MESSAGE(r.status == 0, r.err);
        const auto P = read_csv(out("divided.csv"), true);
        REQUIRE(P.size() == 8);
        for (const auto& p : P) CHECK(p[1] == radiosity::test::approx(0.25));
    }
    check_one_line_error("'" + data("cli_two_squares.obj") + "' --divide 1 --max-area 1",
                         "max-area");
}

TEST_CASE("a missing scene file is a one-line error naming it") {
    check_one_line_error("'" + out("no_such_scene.obj") + "'", "no_such_scene.obj");
}

TEST_CASE("an unknown option is a one-line error") {
    check_one_line_error("--no-such-option", "no-such-option");
}

TEST_CASE("a reflectance of 1 or more is a one-line error naming the file") {
    check_one_line_error("'" + data("cli_bad_reflectance.obj") + "' --max-edge 0",
                         "cli_bad_reflectance");
}

TEST_CASE("a zero-area face is a one-line error naming the face") {
    check_one_line_error("'" + data("cli_zero_area.obj") + "' --max-edge 0", "zero area");
}

TEST_CASE("a self-intersecting face is a one-line error naming the file, line and face") {
    check_one_line_error("'" + data("cli_self_intersecting.obj") + "'",
                         "cli_self_intersecting.obj:7: face 0");
    check_one_line_error("'" + data("cli_self_intersecting.obj") + "'", "intersects itself");
}

TEST_CASE("an L-shaped floor: its patches cover area 3, none in its notch, a sliver reported") {
    const Run r = run("'" + data("cli_l_room.obj") + "' --max-edge 0.25 --dump-patches '" +
                      out("l_room.csv") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    CHECK_MESSAGE(r.err.find("meshing: left out 1 face(s) of zero area (corners merged): 2") !=
                      std::string::npos,
                  r.err);
    double floor = 0.0, ceiling = 0.0;
    std::size_t in_notch = 0;
    for (const auto& p : read_csv(out("l_room.csv"), true)) {
        // columns: patch,area,cx,cy,cz,nx,ny,nz,...
        if (p[7] > 0.5) {
            floor += p[1];
            in_notch += p[2] > 1.0 && p[3] > 1.0;
        } else {
            ceiling += p[1];
        }
    }
    CHECK(floor == radiosity::test::approx(3.0).epsilon(1e-6));  // the dump's 9 digits
    CHECK(ceiling == radiosity::test::approx(4.0).epsilon(1e-6));
    CHECK(in_notch == 0);
}

TEST_CASE("a face index out of range is a one-line error") {
    check_one_line_error("'" + data("cli_bad_index.obj") + "' --max-edge 0", "cli_bad_index");
}

TEST_CASE("an unwritable output is a one-line error naming the path") {
    check_one_line_error(
        "'" + data("cli_two_squares.obj") + "' --max-edge 0 --image /no/such/dir/x.png",
        "/no/such/dir/x.png");
}

TEST_CASE("a NaN tolerance is rejected") {
    const Run r = run("cornell --tolerance nan");
    CHECK(r.status != 0);
    CHECK(line_count(r.err) == 1);
}

TEST_CASE("--lightmap bakes the Cornell box into an HDR lightmap and a glTF that shows it") {
    const Run r = run("cornell --lightmap '" + out("lm.hdr") + "' --lightmap-size 128 --gltf '" +
                      out("lm.gltf") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    std::ifstream hdr(out("lm.hdr"), std::ios::binary);
    std::string magic(10, '\0');
    hdr.read(magic.data(), 10);
    CHECK(magic == "#?RADIANCE");
    std::ifstream gltf(out("lm.gltf"));
    std::stringstream doc;
    doc << gltf.rdbuf();
    CHECK(doc.str().find("\"TEXCOORD_0\"") != std::string::npos);
    CHECK(doc.str().find("\"image/png\"") != std::string::npos);
    CHECK(std::filesystem::file_size(out("lm.bin")) > 128 * 128 / 8);
    check_one_line_error("cornell --lightmap '" + out("lm.tga") + "' --lightmap-size 64",
                         "unknown picture format");
    check_one_line_error("cornell --lightmap '" + out("lm.hdr") + "' --lightmap-size 4",
                         "--lightmap-size");
}

TEST_CASE("a default picture is written only when no output at all is named") {
    const fs::path dir = work_dir() / "default_picture";
    fs::create_directories(dir);
    auto in_dir = [&](const std::string& args) {
        const std::string cmd = "cd '" + dir.string() + "' && '" + RADIOSITY_CLI +
                                "' cornell-empty --max-edge 200 --quiet " + args + " 2>/dev/null";
        return std::system(cmd.c_str());
    };
    REQUIRE(in_dir("--gltf only.glb") == 0);
    CHECK(fs::exists(dir / "only.glb"));
    CHECK_FALSE(fs::exists(dir / "cornell-empty.png"));
    REQUIRE(in_dir("") == 0);
    CHECK(fs::exists(dir / "cornell-empty.png"));
}

TEST_CASE("--help lists every option once, in the option group of its job, each group described") {
    const std::string path = out("help.txt");
    const std::string cmd = std::string("'") + RADIOSITY_CLI + "' --help > '" + path + "'";
    const int raw = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(raw));
    REQUIRE(WEXITSTATUS(raw) == 0);
    // Which group each option line of the help falls under ("" before the first group), and
    // the line after each group's heading (its description).
    std::map<std::string, std::vector<std::string>> found;
    std::map<std::string, std::string> description;
    std::ifstream in(path);
    std::string line, group, heading = "[Option Group: ";
    bool after_heading = false;
    while (std::getline(in, line)) {
        const std::size_t start = line.find_first_not_of(' ');
        if (start == std::string::npos) continue;
        const std::string text = line.substr(start);
        if (after_heading) description[group] = text;
        after_heading = text.rfind(heading, 0) == 0;
        if (after_heading) group = text.substr(heading.size(), text.size() - heading.size() - 1);
        if (text[0] != '-') continue;
        const std::string names = text.substr(0, text.find(' '));  // "-h,--help": "--help"
        found[names.substr(names.rfind(',') + 1)].push_back(group);
    }
    const std::map<std::string, std::vector<std::string>> groups{
        {"", {"--help", "--quiet", "--partial"}},
        {"Scene and meshing",
         {"--max-edge", "--max-area", "--divide", "--unit", "--flip-faces", "--no-cut",
          "--two-sided"}},
        {"Form factors", {"--form-factor", "--resolution", "--samples", "--max-memory"}},
        {"Solver",
         {"--solver", "--tolerance", "--max-iterations", "--link-error", "--min-area",
          "--checkpoint", "--checkpoint-every", "--resume"}},
        {"Pictures",
         {"--image", "--hdr", "--width", "--height", "--camera", "--fov", "--flat", "--exposure"}},
        {"Exports",
         {"--ply", "--ply-float", "--gltf", "--rrv-out", "--dump-form-factors",
          "--form-factors-text", "--dump-patches"}},
        {"Lightmaps",
         {"--lightmap", "--lightmap-size", "--texel-density", "--lightmap-gutter",
          "--texels-per-patch"}}};
    std::size_t options = 0;
    for (const auto& [name, members] : groups) {
        CAPTURE(name);
        if (!name.empty()) CHECK(description[name].size() > 20);  // says what the group is for
        for (const std::string& o : members) {
            CAPTURE(o);
            CHECK(found[o] == std::vector<std::string>{name});
            ++options;
        }
    }
    CHECK(found.size() == options);  // and no option outside the groups above
}

namespace {

/// A scratch file with the given text.
std::string write_file(const std::string& name, const std::string& text) {
    std::ofstream(out(name)) << text;
    return out(name);
}

/// A closed box 2 x 2 x 2 as six quads over the cube's corners, each face listed
/// counter-clockwise about the outward normal when `outward` (as a modelling tool makes a
/// solid), about the inward one otherwise; a lamp under the ceiling faces down into it.
std::string box_obj(bool outward, const std::string& mtl) {
    std::string s = "mtllib " + mtl +
                    "\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 2 -1\nv -1 2 1\nv 1 2 1\nv 1 2 "
                    "-1\nv -0.3 1.9 -0.3\nv 0.3 1.9 -0.3\nv 0.3 1.9 0.3\nv -0.3 1.9 0.3\n"
                    "usemtl white\n";
    const char* inward[] = {"1 2 3 4", "5 8 7 6", "1 4 8 5", "1 5 6 2", "4 3 7 8", "2 6 7 3"};
    for (const char* f : inward) {
        std::stringstream in(f);
        std::vector<std::string> v(4);
        for (auto& x : v) in >> x;
        s += outward ? "f " + v[3] + " " + v[2] + " " + v[1] + " " + v[0] + "\n"
                     : "f " + std::string(f) + "\n";
    }
    return s + "usemtl lamp\nf 9 10 11 12\n";
}

}  // namespace

TEST_CASE("a solver stopped by its iteration guard: a warning, exit status 3, outputs written") {
    const Run r =
        run("cornell-empty --max-edge 200 --solver jacobi --max-iterations 2 "
            "--tolerance 1e-9 --image '" +
            out("short.png") + "' --dump-patches '" + out("short.csv") + "'");
    CHECK(r.status == 3);
    CHECK_MESSAGE(r.err.find("warning: jacobi stopped after 2 iterations") != std::string::npos,
                  r.err);
    CHECK(r.err.find("NOT converged") != std::string::npos);
    CHECK(fs::file_size(out("short.png")) > 0);
    CHECK(read_csv(out("short.csv"), true).size() > 10);
    // The same run allowed to converge exits 0 with no warning.
    const Run ok = run("cornell-empty --max-edge 200 --solver jacobi --tolerance 1e-6 --image '" +
                       out("long.png") + "'");
    CHECK_MESSAGE(ok.status == 0, ok.err);
    CHECK(ok.err.find("warning") == std::string::npos);
}

TEST_CASE("a solve that diverges is a one-line error naming its rows, and writes nothing") {
    // A block floating in a closed room of reflectance 0.99: the analytic method has no
    // visibility, so each wall takes the walls behind the block as well as the block, its rows
    // sum past 1 and the sweeps grow without bound. The hemicube solves the same scene.
    const std::string scene = "'" + data("cli_box_in_box.obj") + "' --max-edge 0";
    const Run r = run(scene + " --form-factor analytic --image '" + out("diverged.png") + "'");
    CHECK(r.status != 0);
    CHECK(r.status != 3);  // not "stopped short": an error
    CHECK(line_count(r.err) == 1);
    CHECK_MESSAGE(
        r.err.find("gauss-seidel: the solution diverged after sweep") != std::string::npos, r.err);
    CHECK_MESSAGE(r.err.find("the analytic method has none") != std::string::npos, r.err);
    CHECK(!fs::exists(out("diverged.png")));
    const Run ok = run(scene + " --image '" + out("hemicube.png") + "'");
    CHECK_MESSAGE(ok.status == 0, ok.err);
    CHECK(fs::file_size(out("hemicube.png")) > 0);
}

TEST_CASE("--solver hierarchical: its leaves are the patches, the summary counts its links") {
    const Run r = run("cornell --solver hierarchical --dump-patches '" + out("h.csv") +
                      "' --image '" + out("h.png") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    CHECK_MESSAGE(r.err.find(" elements, ") != std::string::npos, r.err);
    CHECK(r.err.find(" links (") != std::string::npos);
    const std::size_t at = r.err.find(" patches (leaves)");
    REQUIRE(at != std::string::npos);
    const std::size_t line = r.err.rfind('\n', at);
    const std::size_t patches =
        std::stoul(r.err.substr(line == std::string::npos ? 0 : line + 1, at));
    CHECK(read_csv(out("h.csv"), true).size() == patches);
    CHECK(fs::file_size(out("h.png")) > 0);
    // Its own options are checked like the others.
    check_one_line_error("cornell --solver hierarchical --link-error -1", "--link-error");
    check_one_line_error("cornell --solver hierarchical --min-area 0", "--min-area");
}

TEST_CASE(
    "too big for a dense matrix: solved hierarchically and said so, unless a solver is named") {
    const Run r =
        run("cornell-empty --max-edge 100 --max-memory 0.000001 --image '" + out("auto.png") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    CHECK_MESSAGE(r.err.find("solved by hierarchical radiosity") != std::string::npos, r.err);
    CHECK(r.err.find(" links (") != std::string::npos);
    check_one_line_error("cornell-empty --max-edge 100 --max-memory 0.000001 --solver jacobi",
                         "--solver hierarchical");
}

TEST_CASE("the summary names every file written") {
    const Run r = run("cornell-empty --max-edge 200 --image '" + out("s.png") + "' --gltf '" +
                      out("s.gltf") + "' --ply '" + out("s.ply") + "' --dump-patches '" +
                      out("s.csv") + "' --rrv-out '" + out("s.xml") + "'");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    for (const std::string f : {"s.png", "s.gltf", "s.bin", "s.ply", "s.csv", "s.xml"}) {
        CAPTURE(f);
        CHECK(r.err.find(out(f)) != std::string::npos);
        CHECK(fs::exists(out(f)));
    }
}

TEST_CASE("glTF is written in metres: the Cornell box's millimetres, --unit for files") {
    // The box is 556 mm wide: POSITION's bounds in the glTF span 0.556 m.
    auto x_extent = [](const std::string& gltf) {
        std::ifstream in(gltf);
        std::stringstream s;
        s << in.rdbuf();
        const std::string doc = s.str();
        auto number_after = [&](const std::string& key) {
            const std::size_t at = doc.find(key);
            REQUIRE(at != std::string::npos);
            return std::stod(doc.substr(doc.find('[', at) + 1));
        };
        return number_after("\"max\"") - number_after("\"min\"");
    };
    REQUIRE(run("cornell-empty --max-edge 200 --gltf '" + out("mm.gltf") + "'").status == 0);
    CHECK(x_extent(out("mm.gltf")) == radiosity::test::approx(0.556).epsilon(1e-4));
    // A file's unit: metres unless --unit says otherwise (the two squares are 1 unit wide).
    const std::string sq = "'" + data("cli_two_squares.obj") + "' --max-edge 0 --gltf ";
    REQUIRE(run(sq + "'" + out("m.gltf") + "'").status == 0);
    CHECK(x_extent(out("m.gltf")) == radiosity::test::approx(1.0));
    REQUIRE(run(sq + "'" + out("cm.gltf") + "' --unit cm").status == 0);
    CHECK(x_extent(out("cm.gltf")) == radiosity::test::approx(0.01));
    REQUIRE(run(sq + "'" + out("in.gltf") + "' --unit 0.0254").status == 0);
    CHECK(x_extent(out("in.gltf")) == radiosity::test::approx(0.0254));
    check_one_line_error(sq + "'" + out("x.gltf") + "' --unit furlong", "--unit");
}

TEST_CASE(
    "an inside-out room is refused before the solve, and --flip-faces or --two-sided light it") {
    write_file("box.mtl", "newmtl white\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n");
    // Only the walls are turned out; the lamp still faces down.
    const std::string outward = write_file("outward.obj", box_obj(true, "box.mtl"));
    const Run r = run("'" + outward + "' --max-edge 0.5 --image '" + out("outward.png") + "'");
    CHECK(r.status == 1);
    CHECK(line_count(r.err) == 1);
    CHECK_MESSAGE(r.err.find("faces point out") != std::string::npos, r.err);
    CHECK(r.err.find("--flip-faces") != std::string::npos);
    CHECK(r.err.find("--two-sided") != std::string::npos);
    CHECK_FALSE(fs::exists(out("outward.png")));
    // An inward box is lit; the outward one lit once turned round (its lamp then faces up, at
    // the ceiling 0.1 away) or made two-sided.
    const std::string inward = write_file("inward.obj", box_obj(false, "box.mtl"));
    for (const std::string& args :
         {"'" + inward + "'", "'" + outward + "' --flip-faces", "'" + outward + "' --two-sided"}) {
        CAPTURE(args);
        const Run ok = run(args + " --max-edge 0.5 --dump-patches '" + out("box.csv") + "'");
        REQUIRE_MESSAGE(ok.status == 0, ok.err);
        double lit = 0.0;
        for (const auto& p : read_csv(out("box.csv"), true))
            if (p[11] > 0.5) lit = std::max(lit, p[14]);  // the brightest white wall patch
        CHECK(lit > 0.1);
    }
}

TEST_CASE("a scene with no emitter is refused before the solve, saying what to add") {
    write_file("dark.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
    const std::string dark =
        write_file("dark.obj",
                   "mtllib dark.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl grey\nf 1 2 3 4\n");
    check_one_line_error("'" + dark + "' --max-edge 0", "no face emits light");
    check_one_line_error("'" + dark + "' --max-edge 0", "Ke");
}

TEST_CASE(
    "RRV's room3 with no meshing option: RRV's meshing (9,680 patches uncut), seen from inside") {
    const std::string room3 = std::string(RADIOSITY_REFDATA_DIR) + "/../rrv/room3.xml";
    const auto t0 = std::chrono::steady_clock::now();
    // --no-cut: RRV does not cut its lamps' barrels where they enter their globes.
    const Run r = run("'" + room3 + "' --no-cut --dump-patches '" + out("room3.csv") +
                      "' --image '" + out("room3.png") + "' --width 64 --height 64");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    REQUIRE_MESSAGE(r.status == 0, r.err);
    MESSAGE("room3, no meshing option: " << seconds << " s");
    CHECK(r.err.find("9680 patches") == 0);
    CHECK(read_csv(out("room3.csv"), true).size() == 9680);
    // From inside the closed room every pixel shows a wall, the floor, the ceiling or what
    // stands in the room; from outside most of the picture would be black background.
    int w = 0, h = 0, channels = 0;
    unsigned char* p = stbi_load(out("room3.png").c_str(), &w, &h, &channels, 3);
    REQUIRE(p);
    int black = 0;
    for (int i = 0; i < w * h; ++i)
        black += p[3 * i] == 0 && p[3 * i + 1] == 0 && p[3 * i + 2] == 0;
    stbi_image_free(p);
    CHECK(w == 64);
    CHECK(black == 0);
}

TEST_CASE("a box pushed through a room's wall: the program says what it cut, --no-cut does not") {
    // The room [-2, 2]^3 faces in, lit from under its ceiling; the box reaches through the
    // wall x = -2, its footprint there 0.9 x 1.0.
    std::ofstream mtl(out("cut.mtl"));
    mtl << "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n";
    mtl.close();
    std::ofstream obj(out("cut.obj"));
    obj << "mtllib cut.mtl\n";
    int base = 1;
    auto box = [&](double x0, double y0, double z0, double x1, double y1, double z1, bool in) {
        for (int k = 0; k < 8; ++k)
            obj << "v " << (k & 1 ? x1 : x0) << " " << (k & 2 ? y1 : y0) << " " << (k & 4 ? z1 : z0)
                << "\n";
        const int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
        for (const auto& f : q)
            obj << "f " << base + f[0] << " " << base + f[in ? 3 : 1] << " " << base + f[2] << " "
                << base + f[in ? 1 : 3] << "\n";
        base += 8;
    };
    obj << "usemtl white\n";
    box(-2, -2, -2, 2, 2, 2, true);
    box(-2.45, -1.2, -0.6, -1.55, -0.3, 0.4, false);
    obj << "usemtl lamp\nv -0.5 1.99 -0.5\nv 0.5 1.99 -0.5\nv 0.5 1.99 0.5\nv -0.5 1.99 0.5\n"
        << "f " << base << " " << base + 1 << " " << base + 2 << " " << base + 3 << "\n";
    obj.close();
    auto area = [](const std::string& csv) {
        double a = 0.0;
        for (const auto& row : read_csv(csv, true)) a += row[1];
        return a;
    };
    const Run cut =
        run("'" + out("cut.obj") + "' --max-edge 0.5 --dump-patches '" + out("cut.csv") + "'");
    REQUIRE_MESSAGE(cut.status == 0, cut.err);
    CHECK_MESSAGE(cut.err.find("radiosity: meshing: cut 5 face(s) where other faces cross them; "
                               "left out 1 piece(s) inside closed objects (area 0.9)\n") == 0,
                  cut.err);
    const Run whole = run("'" + out("cut.obj") + "' --max-edge 0.5 --no-cut --dump-patches '" +
                          out("whole.csv") + "'");
    REQUIRE_MESSAGE(whole.status == 0, whole.err);
    CHECK(whole.err.find("meshing") == std::string::npos);
    // The CSV's areas have 9 significant digits.
    CHECK(area(out("cut.csv")) + 0.9 ==
          radiosity::test::approx(area(out("whole.csv"))).epsilon(1e-7));
}
