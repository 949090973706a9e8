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
#include <radiosity/io/gltf_read.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
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

/// A placement whose shift is at most 5 times its scale (0.1 .. 100), so that the corners of a
/// 1,000-gon stay apart as floats and no triangle of a fan over them loses its area.
Placement near_placement(Rng& rng) {
    Placement p = random_placement(rng);
    const double s = std::pow(10.0, 3.0 * rng.uniform() - 1.0) / glm::length(p.u);
    p.u *= s;
    p.v *= s;
    p.origin = glm::length(p.u) * (Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0 - 5.0);
    return p;
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

// ---- glTF ------------------------------------------------------------------------------------

/// A generated glTF scene: the document (a deep nesting is spliced into its text, where
/// nlohmann's own dump would recurse), its buffer, the container, the triangles a load must
/// give, and the expected outcome.
struct GltfCase {
    nlohmann::json doc;
    std::vector<std::uint8_t> bin;
    std::string deep;                    // replaces the string "@deep@" in the text
    int container = 0;                   // 0: .gltf + .bin, 1: .gltf with base64, 2: .glb
    std::vector<std::size_t> triangles;  // per mesh
    std::vector<std::size_t> roots;      // the root nodes
    std::size_t placed = 0;
    Expect expect = Expect::load;
    std::string what;
};

/// Appends values to the buffer with a view and an accessor over them; returns the accessor.
template <class T>
std::size_t gltf_accessor(GltfCase& c, const std::vector<T>& values, int component_type,
                          const char* type, std::size_t count) {
    const std::size_t at = c.bin.size();
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(values.data());
    c.bin.insert(c.bin.end(), bytes, bytes + values.size() * sizeof(T));
    while (c.bin.size() % 4 != 0) c.bin.push_back(0);
    c.doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", at}, {"byteLength", values.size() * sizeof(T)}});
    c.doc["accessors"].push_back({{"bufferView", c.doc["bufferViews"].size() - 1},
                                  {"componentType", component_type},
                                  {"count", count},
                                  {"type", type}});
    return c.doc["accessors"].size() - 1;
}

/// A mesh of one or two primitives over a convex n-gon (n up to 1,000) in a random plane: a fan
/// (mode 6), a strip of the same corners zigzagged (mode 5), or a list with 8-, 16- or 32-bit
/// indices (mode 4); now and then also points or lines, which have no area and are skipped.
void gltf_mesh(GltfCase& c, Rng& rng) {
    nlohmann::json prims = nlohmann::json::array();
    std::size_t triangles = 0;
    for (std::size_t p = 0, np = 1 + below(rng, 2); p < np; ++p) {
        const std::size_t n = one_of<std::size_t>(rng, {3, 4, 17, 250, 1000});
        const std::size_t mode = below(rng, 8);
        const Placement place = near_placement(rng);
        std::vector<float> xyz;
        const Outline o = regular(n);
        for (std::size_t k = 0; k < n; ++k) {  // a strip zigzags: corners 0, 1, n-1, 2, n-2 ..
            const std::size_t at = mode != 1 || k == 0 ? k : k % 2 ? (k + 1) / 2 : n - k / 2;
            const Vec3 q = place(o[at]);
            xyz.insert(xyz.end(), {float(q.x), float(q.y), float(q.z)});
        }
        nlohmann::json prim = {
            {"attributes", {{"POSITION", gltf_accessor(c, xyz, 5126, "VEC3", n)}}}};
        if (mode == 0) {
            prim["mode"] = 6;
        } else if (mode == 1) {
            prim["mode"] = 5;
        } else if (mode == 2) {
            prim["mode"] = one_of<int>(rng, {0, 1, 2, 3});  // points and lines: skipped
            prims.push_back(prim);
            continue;
        } else {
            std::vector<std::uint32_t> fan;
            for (std::size_t k = 1; k + 1 < n; ++k)
                fan.insert(fan.end(), {0u, std::uint32_t(k), std::uint32_t(k + 1)});
            const int kind =
                n > 255 ? one_of<int>(rng, {5123, 5125}) : one_of<int>(rng, {5121, 5123, 5125});
            std::size_t i;
            if (kind == 5121)
                i = gltf_accessor(c, std::vector<std::uint8_t>(fan.begin(), fan.end()), kind,
                                  "SCALAR", fan.size());
            else if (kind == 5123)
                i = gltf_accessor(c, std::vector<std::uint16_t>(fan.begin(), fan.end()), kind,
                                  "SCALAR", fan.size());
            else
                i = gltf_accessor(c, fan, kind, "SCALAR", fan.size());
            prim["indices"] = i;
        }
        if (rng.uniform() < 0.5) prim["material"] = below(rng, 2);
        prims.push_back(prim);
        triangles += n - 2;
    }
    c.doc["meshes"].push_back({{"primitives", prims}});
    c.triangles.push_back(triangles);
}

/// A random local transform: none, translation / rotation / scale (a mirroring one now and
/// then), or a matrix.
void gltf_transform(nlohmann::json& node, Rng& rng) {
    const double a = 2.0 * std::numbers::pi * rng.uniform();
    switch (below(rng, 4)) {
        case 0:
            return;
        case 1:
            node["translation"] = {rng.uniform() * 10, -rng.uniform(), 3.0};
            node["rotation"] = {0.0, std::sin(a / 2), 0.0, std::cos(a / 2)};
            node["scale"] = {rng.uniform() < 0.2 ? -1.0 : 0.5 + rng.uniform(), 1.0, 1.0};
            return;
        case 2:  // exporters round unit quaternions
            node["rotation"] = {0.5, 0.5, 0.5, 0.5001};
            return;
        default:
            node["matrix"] = {
                std::cos(a), std::sin(a), 0, 0, -std::sin(a), std::cos(a), 0, 0, 0, 0, 1, 0,
                1,           2,           3, 1};
    }
}

/// The node tree: a chain of random depth (up to 3,000: the walk has no recursion) with
/// branches, meshes on some nodes; its roots in c.roots.
void gltf_nodes(GltfCase& c, Rng& rng) {
    const std::size_t n = rng.uniform() < 0.1 ? 3000 : 1 + below(rng, 12);
    for (std::size_t k = 0; k < n; ++k) {
        nlohmann::json node = nlohmann::json::object();
        gltf_transform(node, rng);
        if (rng.uniform() < (n > 100 ? 0.005 : 0.6) || k + 1 == n) {
            const std::size_t m = below(rng, c.triangles.size());
            node["mesh"] = m;
            c.placed += c.triangles[m];
        }
        // Each node hangs below an earlier one (a tree) or starts a new root.
        if (k == 0 || rng.uniform() < 0.15)
            c.roots.push_back(k);
        else
            c.doc["nodes"][k - 1 - below(rng, std::min<std::size_t>(k, 3))]["children"].push_back(
                k);
        c.doc["nodes"][k] = node;
    }
}

/// Makes one hostile feature in a valid document and says what the reader must do with it.
void make_gltf_hostile(GltfCase& c, Rng& rng) {
    auto& nodes = c.doc["nodes"];
    // The POSITION accessor of a triangle primitive that the last node places (the reader need
    // not look at what no node places).
    const auto& prims = c.doc["meshes"][nodes.back()["mesh"].get<std::size_t>()]["primitives"];
    std::optional<std::size_t> used;
    for (const auto& p : prims)
        if (p.value("mode", 4) >= 4) used = p["attributes"]["POSITION"].get<std::size_t>();
    c.expect = Expect::refuse;
    std::size_t kind = below(rng, 10);
    if ((kind == 2 || kind == 3) && !used) kind = 4;
    switch (kind) {
        case 0:
            c.what = "a node that is its own ancestor, or has two parents";
            nodes[nodes.size() - 1]["children"].push_back(0);
            c.doc["scenes"] = {{{"nodes", c.roots}}};  // without, node 0 might be reached once
            break;
        case 1:
            c.what = "a mesh that does not exist";
            nodes[0]["mesh"] = c.doc["meshes"].size();
            break;
        case 2:
            c.what = "an accessor that reads past its buffer";
            c.doc["accessors"][*used]["count"] =
                one_of<std::uint64_t>(rng, {1u << 20, 4294967295u});
            break;
        case 3:
            c.what = "a view that starts past the buffer";
            c.doc["bufferViews"][c.doc["accessors"][*used]["bufferView"].get<std::size_t>()]
                 ["byteOffset"] = 1u << 30;
            break;
        case 4:
            c.what = "an extension that changes the geometry";
            c.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
            break;
        case 5:
            c.what = "a deep nesting where an extension's name should be";
            c.doc["extensionsRequired"] = {"@deep@"};
            c.deep = std::string(100000, '[') + std::string(100000, ']');
            break;
        case 6:
            c.what = "a deep nesting in extras (ignored, or refused)";
            c.doc["extras"] = "@deep@";
            c.deep = std::string(100000, '[') + std::string(100000, ']');
            c.expect = Expect::either;
            break;
        case 7:
            c.what = "zero scales (triangles of no area are dropped)";
            for (auto& n : nodes) n["scale"] = {1.0, 0.0, 1.0}, n.erase("matrix");
            c.expect = Expect::either;
            break;
        case 8:
            c.what = "a buffer that is not there";
            c.container = 0;
            c.doc["buffers"][0]["uri"] = "missing.bin";
            break;
        default:
            c.what = "a child index out of range";
            nodes[0]["children"].push_back(nodes.size() + below(rng, 1000));
    }
}

/// A random glTF scene: 1 to 3 meshes, a node tree over them, two materials.
GltfCase random_gltf(Rng& rng) {
    GltfCase c;
    c.doc = {{"asset", {{"version", "2.0"}}},
             {"materials",
              {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.5, 0.2, 1.0}}}}},
               {{"emissiveFactor", {1.0, 1.0, 0.5}}}}}};
    for (std::size_t m = 0, n = 1 + below(rng, 3); m < n; ++m) gltf_mesh(c, rng);
    gltf_nodes(c, rng);
    if (rng.uniform() < 0.7) c.doc["scenes"] = {{{"nodes", c.roots}}};  // else: every root node
    c.container = int(below(rng, 3));
    c.doc["buffers"] = {{{"byteLength", c.bin.size()}}};
    if (c.container == 0) c.doc["buffers"][0]["uri"] = "case.bin";
    if (c.placed == 0) c.expect = Expect::refuse, c.what = "no triangles";
    if (rng.uniform() < 0.35 && c.placed > 0) make_gltf_hostile(c, rng);
    return c;
}

std::string base64(const std::vector<std::uint8_t>& b) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t k = 0; k < b.size(); k += 3) {
        const std::size_t left = std::min<std::size_t>(3, b.size() - k);
        const std::uint32_t v = (std::uint32_t(b[k]) << 16) |
                                (left > 1 ? std::uint32_t(b[k + 1]) << 8 : 0) |
                                (left > 2 ? b[k + 2] : 0);
        for (std::size_t d = 0; d < 4; ++d)
            out += d <= left ? digits[(v >> (18 - 6 * d)) & 63] : '=';
    }
    return out;
}

/// Writes the case as a .gltf (with case.bin, or its buffer in base64) or a .glb; returns its path.
std::string write_gltf_case(GltfCase c, const Scratch& scratch) {
    if (c.container == 1 && c.doc["buffers"][0].find("uri") == c.doc["buffers"][0].end())
        c.doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(c.bin);
    std::string json = c.doc.dump();
    if (!c.deep.empty()) json.replace(json.find("\"@deep@\""), 8, c.deep);
    if (c.container != 2) {
        scratch.write("case.bin", std::string(c.bin.begin(), c.bin.end()));
        return scratch.write("case.gltf", json);
    }
    while (json.size() % 4 != 0) json += ' ';
    std::string glb;
    auto word = [&](std::uint32_t w) {
        for (int k = 0; k < 4; ++k) glb += char((w >> (8 * k)) & 0xFF);
    };
    word(0x46546C67u), word(2), word(std::uint32_t(12 + 8 + json.size() + 8 + c.bin.size()));
    word(std::uint32_t(json.size())), word(0x4E4F534Au);
    glb += json;
    word(std::uint32_t(c.bin.size())), word(0x004E4942u);
    glb.append(c.bin.begin(), c.bin.end());
    return scratch.write("case.glb", glb);
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

TEST_CASE(
    "glTF generator: 200 hostile scenes (.gltf, base64, .glb) give every triangle or are refused") {
    Scratch scratch;
    Rng rng(14);
    int loaded = 0, refused = 0;
    for (int k = 0; k < 200; ++k) {
        const GltfCase c = random_gltf(rng);
        CAPTURE(k);
        CAPTURE(c.what);
        CAPTURE(c.container);
        try {
            const GltfReadResult<Rgb> r = read_gltf_result<Rgb>(write_gltf_case(c, scratch));
            check_loaded(r.scene);
            CHECK(c.expect != Expect::refuse);
            if (c.expect == Expect::load) {
                CHECK(r.scene.faces.size() == c.placed);
                CHECK(r.dropped_triangles == 0);
            }
            ++loaded;
        } catch (const Error& e) {
            CHECK_MESSAGE(c.expect != Expect::load, e.what());
            CHECK(std::string(e.what()).find("case.") != std::string::npos);
            ++refused;
        }
    }
    CHECK(loaded > 80);
    CHECK(refused > 30);
    MESSAGE("loaded " << loaded << ", refused " << refused);
}
