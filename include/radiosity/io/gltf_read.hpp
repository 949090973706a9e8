#pragma once
/// @file gltf_read.hpp  Reading scenes from glTF 2.0 (Khronos Group 2017): .gltf with external
/// or base64-embedded buffers, and .glb, parsed by tinygltf into its Model (io/gltf_load.hpp),
/// which this header turns into a Scene. The default scene's node hierarchy is flattened into
/// world-space triangles; baseColorFactor is the reflectance and emissiveFactor (times
/// KHR_materials_emissive_strength) the emission; TEXCOORD_1, or TEXCOORD_0 when there is only
/// one, gives the lightmap UVs. Every problem becomes a one-line radiosity::Error naming the file
/// and the element, e.g. "scene.gltf: accessors[3]: needs 1200 bytes, bufferViews[1] has 800".

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/io/gltf_load.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/spectrum.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace radiosity {

/// A scene read from glTF, with what the reader left out on the way.
template <SpectrumType S>
struct GltfReadResult {
    Scene<S> scene;                      ///< what read_gltf returns
    std::size_t dropped_triangles = 0;   ///< zero-area triangles (repeated or collinear corners)
    std::size_t skipped_primitives = 0;  ///< points and lines primitives, which have no area
};

namespace detail {

/// A node's or material's array of N finite numbers; `fallback` if tinygltf found none.
template <std::size_t N>
std::array<double, N> gltf_numbers(const GltfSource& g, const std::string& at, const char* key,
                                   const std::vector<double>& v,
                                   const std::array<double, N>& fallback) {
    if (v.empty()) return fallback;
    if (v.size() != N)
        gltf_fail(
            g, at,
            std::string("'") + key + "' is not an array of " + std::to_string(N) + " numbers");
    std::array<double, N> out{};
    for (std::size_t k = 0; k < N; ++k) {
        if (!std::isfinite(v[k]))
            gltf_fail(g, at, std::string("'") + key + "' has an entry that is not a number");
        out[k] = v[k];
    }
    return out;
}

/// A node's local transform: its column-major "matrix", or translation * rotation * scale with
/// the rotation a unit quaternion (x, y, z, w), as the specification's section 3.5.3 says.
inline glm::dmat4 node_transform(const GltfSource& g, const tinygltf::Node& node,
                                 const std::string& at) {
    if (!node.matrix.empty()) {
        const auto m = gltf_numbers<16>(g, at, "matrix", node.matrix, {});
        glm::dmat4 out;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) out[c][r] = m[static_cast<std::size_t>(4 * c + r)];
        return out;
    }
    const auto t = gltf_numbers<3>(g, at, "translation", node.translation, {0.0, 0.0, 0.0});
    const auto q = gltf_numbers<4>(g, at, "rotation", node.rotation, {0.0, 0.0, 0.0, 1.0});
    const auto s = gltf_numbers<3>(g, at, "scale", node.scale, {1.0, 1.0, 1.0});
    glm::dquat rotation(q[3], q[0], q[1], q[2]);  // glm takes w first
    const double length = glm::length(rotation);
    // Exporters round unit quaternions; normalising keeps the rotation rigid.
    if (!(length > 0.0) || !std::isfinite(length))
        gltf_fail(g, at, "'rotation' is not a rotation quaternion");
    rotation /= length;
    return glm::translate(glm::dmat4(1.0), {t[0], t[1], t[2]}) * glm::mat4_cast(rotation) *
           glm::scale(glm::dmat4(1.0), {s[0], s[1], s[2]});
}

/// KHR_materials_emissive_strength's factor on a material's emission, 1 without it.
inline double emissive_strength(const GltfSource& g, const tinygltf::Material& m,
                                const std::string& at) {
    const auto ext = m.extensions.find("KHR_materials_emissive_strength");
    if (ext == m.extensions.end() || !ext->second.Has("emissiveStrength")) return 1.0;
    const tinygltf::Value& s = ext->second.Get("emissiveStrength");
    if (!s.IsNumber() || !std::isfinite(s.GetNumberAsDouble()))
        gltf_fail(g, at + ".KHR_materials_emissive_strength", "'emissiveStrength' is not a number");
    return s.GetNumberAsDouble();
}

/// Converts a glTF material: baseColorFactor (rgb) -> R, emissiveFactor times
/// KHR_materials_emissive_strength -> E. Textures are not sampled: a patch has one colour.
template <SpectrumType S>
Material<S> gltf_material(const GltfSource& g, std::size_t i) {
    const tinygltf::Material& m = g.model.materials[i];
    const std::string at = "materials[" + std::to_string(i) + "]";
    const auto base = gltf_numbers<4>(g, at + ".pbrMetallicRoughness", "baseColorFactor",
                                      m.pbrMetallicRoughness.baseColorFactor, {1.0, 1.0, 1.0, 1.0});
    const auto e = gltf_numbers<3>(g, at, "emissiveFactor", m.emissiveFactor, {0.0, 0.0, 0.0});
    const double strength = emissive_strength(g, m, at);
    if (e[0] < 0.0 || e[1] < 0.0 || e[2] < 0.0 || strength < 0.0)
        gltf_fail(g, at, "emission is negative");
    // glTF's default (and common) base colour is 1: a surface that reflects all light it gets,
    // which makes B = E + R F B singular in a closed room (and Scene validation refuses R >= 1).
    // 0.99 keeps the asset loadable with nearly the look it asks for.
    auto r = [&](int k) { return static_cast<float>(std::clamp(base[std::size_t(k)], 0.0, 0.99)); };
    auto em = [&](int k) { return static_cast<float>(e[std::size_t(k)] * strength); };
    Material<S> out{from_rgb<S>(em(0), em(1), em(2)), from_rgb<S>(r(0), r(1), r(2)),
                    m.name.empty() ? at : m.name};
    if (!all_finite(out.emission)) gltf_fail(g, at, "emission is not a finite number");
    return out;
}

/// Checks what a glTF 2.0 reader must check first: the asset version, and that no extension
/// the file requires changes geometry (Draco or meshopt compression, quantized positions,
/// GPU instancing). Material and texture extensions only change the look, so they pass.
inline void check_gltf_asset(const GltfSource& g) {
    const std::string& version = g.model.asset.version;  // tinygltf refuses a file without one
    if (version.rfind("2.", 0) != 0) gltf_fail(g, "asset", "version " + version + " is not 2.x");
    for (const std::string& name : g.model.extensionsRequired)
        if (name.rfind("KHR_materials_", 0) != 0 && name.rfind("KHR_texture_", 0) != 0)
            gltf_fail(g, "extensionsRequired", name + " is not supported");
}

/// Builds a Scene from a glTF Model: walks the chosen scene's nodes, turns each triangle
/// primitive into faces in world space, and keeps lightmap UVs only if every face has them.
template <SpectrumType S>
class GltfSceneReader {
  public:
    explicit GltfSceneReader(const GltfSource& g) : g_(g) {
        out_.scene.source = g.path;
        for (std::size_t m = 0; m < g.model.materials.size(); ++m)
            out_.scene.materials.push_back(gltf_material<S>(g, m));
    }

    /// Reads the scene and returns it, or throws Error if it has no triangles.
    GltfReadResult<S> read() {
        walk_nodes(root_nodes());
        Scene<S>& s = out_.scene;
        if (!all_uvs_) s.face_uvs.clear();
        if (uses_default_) s.materials.push_back(Material<S>::unnamed());
        if (s.faces.empty()) gltf_fail(g_, "scene", "has no triangles");
        return std::move(out_);
    }

  private:
    const tinygltf::Model& model() const { return g_.model; }

    /// The nodes of the default scene ("scene"), else of scenes[0], else every node that is no
    /// node's child.
    std::vector<int> root_nodes() const {
        const int chosen = model().defaultScene >= 0 ? model().defaultScene
                           : model().scenes.empty()  ? -1
                                                     : 0;
        if (chosen >= 0) return gltf_element(g_, model().scenes, "scenes", chosen).nodes;
        const std::size_t n = model().nodes.size();
        std::vector<char> is_child(n, 0);
        for (const tinygltf::Node& node : model().nodes)
            for (const int child : node.children)
                if (child >= 0 && std::size_t(child) < n) is_child[std::size_t(child)] = 1;
        std::vector<int> roots;
        for (std::size_t k = 0; k < n; ++k)
            if (!is_child[k]) roots.push_back(static_cast<int>(k));
        return roots;
    }

    /// Visits the hierarchy depth first with an explicit stack (a deep chain of nodes cannot
    /// overflow the call stack), each node once: a node reached twice would be a cycle or a
    /// node with two parents, which the specification forbids.
    void walk_nodes(const std::vector<int>& roots) {
        std::vector<char> seen(model().nodes.size(), 0);
        std::vector<std::pair<int, glm::dmat4>> stack;
        for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, 1.0);
        while (!stack.empty()) {
            const auto [n, parent] = stack.back();
            stack.pop_back();
            const tinygltf::Node& node = gltf_element(g_, model().nodes, "nodes", n);
            const std::string at = "nodes[" + std::to_string(n) + "]";
            if (seen[std::size_t(n)])
                gltf_fail(g_, at, "is reached twice (the nodes must form a tree)");
            seen[std::size_t(n)] = 1;
            const glm::dmat4 world = parent * node_transform(g_, node, at);
            if (node.mesh >= 0) add_mesh(node.mesh, world);  // tinygltf: -1 for none
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
                stack.emplace_back(*c, world);
        }
    }

    void add_mesh(int m, const glm::dmat4& world) {
        const tinygltf::Mesh& mesh = gltf_element(g_, model().meshes, "meshes", m);
        const std::string at = "meshes[" + std::to_string(m) + "]";
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
            add_primitive(mesh.primitives[p], at + ".primitives[" + std::to_string(p) + "]", world);
    }

    /// The vertex indices of a primitive (or 0 .. count-1 without "indices"), each checked.
    std::vector<std::uint32_t> indices(const tinygltf::Primitive& prim, std::size_t n) const {
        std::vector<std::uint32_t> out;
        if (prim.indices < 0) {  // tinygltf: -1 for none
            out.resize(n);
            for (std::size_t k = 0; k < n; ++k) out[k] = static_cast<std::uint32_t>(k);
            return out;
        }
        const AccessorData d = gltf_accessor(
            g_, prim.indices, TINYGLTF_TYPE_SCALAR,
            {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
             TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
        out.reserve(d.count);
        for (std::size_t k = 0; k < d.count; ++k) {
            const double v = accessor_value(d, k, 0);
            if (v >= static_cast<double>(n))
                gltf_fail(g_, d.name,
                          "index " + std::to_string(static_cast<std::uint64_t>(v)) +
                              " is out of range (POSITION has " + std::to_string(n) + " vertices)");
            out.push_back(static_cast<std::uint32_t>(v));
        }
        return out;
    }

    /// Triangles of a primitive: lists (mode 4), strips (5) and fans (6), numbered as the
    /// specification's section 3.7.2.1 says so that all keep the list's winding.
    std::vector<std::array<std::uint32_t, 3>> triangles(const std::vector<std::uint32_t>& v,
                                                        int mode, const std::string& at) const {
        std::vector<std::array<std::uint32_t, 3>> t;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (v.size() % 3 != 0)
                gltf_fail(g_, at, std::to_string(v.size()) + " indices are not whole triangles");
            for (std::size_t k = 0; k + 2 < v.size(); k += 3)
                t.push_back({v[k], v[k + 1], v[k + 2]});
        } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            for (std::size_t k = 0; k + 2 < v.size(); ++k)
                t.push_back({v[k], v[k + 1 + k % 2], v[k + 2 - k % 2]});
        } else {
            for (std::size_t k = 1; k + 1 < v.size(); ++k) t.push_back({v[k], v[k + 1], v[0]});
        }
        return t;
    }

    /// POSITION as points, each finite.
    std::vector<Vec3> positions(const tinygltf::Primitive& prim, const std::string& at) const {
        const auto it = prim.attributes.find("POSITION");
        if (it == prim.attributes.end())
            gltf_fail(g_, at + ".attributes", "missing required 'POSITION'");
        const AccessorData d =
            gltf_accessor(g_, it->second, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT});
        std::vector<Vec3> p(d.count);
        for (std::size_t e = 0; e < d.count; ++e) {
            p[e] = {accessor_value(d, e, 0), accessor_value(d, e, 1), accessor_value(d, e, 2)};
            if (!std::isfinite(p[e].x) || !std::isfinite(p[e].y) || !std::isfinite(p[e].z))
                gltf_fail(g_, d.name, "element " + std::to_string(e) + " is not a finite point");
        }
        return p;
    }

    /// The lightmap UVs: TEXCOORD_1 if the primitive has it, else TEXCOORD_0, else none.
    std::vector<glm::vec2> uvs(const tinygltf::Primitive& prim, std::size_t n) const {
        auto it = prim.attributes.find("TEXCOORD_1");
        if (it == prim.attributes.end()) it = prim.attributes.find("TEXCOORD_0");
        std::vector<glm::vec2> uv;
        if (it == prim.attributes.end()) return uv;
        const AccessorData d =
            gltf_accessor(g_, it->second, TINYGLTF_TYPE_VEC2,
                          {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                           TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_COMPONENT_TYPE_FLOAT});
        if (d.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && !d.normalized)
            gltf_fail(g_, d.name, "integer texture coordinates must be normalized");
        if (d.count != n)
            gltf_fail(g_, d.name,
                      std::to_string(d.count) + " UVs for " + std::to_string(n) + " vertices");
        uv.resize(n);
        for (std::size_t e = 0; e < n; ++e)
            uv[e] = {static_cast<float>(accessor_value(d, e, 0)),
                     static_cast<float>(accessor_value(d, e, 1))};
        return uv;
    }

    /// Adds a primitive's triangles in world space. A zero-area triangle is dropped and counted
    /// rather than refused: exporters leave them in real assets, and build_mesh would refuse the
    /// whole scene for one. A mirroring transform (negative determinant) turns the winding round,
    /// so the corners are swapped to keep the front side in front (section 3.7.4).
    void add_primitive(const tinygltf::Primitive& prim, const std::string& at,
                       const glm::dmat4& world) {
        if (prim.mode < 0 || prim.mode > 6)
            gltf_fail(g_, at, "mode " + std::to_string(prim.mode) + " is not 0..6");
        if (prim.mode < TINYGLTF_MODE_TRIANGLES) {  // points and lines have no area
            ++out_.skipped_primitives;
            return;
        }
        const std::vector<Vec3> local = positions(prim, at);
        const std::vector<glm::vec2> uv = uvs(prim, local.size());
        const auto tris = triangles(indices(prim, local.size()), prim.mode, at);
        const std::uint32_t material = material_of(prim);
        const bool mirrored = glm::determinant(world) < 0.0;
        std::vector<std::uint32_t> added(local.size(), std::numeric_limits<std::uint32_t>::max());
        if (uv.empty()) all_uvs_ = false;
        std::vector<Vec3> placed(local.size());  // each vertex transformed once
        for (std::size_t v = 0; v < local.size(); ++v)
            placed[v] = Vec3(world * glm::dvec4(local[v], 1.0));
        for (auto t : tris) {
            if (mirrored) std::swap(t[1], t[2]);
            const std::array<Vec3, 3> p{placed[t[0]], placed[t[1]], placed[t[2]]};
            if (!(polygon_area(p) > 0.0)) {  // also a repeated index, or an overflow to inf/nan
                ++out_.dropped_triangles;
                continue;
            }
            add_face(t, p, added, uv, material, at);
        }
    }

    /// Appends one triangle, adding its corners as vertices the first time they are used (so
    /// vertices of points, lines and dropped triangles do not linger, unconnected).
    void add_face(const std::array<std::uint32_t, 3>& t, const std::array<Vec3, 3>& p,
                  std::vector<std::uint32_t>& added, const std::vector<glm::vec2>& uv,
                  std::uint32_t material, const std::string& at) {
        Scene<S>& s = out_.scene;
        std::vector<std::uint32_t> face(3);
        for (int k = 0; k < 3; ++k) {
            if (added[t[k]] == std::numeric_limits<std::uint32_t>::max()) {  // checked once
                if (!std::isfinite(p[k].x) || !std::isfinite(p[k].y) || !std::isfinite(p[k].z))
                    gltf_fail(g_, at, "a transformed vertex is not a finite point");
                if (s.positions.size() >= std::numeric_limits<std::uint32_t>::max())
                    gltf_fail(g_, at, "the scene has more than 2^32 - 1 vertices");
                added[t[k]] = static_cast<std::uint32_t>(s.positions.size());
                s.positions.push_back(p[k]);
            }
            face[k] = added[t[k]];
        }
        s.faces.push_back(std::move(face));
        s.face_material.push_back(material);
        if (!all_uvs_) return;
        std::vector<glm::vec2> corners{uv[t[0]], uv[t[1]], uv[t[2]]};
        // Tiled texture coordinates (outside [0, 1]) cannot address a lightmap: same rule as OBJ.
        for (const glm::vec2& c : corners)
            if (!in_unit_square(c)) all_uvs_ = false;
        s.face_uvs.push_back(std::move(corners));
    }

    std::uint32_t material_of(const tinygltf::Primitive& prim) {
        if (prim.material < 0) {  // tinygltf: -1 for none
            uses_default_ = true;
            return static_cast<std::uint32_t>(model().materials.size());
        }
        gltf_element(g_, model().materials, "materials", prim.material);  // refuses a missing one
        return static_cast<std::uint32_t>(prim.material);
    }

    const GltfSource& g_;
    GltfReadResult<S> out_;
    bool all_uvs_ = true;
    bool uses_default_ = false;
};

}  // namespace detail

/// Reads a glTF 2.0 file (.gltf with its buffers, or .glb; Khronos Group 2017) into a Scene, and
/// says what it left out. The default scene (else scenes[0], else every root node) is flattened
/// through its node transforms (matrix, or translation * rotation * scale) into world-space
/// triangles: triangle lists, strips and fans become faces; points and lines are skipped; a
/// zero-area triangle is dropped (both counted). baseColorFactor's rgb, clamped to [0, 0.99],
/// is the reflectance, emissiveFactor times KHR_materials_emissive_strength the emission, a
/// primitive without a material gets grey 0.5. Lightmap UVs come from TEXCOORD_1, or TEXCOORD_0
/// when there is only one (glTF's v already grows downward, as ours does), and are kept only if
/// every face has them, all in [0, 1]. Textures, normals, skins, morph targets, cameras and
/// doubleSided are not used. tinygltf parses the file (io/gltf_load.hpp); as it does, a property
/// of the wrong JSON type reads as absent. Throws a one-line Error naming the file and the
/// element for a missing or malformed file (tinygltf's message, which names the kind of element),
/// an index out of range, data outside its buffer, a wrong accessor type, a non-finite position,
/// a sparse accessor, a missing buffer file or a required extension that changes geometry
/// (Draco, meshopt). Cost: linear in the file and the flattened scene.
template <SpectrumType S>
GltfReadResult<S> read_gltf_result(const std::string& path) {
    const detail::GltfSource g = detail::open_gltf(path);
    detail::check_gltf_asset(g);
    return detail::GltfSceneReader<S>(g).read();
}

/// Reads a glTF 2.0 file (.gltf or .glb) into a Scene: read_gltf_result without the counts of
/// what was left out.
template <SpectrumType S>
Scene<S> read_gltf(const std::string& path) {
    return read_gltf_result<S>(path).scene;
}

}  // namespace radiosity
