#pragma once
/// @file obj.hpp  Reading scenes from Wavefront OBJ + MTL files through tinyobjloader: polygons
/// are kept as they are (not triangulated), Kd is the reflectance and Ke the emission. Every
/// problem becomes a one-line radiosity::Error naming the file and, where it can, the line.
/// tinyobjloader (2.0.0rc10) reads a word that is not a number as 0 and keeps a face's corner
/// count modulo 256, so the files are scanned here too, split into lines and words as it splits
/// them: the numbers are checked and the true corner counts used.

#include <radiosity/error.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace radiosity {

namespace detail {

/// Joins a multi-line message (tinyobjloader's errors and warnings) into one line.
inline std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.pop_back();
    return s;
}

/// The whole of a file, or nothing if it cannot be opened.
inline std::optional<std::string> slurp_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Calls visit(line number, statement) for every line of an OBJ or MTL text, split as
/// tinyobjloader splits it: a line ends at \n, \r or \r\n, and at a NUL byte; leading spaces
/// and tabs are skipped.
template <class Visit>
void for_each_obj_line(const std::string& text, Visit&& visit) {
    std::size_t n = 0;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t end = std::min(text.find_first_of("\r\n", at), text.size());
        const std::string line = text.substr(at, end - at);  // c_str() stops at a NUL byte
        at = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
        const char* s = line.c_str();
        visit(++n, s + std::strspn(s, " \t"));
    }
}

/// Checks the first three words of a statement's arguments: each a decimal number (tinyobjloader
/// reads anything else, "nan" too, as 0) that is finite as a float (its real_t), else Error.
inline void check_obj_numbers(const char* s, const std::string& at, const char* what) {
    for (int k = 0; k < 3; ++k) {
        s += std::strspn(s, " \t");
        const std::size_t n = std::strcspn(s, " \t");
        const std::string word(s, n);
        if (n == 0) throw Error(at + ": " + what + " needs three numbers");
        char* end = nullptr;
        const double x = std::strtod(word.c_str(), &end);
        if (word.find_first_not_of("0123456789+-.eE") != std::string::npos ||
            end != word.c_str() + n || !(std::abs(x) <= std::numeric_limits<float>::max()))
            throw Error(at + ": " + what + " '" + word + "' is not a finite number");
        s += n;
    }
}

/// Whether statement s is the keyword followed by a space or a tab (tinyobjloader's test).
inline bool is_obj_statement(const char* s, const char* keyword) {
    const std::size_t n = std::strlen(keyword);
    return std::strncmp(s, keyword, n) == 0 && (s[n] == ' ' || s[n] == '\t');
}

/// Turns every skin weight statement ('vw', a tinyobjloader extension that radiosity has no use
/// for) into a comment, in place, keeping every line where it was: tinyobjloader converts a
/// joint id read as a real to int unchecked, undefined for one past int's range (a fuzzer's
/// find). A statement starts a line, as for_each_obj_line splits them. Cost: one pass over the
/// text.
inline void blank_skin_weights(std::string& text) {
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t first = text.find_first_not_of(" \t", at);
        if (first == std::string::npos) break;
        if (is_obj_statement(text.c_str() + first, "vw")) text[first] = '#';
        const std::size_t end = text.find_first_of("\r\n", first);
        if (end == std::string::npos) break;
        at = end + 1;
    }
}

/// The line and the true number of corners of every face ('f') statement of an OBJ text, in
/// order (tinyobjloader makes one face of each, or warns), and the line of every vertex ('v').
struct ObjStatements {
    std::vector<std::size_t> line, corners;
    std::vector<std::size_t> vertex_line;
};

/// Scans an OBJ text: checks every vertex's coordinates and finds the face statements. One pass.
inline ObjStatements scan_obj(const std::string& text, const std::string& path) {
    ObjStatements faces;
    for_each_obj_line(text, [&](std::size_t n, const char* s) {
        if (is_obj_statement(s, "v")) {
            check_obj_numbers(s + 2, path + ":" + std::to_string(n), "vertex coordinate");
            faces.vertex_line.push_back(n);
        }
        if (!is_obj_statement(s, "f")) return;
        std::size_t corners = 0;  // words, as tinyobjloader reads one corner from each
        for (s += 2; *(s += std::strspn(s, " \t")) != '\0'; s += std::strcspn(s, " \t")) ++corners;
        faces.line.push_back(n);
        faces.corners.push_back(corners);
    });
    return faces;
}

/// tinyobjloader's reading of the MTL files an OBJ names (in the OBJ's folder), each file's Kd
/// and Ke checked first for what tinyobjloader would read as 0.
class CheckedMtlReader : public tinyobj::MaterialReader {
  public:
    explicit CheckedMtlReader(std::string dir) : dir_(std::move(dir)) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn, std::string*) override {
        const std::string path =
            dir_.empty() ? name : (std::filesystem::path(dir_) / name).string();
        const std::optional<std::string> text = slurp_file(path);
        if (!text) {
            *warn += "material file " + path + " not found\n";
            return false;
        }
        for_each_obj_line(*text, [&](std::size_t n, const char* s) {
            for (const char* key : {"Kd", "Ke"})
                if (is_obj_statement(s, key))
                    check_obj_numbers(s + 3, path + ":" + std::to_string(n), key);
        });
        std::istringstream in(*text);
        tinyobj::LoadMtl(names, materials, &in, warn, nullptr);
        return true;
    }

  private:
    std::string dir_;
};

/// Checks an MTL material: Kd in [0, 1), Ke finite and >= 0, all finite.
inline void check_obj_material(const tinyobj::material_t& m, const std::string& where) {
    for (int k = 0; k < 3; ++k) {
        const double kd = m.diffuse[k], ke = m.emission[k];
        if (!std::isfinite(kd) || !std::isfinite(ke))
            throw Error(where + ": Kd or Ke is not a finite number");
        if (kd < 0.0 || kd >= 1.0)
            throw Error(where + ": Kd " + std::to_string(kd) +
                        " is outside [0, 1) (a surface cannot reflect all the light it gets)");
        if (ke < 0.0) throw Error(where + ": Ke " + std::to_string(ke) + " is negative");
    }
}

/// What tinyobjloader read from an OBJ file.
struct ObjParse {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
};

/// Adds the faces of tinyobjloader's shapes to a scene, with the corner counts of the scan, every
/// index checked. Lightmap UVs are kept only if every face has them, all in [0, 1].
template <SpectrumType S>
void add_obj_faces(const ObjParse& obj, const ObjStatements& statements, Scene<S>& scene) {
    const std::string& path = scene.source;
    const std::size_t nv = scene.positions.size(), nt = obj.attrib.texcoords.size() / 2;
    const auto default_material = static_cast<std::uint32_t>(scene.materials.size());
    bool uses_default = false, all_uvs = true;  // lightmap UVs only if every face has them
    std::size_t face_number = 0;
    for (const auto& shape : obj.shapes) {
        const auto& mesh = shape.mesh;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f, ++face_number) {
            if (face_number >= statements.line.size() ||
                statements.corners[face_number] % 256 != mesh.num_face_vertices[f] ||
                statements.corners[face_number] > mesh.indices.size() - offset)
                throw Error(path + ": face " + std::to_string(face_number) +
                            " does not match the file's face statements");
            const std::string at = path + ":" + std::to_string(statements.line[face_number]);
            const std::size_t count = statements.corners[face_number];
            if (count < 3) throw Error(at + ": a face needs at least 3 vertices");
            std::vector<std::uint32_t> face;
            std::vector<glm::vec2> uv;
            for (std::size_t k = 0; k < count; ++k) {
                const int v = mesh.indices[offset + k].vertex_index;
                const int t = mesh.indices[offset + k].texcoord_index;
                if (t >= 0 && static_cast<std::size_t>(t) < nt)  // v grows upward in OBJ
                    uv.emplace_back(obj.attrib.texcoords[2 * std::size_t(t)],
                                    1.0f - obj.attrib.texcoords[2 * std::size_t(t) + 1]);
                if (v < 0 || static_cast<std::size_t>(v) >= nv)
                    throw Error(at + ": vertex index " + std::to_string(v + 1) +
                                " is out of range (the file has " + std::to_string(nv) +
                                " vertices)");
                face.push_back(static_cast<std::uint32_t>(v));
            }
            offset += count;
            const int m = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
            uses_default |= m < 0;
            // Texture coordinates outside [0, 1] (a tiled texture) cannot be lightmap UVs.
            all_uvs &=
                uv.size() == face.size() && std::all_of(uv.begin(), uv.end(), in_unit_square);
            scene.faces.push_back(std::move(face));
            scene.face_uvs.push_back(std::move(uv));
            scene.face_lines.push_back(statements.line[face_number]);
            scene.face_material.push_back(m < 0 ? default_material : static_cast<std::uint32_t>(m));
        }
        if (offset != mesh.indices.size())
            throw Error(path + ": shape '" + shape.name + "' does not match its face statements");
    }
    if (face_number != statements.line.size())
        throw Error(path + ": " + std::to_string(statements.line.size() - face_number) +
                    " face statements were not read");
    if (!all_uvs) scene.face_uvs.clear();
    if (scene.face_lines.size() != scene.faces.size()) scene.face_lines.clear();
    if (uses_default) scene.materials.push_back(Material<S>::unnamed());
}

}  // namespace detail

/// Reads an OBJ file and the MTL files it names into a Scene (Wavefront Technologies 1992
/// format, via tinyobjloader). Kd -> reflectance, Ke -> emission (converted with from_rgb);
/// faces without a material get grey reflectance 0.5 and no emission. Polygons are kept, of any
/// number of corners. Texture coordinates (vt) become lightmap UVs, v flipped to our
/// top-row-first convention, when every face has them (else, or if one lies outside [0, 1], the
/// scene has none and a lightmap baker makes its own). Throws Error naming the file (and the
/// line or material) for a missing or unreadable file, a missing MTL file, a face with fewer
/// than 3 vertices or an index out of range, a coordinate, Kd or Ke that is not a finite number
/// (as a float), or a Kd outside [0, 1). build_mesh then checks areas, naming the file too.
/// Skin weights ('vw') are ignored.
/// Cost: linear in the files.
template <SpectrumType S>
Scene<S> read_obj(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::optional<std::string> text =
        fs::is_regular_file(path, ec) ? detail::slurp_file(path) : std::nullopt;
    if (!text) throw Error(path + ": no such file");
    detail::blank_skin_weights(*text);
    const detail::ObjStatements statements = detail::scan_obj(*text, path);
    detail::ObjParse obj;
    std::string warn, err;
    std::istringstream in(*text);
    detail::CheckedMtlReader mtl(fs::path(path).parent_path().string());
    if (!tinyobj::LoadObj(&obj.attrib, &obj.shapes, &obj.materials, &warn, &err, &in, &mtl,
                          /*triangulate=*/false, /*default_vcols_fallback=*/false))
        throw Error(path + ": " + detail::one_line(err));
    if (!warn.empty())  // e.g. a material file that is missing: not to be ignored
        throw Error(path + ": " + detail::one_line(warn));

    Scene<S> scene;
    scene.source = path;
    const auto& v = obj.attrib.vertices;
    for (std::size_t k = 0; k + 2 < v.size(); k += 3) {
        scene.positions.emplace_back(v[k], v[k + 1], v[k + 2]);
        // tinyobjloader's own number parser can make what strtod reads as finite infinite or
        // NaN ("0.0E2791": 0 times 10 to a power past a double's range), so the coordinates
        // are checked as it read them too.
        const Vec3& p = scene.positions.back();
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            const std::size_t i = k / 3;
            const std::string line = i < statements.vertex_line.size()
                                         ? ":" + std::to_string(statements.vertex_line[i])
                                         : "";
            throw Error(path + line + ": a vertex coordinate is not a finite number as read " +
                        "(an exponent out of range?)");
        }
    }
    for (const auto& m : obj.materials) {
        detail::check_obj_material(m, path + ": material '" + m.name + "'");
        scene.materials.push_back(
            {from_rgb<S>(float(m.emission[0]), float(m.emission[1]), float(m.emission[2])),
             from_rgb<S>(float(m.diffuse[0]), float(m.diffuse[1]), float(m.diffuse[2])), m.name});
    }
    detail::add_obj_faces(obj, statements, scene);
    if (scene.faces.empty()) throw Error(path + ": no faces");
    return scene;
}

}  // namespace radiosity
