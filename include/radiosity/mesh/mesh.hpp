#pragma once
/// @file mesh.hpp  The scene as an OpenMesh half-edge polygon mesh whose faces are the patches,
/// each carrying emission E, reflectance R and radiosity B in the colour type S; building such a
/// mesh from plain arrays; and the flat patch table made from it.

// OpenMesh's IO header must come before its mesh headers (DESIGN.md, known quirks).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/geometry/triangulate.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/mesh/corner_uv.hpp>
#include <radiosity/mesh/manifold.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/spectrum.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace radiosity {

/// OpenMesh traits of a radiosity mesh: double-precision points, and per face the patch data.
template <SpectrumType S>
struct PatchTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
    FaceTraits {
        S emission{};                ///< E: radiant exitance the patch emits by itself
        S reflectance{};             ///< R: diffuse reflectance, each band in [0, 1)
        S radiosity{};               ///< B: total radiant exitance, filled by a solve
        std::uint32_t material = 0;  ///< index into the scene's materials (for shading breaks)
        std::uint32_t surface = 0;   ///< index of the input face this patch was cut from
    };
};

/// A radiosity scene: a polygon mesh (triangles and quads) whose faces are patches.
template <SpectrumType S>
using Mesh = OpenMesh::PolyMesh_ArrayKernelT<PatchTraits<S>>;

/// A diffuse material: emission E and reflectance R.
template <SpectrumType S>
struct Material {
    S emission{};      ///< E (W/m^2 or any consistent unit); radiance is E / pi
    S reflectance{};   ///< R, each band in [0, 1)
    std::string name;  ///< for messages and exports

    /// The material of faces whose file names none: reflectance 0.5 in every band, no emission.
    static Material unnamed() { return {S{}, from_rgb<S>(0.5f, 0.5f, 0.5f), "default"}; }
};

/// A scene as plain arrays: vertex positions, polygon faces (vertex indices, counter-clockwise
/// seen from the front), the material of each face, the materials and, optionally, lightmap
/// UVs per face corner (mesh/corner_uv.hpp gives their convention).
template <SpectrumType S>
struct Scene {
    std::vector<Vec3> positions;                    ///< vertex positions
    std::vector<std::vector<std::uint32_t>> faces;  ///< each face's vertex indices
    std::vector<std::uint32_t> face_material;       ///< material index per face
    std::vector<Material<S>> materials;             ///< the materials
    std::vector<std::vector<glm::vec2>> face_uvs;   ///< UV per corner of every face, or empty
    std::string source = "scene";                   ///< file or scene name, for messages
    std::vector<std::size_t> face_lines;  ///< line of each face in the source file, or empty
    /// Faces of zero area that the reader left out on purpose (counted, so that programs can
    /// say so: nothing is lost silently); build_mesh refuses such faces where they remain.
    std::size_t zero_area_faces = 0;
    /// The length unit of positions, in metres (the Cornell box: millimetres, 0.001); files
    /// other than glTF (metres by its specification) do not say, so 1 unless the user sets it.
    /// Radiosity does not depend on it (E and B are per unit area); glTF export converts to it.
    double metres_per_unit = 1.0;
};

namespace detail {
template <SpectrumType S>
void validate_material(const Material<S>& m, const std::string& where) {
    if (!all_finite(m.emission) || !all_finite(m.reflectance))
        throw Error(where + ": emission or reflectance is not a finite number");
    for (std::size_t k = 0; k < band_count<S>; ++k) {
        if (band(m.reflectance, k) < 0.0f || band(m.reflectance, k) >= 1.0f)
            throw Error(where + ": reflectance " + std::to_string(band(m.reflectance, k)) +
                        " is outside [0, 1)");
        if (band(m.emission, k) < 0.0f) throw Error(where + ": emission is negative");
    }
}
/// Whether polygon q, seen along its Newell normal, is simple: a triangle or convex quad is; any
/// other is triangulated (geometry/triangulate.hpp), which refuses crossing, touching or
/// overlapping edges with an Error beginning with `at`. A corner repeated in a row (a quad with
/// two corners at one point, as at a sphere's pole) counts once.
inline void check_simple(std::span<const Vec3> q, const std::string& at) {
    std::vector<Vec3> p;
    for (std::size_t k = 0; k < q.size(); ++k)
        if (q[k] != q[(k + 1) % q.size()]) p.push_back(q[k]);
    const Vec3 n = glm::normalize(newell_vector(p));
    if (p.size() <= 3) return;
    if (p.size() == 4) {
        bool convex = true;
        for (std::size_t k = 0; k < 4; ++k)
            convex = convex &&
                     glm::dot(glm::cross(p[k] - p[(k + 3) % 4], p[(k + 1) % 4] - p[k]), n) > 0.0;
        if (convex) return;
    }
    Vec3 u, v;
    orthonormal_basis(n, u, v);
    TriangulationInput in;
    in.exact_delaunay = false;  // only the edges' crossings matter here
    in.loops.emplace_back();
    for (const Vec3& x : p) {
        in.loops[0].push_back(static_cast<std::uint32_t>(in.points.size()));
        in.points.emplace_back(glm::dot(x - p[0], u), glm::dot(x - p[0], v));
    }
    triangulate(in, at);
}

/// Checks face f of a scene: at least 3 vertices, all existing and distinct, non-zero area, no
/// edges that cross or touch (seen along its normal), an existing material. Throws Error naming
/// the source, the line where the scene knows it, and the face.
template <SpectrumType S>
void validate_face(const Scene<S>& scene, std::size_t f) {
    const std::string at =
        scene.source +
        (f < scene.face_lines.size() ? ":" + std::to_string(scene.face_lines[f]) : "") + ": face " +
        std::to_string(f);
    const auto& face = scene.faces[f];
    if (face.size() < 3) throw Error(at + " has fewer than 3 vertices");
    std::vector<Vec3> poly;
    for (std::size_t k = 0; k < face.size(); ++k) {
        const std::uint32_t v = face[k];
        if (v >= scene.positions.size())
            throw Error(at + " refers to vertex " + std::to_string(v) + ", which does not exist");
        if (std::find(face.begin(), face.begin() + static_cast<std::ptrdiff_t>(k), v) !=
            face.begin() + static_cast<std::ptrdiff_t>(k))
            throw Error(at + " uses vertex " + std::to_string(v) + " more than once");
        poly.push_back(scene.positions[v]);
    }
    if (!(polygon_area(poly) > 0.0)) throw Error(at + " has zero area");
    check_simple(poly, at);
    if (scene.face_material[f] >= scene.materials.size())
        throw Error(at + " refers to material " + std::to_string(scene.face_material[f]) +
                    ", which does not exist");
}

/// Checks the scene's lightmap UVs: none at all, or one finite UV in [0, 1] per corner of
/// every face. Throws Error naming the source and the face.
template <SpectrumType S>
void validate_uvs(const Scene<S>& scene) {
    if (scene.face_uvs.empty()) return;
    if (scene.face_uvs.size() != scene.faces.size())
        throw Error(scene.source + ": need lightmap UVs for every face or for none");
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
        const std::string at = scene.source + ": face " + std::to_string(f);
        if (scene.face_uvs[f].size() != scene.faces[f].size())
            throw Error(at + " has " + std::to_string(scene.face_uvs[f].size()) + " UVs for " +
                        std::to_string(scene.faces[f].size()) + " corners");
        for (const glm::vec2& t : scene.face_uvs[f])
            if (!in_unit_square(t))
                throw Error(at + " has a lightmap UV outside [0, 1] (or not a number)");
    }
}

/// Stores face f's UVs on the half-edges of mesh face h, matching corners by vertex.
template <class M>
void set_face_uvs(M& mesh, typename M::FaceHandle h,
                  const std::vector<typename M::VertexHandle>& corners,
                  const std::vector<glm::vec2>& uv) {
    std::vector<glm::vec2> ordered;
    for (auto v : mesh.fv_range(h))
        ordered.push_back(uv[static_cast<std::size_t>(std::find(corners.begin(), corners.end(), v) -
                                                      corners.begin())]);
    set_corner_uvs(mesh, h, ordered);
}

/// Adds make_manifold's faces to an empty mesh: a vertex for every origin o at position(o), then
/// every face, calling added(f, handle, corners) on each. OpenMesh refusing a face cannot happen
/// after make_manifold; as a safety net the face is retried on copies of its corners, and if it is
/// still refused Error(refused(f)) is thrown. Cost: O(corners).
template <SpectrumType S, class Position, class Added, class Refused>
void add_manifold_faces(Mesh<S>& mesh, const ManifoldFaces& m, Position&& position, Added&& added,
                        Refused&& refused) {
    std::vector<typename Mesh<S>::VertexHandle> vh;
    vh.reserve(m.origin.size());
    for (std::uint32_t o : m.origin) {
        const Vec3& p = position(o);
        vh.push_back(mesh.add_vertex({p.x, p.y, p.z}));
    }
    std::vector<typename Mesh<S>::VertexHandle> corners;
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        corners.clear();
        for (std::uint32_t v : m.faces[f]) corners.push_back(vh[v]);
        auto fh = mesh.add_face(corners);
        if (!fh.is_valid()) {
            for (auto& c : corners) c = mesh.add_vertex(mesh.point(c));
            fh = mesh.add_face(corners);
            if (!fh.is_valid()) throw Error(refused(f));
        }
        added(f, fh, corners);
    }
}

}  // namespace detail

/// Builds the patch mesh of a scene, checking every input: indices in range, at least three
/// vertices, finite coordinates, non-zero area, faces that do not intersect themselves,
/// reflectance in [0, 1), finite non-negative emission. Throws Error naming the source and the face
/// or material at fault. Where the faces are not a manifold (an edge of three faces, faces of
/// opposite orientation on one edge, bow-tie vertices), vertices are split (make_manifold): every
/// face stays a patch. Lightmap UVs, if the scene has them, go onto the half-edges (corner_uv.hpp).
template <SpectrumType S>
Mesh<S> build_mesh(const Scene<S>& scene) {
    const std::string& src = scene.source;
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        detail::validate_material(scene.materials[m], src + ": material " + std::to_string(m) +
                                                          " '" + scene.materials[m].name + "'");
    if (scene.face_material.size() != scene.faces.size())
        throw Error(src + ": need one material index per face");
    Mesh<S> mesh;
    for (std::size_t v = 0; v < scene.positions.size(); ++v) {
        const Vec3& p = scene.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error(src + ": vertex " + std::to_string(v) + " is not a finite point");
    }
    for (std::size_t f = 0; f < scene.faces.size(); ++f) detail::validate_face(scene, f);
    detail::validate_uvs(scene);
    // Split what a half-edge mesh cannot hold (edges of three faces, bow-ties), then add.
    const ManifoldFaces m = make_manifold(scene.faces, scene.positions.size());
    detail::add_manifold_faces(
        mesh, m, [&](std::uint32_t o) -> const Vec3& { return scene.positions[o]; },
        [&](std::size_t f, auto fh, const auto& corners) {
            if (!scene.face_uvs.empty()) detail::set_face_uvs(mesh, fh, corners, scene.face_uvs[f]);
            const std::uint32_t mat = scene.face_material[f];
            auto& d = mesh.data(fh);
            d.emission = scene.materials[mat].emission;
            d.reflectance = scene.materials[mat].reflectance;
            d.material = mat;
            d.surface = static_cast<std::uint32_t>(f);
        },
        [&](std::size_t f) {
            return src + ": face " + std::to_string(f) + " could not be added to the mesh";
        });
    return mesh;
}

/// Vertices of face f of a mesh, in order, as scene-space points.
template <class M>
std::vector<Vec3> face_polygon(const M& mesh, typename M::FaceHandle f) {
    std::vector<Vec3> poly;
    for (auto v : mesh.fv_range(f)) {
        const auto& p = mesh.point(v);
        poly.emplace_back(p[0], p[1], p[2]);
    }
    return poly;
}

/// The flat patch table of a mesh: patch i is face i. Throws Error for a zero-area face.
template <class M>
PatchTable make_patch_table(const M& mesh) {
    PatchTable table;
    for (auto f : mesh.faces()) table.add(face_polygon(mesh, f), "face " + std::to_string(f.idx()));
    return table;
}

/// E_i of every face, in face order.
template <SpectrumType S>
std::vector<S> face_emission(const Mesh<S>& mesh) {
    std::vector<S> out;
    out.reserve(mesh.n_faces());
    for (auto f : mesh.faces()) out.push_back(mesh.data(f).emission);
    return out;
}

/// R_i of every face, in face order.
template <SpectrumType S>
std::vector<S> face_reflectance(const Mesh<S>& mesh) {
    std::vector<S> out;
    out.reserve(mesh.n_faces());
    for (auto f : mesh.faces()) out.push_back(mesh.data(f).reflectance);
    return out;
}

/// Stores B_i into the faces, in face order.
template <SpectrumType S>
void set_face_radiosity(Mesh<S>& mesh, std::span<const S> B) {
    if (B.size() != mesh.n_faces()) throw Error("set_face_radiosity: need one value per face");
    for (auto f : mesh.faces()) mesh.data(f).radiosity = B[static_cast<std::size_t>(f.idx())];
}

}  // namespace radiosity
