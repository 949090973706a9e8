#pragma once
/// @file gltf.hpp  glTF 2.0 export of a shaded mesh (Khronos Group 2017): one mesh with
/// POSITION, per-vertex COLOR_0 (linear RGB, what the radiosity solve found, after exposure) and
/// 32-bit indices, with an unlit material (KHR_materials_unlit) so that viewers show the baked
/// light as it is instead of lighting it again. Blender, three.js and game engines open it.
/// `.glb` writes one binary file; any other name writes NAME.gltf (JSON) beside NAME.bin.

#include <radiosity/error.hpp>
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

/// The glTF document and its binary buffer for a shaded mesh.
inline nlohmann::json gltf_document(const ShadedMesh& mesh, double exposure_scale,
                                    std::vector<std::uint8_t>& bin) {
    std::vector<float> position, colour;
    std::array<float, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<float>::max());
    hi.fill(-std::numeric_limits<float>::max());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            const auto p = static_cast<float>(mesh.positions[v][k]);
            position.push_back(p);
            lo[k] = std::min(lo[k], p);
            hi[k] = std::max(hi[k], p);
            colour.push_back(
                std::clamp(static_cast<float>(exposure_scale * mesh.colours[v][k]), 0.0f, 1.0f));
        }
    std::vector<std::uint32_t> index;
    for (const auto& t : mesh.triangles) index.insert(index.end(), t.begin(), t.end());
    const std::size_t p_at = append(bin, position), c_at = append(bin, colour),
                      i_at = append(bin, index);
    using nlohmann::json;
    const auto count = mesh.positions.size();
    json doc = {{"asset", {{"version", "2.0"}, {"generator", "radiosity"}}},
                {"extensionsUsed", {"KHR_materials_unlit"}},
                {"scene", 0},
                {"scenes", {{{"nodes", {0}}}}},
                {"nodes", {{{"mesh", 0}}}},
                {"materials",
                 {{{"pbrMetallicRoughness",
                    {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}},
                     {"metallicFactor", 0.0},
                     {"roughnessFactor", 1.0}}},
                   {"extensions", {{"KHR_materials_unlit", json::object()}}}}}},
                {"meshes",
                 {{{"primitives",
                    {{{"attributes", {{"POSITION", 0}, {"COLOR_0", 1}}},
                      {"indices", 2},
                      {"material", 0}}}}}}},
                {"buffers", {{{"byteLength", bin.size()}}}},
                {"bufferViews",
                 {{{"buffer", 0},
                   {"byteOffset", p_at},
                   {"byteLength", position.size() * 4},
                   {"target", 34962}},
                  {{"buffer", 0},
                   {"byteOffset", c_at},
                   {"byteLength", colour.size() * 4},
                   {"target", 34962}},
                  {{"buffer", 0},
                   {"byteOffset", i_at},
                   {"byteLength", index.size() * 4},
                   {"target", 34963}}}},
                {"accessors",
                 {{{"bufferView", 0},
                   {"componentType", 5126},
                   {"count", count},
                   {"type", "VEC3"},
                   {"min", lo},
                   {"max", hi}},
                  {{"bufferView", 1}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}},
                  {{"bufferView", 2},
                   {"componentType", 5125},
                   {"count", index.size()},
                   {"type", "SCALAR"}}}}};
    return doc;
}

inline void write_bytes(std::ofstream& out, const void* data, std::size_t n) {
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
}

}  // namespace detail

/// Writes the mesh as glTF 2.0 with linear vertex colours exposure_scale * colour,
/// clamped to [0, 1] (the same exposure as the PNG gives the same picture in a viewer that
/// shows unlit vertex colours). Throws Error naming the path on failure.
inline void write_gltf(const ShadedMesh& mesh, const std::string& path, double exposure_scale) {
    namespace fs = std::filesystem;
    std::vector<std::uint8_t> bin;
    nlohmann::json doc = detail::gltf_document(mesh, exposure_scale, bin);
    const bool binary = fs::path(path).extension() == ".glb";
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error("cannot write '" + path + "'");
    if (binary) {  // GLB: 12-byte header, a JSON chunk padded with spaces, a BIN chunk
        std::string json = doc.dump();
        while (json.size() % 4 != 0) json.push_back(' ');
        const std::uint32_t total = 12 + 8 + static_cast<std::uint32_t>(json.size()) + 8 +
                                    static_cast<std::uint32_t>(bin.size());
        const std::uint32_t header[3] = {0x46546C67u, 2u, total};
        const std::uint32_t json_chunk[2] = {static_cast<std::uint32_t>(json.size()), 0x4E4F534Au};
        const std::uint32_t bin_chunk[2] = {static_cast<std::uint32_t>(bin.size()), 0x004E4942u};
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

}  // namespace radiosity
