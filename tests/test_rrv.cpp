// RRV scenes: the transform semantics of ../shared/rrv/README.md checked on hand-made scenes
// (RRV's rotation order and turn direction, innermost transform first, strip winding, colour
// overrides), RRV's example rooms loading into closed, inward-facing rooms, the write-back read
// again, and bad input refused with file and line.
#include <radiosity/io/rrv.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace radiosity;
namespace fs = std::filesystem;

namespace {

const std::string rrv_dir = std::string(RADIOSITY_REFDATA_DIR) + "/../rrv";

struct Scratch {
    fs::path dir = fs::temp_directory_path() / ("radiosity_rrv_" + std::to_string(::getpid()));
    Scratch() { fs::create_directories(dir); }
    ~Scratch() { fs::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name) << text;
        return (dir / name).string();
    }
};

/// A scene with one triangle (0,0,0) (1,0,0) (0,1,0) placed inside the given transforms.
std::string one_triangle(const std::string& open, const std::string& close) {
    return "<scene><head><objectdef name=\"t\"><triangleset reflectivity=\".5,.5,.5\"><triangle>"
           "<vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/>"
           "<vertex x=\"0\" y=\"1\" z=\"0\"/></triangle></triangleset></objectdef></head><body>" +
           open + "<object name=\"t\"/>" + close + "</body></scene>";
}

Vec3 vertex(const Scene<float>& s, std::size_t corner) {
    return s.positions[s.faces[0][corner]];
}

}  // namespace

TEST_CASE("RRV transforms: rotation order and direction, innermost first") {
    Scratch scratch;
    // About y by 90 degrees, RRV's way: (x, z) -> (x cos - z sin, x sin + z cos): (1,0,0) ->
    // (0,0,1).
    auto s = read_rrv<float>(
        scratch.write("y.xml", one_triangle("<rotate angle=\"90\" dy=\"1\">", "</rotate>")));
    CHECK(glm::distance(vertex(s, 1), Vec3(0, 0, 1)) < 1e-12);
    // About z by 90: (x, y) -> (x cos - y sin, x sin + y cos): (1,0,0) -> (0,1,0), (0,1,0) ->
    // (-1,0,0).
    s = read_rrv<float>(
        scratch.write("z.xml", one_triangle("<rotate angle=\"90\" dz=\"1\">", "</rotate>")));
    CHECK(glm::distance(vertex(s, 1), Vec3(0, 1, 0)) < 1e-12);
    CHECK(glm::distance(vertex(s, 2), Vec3(-1, 0, 0)) < 1e-12);
    // Innermost first: scale by 2, then move by 1 in x: (1,0,0) -> (3,0,0).
    s = read_rrv<float>(scratch.write(
        "ts.xml", one_triangle("<translate dx=\"1\"><scale dx=\"2\" dy=\"2\" dz=\"2\">",
                               "</scale></translate>")));
    CHECK(glm::distance(vertex(s, 1), Vec3(3, 0, 0)) < 1e-12);
    // Shear is accepted and ignored.
    s = read_rrv<float>(scratch.write("sh.xml", one_triangle("<shear dx=\"5\">", "</shear>")));
    CHECK(glm::distance(vertex(s, 1), Vec3(1, 0, 0)) < 1e-12);
}

TEST_CASE("RRV: triangles placed with zero area are left out and counted, not lost silently") {
    Scratch scratch;
    // The same triangle twice: once as it is, once flattened by a zero scale in z and y.
    const auto s = read_rrv<float>(scratch.write(
        "flat.xml",
        one_triangle("<object name=\"t\"/><scale dx=\"1\" dy=\"0\" dz=\"0\">", "</scale>")));
    CHECK(s.faces.size() == 1);
    CHECK(s.zero_area_faces == 1);
    CHECK(read_rrv<float>(scratch.write("one.xml", one_triangle("", ""))).zero_area_faces == 0);
}

TEST_CASE("RRV strips keep one winding, colours override from set to triangle") {
    Scratch scratch;
    const auto s = read_rrv<Rgb>(scratch.write(
        "strip.xml",
        "<scene><head><objectdef name=\"q\"><triangleset reflectivity=\".2,.3,.4\">"
        "<triangle><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"1\" y=\"0\" z=\"0\"/>"
        "<vertex x=\"0\" y=\"1\" z=\"0\"/></triangle>"
        "<trianglenext emission=\"1,2,3\"><vertex x=\"1\" y=\"1\" z=\"0\"/></trianglenext>"
        "</triangleset></objectdef></head><body><object name=\"q\"/></body></scene>"));
    REQUIRE(s.faces.size() == 2);
    for (const auto& f : s.faces) {
        std::vector<Vec3> p;
        for (auto v : f) p.push_back(s.positions[v]);
        CHECK(polygon_normal(p).z == test::approx(1.0));  // both counter-clockwise from +z
    }
    CHECK(s.materials[s.face_material[0]].emission == Rgb(0.0f));
    CHECK(s.materials[s.face_material[1]].emission == Rgb(1.0f, 2.0f, 3.0f));
    CHECK(s.materials[s.face_material[1]].reflectance == Rgb(0.2f, 0.3f, 0.4f));
}

TEST_CASE("RRV's rooms load: closed, lit, walls facing in, teapot included") {
    for (const std::string room : {"room2.xml", "room3.xml"}) {
        CAPTURE(room);
        const Scene<Rgb> s = read_rrv<Rgb>(rrv_dir + "/" + room);
        const Mesh<Rgb> mesh = build_mesh(s);
        CHECK(mesh.n_faces() > 3752);  // the teapot alone has 3752 triangles
        double emitting = 0.0;
        for (auto f : mesh.faces()) emitting += max_abs(mesh.data(f).emission) > 0.0f;
        CHECK(emitting > 0);
        // The largest faces are the room's walls: their normals point to the room's middle.
        Vec3 lo(1e300), hi(-1e300);
        for (const Vec3& p : s.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const Vec3 middle = 0.5 * (lo + hi);
        std::size_t walls = 0;
        for (auto f : mesh.faces()) {
            const auto p = face_polygon(mesh, f);
            if (polygon_area(p) < 100.0) continue;
            ++walls;
            CHECK(glm::dot(polygon_normal(p), middle - polygon_centroid(p)) > 0.0);
        }
        CHECK(walls == 12);  // six walls of two triangles
    }
}

TEST_CASE("RRV's divide rule on room3: no patch over 1.0, RRV's 9,680 patches when split alone") {
    const Mesh<Rgb> mesh = build_mesh(read_rrv<Rgb>(rrv_dir + "/room3.xml"));
    SubdivisionOptions o;
    o.max_area = 1.0;             // RRV's default divide
    o.cut_intersections = false;  // RRV does not cut its lamps' barrels where they enter globes
    const Mesh<Rgb> sub = subdivide(mesh, o);
    // RRV splits each triangle alone and leaves T-junctions (9,680 patches); splitting the
    // neighbours along a shared edge alike can only add patches.
    CHECK(sub.n_faces() >= 9680);
    CHECK(sub.n_faces() <= 9680 * 11 / 10);
    double largest = 0.0, total = 0.0, before = 0.0;
    for (auto f : sub.faces()) {
        const double a = polygon_area(face_polygon(sub, f));
        largest = std::max(largest, a);
        total += a;
    }
    for (auto f : mesh.faces()) before += polygon_area(face_polygon(mesh, f));
    CHECK(largest <= 1.0);
    CHECK(total == test::approx(before).epsilon(1e-9));
    o.conforming = false;  // RRV's own way: each triangle by itself
    CHECK(subdivide(mesh, o).n_faces() == 9680);
}

TEST_CASE("RRV write-back: a radiosity per triangle, read again") {
    Scratch scratch;
    Mesh<Rgb> mesh = build_mesh(read_rrv<Rgb>(rrv_dir + "/room2.xml"));
    std::vector<Rgb> B(mesh.n_faces(), Rgb(0.25f, 0.5f, 0.75f));
    set_face_radiosity<Rgb>(mesh, B);
    const std::string out = (scratch.dir / "solved.xml").string();
    write_rrv(mesh, out);
    const Scene<Rgb> back = read_rrv<Rgb>(out);
    CHECK(back.faces.size() == mesh.n_faces());
    std::ifstream in(out);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    CHECK(text.find("radiosity=\"0.25,0.5,0.75\"") != std::string::npos);
}

TEST_CASE("bad RRV input: file and line") {
    Scratch scratch;
    auto error_of = [&](const std::string& name, const std::string& text) {
        try {
            read_rrv<float>(scratch.write(name, text));
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(error_of("broken.xml", "<scene>\n<head>\n</scene>").find("broken.xml:") !=
          std::string::npos);
    CHECK(error_of("noobj.xml", "<scene><head/>\n<body>\n<object name=\"x\"/></body></scene>")
              .find("noobj.xml:3: no objectdef named 'x'") != std::string::npos);
    CHECK(error_of("num.xml", one_triangle("<translate\ndx=\"abc\">", "</translate>"))
              .find("not a number") != std::string::npos);
    CHECK(error_of("what.xml",
                   "<scene><head><objectdef name=\"a\"><sphere/></objectdef></head><body/></scene>")
              .find("unknown element <sphere>") != std::string::npos);
    CHECK(error_of("empty.xml", "<scene><head/><body/></scene>").find("places no triangles") !=
          std::string::npos);
    CHECK(
        error_of("colour.xml",
                 "<scene><head><objectdef name=\"a\"><cuboid emission=\"1,x\"/></objectdef></head>"
                 "<body><object name=\"a\"/></body></scene>")
            .find("not three numbers") != std::string::npos);
}

namespace {

/// one_triangle inside n nested copies of the element open ... close.
std::string nested(std::size_t n, const std::string& open, const std::string& close) {
    std::string o, c;
    for (std::size_t k = 0; k < n; ++k) {
        o += open;
        c += close;
    }
    return one_triangle(o, c);
}

}  // namespace

TEST_CASE("RRV nesting: 256 levels are read exactly, 20,000 refused with file and line") {
    Scratch scratch;
    // 256 translations by 1/4 (exact in binary): the corner (1,0,0) lands at (65,0,0) exactly.
    const auto s = read_rrv<float>(
        scratch.write("deep.xml", nested(256, "<translate dx=\"0.25\">", "</translate>")));
    CHECK(vertex(s, 1) == Vec3(65, 0, 0));
    // Before the walk was iterative this crashed the program (one call per level).
    std::string message;
    try {
        read_rrv<float>(
            scratch.write("deeper.xml", nested(20000, "<translate dx=\"1\">\n", "</translate>")));
    } catch (const Error& e) {
        message = e.what();
    }
    CHECK(message.find("deeper.xml:257: <translate> is nested deeper than 256 transforms") !=
          std::string::npos);
    RrvOptions o;
    o.max_depth = 20000;  // a raised limit reads it: one step per level and corner
    CHECK(read_rrv<float>((scratch.dir / "deeper.xml").string(), o).faces.size() == 1);
}

TEST_CASE("RRV transforms that overflow are refused, zero and tiny scales drop the triangle") {
    Scratch scratch;
    auto error_of = [&](const std::string& text) {
        try {
            read_rrv<float>(scratch.write("t.xml", text));
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(error_of(nested(2, "<scale dx=\"1e200\" dy=\"1e200\" dz=\"1\">", "</scale>"))
              .find("t.xml:1: object 't' is placed beyond the range of numbers") !=
          std::string::npos);
    CHECK(error_of(nested(2, "<translate dx=\"1.7e308\">", "</translate>"))
              .find("beyond the range of numbers") != std::string::npos);
    CHECK(error_of(one_triangle("<scale dx=\"nan\" dy=\"1\" dz=\"1\">", "</scale>"))
              .find("scale dx=\"nan\" is not a number") != std::string::npos);
    // A zero scale flattens the triangle to no area; 1e-9 shrinks it below the 1e-6 at which
    // the reader shares corners. Neither reaches the scene, which then places nothing.
    for (const char* d : {"0", "1e-9"}) {
        CAPTURE(d);
        const std::string scale = std::string("<scale dx=\"") + d + "\" dy=\"1\" dz=\"1\">";
        CHECK(error_of(one_triangle(scale, "</scale>")).find("places no triangles") !=
              std::string::npos);
    }
    // Beside a triangle that stays, the scene loads and builds.
    const std::string both =
        one_triangle("<object name=\"t\"/><scale dx=\"1e-9\" dy=\"1e-9\" dz=\"1\">", "</scale>");
    const auto s = read_rrv<float>(scratch.write("both.xml", both));
    CHECK(s.faces.size() == 1);
    CHECK(build_mesh(s).n_faces() == 1);
}

TEST_CASE("RRV rotations: huge angles and axes of extreme length stay exact rotations") {
    Scratch scratch;
    auto corner = [&](const std::string& rotate) {
        return vertex(read_rrv<float>(scratch.write("r.xml", one_triangle(rotate, "</rotate>"))),
                      1);
    };
    // 90 + 360 * 10^12 degrees is 90 degrees (fmod is exact); about z: (1,0,0) -> (0,1,0).
    CHECK(glm::distance(corner("<rotate angle=\"360000000000090\" dz=\"1\">"), Vec3(0, 1, 0)) <
          1e-12);
    // An angle of 1e308 degrees stays finite (it was infinite in radians, then NaN).
    const Vec3 far = corner("<rotate angle=\"1e308\" dx=\"1\" dy=\"1\">");
    CHECK(std::isfinite(far.x + far.y + far.z));
    CHECK(glm::length(far) == test::approx(1.0));
    // An axis of length 1e-200 or 1e200 is the same axis as one of length 1.
    const Vec3 unit = corner("<rotate angle=\"30\" dx=\"1\" dy=\"2\" dz=\"3\">");
    for (const char* axis :
         {"dx=\"1e-200\" dy=\"2e-200\" dz=\"3e-200\"", "dx=\"1e200\" dy=\"2e200\" dz=\"3e200\""}) {
        CAPTURE(axis);
        CHECK(glm::distance(corner(std::string("<rotate angle=\"30\" ") + axis + ">"), unit) <
              1e-12);
    }
}

TEST_CASE("RRV scene size: a short file that places a large object many times is refused") {
    Scratch scratch;
    std::string body;
    for (int k = 0; k < 100; ++k)
        body +=
            "<translate dx=\"" + std::to_string(k) + "\">" + "<object name=\"pot\"/></translate>";
    const std::string text =
        "<scene><head><objectdef name=\"pot\"><teapot/></objectdef></head>"
        "<body>" +
        body + "</body></scene>";
    RrvOptions o;
    o.teapot_obj = rrv_dir + "/teapot.obj";
    o.max_triangles = 50 * 3752;  // room for the definition and 49 placements
    std::string message;
    try {
        read_rrv<float>(scratch.write("pots.xml", text), o);
    } catch (const Error& e) {
        message = e.what();
    }
    CHECK(message.find("pots.xml:1: <object> makes the scene larger than 187600 triangles "
                       "(RrvOptions::max_triangles)") != std::string::npos);
    o.max_triangles = 101 * 3752;
    CHECK(read_rrv<float>((scratch.dir / "pots.xml").string(), o).faces.size() > 99 * 3700);
    // At the default limit (10 million), 3,000 placements of the teapot (11 million triangles,
    // from a file of 130 KB) are refused after counting, before a triangle is placed.
    std::string many;
    for (int k = 0; k < 3000; ++k)
        many += "<translate dx=\"" + std::to_string(k) + "\"><object name=\"pot\"/></translate>\n";
    message.clear();
    try {
        read_rrv<float>(scratch.write("many.xml",
                                      "<scene><head><objectdef name=\"pot\"><teapot/></objectdef>"
                                      "</head><body>\n" +
                                          many + "</body></scene>"),
                        RrvOptions{.teapot_obj = rrv_dir + "/teapot.obj"});
    } catch (const Error& e) {
        message = e.what();
    }
    // The definition and 2,664 placements fit in 10 million; the 2,665th (line 2,666) does not.
    CHECK(message.find("many.xml:2666: <object> makes the scene larger than 10000000") !=
          std::string::npos);
}

TEST_CASE("bad RRV input: bytes that a terminal would act on are escaped in the message") {
    Scratch scratch;
    // An attribute holding ESC [2J (clear the screen), a bell, DEL and a byte that is not
    // UTF-8 (0xff), beside a well-formed UTF-8 letter (e acute), which stays as it is.
    const std::string bad = "1,\x1b[2J\x07\x7f\xff\xc3\xa9";
    std::string message;
    try {
        read_rrv<float>(scratch.write(
            "bytes.xml", "<scene><head><objectdef name=\"a\"><cuboid emission=\"" + bad +
                             "\"/></objectdef></head><body><object name=\"a\"/></body></scene>"));
    } catch (const Error& e) {
        message = e.what();
    }
    CAPTURE(message);
    REQUIRE(message.find("bytes.xml") != std::string::npos);
    CHECK(message.find("1,\\x1b[2J\\x07\\x7f\\xff\xc3\xa9") != std::string::npos);
    for (const char c : message) {
        const auto b = static_cast<unsigned char>(c);
        CHECK((b >= 0x20 && b != 0x7f && b != 0xff));  // no raw control byte, DEL or 0xff left
    }
}

TEST_CASE("printable: control bytes and broken UTF-8 escaped, text and UTF-8 kept") {
    CHECK(detail::printable("plain text \\ 42") == "plain text \\ 42");
    CHECK(detail::printable(std::string("a\0b", 3)) == "a\\x00b");
    CHECK(detail::printable("tab\there") == "tab\\x09here");
    CHECK(detail::printable("\xe2\x82\xac") == "\xe2\x82\xac");              // the euro sign
    CHECK(detail::printable("\xe2\x82") == "\\xe2\\x82");                    // cut short
    CHECK(detail::printable("\xc0\xaf") == "\\xc0\\xaf");                    // overlong '/'
    CHECK(detail::printable("\xed\xa0\x80") == "\\xed\\xa0\\x80");           // a surrogate
    CHECK(detail::printable("\xf4\x90\x80\x80") == "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
    CHECK(std::string(Error("x\x1b").what()) == "x\\x1b");
}
