#pragma once
/// @file rrv.hpp  Scenes of RRV, the Radiosity Renderer and Visualizer (Dudka 2007): its XML format
/// read (object definitions of triangle strips and the cuboid, barrel, globe and teapot
/// primitives; nested translate, rotate and scale; emission, reflectivity and radiosity
/// attributes) and written back with a radiosity per triangle, as RRV does. XML through pugixml.
/// The meanings follow RRV exactly (../shared/rrv/README.md): innermost transform first; RRV's
/// own rotation order and turn directions; missing numbers 0; shear accepted and ignored.

#include <radiosity/error.hpp>
#include <radiosity/io/rrv_primitives.hpp>
#include <radiosity/io/rrv_transform.hpp>
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
#include <map>
#include <optional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace radiosity {

/// Settings of the RRV reader.
struct RrvOptions {
    std::string teapot_obj;         ///< RRV's teapot mesh; empty: teapot.obj beside the scene
    float max_reflectance = 0.99f;  ///< RRV allows 1; radiosity needs < 1: clamped to this
    std::size_t max_depth = 256;    ///< transforms nested deeper than this are refused
    /// Triangles defined and placed, at most: a short file can place a large definition many
    /// times (a teapot is 2,256 triangles), so the scene's size is bounded here, not by the file.
    std::size_t max_triangles = 10'000'000;
};

namespace detail {

/// An RRV colour attribute "r,g,b", or nothing when absent.
struct RrvColours {
    std::array<float, 3> emission{}, reflectivity{};
    bool has_emission = false, has_reflectivity = false;
};

/// The file's text, parsed once by pugixml, and the line of a node for messages (pugixml gives
/// offsets, not lines; a line is counted only when a message needs it).
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
    const std::string& text() const { return text_; }

  private:
    std::string path_, text_;
};

/// Parses "r,g,b" (RRV colour attributes) of node n.
inline std::array<float, 3> rrv_colour(const pugi::xml_node& n, const pugi::xml_attribute& a,
                                       const RrvText& text) {
    std::array<float, 3> c{};
    std::string s = a.value();
    std::replace(s.begin(), s.end(), ',', ' ');
    std::istringstream in(s);
    for (float& x : c)
        if (!(in >> x) || !std::isfinite(x))
            throw Error(text.where(n) + ": attribute " + a.name() + "=\"" + a.value() +
                        "\" is not three numbers r,g,b");
    return c;
}

/// Overrides the colours with the attributes present on a node.
inline RrvColours rrv_colours(const pugi::xml_node& n, RrvColours c, const RrvText& text) {
    if (auto a = n.attribute("emission")) {
        c.emission = rrv_colour(n, a, text);
        c.has_emission = true;
    }
    if (auto a = n.attribute("reflectivity")) {
        c.reflectivity = rrv_colour(n, a, text);
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

/// Counts the triangles a scene makes (defined and placed) against RrvOptions::max_triangles.
class RrvBudget {
  public:
    explicit RrvBudget(std::size_t max) : max_(max) {}
    void spend(std::size_t n, const RrvText& text, const pugi::xml_node& at) {
        if (n > max_ - used_)
            throw Error(text.where(at) + ": <" + at.name() + "> makes the scene larger than " +
                        std::to_string(max_) + " triangles (RrvOptions::max_triangles)");
        used_ += n;
    }

  private:
    std::size_t max_, used_ = 0;
};

/// The triangles of a triangleset (an OpenGL strip: each vertex after the first two makes one).
inline void rrv_triangleset(const pugi::xml_node& item, const RrvColours& base, const RrvText& text,
                            RrvBudget& budget, std::vector<RrvTriangle>& tris) {
    std::vector<Vec3> strip;
    std::vector<RrvColours> colours;
    for (pugi::xml_node t : item.children()) {
        if (t.type() != pugi::node_element) continue;
        if (std::string(t.name()) != "triangle" && std::string(t.name()) != "trianglenext")
            throw Error(text.where(t) + ": unexpected <" + t.name() + "> in a triangleset");
        const RrvColours c = rrv_colours(t, base, text);
        for (pugi::xml_node v : t.children("vertex")) {
            strip.emplace_back(rrv_number(v, "x", text), rrv_number(v, "y", text),
                               rrv_number(v, "z", text));
            colours.push_back(c);
        }
    }
    if (strip.size() < 3)
        throw Error(text.where(item) + ": a triangle set needs at least 3 vertices");
    budget.spend(strip.size() - 2, text, item);
    for (std::size_t k = 0; k + 2 < strip.size(); ++k) {  // OpenGL strip order
        const bool odd = k % 2 == 1;
        tris.push_back(
            {{odd ? strip[k + 1] : strip[k], odd ? strip[k] : strip[k + 1], strip[k + 2]},
             colours[k + 2]});
    }
}

/// The object definitions of the head: triangles in object space with their colours. The
/// teapot's mesh is read once, however many definitions use it.
inline std::map<std::string, std::vector<RrvTriangle>> rrv_objectdefs(const pugi::xml_node& head,
                                                                      const RrvText& text,
                                                                      const std::string& teapot,
                                                                      RrvBudget& budget) {
    std::map<std::string, std::vector<RrvTriangle>> defs;
    std::vector<std::array<Vec3, 3>> teapot_shape;
    for (pugi::xml_node def : head.children("objectdef")) {
        auto& tris = defs[def.attribute("name").value()];
        for (pugi::xml_node item : def.children()) {
            if (item.type() != pugi::node_element) continue;
            const std::string kind = item.name();
            const RrvColours base = rrv_colours(item, {}, text);
            if (kind == "triangleset") {
                rrv_triangleset(item, base, text, budget, tris);
                continue;
            }
            std::vector<std::array<Vec3, 3>> shape;
            if (kind == "cuboid")
                rrv_cuboid(shape);
            else if (kind == "barrel")
                rrv_barrel(shape);
            else if (kind == "globe")
                rrv_globe(shape);
            else if (kind == "teapot") {
                if (teapot_shape.empty()) rrv_teapot(teapot, teapot_shape);
                shape = teapot_shape;
            } else
                throw Error(text.where(item) + ": unknown element <" + kind + "> in an objectdef");
            budget.spend(shape.size(), text, item);
            for (const auto& t : shape) tris.push_back({t, base});
        }
    }
    return defs;
}

/// The transform an element of the body opens (RRV's meanings, rrv_transform.hpp), with its
/// numbers checked; an element that is not a transform gives nothing.
inline std::optional<RrvTransform> rrv_transform(const pugi::xml_node& n, const RrvText& text) {
    const std::string kind = n.name();
    const Vec3 d(rrv_number(n, "dx", text), rrv_number(n, "dy", text), rrv_number(n, "dz", text));
    RrvTransform t;
    t.d = d;
    if (kind == "translate")
        t.kind = RrvTransform::Kind::translate;
    else if (kind == "scale")
        t.kind = RrvTransform::Kind::scale;
    else if (kind == "rotate") {
        t.kind = RrvTransform::Kind::rotate;
        t.rotation = RrvRotation(rrv_rotation_angles(d, rrv_number(n, "angle", text)));
    } else if (kind == "shear")
        t.kind = RrvTransform::Kind::shear;  // accepted and ignored, as RRV does
    else
        return std::nullopt;
    return t;
}

/// Places the objects of an RRV body through its nested transforms into a scene. The nesting is
/// walked with an explicit stack of elements (and one of transforms beside it), so its depth is
/// bounded by RrvOptions::max_depth with a message, never by the call stack. The walk is made
/// twice: first to count the triangles the body places against RrvOptions::max_triangles
/// (refused at once, before any is placed), then to place them. A placed triangle whose corners
/// or area are not finite (a transform overflowed) is refused naming its object; one of zero
/// area, or whose corners the scene shares into fewer than three vertices (closer than 1e-6), is
/// dropped (counted in Scene::zero_area_faces if of zero area).
template <SpectrumType S>
class RrvBodyReader {
  public:
    RrvBodyReader(const RrvText& text, const RrvOptions& options,
                  const std::map<std::string, std::vector<RrvTriangle>>& defs, RrvBudget& budget)
        : text_(text), options_(options), defs_(defs), budget_(budget), builder_(text.path()) {}

    Scene<S> read(const pugi::xml_node& body) {
        walk(body, [&](const pugi::xml_node& n, const RrvTransformStack&) {
            budget_.spend(definition(n).size(), text_, n);
        });
        walk(body, [&](const pugi::xml_node& n, const RrvTransformStack& t) { place(n, t); });
        Scene<S> scene = builder_.take();
        scene.zero_area_faces = zero_area_;
        return scene;
    }

  private:
    /// Calls visit(object, transforms) for every object of the body, in document order.
    template <class Visit>
    void walk(const pugi::xml_node& body, Visit&& visit) const {
        std::vector<pugi::xml_node> next{body.first_child()};  // per level: the next child
        RrvTransformStack transforms;                          // one per level below the body
        while (!next.empty()) {
            const pugi::xml_node n = next.back();
            if (!n) {  // this level is done
                next.pop_back();
                if (!next.empty()) transforms.pop();
                continue;
            }
            next.back() = n.next_sibling();
            if (n.type() != pugi::node_element) continue;
            if (const auto t = rrv_transform(n, text_)) {
                if (transforms.depth() >= options_.max_depth)
                    throw Error(text_.where(n) + ": <" + n.name() + "> is nested deeper than " +
                                std::to_string(options_.max_depth) +
                                " transforms (RrvOptions::max_depth)");
                transforms.push(*t);
                next.push_back(n.first_child());
            } else if (std::string(n.name()) == "object") {
                visit(n, transforms);
            } else {
                throw Error(text_.where(n) + ": unknown element <" + n.name() + "> in the body");
            }
        }
    }

    const std::vector<RrvTriangle>& definition(const pugi::xml_node& n) const {
        const std::string name = n.attribute("name").value();
        const auto it = defs_.find(name);
        if (it == defs_.end()) throw Error(text_.where(n) + ": no objectdef named '" + name + "'");
        return it->second;
    }

    void place(const pugi::xml_node& n, const RrvTransformStack& transforms) {
        for (const auto& t : definition(n)) {
            const std::uint32_t m = material(t.colours);  // also for a dropped triangle, as before
            const std::vector<Vec3> placed{transforms.place(t.v[0]), transforms.place(t.v[1]),
                                           transforms.place(t.v[2])};
            const double area = polygon_area(placed);  // not finite if any corner is not
            if (!std::isfinite(area))
                throw Error(text_.where(n) + ": object '" + n.attribute("name").value() +
                            "' is placed beyond the range of numbers (a transform overflows)");
            if (area > 0.0)
                builder_.face(placed, m);
            else
                ++zero_area_;  // a zero scale, or a degenerate triangle: counted
        }
    }

    std::uint32_t material(const RrvColours& c) {
        std::array<float, 6> key{};
        for (int k = 0; k < 3; ++k) {
            key[k] = std::max(0.0f, c.emission[k]);
            key[3 + k] = std::clamp(c.reflectivity[k], 0.0f, options_.max_reflectance);
        }
        auto [m, fresh] = material_of_.try_emplace(key, 0);
        if (fresh)
            m->second = builder_.material({from_rgb<S>(key[0], key[1], key[2]),
                                           from_rgb<S>(key[3], key[4], key[5]),
                                           "rrv " + std::to_string(material_of_.size())});
        return m->second;
    }

    const RrvText& text_;
    const RrvOptions& options_;
    const std::map<std::string, std::vector<RrvTriangle>>& defs_;
    RrvBudget& budget_;
    SceneBuilder<S> builder_;
    std::map<std::array<float, 6>, std::uint32_t> material_of_;
    std::size_t zero_area_ = 0;  ///< triangles placed with zero area, left out
};

}  // namespace detail

/// Reads an RRV scene (see the file comment). Patch colours: the most specific attribute wins
/// (triangle over triangle set over primitive); a missing reflectivity is 0, a missing emission
/// 0; a reflectivity of 1 or more (RRV allows it) is clamped to options.max_reflectance. The
/// `radiosity` attributes (RRV's starting values) are read but not used: a solve starts anew.
/// Triangles placed with zero area (a zero scale, repeated corners) are left out and counted in
/// Scene::zero_area_faces. Throws Error naming the file and line for
/// malformed XML, unknown elements or objects, bad numbers, a strip with too few vertices, a
/// transform that overflows, transforms nested deeper than options.max_depth or a scene of more
/// than options.max_triangles. Cost: linear in the file, times the depth for each placed vertex.
template <SpectrumType S>
Scene<S> read_rrv(const std::string& path, const RrvOptions& options = {}) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw Error(path + ": no such file");
    const detail::RrvText text(path);
    pugi::xml_document doc;  // pugixml parses nesting without recursion (checked 10^6 deep)
    const pugi::xml_parse_result parsed = doc.load_buffer(text.text().data(), text.text().size());
    if (!parsed) throw Error(text.where(parsed.offset) + ": " + parsed.description());
    const pugi::xml_node scene_node = doc.child("scene");
    if (!scene_node) throw Error(path + ": not an RRV scene (no <scene> element)");
    const std::string teapot = options.teapot_obj.empty()
                                   ? (fs::path(path).parent_path() / "teapot.obj").string()
                                   : options.teapot_obj;
    detail::RrvBudget budget(options.max_triangles);
    const auto defs = detail::rrv_objectdefs(scene_node.child("head"), text, teapot, budget);
    Scene<S> scene =
        detail::RrvBodyReader<S>(text, options, defs, budget).read(scene_node.child("body"));
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
