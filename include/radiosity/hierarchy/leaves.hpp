#pragma once
/// @file leaves.hpp  The leaves of a hierarchy as a patch mesh, the result every other method
/// gives: one face per leaf element, with the corners of finer neighbours that lie on its edges
/// (T-vertices) inserted into its polygon, so that neighbours at different depths share their
/// vertices and smooth shading has neither cracks nor steps.

#include <radiosity/hierarchy/nodes.hpp>
#include <radiosity/mesh/manifold.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace radiosity {

namespace detail {

/// Exact bits of a point, for matching vertices that were computed the same way (midpoint).
struct PointKey {
    std::uint64_t x, y, z;
    bool operator==(const PointKey&) const = default;
};
inline PointKey point_key(const Vec3& p) {
    PointKey k;
    std::memcpy(&k.x, &p.x, 8);
    std::memcpy(&k.y, &p.y, 8);
    std::memcpy(&k.z, &p.z, 8);
    return k;
}

/// The index of each distinct point by its exact bits: an open-addressing hash table with
/// linear probing (Knuth 1973, 6.4, algorithm L), kept at most half full by doubling. A
/// million leaves ask it about ten million times (every corner, and every edge's midpoint);
/// std::unordered_map, a node per point and a pointer chase per probe, took 1.2 s of the
/// million-triangle box's serial end. Which index a point gets is the caller's (in order of
/// first insertion), never the table's layout.
class PointIndex {
  public:
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

    /// The index of p, or `none`.
    std::uint32_t find(const PointKey& p) const {
        if (slots_.empty()) return none;
        for (std::size_t at = home(p);; at = (at + 1) & mask()) {
            const Slot& s = slots_[at];
            if (s.value == none || s.key == p) return s.value;
        }
    }
    /// The index of p, inserting it with `value` if it is not there yet.
    std::uint32_t insert(const PointKey& p, std::uint32_t value) {
        if (2 * (size_ + 1) > slots_.size()) grow();
        for (std::size_t at = home(p);; at = (at + 1) & mask()) {
            Slot& s = slots_[at];
            if (s.value == none) {
                s = {p, value};
                ++size_;
                return value;
            }
            if (s.key == p) return s.value;
        }
    }

  private:
    struct Slot {
        PointKey key{};
        std::uint32_t value = none;
    };
    std::size_t mask() const { return slots_.size() - 1; }
    std::size_t home(const PointKey& p) const {
        return static_cast<std::size_t>(splitmix64(p.x ^ splitmix64(p.y ^ splitmix64(p.z)))) &
               mask();
    }
    void grow() {
        std::vector<Slot> old = std::move(slots_);
        slots_.assign(std::max<std::size_t>(1024, 2 * old.size()), Slot{});
        size_ = 0;
        for (const Slot& s : old)
            if (s.value != none) insert(s.key, s.value);
    }

    std::vector<Slot> slots_;  // a power of two of them
    std::size_t size_ = 0;
};

/// The points of a leaf polygon's edge p -> q that are corners of other leaves: its dyadic
/// midpoints (the only points a finer neighbour can have there, since every split halves edges
/// by midpoint), in order from p, appended to out as indices into `points`.
/// The UVs (u, v, 0) of the points go to uv_out, halved along the edge's own UVs up and uq.
inline void hanging_points(const Vec3& p, const Vec3& q, const Vec3& up, const Vec3& uq, int depth,
                           const PointIndex& index, std::vector<std::uint32_t>& out,
                           std::vector<glm::vec2>& uv_out) {
    if (depth == 0) return;
    const Vec3 m = midpoint(p, q), um = midpoint(up, uq);
    const std::uint32_t at = index.find(point_key(m));
    if (at == PointIndex::none) return;
    hanging_points(p, m, up, um, depth - 1, index, out, uv_out);
    out.push_back(at);
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
    detail::PointIndex index;
    auto point = [&](const Vec3& p) {
        const auto next = static_cast<std::uint32_t>(out.points.size());
        const std::uint32_t at = index.insert(detail::point_key(p), next);
        if (at == next) out.points.push_back(p);
        return at;
    };
    std::vector<std::uint32_t> corner_points;  // of every leaf's corners, leaf after leaf
    for (NodeId n = 0; n < h.size(); ++n)
        if (!h.is_cluster(n) && h.is_leaf(n)) {
            out.leaf.push_back(n);
            for (const Vec3& v : h.polygon(n)) corner_points.push_back(point(v));
        }
    out.face.resize(out.leaf.size());
    out.uv.resize(out.leaf.size());
    std::size_t next_corner = 0;
    for (std::size_t f = 0; f < out.leaf.size(); ++f) {
        const NodeId n = out.leaf[f];
        const auto p = h.polygon(n);
        const std::array<Vec3, 4> none{};
        const auto& u = h.has_uv ? h.uv[n] : none;
        auto& corners = out.face[f];
        auto& uv = out.uv[f];
        for (std::size_t k = 0; k < p.size(); ++k) {
            const std::size_t next = (k + 1) % p.size();
            corners.push_back(corner_points[next_corner++]);
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
