#pragma once
/// @file subdivide.hpp  Conforming subdivision of the patch mesh to a maximum edge length or
/// patch area (Cohen & Wallace 1993, ch. 8: meshing). Every geometric edge is cut into the same
/// number of segments for all faces that use it, so neighbouring patches share their vertices and
/// there are no T-junctions (smooth shading then has no cracks). Quads become k1 x k2 grids of
/// quads, triangles k^2 triangles, so children keep their parent's shape and no slivers appear.
/// The area rule is RRV's `divide` (Dudka 2007): rounds of 1 -> 4 splits at edge midpoints; RRV
/// applies it to each face by itself, which `conforming = false` reproduces, T-junctions and all.

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/mesh/manifold.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/weld.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <map>
#include <numeric>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

namespace radiosity {

/// Settings of the subdivision.
struct SubdivisionOptions {
    double max_edge = 0.0;  ///< longest edge allowed; 0: no limit
    double max_area = 0.0;  ///< largest patch area allowed (RRV's `divide`); 0: no limit
    std::size_t max_faces = 4'000'000;  ///< refuse to make more patches than this
    bool conforming = true;  ///< split neighbours alike along shared edges (no T-junctions);
                             ///< false: each face by itself, as RRV does (T-junctions)
};

namespace detail {

/// The input as polygons over merged vertices: coincident points (within eps) become one.
struct Welded {
    std::vector<Vec3> point;                       // one per merged vertex
    std::vector<std::vector<std::uint32_t>> face;  // convex polygons, 3 or 4 corners
    std::vector<std::size_t> parent;               // input face of each polygon
    std::vector<std::vector<glm::vec2>> uv;        // lightmap UV per corner, if the mesh has them
};

/// Merges coincident vertices (weld.hpp) and lists the faces over the merged ones. O(n)
/// expected.
template <class M>
Welded weld(const M& mesh) {
    const MeshWeld welded = weld_mesh(mesh);
    const std::size_t nv = welded.point.size();
    Welded w;
    std::vector<std::uint32_t> id(nv, UINT32_MAX);
    std::vector<std::uint32_t> merged(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const std::size_t r = welded.group[v];
        if (id[r] == UINT32_MAX) {
            id[r] = static_cast<std::uint32_t>(w.point.size());
            w.point.push_back(welded.point[r]);
        }
        merged[v] = id[r];
    }
    for (auto f : mesh.faces()) {
        std::vector<std::uint32_t> c;
        for (auto v : mesh.fv_range(f)) c.push_back(merged[static_cast<std::size_t>(v.idx())]);
        const std::vector<glm::vec2> uv = corner_uvs(mesh, f);
        if (c.size() <= 4) {
            w.face.push_back(c);
            w.parent.push_back(static_cast<std::size_t>(f.idx()));
            w.uv.push_back(uv);
        } else {  // larger polygons: a fan of triangles (they are convex)
            for (std::size_t k = 1; k + 1 < c.size(); ++k) {
                w.face.push_back({c[0], c[k], c[k + 1]});
                w.parent.push_back(static_cast<std::size_t>(f.idx()));
                w.uv.push_back(uv.empty() ? uv : std::vector<glm::vec2>{uv[0], uv[k], uv[k + 1]});
            }
        }
    }
    return w;
}

/// Edge ids of the welded polygons, and the grid each polygon is cut into. Conforming, an edge
/// has as many segments as the most any edge of its class needs, where a class joins the
/// opposite sides of each quad and all sides of each triangle (so the grids fit).
struct EdgeSplits {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> id;  // (lo, hi) -> edge
    std::vector<std::vector<std::size_t>> face_edges;  // edge k of face f joins corners k, k+1
    std::vector<std::array<std::size_t, 2>> grid;      // per face: k1 x k2 (a triangle: k x k)
};

/// Segments per side that RRV's area rule gives a face of this area: m rounds of 1 -> 4 splits at
/// edge midpoints, the fewest that bring each child's area to at most max_area, are 2^m segments.
inline std::size_t area_segments(double area, double max_area) {
    std::size_t k = 1;
    while (area > max_area && k < (std::size_t{1} << 20)) {
        area /= 4.0;
        k *= 2;
    }
    return k;
}

/// Area of welded polygon f (3 or 4 corners).
inline double face_area(const Welded& w, std::size_t f) {
    std::array<Vec3, 4> p;
    for (std::size_t k = 0; k < w.face[f].size(); ++k) p[k] = w.point[w.face[f][k]];
    return polygon_area(std::span<const Vec3>(p.data(), w.face[f].size()));
}

/// The grids of faces split each by itself (RRV's way): a triangle k x k with k the most that
/// its edges' lengths or its area ask for, a quad k1 x k2 from its two pairs of opposite sides.
/// Neighbours that differ meet in T-junctions.
inline EdgeSplits split_faces_alone(EdgeSplits e, const std::vector<std::size_t>& need,
                                    const std::vector<std::size_t>& by_area) {
    for (std::size_t f = 0; f < e.face_edges.size(); ++f) {
        const auto& ids = e.face_edges[f];
        if (ids.size() == 4) {
            e.grid.push_back({std::max({need[ids[0]], need[ids[2]], by_area[f]}),
                              std::max({need[ids[1]], need[ids[3]], by_area[f]})});
        } else {
            const std::size_t k = std::max({need[ids[0]], need[ids[1]], need[ids[2]], by_area[f]});
            e.grid.push_back({k, k});
        }
    }
    return e;
}

inline EdgeSplits split_edges(const Welded& w, const SubdivisionOptions& options) {
    EdgeSplits e;
    std::vector<double> length;
    for (const auto& f : w.face) {
        std::vector<std::size_t> ids;
        for (std::size_t k = 0; k < f.size(); ++k) {
            const std::uint32_t a = f[k], b = f[(k + 1) % f.size()];
            const auto key = std::minmax(a, b);
            auto [it, fresh] = e.id.try_emplace({key.first, key.second}, length.size());
            if (fresh) length.push_back(glm::distance(w.point[a], w.point[b]));
            ids.push_back(it->second);
        }
        e.face_edges.push_back(ids);
    }
    std::vector<std::size_t> need(length.size(), 1);
    if (options.max_edge > 0.0)
        for (std::size_t k = 0; k < length.size(); ++k)
            need[k] = static_cast<std::size_t>(
                std::max(1.0, std::ceil(length[k] / options.max_edge - 1e-9)));
    std::vector<std::size_t> by_area(w.face.size(), 1);
    if (options.max_area > 0.0)
        for (std::size_t f = 0; f < w.face.size(); ++f)
            by_area[f] = area_segments(face_area(w, f), options.max_area);
    if (!options.conforming) return split_faces_alone(std::move(e), need, by_area);
    for (std::size_t f = 0; f < w.face.size(); ++f)
        for (std::size_t id : e.face_edges[f]) need[id] = std::max(need[id], by_area[f]);
    DisjointSets classes(length.size());
    // The most any edge of a class needs, at the class's representative.
    auto class_needs = [&] {
        std::vector<std::size_t> most(length.size(), 1);
        for (std::size_t k = 0; k < length.size(); ++k)
            most[classes.find(k)] = std::max(most[classes.find(k)], need[k]);
        return most;
    };
    for (const auto& ids : e.face_edges)
        if (ids.size() == 4) {  // opposite sides of a quad: one grid
            classes.unite(ids[0], ids[2]);
            classes.unite(ids[1], ids[3]);
        }
    // A triangle is cut k x k, so its three edges must agree; but only triangles that are cut
    // at all join their edges (else one long edge would refine a whole connected mesh, such as
    // a teapot of small triangles). Joining can make a neighbour's edge longer in segments, so
    // repeat until no triangle has edges that disagree.
    std::vector<bool> joined(e.face_edges.size(), false);
    for (bool changed = true; changed;) {
        changed = false;
        const std::vector<std::size_t> most = class_needs();
        for (std::size_t f = 0; f < e.face_edges.size(); ++f) {
            const auto& ids = e.face_edges[f];
            if (ids.size() != 3 || joined[f]) continue;
            const std::size_t a = most[classes.find(ids[0])], b = most[classes.find(ids[1])],
                              c = most[classes.find(ids[2])];
            if (a == 1 && b == 1 && c == 1) continue;
            classes.unite(ids[0], ids[1]);
            classes.unite(ids[1], ids[2]);
            joined[f] = changed = true;
        }
    }
    const std::vector<std::size_t> most = class_needs();  // segments of every edge of a class
    for (const auto& ids : e.face_edges)
        e.grid.push_back(
            {most[classes.find(ids[0])], most[classes.find(ids[ids.size() == 4 ? 1 : 0])]});
    return e;
}

/// Builds the output mesh, sharing every vertex that lies on an input vertex or edge.
template <SpectrumType S>
class SubdivisionBuilder {
  public:
    SubdivisionBuilder(const Mesh<S>& in, const Welded& w, const EdgeSplits& e)
        : in_(in), w_(w), e_(e), corner_(w.point.size(), UINT32_MAX) {}

    Mesh<S> build() {
        for (std::size_t f = 0; f < w_.face.size(); ++f) {
            if (w_.face[f].size() == 4)
                quad(f);
            else
                triangle(f);
        }
        // Welding can join faces into shapes a half-edge mesh cannot hold: split those first.
        const ManifoldFaces m = make_manifold(faces_, points_.size());
        Mesh<S> out;
        std::vector<typename Mesh<S>::VertexHandle> vh;
        vh.reserve(m.origin.size());
        for (std::uint32_t o : m.origin)
            vh.push_back(out.add_vertex({points_[o].x, points_[o].y, points_[o].z}));
        std::vector<typename Mesh<S>::VertexHandle> c;
        for (std::size_t f = 0; f < m.faces.size(); ++f) {
            c.clear();
            for (std::uint32_t v : m.faces[f]) c.push_back(vh[v]);
            auto h = out.add_face(c);
            if (!h.is_valid()) {  // a safety net: cannot happen after make_manifold
                for (auto& v : c) v = out.add_vertex(out.point(v));
                h = out.add_face(c);
                if (!h.is_valid())
                    throw Error("subdivide: could not add a child of face " +
                                std::to_string(parent_[f]));
            }
            out.data(h) = in_.data(typename Mesh<S>::FaceHandle(static_cast<int>(parent_[f])));
            if (!uvs_[f].empty()) set_face_uvs(out, h, c, uvs_[f]);
        }
        return out;
    }

  private:
    using VH = std::uint32_t;  // index into points_

    VH add(const Vec3& p) {
        points_.push_back(p);
        return static_cast<VH>(points_.size() - 1);
    }

    /// The vertex at step t (0..k) along the edge from corner a to corner b, the same handle
    /// whichever face asks and in whichever direction it walks the edge.
    VH edge_point(std::uint32_t a, std::uint32_t b, std::size_t t, std::size_t k) {
        if (t == 0) return corner(a);
        if (t == k) return corner(b);
        if (a > b) {
            std::swap(a, b);
            t = k - t;
        }
        // Keyed by the point's fraction t / k in lowest terms: faces that cut the edge into
        // different numbers of segments (without conforming) still share the points in common.
        const std::size_t edge = e_.id.at({a, b}), g = std::gcd(t, k);
        auto [it, fresh] = on_edge_.try_emplace({edge, t / g, k / g});
        if (fresh) {
            const double s = static_cast<double>(t) / static_cast<double>(k);
            it->second = add(w_.point[a] + s * (w_.point[b] - w_.point[a]));
        }
        return it->second;
    }

    VH corner(std::uint32_t v) {
        if (corner_[v] == UINT32_MAX) corner_[v] = add(w_.point[v]);
        return corner_[v];
    }

    /// Adds a child of welded polygon f with corners c, whose lightmap UVs (if the input has
    /// them) are the parent's UVs interpolated at the corners' parameters st, exactly as the
    /// corners' positions are: bilinearly in a quad, linearly in a triangle.
    void face(std::size_t f, std::vector<VH> c, std::initializer_list<Vec2> st) {
        faces_.push_back(std::move(c));
        parent_.push_back(w_.parent[f]);
        std::vector<glm::vec2> uv;
        if (const auto& p = w_.uv[f]; !p.empty())
            for (const Vec2& q : st) {
                const double s = q.x, t = q.y;
                const glm::dvec2 x =
                    p.size() == 4
                        ? (1 - s) * (1 - t) * glm::dvec2(p[0]) + s * (1 - t) * glm::dvec2(p[1]) +
                              s * t * glm::dvec2(p[2]) + (1 - s) * t * glm::dvec2(p[3])
                        : glm::dvec2(p[0]) + s * glm::dvec2(p[1] - p[0]) +
                              t * glm::dvec2(p[2] - p[0]);
                uv.emplace_back(x);
            }
        uvs_.push_back(std::move(uv));
    }

    /// A quad v0 v1 v2 v3 as a k1 x k2 grid: point (a, b) is bilinear in the corners; points on
    /// the sides come from edge_point, so neighbours share them.
    void quad(std::size_t f) {
        const auto& v = w_.face[f];
        // Named, not bound: clang 14 cannot capture structured bindings in the lambdas below.
        const std::size_t k1 = e_.grid[f][0], k2 = e_.grid[f][1];
        std::vector<VH> grid((k1 + 1) * (k2 + 1));
        auto at = [&](std::size_t a, std::size_t b) -> VH& { return grid[b * (k1 + 1) + a]; };
        for (std::size_t b = 0; b <= k2; ++b)
            for (std::size_t a = 0; a <= k1; ++a) {
                if (b == 0)
                    at(a, b) = edge_point(v[0], v[1], a, k1);
                else if (a == k1)
                    at(a, b) = edge_point(v[1], v[2], b, k2);
                else if (b == k2)
                    at(a, b) = edge_point(v[3], v[2], a, k1);
                else if (a == 0)
                    at(a, b) = edge_point(v[0], v[3], b, k2);
                else {
                    const double s = double(a) / double(k1), t = double(b) / double(k2);
                    at(a, b) =
                        add((1 - s) * (1 - t) * w_.point[v[0]] + s * (1 - t) * w_.point[v[1]] +
                            s * t * w_.point[v[2]] + (1 - s) * t * w_.point[v[3]]);
                }
            }
        auto st = [&](std::size_t a, std::size_t b) {
            return Vec2(double(a) / k1, double(b) / k2);
        };
        for (std::size_t b = 0; b < k2; ++b)
            for (std::size_t a = 0; a < k1; ++a)
                face(f, {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)},
                     {st(a, b), st(a + 1, b), st(a + 1, b + 1), st(a, b + 1)});
    }

    /// A triangle v0 v1 v2 as k^2 triangles: point (a, b) = v0 + a/k (v1 - v0) + b/k (v2 - v0).
    void triangle(std::size_t f) {
        const auto& v = w_.face[f];
        const std::size_t k = e_.grid[f][0];
        std::vector<VH> row((k + 1) * (k + 2) / 2);
        auto at = [&](std::size_t a, std::size_t b) -> VH& {
            return row[b * (k + 1) - b * (b - 1) / 2 + a];  // rows of k+1, k, ..., 1 points
        };
        for (std::size_t b = 0; b <= k; ++b)
            for (std::size_t a = 0; a + b <= k; ++a) {
                if (b == 0)
                    at(a, b) = edge_point(v[0], v[1], a, k);
                else if (a == 0)
                    at(a, b) = edge_point(v[0], v[2], b, k);
                else if (a + b == k)
                    at(a, b) = edge_point(v[1], v[2], b, k);
                else
                    at(a, b) = add(w_.point[v[0]] +
                                   (double(a) / double(k)) * (w_.point[v[1]] - w_.point[v[0]]) +
                                   (double(b) / double(k)) * (w_.point[v[2]] - w_.point[v[0]]));
            }
        auto st = [&](std::size_t a, std::size_t b) { return Vec2(double(a) / k, double(b) / k); };
        for (std::size_t b = 0; b < k; ++b)
            for (std::size_t a = 0; a + b < k; ++a) {
                face(f, {at(a, b), at(a + 1, b), at(a, b + 1)},
                     {st(a, b), st(a + 1, b), st(a, b + 1)});
                if (a + b + 1 < k)
                    face(f, {at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)},
                         {st(a + 1, b), st(a + 1, b + 1), st(a, b + 1)});
            }
    }

    const Mesh<S>& in_;
    const Welded& w_;
    const EdgeSplits& e_;
    std::vector<Vec3> points_;                       // output vertices
    std::vector<std::vector<std::uint32_t>> faces_;  // output faces over points_
    std::vector<std::size_t> parent_;                // input face of each output face
    std::vector<std::vector<glm::vec2>> uvs_;        // lightmap UVs of each output face
    std::vector<VH> corner_;
    std::map<std::tuple<std::size_t, std::size_t, std::size_t>, VH> on_edge_;
};

}  // namespace detail

namespace detail {
/// The welded input, its edge splits and the number of faces subdivision would make.
struct SubdivisionPlan {
    Welded welded;
    EdgeSplits splits;
    double faces = 0.0;
};

template <SpectrumType S>
SubdivisionPlan plan_subdivision(const Mesh<S>& mesh, const SubdivisionOptions& options) {
    SubdivisionPlan plan{weld(mesh), {}, 0.0};
    plan.splits = split_edges(plan.welded, options);
    for (std::size_t f = 0; f < plan.welded.face.size(); ++f) {
        const auto [k1, k2] = plan.splits.grid[f];
        plan.faces += double(k1) * double(k2);
    }
    return plan;
}

inline void check_limit(double value, const char* what) {
    if (!std::isfinite(value) || value < 0.0)
        throw Error(std::string("subdivision: ") + what + " must be finite and >= 0, not " +
                    std::to_string(value));
}

/// Checks the options; true when they ask for any subdivision at all.
inline bool subdivides(const SubdivisionOptions& options) {
    check_limit(options.max_edge, "max edge");
    check_limit(options.max_area, "max area");
    return options.max_edge > 0.0 || options.max_area > 0.0;
}
}  // namespace detail

/// How many patches subdivide(mesh, options) would make, without making them (for choosing
/// limits that fit a patch budget). Cost: O(n log n) in the input.
template <SpectrumType S>
std::size_t subdivided_face_count(const Mesh<S>& mesh, const SubdivisionOptions& options) {
    if (!detail::subdivides(options)) return mesh.n_faces();
    return static_cast<std::size_t>(detail::plan_subdivision(mesh, options).faces);
}

/// Subdivision (see the file comment): returns a new mesh whose edges are at most max_edge long
/// and whose patches have at most max_area (by RRV's rule, area_segments), conforming unless
/// options.conforming is false (each face by itself: T-junctions where neighbours differ), where
/// coincident input vertices (within 1e-9 of the scene's size) are merged first so that faces
/// meeting along a geometric edge share the new vertices too. Children keep their parent's data
/// (E, R, material, surface), orientation and, interpolated, lightmap UVs. With both limits 0 it
/// returns a copy. Throws Error for a negative or non-finite limit, or when more than max_faces
/// would result. Cost: O(output size + n log n).
template <SpectrumType S>
Mesh<S> subdivide(const Mesh<S>& mesh, const SubdivisionOptions& options = {}) {
    if (!detail::subdivides(options)) return mesh;
    const detail::SubdivisionPlan plan = detail::plan_subdivision(mesh, options);
    if (plan.faces > double(options.max_faces))
        throw Error("subdivision: max edge " + std::to_string(options.max_edge) + " and max area " +
                    std::to_string(options.max_area) + " would make " +
                    std::to_string(static_cast<long long>(plan.faces)) + " patches (more than " +
                    std::to_string(options.max_faces) + ")");
    return detail::SubdivisionBuilder<S>(mesh, plan.welded, plan.splits).build();
}

}  // namespace radiosity
