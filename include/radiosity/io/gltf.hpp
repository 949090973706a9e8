#pragma once
/// @file gltf.hpp  glTF 2.0 export of a shaded mesh (Khronos Group 2017): one mesh with
/// POSITION, per-vertex COLOR_0 (linear RGB, what the radiosity solve found, after exposure) and
/// 32-bit indices, with an unlit material (KHR_materials_unlit) so that viewers show the baked
/// light as it is instead of lighting it again; or, for a baked lightmap, the lightmap UVs and the
/// lightmap as the material's texture. Blender, three.js and game engines open it.
/// `.glb` writes one binary file; any other name writes NAME.gltf (JSON) beside NAME.bin. The
/// binary buffer is packed here; tinygltf (S. Fujita, Debian's libtinygltf) writes the document.

#include <radiosity/error.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/shading/shaded_mesh.hpp>

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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
std::size_t append(std::vector<unsigned char>& buffer, const std::vector<T>& data) {
    const std::size_t offset = buffer.size();
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    buffer.insert(buffer.end(), bytes, bytes + data.size() * sizeof(T));
    while (buffer.size() % 4 != 0) buffer.push_back(0);
    return offset;
}

/// Fills a tinygltf Model's one binary buffer, a buffer view and accessor at a time.
class GltfBuilder {
  public:
    explicit GltfBuilder(tinygltf::Model& model) : model_(model) { model_.buffers.resize(1); }

    /// Appends data as a buffer view (target 0: none, e.g. an image) and returns its index.
    template <class T>
    int view(const std::vector<T>& data, int target) {
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = append(model_.buffers[0].data, data);
        v.byteLength = data.size() * sizeof(T);
        v.target = target;
        model_.bufferViews.push_back(std::move(v));
        return static_cast<int>(model_.bufferViews.size()) - 1;
    }
    /// Appends data as a buffer view with an accessor of `count` elements of `type`
    /// (TINYGLTF_TYPE_VEC3; float or uint32 components) and returns the accessor's index.
    template <class T>
    int accessor(const std::vector<T>& data, std::size_t count, int type, int target,
                 std::vector<double> min = {}, std::vector<double> max = {}) {
        tinygltf::Accessor a;
        a.bufferView = view(data, target);
        a.componentType = std::is_same_v<T, float> ? TINYGLTF_COMPONENT_TYPE_FLOAT
                                                   : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        a.count = count;
        a.type = type;
        a.minValues = std::move(min);
        a.maxValues = std::move(max);
        model_.accessors.push_back(std::move(a));
        return static_cast<int>(model_.accessors.size()) - 1;
    }

  private:
    tinygltf::Model& model_;
};

/// The unlit material (KHR_materials_unlit): base colour white, or the lightmap texture.
inline tinygltf::Material unlit_material(bool textured) {
    tinygltf::Material m;
    m.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 1.0;
    if (textured) m.pbrMetallicRoughness.baseColorTexture.index = 0;  // texCoord 0
    m.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object{});
    return m;
}

/// The lightmap PNG as texture 0: an image in a buffer view, sampled linearly, clamped to edge.
inline void add_lightmap_texture(tinygltf::Model& model, GltfBuilder& b,
                                 const std::vector<unsigned char>& png) {
    tinygltf::Sampler sampler;
    sampler.magFilter = sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    model.samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.sampler = texture.source = 0;
    model.textures.push_back(texture);
    tinygltf::Image image;
    image.bufferView = b.view(png, 0);
    image.mimeType = "image/png";
    model.images.push_back(std::move(image));
}

/// The glTF Model of a shaded mesh, its one buffer filled: vertex colours, or, when a lightmap
/// PNG is given, the lightmap UVs (TEXCOORD_0, and TEXCOORD_1 where engines look for a
/// lightmap) and the PNG as the unlit material's base colour texture. Positions are written in
/// metres, as glTF's specification has them: metres_per_unit times the mesh's coordinates.
inline tinygltf::Model gltf_model(const ShadedMesh& mesh, double exposure_scale,
                                  const std::vector<unsigned char>* lightmap_png = nullptr,
                                  double metres_per_unit = 1.0) {
    std::vector<float> position, colour, uv;
    std::vector<double> lo(3, std::numeric_limits<float>::max()),
        hi(3, -std::numeric_limits<float>::max());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            const auto p = static_cast<float>(metres_per_unit * mesh.positions[v][k]);
            position.push_back(p);
            lo[std::size_t(k)] = std::min(lo[std::size_t(k)], double(p));
            hi[std::size_t(k)] = std::max(hi[std::size_t(k)], double(p));
            if (!lightmap_png)  // with a lightmap, the texture holds the light
                colour.push_back(std::clamp(static_cast<float>(exposure_scale * mesh.colours[v][k]),
                                            0.0f, 1.0f));
        }
    std::vector<std::uint32_t> index;
    for (const auto& t : mesh.triangles) index.insert(index.end(), t.begin(), t.end());
    const auto count = mesh.positions.size();
    tinygltf::Model model;
    model.asset.generator = "radiosity";
    model.extensionsUsed = {"KHR_materials_unlit"};
    GltfBuilder b(model);
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = 0;
    prim.attributes["POSITION"] =
        b.accessor(position, count, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, lo, hi);
    if (lightmap_png) {
        if (mesh.uvs.size() != count) throw Error("glTF: the mesh has no lightmap UVs");
        for (const glm::vec2& t : mesh.uvs) uv.insert(uv.end(), {t.x, t.y});
        prim.attributes["TEXCOORD_0"] = prim.attributes["TEXCOORD_1"] =
            b.accessor(uv, count, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
        add_lightmap_texture(model, b, *lightmap_png);
    } else {
        prim.attributes["COLOR_0"] =
            b.accessor(colour, count, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    prim.indices =
        b.accessor(index, index.size(), TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    model.materials.push_back(unlit_material(lightmap_png != nullptr));
    model.meshes.emplace_back().primitives.push_back(std::move(prim));
    model.nodes.emplace_back().mesh = 0;
    model.scenes.emplace_back().nodes = {0};
    model.defaultScene = 0;
    return model;
}

/// Writes a Model through tinygltf: one .glb, or NAME.gltf beside NAME.bin. tinygltf 2.7.0
/// checks neither that a .glb could be opened nor that any write went through, so the .glb goes
/// to a stream checked here, and the .gltf's buffer file is checked for its size afterwards.
inline void write_gltf_files(tinygltf::Model model, const std::string& path) {
    namespace fs = std::filesystem;
    tinygltf::TinyGLTF writer;
    if (fs::path(path).extension() == ".glb") {
        std::ofstream out(path, std::ios::binary);
        if (!out) throw Error("cannot write '" + path + "'");
        writer.WriteGltfSceneToStream(&model, out, false, true);
        out.close();
        if (!out) throw Error("cannot write '" + path + "'");
        return;
    }
    const fs::path bin = fs::path(path).replace_extension(".bin");
    model.buffers[0].uri = bin.filename().string();  // tinygltf writes it beside the .gltf
    const std::size_t bytes = model.buffers[0].data.size();
    if (!writer.WriteGltfSceneToFile(&model, path, false, false, true, false))
        throw Error("cannot write '" + path + "' and '" + bin.string() + "'");
    std::error_code ec;
    if (fs::file_size(bin, ec) != bytes || ec) throw Error("cannot write '" + bin.string() + "'");
}

}  // namespace detail

/// Writes the mesh as glTF 2.0 with linear vertex colours exposure_scale * colour,
/// clamped to [0, 1] (the same exposure as the PNG gives the same picture in a viewer that
/// shows unlit vertex colours). Positions in metres (glTF's unit): metres_per_unit times the
/// mesh's (Scene::metres_per_unit; 0.001 for the Cornell box's millimetres). Throws Error
/// naming the path on failure.
inline void write_gltf(const ShadedMesh& mesh, const std::string& path, double exposure_scale,
                       double metres_per_unit = 1.0) {
    if (!(metres_per_unit > 0.0) || !std::isfinite(metres_per_unit))
        throw Error("glTF: metres per unit must be a positive number");
    detail::write_gltf_files(detail::gltf_model(mesh, exposure_scale, nullptr, metres_per_unit),
                             path);
}

/// Writes the mesh as glTF 2.0 textured with its lightmap: the lightmap UVs as TEXCOORD_0 and
/// TEXCOORD_1, and the lightmap, times exposure_scale and sRGB-encoded, as an embedded PNG on an
/// unlit material, so a viewer shows the baked light; positions in metres as write_gltf's.
/// Throws Error if the mesh has no UVs or the file cannot be written.
inline void write_gltf_lightmapped(const ShadedMesh& mesh, const Image& lightmap,
                                   const std::string& path, double exposure_scale,
                                   double metres_per_unit = 1.0) {
    if (!(metres_per_unit > 0.0) || !std::isfinite(metres_per_unit))
        throw Error("glTF: metres per unit must be a positive number");
    const std::vector<std::uint8_t> png = png_bytes(lightmap, exposure_scale);
    detail::write_gltf_files(detail::gltf_model(mesh, 1.0, &png, metres_per_unit), path);
}

}  // namespace radiosity
