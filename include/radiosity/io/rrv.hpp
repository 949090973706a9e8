#pragma once
/// @file rrv.hpp  Scenes of RRV, the Radiosity Renderer and Visualizer (Dudka 2007): its XML format
/// read (object definitions of triangle strips and the cuboid, barrel, globe and teapot
/// primitives; nested translate, rotate and scale; emission, reflectivity and radiosity
/// attributes) and written back with a radiosity per triangle, as RRV does. XML through pugixml.
/// The meanings follow RRV exactly (../shared/rrv/README.md): innermost transform first; RRV's
/// own rotation order and turn directions; missing numbers 0; shear accepted and ignored.

#include <radiosity/error.hpp>
#include <radiosity/io/rrv_primitives.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <pugixml.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace radiosity {

/// Settings of the RRV reader.
struct RrvOptions {
    std::string teapot_obj;         ///< RRV's teapot mesh; empty: teapot.obj beside the scene
    float max_reflectance = 0.99f;  ///< RRV allows 1; radiosity needs < 1: clamped to this
};

namespace detail {

/// An RRV colour attribute "r,g,b", or nothing when absent.
struct RrvColours {
    std::array<float, 3> emission{}, reflectivity{};
    bool has_emission = false, has_reflectivity = false;
};

/// Reads the line of a node from the file text (pugixml gives offsets, not lines).
class RrvText {
  public:
    explicit RrvText(const std::string& path) : path_(path) {
        std::ifstream in(path, std::ios::binary);
        std::stringstream s;
        s << in.rdbuf();
        text_ = s.str();
    }
    std::string where(std::ptrdiff_t offset) const {
        if (offset < 0) return path_;
        const auto end =
            text_.begin() + std::min<std::ptrdiff_t>(offset, std::ptrdiff_t(text_.size()));
        return path_ + ":" + std::to_string(1 + std::count(text_.begin(), end, '\n'));
    }
    std::string where(const pugi::xml_node& n) const { return where(n.offset_debug()); }
    const std::string& path() const { return path_; }

  private:
    std::string path_, text_;
};

/// Parses "r,g,b" (RRV colour attributes).
inline std::array<float, 3> rrv_colour(const pugi::xml_attribute& a, const std::string& where) {
    std::array<float, 3> c{};
    std::string s = a.value();
    std::replace(s.begin(), s.end(), ',', ' ');
    std::istringstream in(s);
    for (float& x : c)
        if (!(in >> x) || !std::isfinite(x))
            throw Error(where + ": attribute " + a.name() + "=\"" + a.value() +
                        "\" is not three numbers r,g,b");
    return c;
}

/// Overrides the colours with the attributes present on a node.
inline RrvColours rrv_colours(const pugi::xml_node& n, RrvColours c, const RrvText& text) {
    if (auto a = n.attribute("emission")) {
        c.emission = rrv_colour(a, text.where(n));
        c.has_emission = true;
    }
    if (auto a = n.attribute("reflectivity")) {
        c.reflectivity = rrv_colour(a, text.where(n));
        c.has_reflectivity = true;
    }
    return c;
}

/// A number attribute, 0 when absent (as RRV reads them).
inline double rrv_number(const pugi::xml_node& n, const char* name, const RrvText& text) {
    const auto a = n.attribute(name);
    if (!a) return 0.0;
    char* end = nullptr;
    const double x = std::strtod(a.value(), &end);
    if (end == a.value() || *end != '\0' || !std::isfinite(x))
        throw Error(text.where(n) + ": " + n.name() + " " + name + "=\"" + a.value() +
                    "\" is not a number");
    return x;
}

/// A triangle before placement, with its colours.
struct RrvTriangle {
    std::array<Vec3, 3> v;
    RrvColours colours;
};

/// The transform of a point by RRV's rotate: the axis (normalised) times the angle gives
/// (ax, ay, az); rotate about z by az, then about y by ay (RRV's turn direction), then about x.
inline Vec3 rrv_rotate(Vec3 p, const Vec3& angles) {
    const auto [ax, ay, az] = std::array<double, 3>{angles.x, angles.y, angles.z};
    p = {p.x * std::cos(az) - p.y * std::sin(az), p.x * std::sin(az) + p.y * std::cos(az), p.z};
    p = {p.x * std::cos(ay) - p.z * std::sin(ay), p.y, p.x * std::sin(ay) + p.z * std::cos(ay)};
    p = {p.x, p.y * std::cos(ax) - p.z * std::sin(ax), p.y * std::sin(ax) + p.z * std::cos(ax)};
    return p;
}

}  // namespace detail

/// Reads an RRV scene (see the file comment). Patch colours: the most specific attribute wins
/// (triangle over triangle set over primitive); a missing reflectivity is 0, a missing emission
/// 0; a reflectivity of 1 or more (RRV allows it) is clamped to options.max_reflectance. The
/// `radiosity` attributes (RRV's starting values) are read but not used: a solve starts anew.
/// Triangles placed with zero area (a zero scale, repeated corners) are left out and counted in
/// Scene::zero_area_faces. Throws Error naming the file and line for malformed XML, unknown
/// elements or objects, bad numbers, or a strip with too few vertices.
template <SpectrumType S>
Scene<S> read_rrv(const std::string& path, const RrvOptions& options = {}) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw Error(path + ": no such file");
    const detail::RrvText text(path);
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_file(path.c_str());
    if (!parsed) throw Error(text.where(parsed.offset) + ": " + parsed.description());
    const pugi::xml_node scene_node = doc.child("scene");
    if (!scene_node) throw Error(path + ": not an RRV scene (no <scene> element)");
    const std::string teapot = options.teapot_obj.empty()
                                   ? (fs::path(path).parent_path() / "teapot.obj").string()
                                   : options.teapot_obj;

    // Object definitions: triangles in object space with their colours.
    std::map<std::string, std::vector<detail::RrvTriangle>> defs;
    for (pugi::xml_node def : scene_node.child("head").children("objectdef")) {
        const std::string name = def.attribute("name").value();
        auto& tris = defs[name];
        for (pugi::xml_node item : def.children()) {
            if (item.type() != pugi::node_element) continue;
            const std::string kind = item.name();
            const detail::RrvColours base = detail::rrv_colours(item, {}, text);
            std::vector<std::array<Vec3, 3>> shape;
            if (kind == "triangleset") {
                std::vector<Vec3> strip;
                std::vector<detail::RrvColours> colours;
                for (pugi::xml_node t : item.children()) {
                    if (t.type() != pugi::node_element) continue;
                    if (std::string(t.name()) != "triangle" &&
                        std::string(t.name()) != "trianglenext")
                        throw Error(text.where(t) + ": unexpected <" + t.name() +
                                    "> in a triangleset");
                    const detail::RrvColours c = detail::rrv_colours(t, base, text);
                    for (pugi::xml_node v : t.children("vertex")) {
                        strip.emplace_back(detail::rrv_number(v, "x", text),
                                           detail::rrv_number(v, "y", text),
                                           detail::rrv_number(v, "z", text));
                        colours.push_back(c);
                    }
                }
                if (strip.size() < 3)
                    throw Error(text.where(item) + ": a triangle set needs at least 3 vertices");
                for (std::size_t k = 0; k + 2 < strip.size(); ++k) {  // OpenGL strip order
                    const bool odd = k % 2 == 1;
                    tris.push_back({{odd ? strip[k + 1] : strip[k], odd ? strip[k] : strip[k + 1],
                                     strip[k + 2]},
                                    colours[k + 2]});
                }
                continue;
            }
            if (kind == "cuboid")
                detail::rrv_cuboid(shape);
            else if (kind == "barrel")
                detail::rrv_barrel(shape);
            else if (kind == "globe")
                detail::rrv_globe(shape);
            else if (kind == "teapot")
                detail::rrv_teapot(teapot, shape);
            else
                throw Error(text.where(item) + ": unknown element <" + kind + "> in an objectdef");
            for (const auto& t : shape) tris.push_back({t, base});
        }
    }

    // The body: place objects through the nested transforms (innermost first).
    detail::SceneBuilder<S> builder(path);
    std::map<std::array<float, 6>, std::uint32_t> material_of;
    using Transform = std::function<Vec3(const Vec3&)>;
    std::size_t zero_area = 0;
    std::function<void(pugi::xml_node, const Transform&)> walk = [&](pugi::xml_node node,
                                                                     const Transform& outer) {
        for (pugi::xml_node n : node.children()) {
            if (n.type() != pugi::node_element) continue;
            const std::string kind = n.name();
            const Vec3 d(detail::rrv_number(n, "dx", text), detail::rrv_number(n, "dy", text),
                         detail::rrv_number(n, "dz", text));
            if (kind == "translate") {
                walk(n, [&outer, d](const Vec3& p) { return outer(p + d); });
            } else if (kind == "scale") {
                walk(n, [&outer, d](const Vec3& p) { return outer(p * d); });
            } else if (kind == "rotate") {
                const double angle =
                    detail::rrv_number(n, "angle", text) * std::numbers::pi / 180.0;
                const double len = glm::length(d);
                const Vec3 angles = len > 0.0 ? d / len * angle : Vec3(0.0);
                walk(n, [&outer, angles](const Vec3& p) {
                    return outer(detail::rrv_rotate(p, angles));
                });
            } else if (kind == "shear") {
                walk(n, outer);  // accepted and ignored, as RRV does
            } else if (kind == "object") {
                const std::string name = n.attribute("name").value();
                const auto it = defs.find(name);
                if (it == defs.end())
                    throw Error(text.where(n) + ": no objectdef named '" + name + "'");
                for (const auto& t : it->second) {
                    const auto& c = t.colours;
                    std::array<float, 6> key{};
                    for (int k = 0; k < 3; ++k) {
                        key[k] = std::max(0.0f, c.emission[k]);
                        key[3 + k] = std::clamp(c.reflectivity[k], 0.0f, options.max_reflectance);
                    }
                    auto [m, fresh] = material_of.try_emplace(key, 0);
                    if (fresh)
                        m->second = builder.material({from_rgb<S>(key[0], key[1], key[2]),
                                                      from_rgb<S>(key[3], key[4], key[5]),
                                                      "rrv " + std::to_string(material_of.size())});
                    const std::vector<Vec3> placed{outer(t.v[0]), outer(t.v[1]), outer(t.v[2])};
                    if (polygon_area(placed) > 0.0)
                        builder.face(placed, m->second);
                    else
                        ++zero_area;  // a zero scale, or a degenerate triangle: counted
                }
            } else {
                throw Error(text.where(n) + ": unknown element <" + kind + "> in the body");
            }
        }
    };
    walk(scene_node.child("body"), [](const Vec3& p) { return p; });
    Scene<S> scene = builder.take();
    scene.zero_area_faces = zero_area;
    if (scene.faces.empty()) throw Error(path + ": the scene places no triangles");
    return scene;
}

/// Writes a solved mesh as an RRV scene: one object of triangles (polygons fanned), each with
/// its emission, reflectivity and solved radiosity, as RRV saves its results. Throws Error
/// naming the path on failure.
template <SpectrumType S>
void write_rrv(const Mesh<S>& mesh, const std::string& path) {
    std::ofstream out(path);
    if (!out) throw Error("cannot write '" + path + "'");
    auto colour = [](const S& s) {
        const auto c = to_rgb(s);
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.6g,%.6g,%.6g", c[0], c[1], c[2]);
        return std::string(buf);
    };
    out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<scene>\n  <head>\n    <objectdef "
           "name=\"solved\">\n";
    for (auto f : mesh.faces()) {
        const auto& d = mesh.data(f);
        const auto poly = face_polygon(mesh, f);
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            out << "      <triangleset emission=\"" << colour(d.emission) << "\" reflectivity=\""
                << colour(d.reflectance) << "\" radiosity=\"" << colour(d.radiosity) << "\">\n"
                << "        <triangle>\n";
            for (const Vec3& p : {poly[0], poly[k], poly[k + 1]}) {
                char buf[128];
                std::snprintf(buf, sizeof buf,
                              "          <vertex x=\"%.9g\" y=\"%.9g\" z=\"%.9g\"/>\n", p.x, p.y,
                              p.z);
                out << buf;
            }
            out << "        </triangle>\n      </triangleset>\n";
        }
    }
    out << "    </objectdef>\n  </head>\n  <body>\n    <object name=\"solved\"/>\n  </body>\n"
           "</scene>\n";
    if (!out) throw Error("cannot write '" + path + "'");
}

}  // namespace radiosity
