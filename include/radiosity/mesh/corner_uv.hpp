#pragma once
/// @file corner_uv.hpp  Lightmap texture coordinates of a mesh, one per face corner. A vertex
/// where two UV charts meet (a seam) has a different UV in the faces on either side, so the
/// coordinates live on OpenMesh's half-edges: the half-edge of face f that points to vertex v
/// holds v's UV in f. Convention (glTF's): u and v in [0, 1], texel (x, y) of a W x H lightmap
/// covers [x/W, (x+1)/W] x [y/H, (y+1)/H], and row y = 0 is the top row of the image.

#include <radiosity/error.hpp>

#include <glm/vec2.hpp>

#include <span>
#include <string>
#include <vector>

namespace radiosity {

/// Whether a UV can address a lightmap: both coordinates finite and in [0, 1] (a tiled texture's
/// coordinates are not lightmap UVs).
inline bool in_unit_square(const glm::vec2& uv) {
    return uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f;
}

/// Whether the mesh carries per-corner lightmap UVs.
template <class M>
bool has_corner_uvs(const M& mesh) {
    return mesh.has_halfedge_texcoords2D();
}

/// The UVs of face f's corners, in the order of mesh.fv_range(f). Empty if the mesh has none.
template <class M>
std::vector<glm::vec2> corner_uvs(const M& mesh, typename M::FaceHandle f) {
    std::vector<glm::vec2> uv;
    if (!has_corner_uvs(mesh)) return uv;
    for (auto h : mesh.fh_range(f)) {  // fh_range and fv_range start at the same corner
        const auto& t = mesh.texcoord2D(h);
        uv.emplace_back(t[0], t[1]);
    }
    return uv;
}

/// The UV of vertex v in face f (the texcoord of the half-edge of f that points to v); (0, 0)
/// if the mesh has none or v is not a corner of f.
template <class M>
glm::vec2 corner_uv(const M& mesh, typename M::FaceHandle f, typename M::VertexHandle v) {
    if (has_corner_uvs(mesh))
        for (auto h : mesh.vih_range(v))
            if (mesh.face_handle(h) == f) {
                const auto& t = mesh.texcoord2D(h);
                return {t[0], t[1]};
            }
    return {0.0f, 0.0f};
}

/// Sets the UVs of face f's corners (in the order of mesh.fv_range(f)), requesting the
/// half-edge texcoord property if the mesh has none yet. Throws Error if the count is wrong.
template <class M>
void set_corner_uvs(M& mesh, typename M::FaceHandle f, std::span<const glm::vec2> uv) {
    if (mesh.valence(f) != uv.size())
        throw Error("face " + std::to_string(f.idx()) + ": " + std::to_string(uv.size()) +
                    " UVs for " + std::to_string(mesh.valence(f)) + " corners");
    if (!has_corner_uvs(mesh)) mesh.request_halfedge_texcoords2D();
    std::size_t k = 0;
    for (auto h : mesh.fh_range(f)) {
        mesh.set_texcoord2D(h, {uv[k].x, uv[k].y});
        ++k;
    }
}

}  // namespace radiosity
