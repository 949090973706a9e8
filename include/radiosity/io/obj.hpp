#pragma once
/// @file obj.hpp  Reading scenes from Wavefront OBJ + MTL files through tinyobjloader: polygons
/// are kept as they are (not triangulated), Kd is the reflectance and Ke the emission. Every
/// problem becomes a one-line radiosity::Error naming the file and, where it can, the line.

#include <radiosity/error.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
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

/// The face ('f') statements of an OBJ file, in order: their line numbers (for error messages)
/// and the number of corners each lists (tinyobjloader keeps that number in 8 bits).
struct FaceLines {
    std::vector<std::size_t> line, corners;
};

inline FaceLines face_lines(const std::string& path) {
    std::ifstream in(path);
    FaceLines out;
    std::string line;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
        std::istringstream words(line);
        std::string first;
        if (!(words >> first) || first != "f") continue;
        std::size_t corners = 0;
        for (std::string w; words >> w;) ++corners;
        out.line.push_back(n);
        out.corners.push_back(corners);
    }
    return out;
}

/// The number of corners of face `face` read by tinyobjloader: its count is the true count
/// modulo 256, so a face of 256 corners or more takes the count of its line instead.
inline std::size_t corner_count(std::size_t read, const FaceLines& lines, std::size_t face) {
    if (face >= lines.corners.size()) return read;
    const std::size_t listed = lines.corners[face];
    return listed >= 256 && listed % 256 == read ? listed : read;
}

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

}  // namespace detail

/// Reads an OBJ file and the MTL files it names into a Scene (Wavefront Technologies 1992
/// format, via tinyobjloader). Kd -> reflectance, Ke -> emission (converted with from_rgb);
/// faces without a material get grey reflectance 0.5 and no emission. Polygons are kept. Texture
/// coordinates (vt) become lightmap UVs, v flipped to our top-row-first convention, when every
/// face has them (else, or if one lies outside [0, 1], the scene has none and a lightmap baker
/// makes its own). Throws Error naming the file (and the line or material) for a missing or
/// unreadable file, a missing MTL file, a face with fewer than 3 vertices or an index out of range,
/// a non-finite coordinate, or a Kd outside [0, 1). Faces of any number of corners are read
/// (tinyobjloader counts them modulo 256; the file's lines settle the rest). build_mesh then
/// checks areas, naming the file too.
template <SpectrumType S>
Scene<S> read_obj(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw Error(path + ": no such file");
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;
    config.vertex_color = false;
    config.mtl_search_path = fs::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config))
        throw Error(path + ": " + detail::one_line(reader.Error()));
    if (!reader.Warning().empty())  // e.g. a material file that is missing: not to be ignored
        throw Error(path + ": " + detail::one_line(reader.Warning()));

    const auto& attrib = reader.GetAttrib();
    Scene<S> scene;
    scene.source = path;
    const std::size_t nv = attrib.vertices.size() / 3;
    for (std::size_t v = 0; v < nv; ++v)
        scene.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1],
                                     attrib.vertices[3 * v + 2]);
    for (const auto& m : reader.GetMaterials()) {
        detail::check_obj_material(m, path + ": material '" + m.name + "'");
        scene.materials.push_back(
            {from_rgb<S>(float(m.emission[0]), float(m.emission[1]), float(m.emission[2])),
             from_rgb<S>(float(m.diffuse[0]), float(m.diffuse[1]), float(m.diffuse[2])), m.name});
    }
    const auto default_material = static_cast<std::uint32_t>(scene.materials.size());
    bool uses_default = false;
    const detail::FaceLines lines = detail::face_lines(path);
    std::size_t face_number = 0;
    bool all_uvs = true;  // lightmap UVs are used only if every face has them
    for (const auto& shape : reader.GetShapes()) {
        std::size_t offset = 0;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++face_number) {
            std::string at = path;  // "file:line", or "file: face n" if lines are unknown
            at += face_number < lines.line.size() ? ":" : ": face ";
            at += std::to_string(face_number < lines.line.size() ? lines.line[face_number]
                                                                 : face_number);
            const std::size_t count =
                detail::corner_count(shape.mesh.num_face_vertices[f], lines, face_number);
            if (offset + count > shape.mesh.indices.size())
                throw Error(at + ": the face's corners could not be read");
            if (count < 3) throw Error(at + ": a face needs at least 3 vertices");
            std::vector<std::uint32_t> face;
            std::vector<glm::vec2> uv;
            for (std::size_t k = 0; k < count; ++k) {
                const int v = shape.mesh.indices[offset + k].vertex_index;
                const int t = shape.mesh.indices[offset + k].texcoord_index;
                if (t >= 0 && static_cast<std::size_t>(t) < attrib.texcoords.size() / 2) {
                    // OBJ's v grows upward from the image's bottom row; ours from the top row.
                    uv.emplace_back(attrib.texcoords[2 * std::size_t(t)],
                                    1.0f - attrib.texcoords[2 * std::size_t(t) + 1]);
                }
                if (v < 0 || static_cast<std::size_t>(v) >= nv)
                    throw Error(at + ": vertex index " + std::to_string(v + 1) +
                                " is out of range (the file has " + std::to_string(nv) +
                                " vertices)");
                face.push_back(static_cast<std::uint32_t>(v));
            }
            offset += count;
            const int m = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
            if (m < 0) uses_default = true;
            // Texture coordinates outside [0, 1] (a tiled texture) cannot be lightmap UVs.
            for (const glm::vec2& x : uv)
                if (!in_unit_square(x)) all_uvs = false;
            if (uv.size() != face.size()) all_uvs = false;
            scene.faces.push_back(std::move(face));
            scene.face_uvs.push_back(std::move(uv));
            if (face_number < lines.line.size())
                scene.face_lines.push_back(lines.line[face_number]);
            scene.face_material.push_back(m < 0 ? default_material : static_cast<std::uint32_t>(m));
        }
        if (offset != shape.mesh.indices.size())
            throw Error(path + ": the faces' corners could not be read (" +
                        std::to_string(shape.mesh.indices.size()) + " listed, " +
                        std::to_string(offset) + " in faces)");
    }
    if (!all_uvs) scene.face_uvs.clear();
    if (scene.face_lines.size() != scene.faces.size()) scene.face_lines.clear();
    if (uses_default) scene.materials.push_back(Material<S>::unnamed());
    if (scene.faces.empty()) throw Error(path + ": no faces");
    return scene;
}

}  // namespace radiosity
