#pragma once
/// @file leaves.hpp  The leaves of a hierarchy as a patch mesh, the result every other method
/// gives: one face per leaf element, with the corners of finer neighbours that lie on its edges
/// (T-vertices) inserted into its polygon, so that neighbours at different depths share their
/// vertices and smooth shading has neither cracks nor steps.

#include <radiosity/hierarchy/nodes.hpp>
#include <radiosity/mesh/manifold.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace radiosity {

namespace detail {

/// Exact bits of a point, for matching vertices that were computed the same way (midpoint).
struct PointKey {
    std::uint64_t x, y, z;
    bool operator==(const PointKey&) const = default;
};
struct PointKeyHash {
    std::size_t operator()(const PointKey& k) const {
        return static_cast<std::size_t>(splitmix64(k.x ^ splitmix64(k.y ^ splitmix64(k.z))));
    }
};
inline PointKey point_key(const Vec3& p) {
    PointKey k;
    std::memcpy(&k.x, &p.x, 8);
    std::memcpy(&k.y, &p.y, 8);
    std::memcpy(&k.z, &p.z, 8);
    return k;
}

/// The points of a leaf polygon's edge p -> q that are corners of other leaves: its dyadic
/// midpoints (the only points a finer neighbour can have there, since every split halves edges
/// by midpoint), in order from p, appended to out as indices into `points`.
/// The UVs (u, v, 0) of the points go to uv_out, halved along the edge's own UVs up and uq.
inline void hanging_points(const Vec3& p, const Vec3& q, const Vec3& up, const Vec3& uq, int depth,
                           const std::unordered_map<PointKey, std::uint32_t, PointKeyHash>& index,
                           std::vector<std::uint32_t>& out, std::vector<glm::vec2>& uv_out) {
    if (depth == 0) return;
    const Vec3 m = midpoint(p, q), um = midpoint(up, uq);
    const auto it = index.find(point_key(m));
    if (it == index.end()) return;
    hanging_points(p, m, up, um, depth - 1, index, out, uv_out);
    out.push_back(it->second);
    uv_out.emplace_back(um.x, um.y);
    hanging_points(m, q, um, uq, depth - 1, index, out, uv_out);
}

}  // namespace detail

/// The leaves of a hierarchy: ids in increasing order, and each one's polygon as indices into
/// `points`, T-vertices included.
struct LeafPolygons {
    std::vector<NodeId> leaf;                      ///< the leaf element of each polygon
    std::vector<Vec3> points;                      ///< every distinct corner
    std::vector<std::vector<std::uint32_t>> face;  ///< corners, counter-clockwise
    std::vector<std::vector<glm::vec2>> uv;  ///< lightmap UVs of the corners, if the scene has any
};

/// The leaf polygons with T-vertices (see the file comment). Cost: O(leaves) expected.
inline LeafPolygons leaf_polygons(const Hierarchy& h) {
    LeafPolygons out;
    std::unordered_map<detail::PointKey, std::uint32_t, detail::PointKeyHash> index;
    auto point = [&](const Vec3& p) {
        const auto [it, fresh] =
            index.try_emplace(detail::point_key(p), static_cast<std::uint32_t>(out.points.size()));
        if (fresh) out.points.push_back(p);
        return it->second;
    };
    for (NodeId n = 0; n < h.size(); ++n)
        if (!h.is_cluster(n) && h.is_leaf(n)) {
            out.leaf.push_back(n);
            for (const Vec3& v : h.polygon(n)) point(v);
        }
    out.face.resize(out.leaf.size());
    out.uv.resize(out.leaf.size());
    for (std::size_t f = 0; f < out.leaf.size(); ++f) {
        const NodeId n = out.leaf[f];
        const auto p = h.polygon(n);
        const std::array<Vec3, 4> none{};
        const auto& u = h.has_uv ? h.uv[n] : none;
        auto& corners = out.face[f];
        auto& uv = out.uv[f];
        for (std::size_t k = 0; k < p.size(); ++k) {
            const std::size_t next = (k + 1) % p.size();
            corners.push_back(index.at(detail::point_key(p[k])));
            uv.emplace_back(u[k].x, u[k].y);
            detail::hanging_points(p[k], p[next], u[k], u[next], 32, index, corners, uv);
        }
        if (!h.has_uv) uv.clear();
    }
    return out;
}

/// The patch mesh of a hierarchy's leaves, with the lightmap UVs the hierarchy carries: each face
/// takes the material and surface of the patch-mesh face its root came from (`input`), and B from
/// `B` (one value per leaf, in leaf_polygons order). Cost: O(leaves).
template <SpectrumType S>
Mesh<S> leaf_mesh(const Hierarchy& h, const LeafPolygons& leaves, const Mesh<S>& input,
                  std::span<const S> B) {
    Mesh<S> mesh;
    const ManifoldFaces m = make_manifold(leaves.face, leaves.points.size());
    detail::add_manifold_faces(
        mesh, m, [&](std::uint32_t o) -> const Vec3& { return leaves.points[o]; },
        [&](std::size_t f, auto fh, const auto& corners) {
            if (h.has_uv) detail::set_face_uvs(mesh, fh, corners, leaves.uv[f]);
            const auto src =
                input.face_handle(static_cast<int>(h.surface[h.root_of(leaves.leaf[f])]));
            auto& d = mesh.data(fh);
            d = input.data(src);
            d.radiosity = B[f];
        },
        [&](std::size_t f) {
            return "hierarchical radiosity: leaf " + std::to_string(f) +
                   " could not be added to the mesh";
        });
    return mesh;
}

}  // namespace radiosity
