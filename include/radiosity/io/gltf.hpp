#pragma once
/// @file gltf.hpp  glTF 2.0 export of a shaded mesh (Khronos Group 2017): one mesh with
/// POSITION, per-vertex COLOR_0 (linear RGB, what the radiosity solve found, after exposure) and
/// 32-bit indices, with an unlit material (KHR_materials_unlit) so that viewers show the baked
/// light as it is instead of lighting it again; or, for a baked lightmap, the lightmap UVs and the
/// lightmap as the material's texture. Blender, three.js and game engines open it.
/// `.glb` writes one binary file; any other name writes NAME.gltf (JSON) beside NAME.bin.

#include <radiosity/error.hpp>
#include <radiosity/io/gltf_constants.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/shading/shaded_mesh.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace radiosity {

namespace detail {

/// Appends raw bytes of a vector to a buffer, then pads it to a multiple of 4 bytes (glTF
/// requires accessors aligned to their component size).
template <class T>
std::size_t append(std::vector<std::uint8_t>& buffer, const std::vector<T>& data) {
    const std::size_t offset = buffer.size();
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data.data());
    buffer.insert(buffer.end(), bytes, bytes + data.size() * sizeof(T));
    while (buffer.size() % 4 != 0) buffer.push_back(0);
    return offset;
}

/// Builds a glTF document over one binary buffer, a buffer view and accessor at a time.
class GltfBuilder {
  public:
    explicit GltfBuilder(std::vector<std::uint8_t>& bin) : bin_(bin) {}

    /// Appends data as a buffer view (target 0: none, e.g. an image) and returns its index.
    template <class T>
    std::size_t view(const std::vector<T>& data, int target) {
        const std::size_t at = append(bin_, data);
        nlohmann::json v = {
            {"buffer", 0}, {"byteOffset", at}, {"byteLength", data.size() * sizeof(T)}};
        if (target != 0) v["target"] = target;
        views_.push_back(v);
        return views_.size() - 1;
    }
    /// Appends data as a buffer view with an accessor of `count` elements of `type` (float or
    /// uint32 components) and returns the accessor's index.
    template <class T>
    std::size_t accessor(const std::vector<T>& data, std::size_t count, const char* type,
                         int target, nlohmann::json extra = nlohmann::json::object()) {
        nlohmann::json a = {
            {"bufferView", view(data, target)},
            {"componentType", std::is_same_v<T, float> ? gltf::float32 : gltf::unsigned_int},
            {"count", count},
            {"type", type}};
        a.update(extra);
        accessors_.push_back(a);
        return accessors_.size() - 1;
    }
    const nlohmann::json& views() const { return views_; }          ///< the bufferViews
    const nlohmann::json& accessors() const { return accessors_; }  ///< the accessors

  private:
    std::vector<std::uint8_t>& bin_;
    nlohmann::json views_ = nlohmann::json::array(), accessors_ = nlohmann::json::array();
};

/// The glTF document and its binary buffer for a shaded mesh: vertex colours, or, when a
/// lightmap PNG is given, the lightmap UVs (TEXCOORD_0, and TEXCOORD_1 where engines look for
/// a lightmap) and the PNG as the unlit material's base colour texture.
inline nlohmann::json gltf_document(const ShadedMesh& mesh, double exposure_scale,
                                    std::vector<std::uint8_t>& bin,
                                    const std::vector<std::uint8_t>* lightmap_png = nullptr) {
    std::vector<float> position, colour, uv;
    std::array<float, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<float>::max());
    hi.fill(-std::numeric_limits<float>::max());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            const auto p = static_cast<float>(mesh.positions[v][k]);
            position.push_back(p);
            lo[k] = std::min(lo[k], p);
            hi[k] = std::max(hi[k], p);
            if (!lightmap_png)  // with a lightmap, the texture holds the light
                colour.push_back(std::clamp(static_cast<float>(exposure_scale * mesh.colours[v][k]),
                                            0.0f, 1.0f));
        }
    std::vector<std::uint32_t> index;
    for (const auto& t : mesh.triangles) index.insert(index.end(), t.begin(), t.end());
    using nlohmann::json;
    const auto count = mesh.positions.size();
    GltfBuilder b(bin);
    json attributes = {{"POSITION", b.accessor(position, count, "VEC3", gltf::array_buffer,
                                               {{"min", lo}, {"max", hi}})}};
    json material = {{"pbrMetallicRoughness",
                      {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}},
                       {"metallicFactor", 0.0},
                       {"roughnessFactor", 1.0}}},
                     {"extensions", {{"KHR_materials_unlit", json::object()}}}};
    json doc = {{"asset", {{"version", "2.0"}, {"generator", "radiosity"}}},
                {"extensionsUsed", {"KHR_materials_unlit"}},
                {"scene", 0},
                {"scenes", {{{"nodes", {0}}}}},
                {"nodes", {{{"mesh", 0}}}}};
    if (lightmap_png) {
        if (mesh.uvs.size() != count) throw Error("glTF: the mesh has no lightmap UVs");
        for (const glm::vec2& t : mesh.uvs) uv.insert(uv.end(), {t.x, t.y});
        attributes["TEXCOORD_0"] = attributes["TEXCOORD_1"] =
            b.accessor(uv, count, "VEC2", gltf::array_buffer);
        material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}, {"texCoord", 0}};
        doc["textures"] = {{{"sampler", 0}, {"source", 0}}};
        doc["samplers"] = {{{"magFilter", 9729},
                            {"minFilter", 9729},  // linear, clamp to edge
                            {"wrapS", 33071},
                            {"wrapT", 33071}}};
        doc["images"] = {{{"bufferView", b.view(*lightmap_png, 0)}, {"mimeType", "image/png"}}};
    } else {
        attributes["COLOR_0"] = b.accessor(colour, count, "VEC3", gltf::array_buffer);
    }
    const std::size_t indices =
        b.accessor(index, index.size(), "SCALAR", gltf::element_array_buffer);
    // json::array: a braced single json is copied, not wrapped, by clang (nlohmann/json README).
    doc["materials"] = json::array({material});
    doc["meshes"] = {
        {{"primitives", {{{"attributes", attributes}, {"indices", indices}, {"material", 0}}}}}};
    doc["buffers"] = {{{"byteLength", bin.size()}}};
    doc["bufferViews"] = b.views();
    doc["accessors"] = b.accessors();
    return doc;
}

inline void write_bytes(std::ofstream& out, const void* data, std::size_t n) {
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
}

/// Writes a document and its buffer: one .glb, or NAME.gltf beside NAME.bin.
inline void write_gltf_files(nlohmann::json doc, const std::vector<std::uint8_t>& bin,
                             const std::string& path) {
    namespace fs = std::filesystem;
    const bool binary = fs::path(path).extension() == ".glb";
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error("cannot write '" + path + "'");
    if (binary) {  // GLB: 12-byte header, a JSON chunk padded with spaces, a BIN chunk
        std::string json = doc.dump();
        while (json.size() % 4 != 0) json.push_back(' ');
        const std::uint32_t total = 12 + 8 + static_cast<std::uint32_t>(json.size()) + 8 +
                                    static_cast<std::uint32_t>(bin.size());
        const std::uint32_t header[3] = {gltf::glb_magic, 2u, total};
        const std::uint32_t json_chunk[2] = {static_cast<std::uint32_t>(json.size()),
                                             gltf::glb_json_chunk};
        const std::uint32_t bin_chunk[2] = {static_cast<std::uint32_t>(bin.size()),
                                            gltf::glb_bin_chunk};
        detail::write_bytes(out, header, sizeof header);
        detail::write_bytes(out, json_chunk, sizeof json_chunk);
        detail::write_bytes(out, json.data(), json.size());
        detail::write_bytes(out, bin_chunk, sizeof bin_chunk);
        detail::write_bytes(out, bin.data(), bin.size());
    } else {
        const fs::path bin_path = fs::path(path).replace_extension(".bin");
        doc["buffers"][0]["uri"] = bin_path.filename().string();
        out << doc.dump(1);
        std::ofstream b(bin_path, std::ios::binary);
        if (!b) throw Error("cannot write '" + bin_path.string() + "'");
        detail::write_bytes(b, bin.data(), bin.size());
        if (!b) throw Error("cannot write '" + bin_path.string() + "'");
    }
    if (!out) throw Error("cannot write '" + path + "'");
}

}  // namespace detail

/// Writes the mesh as glTF 2.0 with linear vertex colours exposure_scale * colour,
/// clamped to [0, 1] (the same exposure as the PNG gives the same picture in a viewer that
/// shows unlit vertex colours). Throws Error naming the path on failure.
inline void write_gltf(const ShadedMesh& mesh, const std::string& path, double exposure_scale) {
    std::vector<std::uint8_t> bin;
    nlohmann::json doc = detail::gltf_document(mesh, exposure_scale, bin);
    detail::write_gltf_files(std::move(doc), bin, path);
}

/// Writes the mesh as glTF 2.0 textured with its lightmap: the lightmap UVs as TEXCOORD_0 and
/// TEXCOORD_1, and the lightmap, times exposure_scale and sRGB-encoded, as an embedded PNG on an
/// unlit material, so a viewer shows the baked light. Throws Error if the mesh has no UVs or
/// the file cannot be written.
inline void write_gltf_lightmapped(const ShadedMesh& mesh, const Image& lightmap,
                                   const std::string& path, double exposure_scale) {
    std::vector<std::uint8_t> bin;
    const std::vector<std::uint8_t> png = png_bytes(lightmap, exposure_scale);
    nlohmann::json doc = detail::gltf_document(mesh, 1.0, bin, &png);
    detail::write_gltf_files(std::move(doc), bin, path);
}

}  // namespace radiosity
