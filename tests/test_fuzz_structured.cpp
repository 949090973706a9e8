// Structure-aware fuzzing of the readers, in the normal suite (beside test_fuzz.cpp's byte
// mutations): seeded generators build hostile but well-formed inputs (polygons of thousands of
// corners, concave and star-shaped polygons, collinear runs, duplicate and unreferenced
// vertices, relative and out-of-range indices, missing materials and files, deep nesting, NaN,
// infinite and zero scales, huge counts) together with what the reader must make of each: load
// exactly what was written, or refuse it with radiosity::Error. A loaded scene must build into
// a mesh whose points and areas are finite. Each generator runs a bounded number of seeded cases
// (a few seconds).
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>

#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <unistd.h>
#include <vector>

using namespace radiosity;
namespace fs = std::filesystem;

namespace {

/// What a generated input must do.
enum class Expect { load, refuse, either };

/// A scratch folder for the generated files, removed at the end.
struct Scratch {
    fs::path dir =
        fs::temp_directory_path() / ("radiosity_fuzz_structured_" + std::to_string(::getpid()));
    Scratch() { fs::create_directories(dir); }
    ~Scratch() { fs::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
        return (dir / name).string();
    }
};

std::size_t below(Rng& rng, std::size_t n) {
    return static_cast<std::size_t>(rng.uniform() * double(n));
}

template <class T>
const T& one_of(Rng& rng, const std::vector<T>& v) {
    return v[below(rng, v.size())];
}

/// A number written so that a float reads it back to within its rounding.
std::string num(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    return buf;
}

/// The checks every loaded scene must pass: finite points, and a mesh of the same faces with
/// finite, positive areas.
template <SpectrumType S>
void check_loaded(const Scene<S>& scene) {
    for (const Vec3& p : scene.positions)
        REQUIRE((std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)));
    const Mesh<S> mesh = build_mesh(scene);
    REQUIRE(mesh.n_faces() == scene.faces.size());
    for (auto f : mesh.faces()) {
        const double a = polygon_area(face_polygon(mesh, f));
        REQUIRE((std::isfinite(a) && a > 0.0));
    }
}

// ---- Simple polygons in the plane, counter-clockwise -------------------------------------

using Outline = std::vector<glm::dvec2>;

/// A regular n-gon of radius 1.
Outline regular(std::size_t n) {
    Outline o;
    for (std::size_t k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * double(k) / double(n);
        o.emplace_back(std::cos(a), std::sin(a));
    }
    return o;
}

/// A star of m points: 2m corners alternating between radii 1 and r (star-shaped, concave).
Outline star(std::size_t m, double r) {
    Outline o;
    for (std::size_t k = 0; k < 2 * m; ++k) {
        const double a = std::numbers::pi * double(k) / double(m), rk = k % 2 ? r : 1.0;
        o.emplace_back(rk * std::cos(a), rk * std::sin(a));
    }
    return o;
}

/// A comb of t teeth along x (concave, 4t corners): a wall with t - 1 notches cut from the top.
Outline comb(std::size_t t) {
    Outline o{{0, 0}, {double(2 * t - 1), 0}};
    for (std::size_t k = t; k-- > 0;) {
        const double x = 2.0 * double(k);
        o.insert(o.end(), {{x + 1, 2}, {x, 2}});
        if (k > 0) o.insert(o.end(), {{x, 1}, {x - 1, 1}});
    }
    return o;
}

/// The L-shaped hexagon of area 3 (a wall with a door cut out of a corner).
Outline l_shape() {
    return {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
}

/// The unit square with k collinear points inserted along each side.
Outline collinear_square(std::size_t k) {
    const Outline corners{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    Outline o;
    for (std::size_t s = 0; s < 4; ++s)
        for (std::size_t j = 0; j <= k; ++j)
            o.push_back(glm::mix(corners[s], corners[(s + 1) % 4], double(j) / double(k + 1)));
    return o;
}

/// A random simple polygon of one of the kinds above.
Outline random_outline(Rng& rng) {
    switch (below(rng, 6)) {
        case 0:
            return regular(one_of<std::size_t>(rng, {3, 4, 7, 255, 256, 257, 1000, 4000}));
        case 1:
            return star(3 + below(rng, 400), 0.2 + 0.6 * rng.uniform());
        case 2:
            return comb(1 + below(rng, 300));
        case 3:
            return l_shape();
        case 4:
            return collinear_square(below(rng, 500));
        default:
            return regular(3 + below(rng, 20));
    }
}

/// A random placement of the plane z = 0 in space: a rotation, a scale of 1e-3 .. 1e3, a shift.
struct Placement {
    Vec3 u, v, origin;
    Vec3 operator()(const glm::dvec2& p) const { return origin + p.x * u + p.y * v; }
};

Placement random_placement(Rng& rng) {
    const Vec3 n = glm::normalize(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform()));
    Vec3 u, v;
    orthonormal_basis(n, u, v);
    const double s = std::pow(10.0, 6.0 * rng.uniform() - 3.0);
    return {s * u, s * v, Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 100.0 - 50.0};
}

// ---- OBJ + MTL -------------------------------------------------------------------------------

/// A generated OBJ scene: the texts, the faces as points (what a load must give back), and the
/// expected outcome.
struct ObjCase {
    std::string obj, mtl;  // the OBJ names the MTL file case.mtl
    std::vector<std::vector<Vec3>> faces;
    Expect expect = Expect::load;
    std::string what;  // the hostile feature, for messages
};

/// Appends a face to an OBJ text: its corners as fresh vertices (duplicates of other faces'
/// points, never welded) or, with relative = true, indexed from the end (-1 is the last).
void add_obj_face(ObjCase& c, std::size_t& nv, const std::vector<Vec3>& points, bool relative) {
    std::string f = "f";
    for (const Vec3& p : points) c.obj += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    for (std::size_t k = 0; k < points.size(); ++k)
        f += " " + std::to_string(relative ? -long(points.size() - k) : long(nv + k + 1));
    c.obj += f + "\n";
    nv += points.size();
    c.faces.push_back(points);
}

/// Makes one hostile feature in a valid scene and says what the reader must do with it.
void make_obj_hostile(ObjCase& c, Rng& rng, std::size_t nv) {
    const std::size_t kind = below(rng, 10);
    const std::vector<std::string> bad_numbers{"nan", "-inf", "1e39", "0x1p3", "1..5", ""};
    c.expect = Expect::refuse;
    switch (kind) {
        case 0:
            c.what = "an index out of range";
            c.obj += "f 1 2 " + std::to_string(rng.uniform() < 0.5 ? long(nv + 1) : -long(nv + 1));
            break;
        case 1:
            c.what = "a corner used twice";
            c.obj += "f 1 2 3 1\n";
            break;
        case 2:
            c.what = "a coordinate that is not a number";
            c.obj += "v 1 " + one_of(rng, bad_numbers) + " 2\n";
            break;
        case 3:
            c.what = "no faces";
            c.obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
            break;
        case 4:
            c.what = "a material the MTL file lacks";
            c.obj += "usemtl nowhere\nf 1 2 3\n";
            break;
        case 5:
            c.what = "a missing MTL file";
            c.obj = "mtllib missing.mtl\n" + c.obj;
            break;
        case 6:
            c.what = "a reflectance of 1 or more, or a negative emission";
            c.mtl += rng.uniform() < 0.5 ? "newmtl bad\nKd 1 0.5 0.5\n" : "newmtl bad\nKe -1 0 0\n";
            c.obj += "usemtl bad\nf 1 2 3\n";
            break;
        case 7:
            c.what = "a face of zero area (collinear corners)";
            c.obj += "v 0 0 0\nv 1 1 1\nv 2 2 2\nf -3 -2 -1\n";
            break;
        case 8:
            c.what = "a face of two corners";
            c.obj += "f 1 2\n";
            break;
        default:
            c.what = "an MTL number that is not a number";
            c.mtl += "newmtl nan\nKd " + one_of(rng, bad_numbers) + " 0.5 0.5\n";
            c.obj += "usemtl nan\nf 1 2 3\n";
    }
}

/// A random OBJ scene: 1 to 6 polygons of the kinds above, placed anywhere, unwelded or indexed
/// from the end, with unreferenced vertices, materials and texture coordinates here and there;
/// one case in three has a hostile feature.
ObjCase random_obj(Rng& rng) {
    ObjCase c;
    c.obj = "mtllib case.mtl\n";
    c.mtl = "newmtl lamp\nKd 0.5 0.5 0.5\nKe 10 10 10\nnewmtl wall\nKd 0.2 0.8 0.99\n";
    std::size_t nv = 0;
    const std::size_t faces = 1 + below(rng, 6);
    for (std::size_t f = 0; f < faces; ++f) {
        if (rng.uniform() < 0.3) {  // vertices that no face uses
            c.obj += "v 1e30 -1e30 3e38\nv 0 0 0\n";
            nv += 2;
        }
        if (rng.uniform() < 0.5) c.obj += rng.uniform() < 0.5 ? "usemtl lamp\n" : "usemtl wall\n";
        const Placement place = random_placement(rng);
        std::vector<Vec3> points;
        for (const glm::dvec2& p : random_outline(rng)) points.push_back(place(p));
        add_obj_face(c, nv, points, rng.uniform() < 0.3);
    }
    if (rng.uniform() < 0.2) c.obj += "vt 0.5 0.5\n";  // a texture coordinate no face uses
    if (rng.uniform() < 0.35) make_obj_hostile(c, rng, nv);
    if (rng.uniform() < 0.2) {  // Windows line ends and tabs change nothing
        std::string crlf;
        for (char ch : c.obj) crlf += ch == '\n' ? "\r\n" : ch == ' ' ? "\t" : std::string(1, ch);
        c.obj = crlf;
    }
    return c;
}

/// Checks that a loaded OBJ scene is what was written: the same faces, corner for corner, each
/// point to a float's rounding.
void check_obj_model(const Scene<Rgb>& s, const ObjCase& c) {
    REQUIRE(s.faces.size() == c.faces.size());
    for (std::size_t f = 0; f < c.faces.size(); ++f) {
        REQUIRE(s.faces[f].size() == c.faces[f].size());
        for (std::size_t k = 0; k < c.faces[f].size(); ++k) {
            const Vec3& p = s.positions[s.faces[f][k]];
            const Vec3& q = c.faces[f][k];
            REQUIRE(glm::distance(p, q) <= 1e-6 * (glm::length(q) + 1e-3));
        }
    }
}

// ---- RRV ---------------------------------------------------------------------------------------

/// RRV's teapot for the generated scenes: a tetrahedron (4 triangles) instead of 3752.
const std::string tiny_teapot =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// A generated RRV scene, the number of triangles a load must place, the triangles it defines
/// and places (what RrvOptions::max_triangles counts), and the expected outcome.
struct RrvCase {
    std::string xml;
    std::size_t placed = 0, budget = 0;
    Expect expect = Expect::load;
    std::string what;
};

/// A colour attribute, now and then a reflectivity of 1 or more (RRV allows it; clamped).
std::string rrv_colours(Rng& rng) {
    std::string a;
    if (rng.uniform() < 0.3) a += " emission=\"" + num(10 * rng.uniform()) + ",1,1\"";
    if (rng.uniform() < 0.6) a += " reflectivity=\"" + num(1.2 * rng.uniform()) + ",0.5,0.5\"";
    return a;
}

/// An object definition of 1 to 3 items: a triangle strip of 3 to 2,000 vertices (a zigzag in
/// a plane, every triangle of area 1/4), or a primitive; returns its triangle count.
std::size_t rrv_objectdef(Rng& rng, const std::string& name, std::string& xml) {
    static const std::vector<std::pair<std::string, std::size_t>> primitives{
        {"cuboid", 12}, {"barrel", 80}, {"globe", 360}, {"teapot", 4}};
    xml += "<objectdef name=\"" + name + "\">";
    std::size_t triangles = 0;
    for (std::size_t i = 0, n = 1 + below(rng, 3); i < n; ++i) {
        if (rng.uniform() < 0.4) {
            const auto& [kind, count] = one_of(rng, primitives);
            xml += "<" + kind + rrv_colours(rng) + "/>";
            triangles += count;
            continue;
        }
        const std::size_t n_strip = one_of<std::size_t>(rng, {3, 4, 5, 50, 2000});
        xml += "<triangleset" + rrv_colours(rng) + "><triangle>";
        for (std::size_t k = 0; k < n_strip; ++k) {
            if (k == 3) xml += "</triangle>";
            if (k >= 3) xml += "<trianglenext" + std::string(k % 7 ? "" : rrv_colours(rng)) + ">";
            xml += "<vertex x=\"" + num(0.5 * double(k / 2)) + "\" y=\"" + num(double(k % 2)) +
                   "\" z=\"" + num(0.25) + "\"/>";
            if (k >= 3) xml += "</trianglenext>";
        }
        xml += std::string(n_strip == 3 ? "</triangle>" : "") + "</triangleset>";
        triangles += n_strip - 2;
    }
    xml += "</objectdef>";
    return triangles;
}

/// A transform element that keeps every triangle's area (no zero or huge scales); the angle
/// and the axis may be as large as a number goes.
std::pair<std::string, std::string> safe_transform(Rng& rng) {
    auto d = [&](double s) {
        return " dx=\"" + num(s * (rng.uniform() - 0.5)) + "\" dy=\"" + num(s * rng.uniform()) +
               "\" dz=\"" + num(s * (rng.uniform() - 0.5)) + "\"";
    };
    switch (below(rng, 4)) {
        case 0:
            return {"<translate" + d(20.0) + ">", "</translate>"};
        case 1:
            return {"<scale dx=\"" + num(0.5 + rng.uniform()) + "\" dy=\"" +
                        num(0.5 + rng.uniform()) + "\" dz=\"" + num(-0.5 - rng.uniform()) + "\">",
                    "</scale>"};
        case 2: {
            const double angle = rng.uniform() < 0.2 ? 1e300 : 720.0 * (rng.uniform() - 0.5);
            return {"<rotate angle=\"" + num(angle) + "\"" + d(rng.uniform() < 0.2 ? 1e-200 : 1.0) +
                        ">",
                    "</rotate>"};
        }
        default:
            return {"<shear" + d(1.0) + ">", "</shear>"};
    }
}

/// A hostile transform: a zero scale (its triangles have no area and are dropped), scales that
/// overflow when nested, a number that is not one.
std::pair<std::string, std::string> hostile_transform(Rng& rng, RrvCase& c) {
    c.expect = Expect::either;  // dropped triangles may leave none; overflow is refused
    switch (below(rng, 3)) {
        case 0:
            c.what = "a zero scale";
            return {"<scale dx=\"0\" dy=\"1\" dz=\"1\">", "</scale>"};
        case 1:
            c.what = "a scale that overflows when nested";
            return {"<scale dx=\"1e200\" dy=\"1e200\" dz=\"1e200\">", "</scale>"};
        default:
            c.what = "a number that is not one";
            c.expect = Expect::refuse;
            return {
                "<translate dx=\"" + one_of<std::string>(rng, {"nan", "inf", "1e999", "x"}) + "\">",
                "</translate>"};
    }
}

/// The body: placements of the definitions inside chains of nested transforms of random depth
/// (now and then beyond RrvOptions::max_depth, now and then around an undefined object).
void rrv_body(Rng& rng, const std::vector<std::size_t>& defs, RrvCase& c, std::size_t max_depth) {
    c.xml += "<body>";
    for (std::size_t p = 0, n = 1 + below(rng, 8); p < n; ++p) {
        const bool deep = rng.uniform() < 0.03;
        const std::size_t depth =
            deep ? one_of<std::size_t>(rng, {max_depth, max_depth + 1, 5000}) : below(rng, 6);
        if (depth > max_depth) {
            c.expect = Expect::refuse;
            c.what = "transforms nested too deep";
        }
        std::string close;
        for (std::size_t k = 0; k < depth; ++k) {
            const auto [open, end] =
                rng.uniform() < 0.03 ? hostile_transform(rng, c) : safe_transform(rng);
            c.xml += open;
            close = end + close;
        }
        const std::size_t d = below(rng, defs.size() + 1);
        if (d == defs.size() && rng.uniform() < 0.15) {
            c.expect = Expect::refuse;
            c.what = "an undefined object";
            c.xml += "<object name=\"nowhere\"/>";
        } else {
            c.xml += "<object name=\"d" + std::to_string(d % defs.size()) + "\"/>";
            c.placed += defs[d % defs.size()];
        }
        c.xml += close;
    }
    c.xml += "</body></scene>";
}

/// A random RRV scene of 1 to 4 definitions placed 1 to 8 times.
RrvCase random_rrv(Rng& rng, std::size_t max_depth) {
    RrvCase c;
    c.xml = "<?xml version=\"1.0\"?>\n<scene><head>";
    std::vector<std::size_t> defs;
    for (std::size_t d = 0, n = 1 + below(rng, 4); d < n; ++d)
        defs.push_back(rrv_objectdef(rng, "d" + std::to_string(d), c.xml));
    c.xml += "</head>";
    rrv_body(rng, defs, c, max_depth);
    for (std::size_t t : defs) c.budget += t;
    c.budget += c.placed;
    return c;
}

}  // namespace

TEST_CASE("OBJ/MTL generator: 300 hostile scenes load exactly as written or are refused") {
    Scratch scratch;
    Rng rng(12);
    int loaded = 0, refused = 0;
    for (int k = 0; k < 300; ++k) {
        const ObjCase c = random_obj(rng);
        CAPTURE(k);
        CAPTURE(c.what);
        scratch.write("case.mtl", c.mtl);
        const std::string path = scratch.write("case.obj", c.obj);
        try {
            const Scene<Rgb> s = read_obj<Rgb>(path);
            check_loaded(s);  // build_mesh refuses zero areas, repeated corners: caught below
            CHECK(c.expect != Expect::refuse);
            check_obj_model(s, c);
            ++loaded;
        } catch (const Error& e) {
            CHECK_MESSAGE(c.expect != Expect::load, e.what());
            CHECK(std::string(e.what()).find("case.") != std::string::npos);
            ++refused;
        }
    }
    CHECK(loaded > 100);
    CHECK(refused > 50);
    MESSAGE("loaded " << loaded << ", refused " << refused);
}

TEST_CASE("RRV generator: 300 hostile scenes place every triangle or are refused") {
    Scratch scratch;
    Rng rng(13);
    RrvOptions options;
    options.teapot_obj = scratch.write("teapot.obj", tiny_teapot);
    int loaded = 0, refused = 0, over_budget = 0;
    for (int k = 0; k < 300; ++k) {
        RrvCase c = random_rrv(rng, options.max_depth);
        options.max_triangles = rng.uniform() < 0.15 ? c.budget / 2 : 10'000'000;
        if (c.budget > options.max_triangles && c.expect == Expect::load) {
            c.expect = Expect::refuse;
            c.what = "more triangles than RrvOptions::max_triangles";
            ++over_budget;
        }
        CAPTURE(k);
        CAPTURE(c.what);
        try {
            const Scene<Rgb> s = read_rrv<Rgb>(scratch.write("case.xml", c.xml), options);
            check_loaded(s);
            CHECK(c.expect != Expect::refuse);
            if (c.expect == Expect::load) CHECK(s.faces.size() == c.placed);
            CHECK(s.faces.size() <= c.placed);
            ++loaded;
        } catch (const Error& e) {
            CHECK_MESSAGE(c.expect != Expect::load, e.what());
            CHECK(std::string(e.what()).find("case.xml") != std::string::npos);
            ++refused;
        }
    }
    CHECK(loaded > 100);
    CHECK(refused > 30);
    CHECK(over_budget > 10);
    MESSAGE("loaded " << loaded << ", refused " << refused << " (" << over_budget
                      << " for the triangle budget)");
}
