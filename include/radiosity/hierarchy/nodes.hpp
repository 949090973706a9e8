#pragma once
/// @file nodes.hpp  The nodes of hierarchical radiosity in flat arrays: elements, quadtrees over
/// the input faces (Hanrahan, Salzman & Aupperle 1991), and clusters, a binary volume hierarchy
/// over those faces (Smits, Arvo & Greenberg 1994; Sillion 1995), so that the whole scene starts
/// as one node and initial linking is a single self-link. Indices, not pointers: cheap to copy,
/// to checkpoint and to send between processes.

#include <radiosity/config.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

namespace radiosity {

/// Index of a node (cluster or element) of a Hierarchy.
using NodeId = std::uint32_t;
/// "No node": the parent of the top node, the first child of a leaf.
inline constexpr NodeId no_node = 0xffffffffu;

/// Midpoint of p and q, computed one way only: an edge split from either of its two faces gives
/// the same bits, so neighbours' vertices can be matched exactly (see leaves.hpp).
inline Vec3 midpoint(const Vec3& p, const Vec3& q) {
    return 0.5 * (p + q);
}

/// The orientation classes of faces in a cluster: +x, -x, +y, -y, +z, -z, the six faces of a
/// cube around the cluster. A face belongs wholly to the class of its normal's largest
/// component (by sign): the faces of a box, axis-aligned or turned by less than 45 degrees,
/// fall in six classes, none shared. (Shares by the squared components, smooth in the normal,
/// put 8% of each side of the Cornell box's turned blocks in its neighbours' classes, and so
/// 8% of a bright side's light on a dark one: its front face came out 20% too bright.)
inline constexpr std::size_t facing_classes = 6;

/// The orientation class of a face of normal n (facing_classes).
inline std::size_t facing_class(const Vec3& n) {
    const Vec3 a = glm::abs(n);
    const std::size_t axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return 2 * axis + (n[int(axis)] < 0.0 ? 1 : 0);
}

/// The nodes of the hierarchy. Node 0 is the top: the cluster of all roots (or the only root).
/// Every node's children are consecutive ids after it (first_child .. + child_count), so a pass
/// in increasing id order meets parents before children (push) and in decreasing order children
/// before parents (pull). A root element is one input face (a triangle or a convex quad);
/// elements split 1 -> 4 at their edge midpoints; a cluster has two children.
struct Hierarchy {
    PatchTable roots;                    ///< root faces' polygons; the BVH is built over them
    std::vector<std::uint32_t> surface;  ///< per root: the patch-mesh face it was cut from
    std::vector<std::uint32_t> order;    ///< roots in cluster order: a cluster's are a range
    std::vector<double> order_area;      ///< prefix sums of root areas along `order`

    std::vector<NodeId> parent;               ///< parent node, no_node for node 0
    std::vector<NodeId> first_child;          ///< first child, no_node for a leaf
    std::vector<std::uint8_t> child_count;    ///< 0, 2 (cluster) or 4 (element)
    std::vector<std::uint8_t> corner_count;   ///< 3 or 4 for elements, 0 for clusters
    std::vector<std::uint8_t> depth;          ///< element depth below its root (0 for clusters)
    std::vector<std::uint32_t> member_begin;  ///< first position in `order` of its roots
    std::vector<std::uint32_t> member_end;    ///< one past the last
    std::vector<double> area;                 ///< A: element area; cluster: sum of its roots'
    std::vector<double> radius;               ///< bounding-sphere radius about centre
    std::vector<Vec3> centre;                 ///< element centroid; cluster box centre
    /// Element: its unit normal. Cluster: the area-weighted sum of its roots' normals, N =
    /// sum A n, whose length over the area, |N| / A, is 1 where the faces are coplanar and about
    /// 0 where they face every way (the oracle's oriented estimate, links.hpp).
    std::vector<Vec3> normal;
    /// Cluster: the orientation classes (facing_class) of its roots, bit c for class c; a
    /// root: its own class's bit; 0 for split elements.
    std::vector<std::uint8_t> classes;
    std::vector<std::uint64_t> key;           ///< identity for random streams (not the id)
    std::vector<std::array<Vec3, 4>> corner;  ///< element corners, counter-clockwise
    bool has_uv = false;  ///< the scene has lightmap UVs, and every node an entry in uv
    /// Lightmap UVs of the element corners (u, v, 0), split as the corners are.
    std::vector<std::array<Vec3, 4>> uv;

    std::size_t size() const { return parent.size(); }  ///< number of nodes
    /// The clusters and root elements: nodes [0, top_nodes()); split elements come after.
    std::size_t top_nodes() const { return 2 * roots.size() - 1; }
    bool is_cluster(NodeId n) const { return corner_count[n] == 0; }    ///< cluster or element
    bool is_leaf(NodeId n) const { return first_child[n] == no_node; }  ///< no children
    /// A cluster whose roots fall in more than one orientation class: its faces do not all
    /// face alike, so its links split their light by class (gather.hpp). Never an element
    /// (one class, or none below the roots). More than one bit set: c & (c - 1) clears the
    /// lowest (std::popcount, without a CPU flag for the instruction, calls a library function:
    /// 0.3% of room3's time).
    bool mixed(NodeId n) const {
        const unsigned c = classes[n];
        return (c & (c - 1)) != 0;
    }
    std::uint32_t root_of(NodeId n) const { return order[member_begin[n]]; }  ///< element's root
    /// An element's polygon (3 or 4 corners).
    std::span<const Vec3> polygon(NodeId n) const { return {corner[n].data(), corner_count[n]}; }
    /// Area of the roots in positions [b, e) of `order`.
    double member_area(std::uint32_t b, std::uint32_t e) const {
        return order_area[e] - order_area[b];
    }

    /// Makes room for `nodes` nodes in every per-node array (appending then never copies them).
    void reserve(std::size_t nodes) {
        parent.reserve(nodes);
        first_child.reserve(nodes);
        child_count.reserve(nodes);
        corner_count.reserve(nodes);
        depth.reserve(nodes);
        member_begin.reserve(nodes);
        member_end.reserve(nodes);
        area.reserve(nodes);
        radius.reserve(nodes);
        centre.reserve(nodes);
        normal.reserve(nodes);
        classes.reserve(nodes);
        key.reserve(nodes);
        corner.reserve(nodes);
        if (has_uv) uv.reserve(nodes);
    }

    /// Appends a node with no children; returns its id.
    NodeId add_node(NodeId up, std::uint32_t b, std::uint32_t e, std::uint64_t k) {
        const auto id = static_cast<NodeId>(size());
        parent.push_back(up);
        first_child.push_back(no_node);
        child_count.push_back(0);
        corner_count.push_back(0);
        depth.push_back(0);
        member_begin.push_back(b);
        member_end.push_back(e);
        area.push_back(0.0);
        radius.push_back(0.0);
        centre.push_back(Vec3(0.0));
        normal.push_back(Vec3(0.0));
        classes.push_back(0);
        key.push_back(k);
        corner.push_back({});
        if (has_uv) uv.push_back({});
        return id;
    }

    /// Makes node n the element of polygon p (3 or 4 corners).
    void set_element(NodeId n, std::span<const Vec3> p) {
        RADIOSITY_ASSERT(p.size() == 3 || p.size() == 4);
        corner_count[n] = static_cast<std::uint8_t>(p.size());
        std::copy(p.begin(), p.end(), corner[n].begin());
        area[n] = polygon_area(p);
        normal[n] = polygon_normal(p);
        centre[n] = polygon_centroid(p);
        double r = 0.0;
        for (const Vec3& v : p) r = std::max(r, glm::length(v - centre[n]));
        radius[n] = r;
    }

    /// Bytes held by the node arrays (for the report).
    std::size_t bytes() const {
        const std::size_t per_node = 3 * sizeof(NodeId) + 4 + 2 * sizeof(std::uint32_t) +
                                     2 * sizeof(double) + 2 * sizeof(Vec3) + sizeof(std::uint64_t) +
                                     sizeof(std::array<Vec3, 4>);
        return size() * per_node + order.size() * (sizeof(std::uint32_t) + sizeof(double));
    }
};

namespace detail {

/// The four children of element polygon p, split at its edge midpoints: a triangle into three
/// corner triangles and the middle one, a quad into four quads about its centre (the mean of its
/// corners). Children keep the parent's orientation.
inline std::array<std::array<Vec3, 4>, 4> split_corners(std::span<const Vec3> p) {
    if (p.size() == 3) {
        const Vec3 ab = midpoint(p[0], p[1]), bc = midpoint(p[1], p[2]), ca = midpoint(p[2], p[0]);
        return {{{p[0], ab, ca, Vec3(0.0)},
                 {ab, p[1], bc, Vec3(0.0)},
                 {ca, bc, p[2], Vec3(0.0)},
                 {ab, bc, ca, Vec3(0.0)}}};
    }
    const Vec3 ab = midpoint(p[0], p[1]), bc = midpoint(p[1], p[2]), cd = midpoint(p[2], p[3]),
               da = midpoint(p[3], p[0]);
    const Vec3 m = 0.25 * (p[0] + p[1] + p[2] + p[3]);
    return {{{p[0], ab, m, da}, {ab, p[1], bc, m}, {m, bc, p[2], cd}, {da, m, cd, p[3]}}};
}

/// A root as the cluster tree's median splits see it: its centroid and index, in a flat array
/// that the splits permute in place (reading the roots' polygons at every level instead, in the
/// permuted order, was a tenth of loading a million triangles).
struct Member {
    Vec3 centroid;
    std::uint32_t root;
};

/// The position at which the cluster of members [b, e) divides: the median of the members'
/// centroids along the longest axis of their box (ties by root index, a total order, so the
/// halves never depend on the order the members come in), members [b, mid) below it.
inline std::uint32_t median_split(std::vector<Member>& members, std::uint32_t b, std::uint32_t e) {
    Vec3 lo(1e300), hi(-1e300);
    for (std::uint32_t i = b; i < e; ++i) {
        lo = glm::min(lo, members[i].centroid);
        hi = glm::max(hi, members[i].centroid);
    }
    const Vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                     : extent.y >= extent.z                       ? 1
                                                                  : 2;
    const std::uint32_t mid = b + (e - b) / 2;
    std::nth_element(members.begin() + b, members.begin() + mid, members.begin() + e,
                     [axis](const Member& x, const Member& y) {
                         const double cx = x.centroid[axis], cy = y.centroid[axis];
                         return cx < cy || (cx == cy && x.root < y.root);
                     });
    return mid;
}

/// Centre and radius of every cluster from the box of its roots' corners, the union of its
/// children's boxes, children (larger ids) before parents: O(nodes), each corner read once.
inline void cluster_spheres(Hierarchy& h) {
    std::vector<std::array<Vec3, 2>> box(h.size());
    for (std::size_t i = h.size(); i-- > 0;) {
        Vec3 lo(1e300), hi(-1e300);
        if (h.is_cluster(NodeId(i))) {
            for (const NodeId c : {h.first_child[i], h.first_child[i] + 1}) {
                lo = glm::min(lo, box[c][0]);
                hi = glm::max(hi, box[c][1]);
            }
            h.centre[i] = 0.5 * (lo + hi);
            h.radius[i] = 0.5 * glm::length(hi - lo);
        } else {
            for (const Vec3& v : h.polygon(NodeId(i))) {
                lo = glm::min(lo, v);
                hi = glm::max(hi, v);
            }
        }
        box[i] = {lo, hi};
    }
}

}  // namespace detail

/// Builds the top of the hierarchy over root polygons (triangles or convex quads, with the
/// patch-mesh face each came from): the cluster tree by median splits (each cluster's two
/// children consecutive), its leaves the root elements, with the roots' corner UVs if given
/// (one per root, or none). Node keys hash the tree position, so random streams depend on where
/// a node is, not on when it was made. Cost: O(n log n).
inline Hierarchy build_hierarchy(PatchTable roots, std::vector<std::uint32_t> surface,
                                 const std::vector<std::array<Vec3, 4>>& root_uvs = {}) {
    Hierarchy h;
    h.roots = std::move(roots);
    h.surface = std::move(surface);
    h.has_uv = !root_uvs.empty();
    const auto n = static_cast<std::uint32_t>(h.roots.size());
    if (n == 0) throw Error("hierarchical radiosity: the scene has no faces");
    // The median splits permute the members within each range; `order` is what they leave, so
    // the prefix areas (and the clusters' areas from them) are summed once the tree is built.
    std::vector<detail::Member> members(n);
    for (std::uint32_t r = 0; r < n; ++r) members[r] = {h.roots.centroid(r), r};
    struct Pending {
        NodeId node;
        std::uint32_t b, e;
    };
    h.reserve(h.top_nodes());
    std::vector<Pending> todo{{h.add_node(no_node, 0, n, splitmix64(1)), 0, n}};
    todo.reserve(h.top_nodes());
    std::vector<Pending> clusters;
    for (std::size_t t = 0; t < todo.size(); ++t) {  // breadth first: todo grows as it goes
        const Pending p = todo[t];
        if (p.e - p.b == 1) continue;  // a root element, filled below
        const std::uint32_t mid = detail::median_split(members, p.b, p.e);
        const NodeId first = h.add_node(p.node, p.b, mid, splitmix64(h.key[p.node] * 2 + 1));
        h.add_node(p.node, mid, p.e, splitmix64(h.key[p.node] * 2 + 2));
        h.first_child[p.node] = first;
        h.child_count[p.node] = 2;
        todo.push_back({first, p.b, mid});
        todo.push_back({first + 1, mid, p.e});
        clusters.push_back(p);
    }
    h.order.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) h.order[i] = members[i].root;
    h.order_area.assign(n + 1, 0.0);
    for (std::uint32_t i = 0; i < n; ++i)
        h.order_area[i + 1] = h.order_area[i] + h.roots.area(h.order[i]);
    for (const Pending& p : clusters) h.area[p.node] = h.member_area(p.b, p.e);
    for (const Pending& p : todo)
        if (p.e - p.b == 1) {
            h.set_element(p.node, h.roots.polygon(h.order[p.b]));
            if (h.has_uv) h.uv[p.node] = root_uvs[h.order[p.b]];
        }
    for (std::size_t i = h.size(); i-- > 0;) {  // children (larger ids) before their parents
        if (!h.is_cluster(NodeId(i))) {
            h.classes[i] = std::uint8_t(1u << facing_class(h.normal[i]));
            continue;
        }
        const NodeId a = h.first_child[i], b = a + 1;
        h.classes[i] = std::uint8_t(h.classes[a] | h.classes[b]);
        const auto weighted = [&](NodeId c) {  // sum A n below c
            return h.is_cluster(c) ? h.normal[c] : h.area[c] * h.normal[c];
        };
        h.normal[i] = weighted(a) + weighted(b);
    }
    detail::cluster_spheres(h);
    return h;
}

/// Splits leaf element n into its four children (split_corners), appended as consecutive nodes
/// whose keys follow from n's. Returns the first child. Not thread-safe (it appends).
inline NodeId split_element(Hierarchy& h, NodeId n) {
    RADIOSITY_ASSERT(!h.is_cluster(n) && h.is_leaf(n));
    const auto children = detail::split_corners(h.polygon(n));
    const std::size_t corners = h.corner_count[n];
    // UVs split as the corners do (midpoints and the mean of four are affine in both).
    const auto uvs = !h.has_uv ? children : detail::split_corners({h.uv[n].data(), corners});
    NodeId first = no_node;
    for (std::size_t c = 0; c < 4; ++c) {
        const NodeId id =
            h.add_node(n, h.member_begin[n], h.member_end[n], splitmix64(h.key[n] * 4 + c + 1));
        if (c == 0) first = id;
        h.set_element(id, std::span<const Vec3>(children[c].data(), corners));
        if (h.has_uv) h.uv[id] = uvs[c];
        h.depth[id] = static_cast<std::uint8_t>(h.depth[n] + 1);
    }
    h.first_child[n] = first;
    h.child_count[n] = 4;
    return first;
}

}  // namespace radiosity
