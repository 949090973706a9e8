#pragma once
/// @file solid.hpp  Which faces form closed objects, and whether a point lies inside one: the
/// test that decides which pieces of cut faces are hidden in a solid (mesh/intersect.hpp). A
/// connected set of faces is closed when every edge joins exactly two of its faces that run it
/// in opposite directions (a consistently oriented closed 2-manifold, Mantyla 1988); it is a
/// solid when its faces point away from what they enclose, that is when its signed volume is
/// positive (the divergence theorem: V = 1/6 sum det(a, b, c) over its triangles). A room
/// modelled facing in is closed but no solid: everything inside it is where the light is.
/// A point lies inside a solid where the first surface a ray from it meets is the back of a
/// face (ray parity in its first-hit form, as in ray-cast point-in-solid tests; Haines 1994):
/// three rays vote, so that one grazing an edge cannot decide alone.

#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/enclosure.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/geometry/triangulate.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/mesh/conservation.hpp>
#include <radiosity/mesh/weld.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

namespace radiosity::detail {

/// Whether polygon p (corners counter-clockwise about n) turns left, or runs straight, at every
/// corner: convex, so that its fan or its centroid may be taken directly. Cost: O(n).
inline bool turns_left_about(std::span<const Vec3> p, const Vec3& n) {
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3 a = p[k] - p[(k + p.size() - 1) % p.size()], b = p[(k + 1) % p.size()] - p[k];
        if (glm::dot(glm::cross(a, b), n) < 0.0) return false;
    }
    return true;
}

/// The triangulation input of polygon p seen in its plane (normal n): its corners, in order, as
/// coordinates along the orthonormal u, v (which it sets) from p[0]. Cost: O(n).
inline TriangulationInput in_plane(std::span<const Vec3> p, const Vec3& n, Vec3& u, Vec3& v) {
    orthonormal_basis(n, u, v);
    TriangulationInput in;
    in.exact_delaunay = false;
    in.loops.emplace_back();
    for (const Vec3& x : p) {
        in.loops[0].push_back(static_cast<std::uint32_t>(in.points.size()));
        in.points.emplace_back(glm::dot(x - p[0], u), glm::dot(x - p[0], v));
    }
    return in;
}

/// A point strictly inside polygon p (corners counter-clockwise about n): its centroid when it
/// is convex, else the centroid of the largest triangle of its constrained Delaunay
/// triangulation (a concave polygon's centroid may lie in its notch). Cost: O(n), O(n log n)
/// for a concave one.
inline Vec3 interior_point(std::span<const Vec3> p, const Vec3& n) {
    if (turns_left_about(p, n)) return local_centroid(p, n);
    Vec3 u, v;
    const Triangulation t = triangulate(in_plane(p, n, u, v));
    double best = -1.0;
    Vec3 out = local_centroid(p, n);
    for (const auto& tri : t.triangles) {
        const Vec2 &a = t.points[tri[0]], &b = t.points[tri[1]], &c = t.points[tri[2]];
        const double area = cross2(b - a, c - a);
        if (area > best) {
            best = area;
            const Vec2 m = (a + b + c) / 3.0;
            out = p[0] + m.x * u + m.y * v;
        }
    }
    return out;
}

/// The connected objects of a set of faces over welded vertices, and which are closed (see the
/// file comment).
struct Objects {
    std::vector<std::uint32_t> of_face;  ///< the object of each face
    std::vector<char> closed;            ///< per object: a closed, consistently oriented surface
};

/// Objects of faces (corner lists over vertex ids below vertex_count; empty lists ignored):
/// faces sharing a vertex are one object. Cost: O(corners log corners).
inline Objects find_objects(const std::vector<std::vector<std::uint32_t>>& faces,
                            std::size_t vertex_count) {
    DisjointSets sets(vertex_count);
    for (const auto& f : faces)
        for (std::size_t k = 1; k < f.size(); ++k) sets.unite(f[0], f[k]);
    Objects o;
    std::vector<std::uint32_t> number(vertex_count, UINT32_MAX);
    o.of_face.assign(faces.size(), UINT32_MAX);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        if (faces[f].empty()) continue;
        auto& n = number[sets.find(faces[f][0])];
        if (n == UINT32_MAX) n = static_cast<std::uint32_t>(o.closed.size()), o.closed.push_back(1);
        o.of_face[f] = n;
    }
    // Closed: each undirected edge used exactly twice, once in each direction.
    std::vector<std::tuple<std::uint32_t, std::uint32_t, int, std::uint32_t>> edges;
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (std::size_t k = 0; k < faces[f].size(); ++k) {
            const std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % faces[f].size()];
            edges.emplace_back(std::min(a, b), std::max(a, b), a < b ? 1 : -1, o.of_face[f]);
        }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
               std::get<1>(edges[j]) == std::get<1>(edges[i]))
            ++j;
        if (j - i != 2 || std::get<2>(edges[i]) == std::get<2>(edges[i + 1]))
            for (std::size_t k = i; k < j; ++k) o.closed[std::get<3>(edges[k])] = 0;
        i = j;
    }
    return o;
}

/// A closed object's surface, ready for point-in-solid queries (see the file comment).
class SolidTest {
  public:
    /// Over the object's triangles (counter-clockwise seen from the front); a positive signed
    /// volume makes it a solid. Cost: O(n log n) to build.
    explicit SolidTest(const std::vector<std::array<Vec3, 3>>& triangles) {
        if (triangles.empty()) return;
        const Vec3 o = triangles[0][0];  // about a corner: rounding relative to the object's size
        for (const auto& t : triangles) {
            const std::array<Vec3, 3> p{t[0], t[1], t[2]};
            if (!(polygon_area(p) > 0.0)) continue;
            volume_ += glm::dot(t[0] - o, glm::cross(t[1] - o, t[2] - o)) / 6.0;
            table_.add(p);
            lo_ = glm::min(lo_, glm::min(t[0], glm::min(t[1], t[2])));
            hi_ = glm::max(hi_, glm::max(t[0], glm::max(t[1], t[2])));
        }
        if (table_.size() > 0) bvh_ = Bvh(table_);
    }

    /// Whether its faces point away from what they enclose (a solid, not a room).
    bool solid() const { return volume_ > 0.0; }

    /// Whether p lies inside the solid: of three rays from p, at least two first meet the back
    /// of a face (a ray that meets nothing votes outside). Cost: three closest-hit queries.
    bool contains(const Vec3& p) const {
        if (!solid() || glm::any(glm::lessThan(p, lo_)) || glm::any(glm::greaterThan(p, hi_)))
            return false;
        const auto& d = probe_directions();
        int back = 0;
        for (std::size_t k : {std::size_t{5}, std::size_t{61}, std::size_t{110}}) {
            const std::optional<Hit> h = bvh_.intersect(p, d[k]);
            if (h && glm::dot(d[k], table_.normal(h->patch)) > 0.0) ++back;
        }
        return back >= 2;
    }

  private:
    PatchTable table_;
    Bvh bvh_;
    double volume_ = 0.0;
    Vec3 lo_{std::numeric_limits<double>::max()}, hi_{-std::numeric_limits<double>::max()};
};

}  // namespace radiosity::detail
