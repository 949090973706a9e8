#pragma once
/// @file subdivide.hpp  Meshing: the scene's faces cut into patches that cover each face
/// exactly, to a maximum edge length or patch area (Cohen & Wallace 1993, ch. 8: meshing), and
/// conforming: neighbouring patches share their vertices, so there are no T-junctions (smooth
/// shading then has no cracks). Triangles and convex quads are cut as before: every geometric
/// edge into the same number of segments for all faces that use it, quads into k1 x k2 grids
/// of quads, triangles into k^2 triangles, so children keep their parent's shape. Any other
/// face (more than four corners, or a concave quad) is cut by polygon_patches.hpp: its
/// constrained Delaunay triangulation, merged into convex pieces, clipped by a grid of cells of
/// the target size; patches are then convex polygons, and the points of neighbours are inserted
/// along shared edges (conforming.hpp). Every run checks that the patches of each face cover it
/// exactly (conservation.hpp). The area rule is RRV's `divide` (Dudka 2007): rounds of 1 -> 4
/// splits at edge midpoints; RRV applies it to each face by itself, which `conforming = false`
/// reproduces, T-junctions and all.

#include <radiosity/error.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/mesh/conforming.hpp>
#include <radiosity/mesh/conservation.hpp>
#include <radiosity/mesh/intersect.hpp>
#include <radiosity/mesh/manifold.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/polygon_patches.hpp>
#include <radiosity/mesh/weld.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <span>
#include <string>
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
    /// Warn about a face whose corners lie farther than this share of its size from its
    /// best-fit plane (Newell's normal through the corners' mean); it is cut as its projection.
    double planarity_tolerance = 1e-5;
    /// Cut faces where other faces cross them, and leave out the pieces inside closed solids,
    /// before making patches (intersect.hpp), so that no patch straddles another surface.
    bool cut_intersections = true;
};

namespace detail {
/// A number in 4 significant digits, for messages.
inline std::string short_number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", x);
    return buf;
}
}  // namespace detail

/// What the meshing did besides making patches: the faces it left out on purpose and what it
/// warns about. The library prints nothing; programs print this (lines()).
struct MeshingReport {
    std::size_t input_faces = 0;  ///< faces of the input mesh
    std::size_t patches = 0;      ///< patches made
    std::size_t polygons = 0;     ///< faces cut as polygons (more than 4 corners, or concave)
    /// Faces left out because they have no area once coincident corners are merged (within
    /// 1e-9 of the scene's size), by input face index.
    std::vector<std::size_t> dropped_faces;
    std::size_t non_planar_faces = 0;       ///< faces beyond the planarity tolerance
    double worst_non_planarity = 0.0;       ///< the largest distance from a plane, per unit of size
    std::size_t worst_non_planar_face = 0;  ///< the face with it
    std::size_t conforming_points = 0;      ///< neighbours' points inserted into patch edges
    IntersectionReport intersections;       ///< faces cut where others cross them (intersect.hpp)

    /// One line per thing worth telling a user (none when all went as usual).
    std::vector<std::string> lines() const {
        std::vector<std::string> out;
        if (!dropped_faces.empty()) {
            std::string l = "meshing: left out " + std::to_string(dropped_faces.size()) +
                            " face(s) of zero area (corners merged):";
            for (std::size_t k = 0; k < dropped_faces.size() && k < 10; ++k)
                l += " " + std::to_string(dropped_faces[k]);
            if (dropped_faces.size() > 10) l += " ...";
            out.push_back(l);
        }
        if (non_planar_faces > 0)
            out.push_back("meshing: " + std::to_string(non_planar_faces) +
                          " face(s) not planar (face " + std::to_string(worst_non_planar_face) +
                          " the most: a corner " + std::to_string(worst_non_planarity) +
                          " of its size off its best-fit plane); polygons among them are cut "
                          "as their projection onto that plane, quads as bilinear grids");
        const IntersectionReport& x = intersections;
        if (x.cut_faces > 0 || x.left_out > 0)
            out.push_back("meshing: cut " + std::to_string(x.cut_faces) +
                          " face(s) where other faces cross them; left out " +
                          std::to_string(x.left_out) + " piece(s) inside closed objects (area " +
                          detail::short_number(x.left_out_area) + ")");
        if (x.failed_faces > 0)
            out.push_back("meshing: " + std::to_string(x.failed_faces) +
                          " face(s) crossed by others were kept whole (not planar, or the cut "
                          "could not be triangulated)");
        return out;
    }
};

/// A subdivided mesh and its report.
template <SpectrumType S>
struct Subdivided {
    Mesh<S> mesh;          ///< the patches
    MeshingReport report;  ///< what was left out or is worth a warning
};

namespace detail {

/// The input as polygons over merged vertices: coincident points (within eps) become one.
struct Welded {
    std::vector<Vec3> point;                       // one per merged vertex
    std::vector<std::vector<std::uint32_t>> face;  // corners, none twice in a row
    std::vector<std::size_t> parent;               // input face of each face
    std::vector<std::vector<glm::vec2>> uv;        // lightmap UV per corner, if the mesh has them
    std::vector<char> polygon;  // cut by polygon_patches: > 4 corners, concave or a corner twice
    std::vector<std::size_t> dropped;  // input faces of zero area once welded
    double eps = 0.0;                  // the welding distance
};

/// Whether quad p turns left (about n) at every corner, up to rounding: then its bilinear grid
/// covers it exactly.
inline bool convex_quad(std::span<const Vec3> p, const Vec3& n) {
    for (std::size_t k = 0; k < 4; ++k) {
        const Vec3 a = p[k] - p[(k + 3) % 4], b = p[(k + 1) % 4] - p[k];
        if (glm::dot(glm::cross(a, b), n) <
            -1e-12 * glm::length(a) * glm::length(b) * glm::length(n))
            return false;
    }
    return true;
}

/// Merges coincident vertices (weld.hpp) and lists the faces over the merged ones, corners that
/// became one kept once; faces left with no area are dropped (and listed). O(n) expected.
template <class M>
Welded weld(const M& mesh) {
    const MeshWeld welded = weld_mesh(mesh);
    const std::size_t nv = welded.point.size();
    Welded w;
    w.eps = 1e-9 * welded.diagonal;
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
        std::vector<std::uint32_t> all;
        for (auto v : mesh.fv_range(f)) all.push_back(merged[static_cast<std::size_t>(v.idx())]);
        const std::vector<glm::vec2> all_uv = corner_uvs(mesh, f);
        std::vector<std::uint32_t> c;
        std::vector<glm::vec2> uv;
        for (std::size_t k = 0; k < all.size(); ++k)
            if (all[k] != all[(k + 1) % all.size()]) {
                c.push_back(all[k]);
                if (!all_uv.empty()) uv.push_back(all_uv[k]);
            }
        std::vector<Vec3> p;
        for (std::uint32_t v : c) p.push_back(w.point[v]);
        const auto parent = static_cast<std::size_t>(f.idx());
        if (c.size() < 3 || !(glm::length(local_newell(p)) > 0.0)) {
            w.dropped.push_back(parent);
            continue;
        }
        std::vector<std::uint32_t> sorted = c;
        std::sort(sorted.begin(), sorted.end());
        const bool repeats = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
        w.polygon.push_back(c.size() > 4 || repeats ||
                            (c.size() == 4 && !convex_quad(p, local_newell(p))));
        w.face.push_back(std::move(c));
        w.parent.push_back(parent);
        w.uv.push_back(std::move(uv));
    }
    return w;
}

/// Edge ids of the welded faces, and the grid each triangle or quad is cut into. Conforming, an
/// edge has as many segments as the most any edge of its class needs, where a class joins the
/// opposite sides of each quad and all sides of each triangle (so the grids fit). Polygons take
/// no part in the classes: they are cut by polygon_patches, and the conforming pass inserts
/// their neighbours' points.
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

/// Area of welded triangle or quad f.
inline double face_area(const Welded& w, std::size_t f) {
    std::array<Vec3, 4> p;
    for (std::size_t k = 0; k < w.face[f].size(); ++k) p[k] = w.point[w.face[f][k]];
    return polygon_area(std::span<const Vec3>(p.data(), w.face[f].size()));
}

/// The grids of faces split each by itself (RRV's way): a triangle k x k with k the most that
/// its edges' lengths or its area ask for, a quad k1 x k2 from its two pairs of opposite sides.
/// Neighbours that differ meet in T-junctions.
inline EdgeSplits split_faces_alone(EdgeSplits e, const std::vector<std::size_t>& need,
                                    const std::vector<std::size_t>& by_area,
                                    const std::vector<char>& polygon) {
    for (std::size_t f = 0; f < e.face_edges.size(); ++f) {
        const auto& ids = e.face_edges[f];
        if (polygon[f]) {
            e.grid.push_back({0, 0});  // cut by polygon_patches instead
        } else if (ids.size() == 4) {
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
            if (!w.polygon[f]) by_area[f] = area_segments(face_area(w, f), options.max_area);
    if (!options.conforming) return split_faces_alone(std::move(e), need, by_area, w.polygon);
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
    for (std::size_t f = 0; f < e.face_edges.size(); ++f)
        if (const auto& ids = e.face_edges[f]; ids.size() == 4 && !w.polygon[f]) {  // one grid
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
            if (ids.size() != 3 || w.polygon[f] || joined[f]) continue;
            const std::size_t a = most[classes.find(ids[0])], b = most[classes.find(ids[1])],
                              c = most[classes.find(ids[2])];
            if (a == 1 && b == 1 && c == 1) continue;
            classes.unite(ids[0], ids[1]);
            classes.unite(ids[1], ids[2]);
            joined[f] = changed = true;
        }
    }
    const std::vector<std::size_t> most = class_needs();  // segments of every edge of a class
    for (std::size_t f = 0; f < e.face_edges.size(); ++f) {
        const auto& ids = e.face_edges[f];
        if (w.polygon[f])
            e.grid.push_back({0, 0});
        else
            e.grid.push_back(
                {most[classes.find(ids[0])], most[classes.find(ids[ids.size() == 4 ? 1 : 0])]});
    }
    return e;
}

/// A face cut as a polygon: its plane's frame (point = origin + x u + y v) and its patches.
struct PolygonFace {
    Vec3 origin, u, v;
    PolygonPatches cut;
};

/// The frame of polygon p in its best-fit plane, u along its longest edge (so that the grid
/// follows the walls of a room), and its corners there.
inline PolygonFace polygon_frame(std::span<const Vec3> p, std::vector<Vec2>& flat) {
    const Vec3 n = glm::normalize(local_newell(p));
    PolygonFace pf;
    pf.origin = Vec3(0.0);
    for (const Vec3& x : p) pf.origin += x;
    pf.origin /= static_cast<double>(p.size());
    Vec3 longest(0.0);
    for (std::size_t k = 0; k < p.size(); ++k) {
        const Vec3 e = p[(k + 1) % p.size()] - p[k];
        if (glm::dot(e, e) > glm::dot(longest, longest)) longest = e;
    }
    const Vec3 along = longest - glm::dot(longest, n) * n;
    if (glm::length(along) > 0.0) {
        pf.u = glm::normalize(along);
        pf.v = glm::cross(n, pf.u);
    } else {
        orthonormal_basis(n, pf.u, pf.v);
    }
    flat.clear();
    for (const Vec3& x : p)
        flat.emplace_back(glm::dot(x - pf.origin, pf.u), glm::dot(x - pf.origin, pf.v));
    return pf;
}

/// The number of grid cells over polygon p's box at these settings (a bound on the work of
/// cutting it, known before it is cut).
inline double polygon_cells(std::span<const Vec2> p, const SubdivisionOptions& o) {
    Vec2 lo(p[0]), hi(p[0]);
    for (const Vec2& x : p) {
        lo = glm::min(lo, x);
        hi = glm::max(hi, x);
    }
    auto cells = [&](double w) {
        double k = 1.0;
        if (o.max_edge > 0.0) k = std::max(k, std::ceil(w / o.max_edge));
        if (o.max_area > 0.0) k = std::max(k, std::ceil(w / std::sqrt(o.max_area)));
        return k;
    };
    return cells(hi.x - lo.x) * cells(hi.y - lo.y);
}

/// Builds the patches as a soup over shared points: every vertex that lies on an input vertex
/// or edge is shared, each patch edge names its carrier (conforming.hpp); input edge e is
/// carrier e, the lines inside polygons follow.
template <SpectrumType S>
class SubdivisionBuilder {
  public:
    SubdivisionBuilder(const Welded& w, const EdgeSplits& e,
                       const std::vector<PolygonFace>& polygons,
                       const std::vector<std::size_t>& polygon_of)
        : w_(w),
          e_(e),
          polygons_(polygons),
          polygon_of_(polygon_of),
          corner_(w.point.size(), UINT32_MAX) {
        std::vector<double> length(e.id.size());
        for (const auto& [ends, id] : e.id)
            length[id] = glm::distance(w.point[ends.first], w.point[ends.second]);
        for (double l : length) soup_.add_carrier(l);
    }

    PatchSoup build() {
        for (std::size_t f = 0; f < w_.face.size(); ++f) {
            if (w_.polygon[f])
                polygon(f, polygons_[polygon_of_[f]]);
            else if (w_.face[f].size() == 4)
                quad(f);
            else
                triangle(f);
        }
        return std::move(soup_);
    }

  private:
    using VH = std::uint32_t;  // index into the soup's points
    static constexpr std::uint32_t none = EdgeOn::none;

    VH add(const Vec3& p) {
        soup_.points.push_back(p);
        on_edge_of_.push_back({none, 0.0});
        return static_cast<VH>(soup_.points.size() - 1);
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
            on_edge_of_[it->second] = {static_cast<std::uint32_t>(edge), s};
        }
        return it->second;
    }

    VH corner(std::uint32_t v) {
        if (corner_[v] == UINT32_MAX) corner_[v] = add(w_.point[v]);
        return corner_[v];
    }

    /// The parameter of point x along edge j of face f (from its lower-numbered end), if x lies
    /// on it: one of its corners or a point made on it.
    bool on_side(std::size_t f, std::size_t j, VH x, double& t) const {
        const auto& v = w_.face[f];
        const std::uint32_t a = v[j], b = v[(j + 1) % v.size()];
        if (x == corner_[a] || x == corner_[b]) {
            t = (x == corner_[a]) == (a < b) ? 0.0 : 1.0;
            return true;
        }
        if (on_edge_of_[x].first != e_.face_edges[f][j]) return false;
        t = on_edge_of_[x].second;
        return true;
    }

    /// The carriers of a child's edges: the input edge of f that both ends lie on, if any.
    std::vector<EdgeOn> sides(std::size_t f, const std::vector<VH>& c) const {
        std::vector<EdgeOn> on(c.size());
        for (std::size_t k = 0; k < c.size(); ++k)
            for (std::size_t j = 0; j < w_.face[f].size(); ++j) {
                double ta, tb;
                if (on_side(f, j, c[k], ta) && on_side(f, j, c[(k + 1) % c.size()], tb)) {
                    on[k] = {static_cast<std::uint32_t>(e_.face_edges[f][j]), ta, tb};
                    break;
                }
            }
        return on;
    }

    /// Adds a child of welded polygon f with corners c, whose lightmap UVs (if the input has
    /// them) are the parent's UVs interpolated at the corners' parameters st, exactly as the
    /// corners' positions are: bilinearly in a quad, linearly in a triangle.
    void face(std::size_t f, std::vector<VH> c, std::initializer_list<Vec2> st) {
        soup_.on.push_back(sides(f, c));
        soup_.faces.push_back(std::move(c));
        soup_.parent.push_back(w_.parent[f]);
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
        soup_.uvs.push_back(std::move(uv));
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

    /// A face cut as a polygon: its patches' points made once each (corners shared with the
    /// neighbours, points on its edges as points of those input edges), their edges on input
    /// edges or on the lines of its cutting, carriers of their own.
    void polygon(std::size_t f, const PolygonFace& pf) {
        const auto& c = w_.face[f];
        const PolygonPatches& cut = pf.cut;
        const auto n = static_cast<std::uint32_t>(c.size());
        std::vector<VH> vh(cut.points.size(), UINT32_MAX);
        auto point = [&](std::uint32_t i) {
            if (vh[i] != UINT32_MAX) return vh[i];
            const PatchPoint& q = cut.points[i];
            if (q.kind == PatchPoint::corner) return vh[i] = corner(c[q.index]);
            if (q.kind == PatchPoint::grid)
                return vh[i] = add(pf.origin + q.xy.x * pf.u + q.xy.y * pf.v);
            const auto [a, b] = ends(cut, q.carrier, n);
            const Vec3 &A = w_.point[c[a]], &B = w_.point[c[b]];
            vh[i] = add(A + q.t * (B - A));
            if (q.carrier.kind == Carrier::edge)
                on_edge_of_[vh[i]] = {static_cast<std::uint32_t>(e_.face_edges[f][a]),
                                      c[a] < c[b] ? q.t : 1.0 - q.t};
            return vh[i];
        };
        // The lines inside: diagonals, then the grid's x and y lines, each a carrier.
        const auto diagonals = static_cast<std::uint32_t>(soup_.carrier_length.size());
        for (const auto& d : cut.partition.diagonals)
            soup_.add_carrier(glm::distance(w_.point[c[d[0]]], w_.point[c[d[1]]]));
        const auto xs = static_cast<std::uint32_t>(soup_.carrier_length.size());
        for (std::size_t i = 0; i < cut.x_lines.size(); ++i) soup_.add_carrier(1.0);
        const auto ys = static_cast<std::uint32_t>(soup_.carrier_length.size());
        for (std::size_t j = 0; j < cut.y_lines.size(); ++j) soup_.add_carrier(1.0);
        auto param = [&](std::uint32_t i, const Carrier& on) {  // of point i along carrier on
            const PatchPoint& q = cut.points[i];
            if (on.kind == Carrier::grid_x) return q.xy.y;
            if (on.kind == Carrier::grid_y) return q.xy.x;
            const auto [a, b] = ends(cut, on, n);
            const double t = q.kind == PatchPoint::corner ? (q.index == a ? 0.0 : 1.0) : q.t;
            return on.kind == Carrier::edge && c[a] > c[b] ? 1.0 - t : t;
        };
        auto carrier = [&](const Carrier& on) -> std::uint32_t {
            switch (on.kind) {
                case Carrier::edge:
                    return static_cast<std::uint32_t>(e_.face_edges[f][on.index]);
                case Carrier::diagonal:
                    return diagonals + on.index;
                case Carrier::grid_x:
                    return xs + on.index;
                case Carrier::grid_y:
                    return ys + on.index;
            }
            return none;
        };
        for (std::size_t p = 0; p < cut.patches.size(); ++p) {
            const auto& corners = cut.patches[p];
            std::vector<VH> v;
            std::vector<EdgeOn> on;
            for (std::size_t k = 0; k < corners.size(); ++k) {
                const Carrier& e = cut.carriers[p][k];
                v.push_back(point(corners[k]));
                on.push_back({carrier(e), param(corners[k], e),
                              param(corners[(k + 1) % corners.size()], e)});
            }
            soup_.faces.push_back(std::move(v));
            soup_.on.push_back(std::move(on));
            soup_.parent.push_back(w_.parent[f]);
            std::vector<glm::vec2> uv;
            if (!w_.uv[f].empty())
                for (std::uint32_t i : corners) uv.push_back(polygon_uv(f, cut, cut.piece[p], i));
            soup_.uvs.push_back(std::move(uv));
        }
    }

    /// The corners (indices into the face) an edge or diagonal carrier runs between.
    static std::array<std::uint32_t, 2> ends(const PolygonPatches& cut, const Carrier& on,
                                             std::uint32_t n) {
        if (on.kind == Carrier::edge) return {on.index, (on.index + 1) % n};
        return cut.partition.diagonals[on.index];
    }

    /// The lightmap UV of point i of a polygon's patches: linear along the edges and diagonals,
    /// and inside, linear in the triangle (of the constrained Delaunay triangulation, within the
    /// patch's convex piece) that holds the point.
    glm::vec2 polygon_uv(std::size_t f, const PolygonPatches& cut, std::uint32_t piece,
                         std::uint32_t i) const {
        const auto& uv = w_.uv[f];
        const PatchPoint& q = cut.points[i];
        const auto n = static_cast<std::uint32_t>(uv.size());
        if (q.kind == PatchPoint::corner) return uv[q.index];
        if (q.kind == PatchPoint::crossing) {
            const auto [a, b] = ends(cut, q.carrier, n);
            return uv[a] + static_cast<float>(q.t) * (uv[b] - uv[a]);
        }
        const auto& T = cut.triangulation;
        std::uint32_t best = cut.partition.triangles[piece][0];
        double best_min = -std::numeric_limits<double>::max();
        std::array<double, 3> weight{1.0, 0.0, 0.0};
        for (std::uint32_t t : cut.partition.triangles[piece]) {
            const auto& v = T.triangles[t];
            const Vec2 &a = T.points[v[0]], &b = T.points[v[1]], &c2 = T.points[v[2]];
            const double d = cross2(b - a, c2 - a);
            const std::array<double, 3> l{cross2(b - q.xy, c2 - q.xy) / d,
                                          cross2(c2 - q.xy, a - q.xy) / d,
                                          cross2(a - q.xy, b - q.xy) / d};
            const double m = std::min({l[0], l[1], l[2]});
            if (m > best_min) {
                best_min = m;
                best = t;
                weight = l;
            }
            if (m >= 0.0) break;
        }
        const auto& v = T.triangles[best];
        glm::dvec2 x(0.0);
        for (int k = 0; k < 3; ++k) x += weight[k] * glm::dvec2(uv[v[k]]);
        return glm::vec2(x);
    }

    const Welded& w_;
    const EdgeSplits& e_;
    const std::vector<PolygonFace>& polygons_;
    const std::vector<std::size_t>& polygon_of_;
    PatchSoup soup_;
    std::vector<VH> corner_;
    std::vector<std::pair<std::uint32_t, double>> on_edge_of_;  // input edge and parameter
    std::map<std::tuple<std::size_t, std::size_t, std::size_t>, VH> on_edge_;
};

/// The soup as an OpenMesh mesh, without the points no patch uses (points made one by the
/// conforming pass); welding can join faces into shapes a half-edge mesh cannot hold, so those
/// are split first (make_manifold).
template <SpectrumType S>
Mesh<S> soup_mesh(const Mesh<S>& in, const PatchSoup& soup) {
    std::vector<std::uint32_t> number(soup.points.size(), UINT32_MAX);
    for (const auto& f : soup.faces)
        for (std::uint32_t v : f) number[v] = 0;
    std::vector<std::uint32_t> point;  // the soup's point of each vertex, in order
    for (std::uint32_t v = 0; v < number.size(); ++v)
        if (number[v] == 0) {
            number[v] = static_cast<std::uint32_t>(point.size());
            point.push_back(v);
        }
    std::vector<std::vector<std::uint32_t>> faces = soup.faces;
    for (auto& f : faces)
        for (std::uint32_t& v : f) v = number[v];
    const ManifoldFaces m = make_manifold(faces, point.size());
    Mesh<S> out;
    add_manifold_faces(
        out, m, [&](std::uint32_t o) -> const Vec3& { return soup.points[point[o]]; },
        [&](std::size_t f, auto h, const auto& c) {
            out.data(h) = in.data(typename Mesh<S>::FaceHandle(static_cast<int>(soup.parent[f])));
            if (!soup.uvs[f].empty()) set_face_uvs(out, h, c, soup.uvs[f]);
        },
        [&](std::size_t f) {
            return "subdivide: could not add a child of face " + std::to_string(soup.parent[f]);
        });
    return out;
}

}  // namespace detail

namespace detail {
/// The welded input, its edge splits, the polygons' cuts and the number of patches.
struct SubdivisionPlan {
    Welded welded;
    EdgeSplits splits;
    std::vector<PolygonFace> polygons;
    std::vector<std::size_t> polygon_of;  // welded face -> its entry in polygons
    std::vector<double> non_planarity;    // per welded face
    double faces = 0.0;
    bool too_many = false;  // the polygons were not cut: their cells alone exceed max_faces
};

template <SpectrumType S>
SubdivisionPlan plan_subdivision(const Mesh<S>& mesh, const SubdivisionOptions& options) {
    SubdivisionPlan plan{weld(mesh), {}, {}, {}, {}, 0.0, false};
    const Welded& w = plan.welded;
    plan.splits = split_edges(w, options);
    plan.polygon_of.assign(w.face.size(), 0);
    std::vector<Vec3> p;
    std::vector<Vec2> flat;
    const PolygonPatchOptions cut{options.max_edge, options.max_area, 0.5, 0.1, w.eps};
    for (std::size_t f = 0; f < w.face.size(); ++f) {
        p.clear();
        for (std::uint32_t v : w.face[f]) p.push_back(w.point[v]);
        plan.non_planarity.push_back(non_planarity(p));
        if (!w.polygon[f]) {
            const auto [k1, k2] = plan.splits.grid[f];
            plan.faces += double(k1) * double(k2);
            continue;
        }
        PolygonFace pf = polygon_frame(p, flat);
        const double cells = polygon_cells(flat, options);
        if (plan.too_many || cells > 4.0 * double(options.max_faces)) {
            plan.too_many = true;  // the cells bound the patches, near enough to refuse
            plan.faces += cells;
            continue;
        }
        pf.cut = polygon_patches(flat, cut, "face " + std::to_string(w.parent[f]));
        plan.faces += double(pf.cut.patches.size());
        plan.polygon_of[f] = plan.polygons.size();
        plan.polygons.push_back(std::move(pf));
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
    check_limit(options.planarity_tolerance, "planarity tolerance");
    return options.max_edge > 0.0 || options.max_area > 0.0;
}

/// Whether every face of the mesh is a triangle or a convex quad (which need no cutting).
template <SpectrumType S>
bool only_triangles_and_convex_quads(const Mesh<S>& mesh) {
    for (auto f : mesh.faces()) {
        const std::vector<Vec3> p = face_polygon(mesh, f);
        if (p.size() > 4 || (p.size() == 4 && !convex_quad(p, local_newell(p)))) return false;
    }
    return true;
}
}  // namespace detail

/// How many patches subdivide(mesh, options) would make, without making them (for choosing
/// limits that fit a patch budget); where polygons' grid cells alone exceed 4 max_faces, that
/// count of cells instead. Intersecting faces are cut first, as subdivide does. Cost:
/// O(n log n) in the input plus cutting its polygons.
template <SpectrumType S>
std::size_t subdivided_face_count(const Mesh<S>& mesh, const SubdivisionOptions& options) {
    const bool limits = detail::subdivides(options);
    std::optional<CutMesh<S>> cut;
    if (options.cut_intersections) {
        cut = cut_intersections(mesh, options.planarity_tolerance);
        if (!cut->changed()) cut.reset();
    }
    if (!cut && !limits && detail::only_triangles_and_convex_quads(mesh)) return mesh.n_faces();
    return static_cast<std::size_t>(
        detail::plan_subdivision(cut ? cut->mesh : mesh, options).faces);
}

namespace detail {
/// The meshing's check (conservation.hpp) of a soup cut from mesh faces that are the input
/// faces themselves: against each welded face, its corners' distance from a plane deciding
/// whether the patches' own areas must add up too; fills the report's non-planar counts.
inline void check_input_cover(const PatchSoup& soup, const SubdivisionPlan& plan,
                              std::size_t input_faces, const SubdivisionOptions& options,
                              MeshingReport& report) {
    const Welded& w = plan.welded;
    std::vector<std::vector<Vec3>> face(input_faces);
    std::vector<char> flat(input_faces, 0);
    for (std::size_t f = 0; f < w.face.size(); ++f) {
        for (std::uint32_t v : w.face[f]) face[w.parent[f]].push_back(w.point[v]);
        flat[w.parent[f]] = plan.non_planarity[f] <= options.planarity_tolerance;
        if (!flat[w.parent[f]]) {
            ++report.non_planar_faces;
            if (plan.non_planarity[f] > report.worst_non_planarity) {
                report.worst_non_planarity = plan.non_planarity[f];
                report.worst_non_planar_face = w.parent[f];
            }
        }
    }
    check_conservation(soup, face, flat);
}

/// The meshing's check of a soup cut from the pieces of a cut mesh: against the input faces,
/// each covered by its pieces' patches and its left-out pieces together.
template <SpectrumType S>
void check_cut_cover(const PatchSoup& soup, const CutMesh<S>& cut,
                     const SubdivisionOptions& options, MeshingReport& report) {
    PatchSoup all;  // only what the check reads: points, faces, parents
    all.points = soup.points;
    all.faces = soup.faces;
    for (std::size_t p : soup.parent) all.parent.push_back(cut.input_face[p]);
    for (std::size_t k = 0; k < cut.left_out.size(); ++k) {
        all.faces.emplace_back();
        for (const Vec3& x : cut.left_out[k]) {
            all.faces.back().push_back(static_cast<std::uint32_t>(all.points.size()));
            all.points.push_back(x);
        }
        all.parent.push_back(cut.left_out_face[k]);
    }
    std::vector<char> flat(cut.input_polygon.size(), 0);
    for (std::size_t f = 0; f < flat.size(); ++f) {
        const double off = non_planarity(cut.input_polygon[f]);
        flat[f] = off <= options.planarity_tolerance;
        if (!flat[f]) {
            ++report.non_planar_faces;
            if (off > report.worst_non_planarity) {
                report.worst_non_planarity = off;
                report.worst_non_planar_face = f;
            }
        }
    }
    check_conservation(all, cut.input_polygon, flat);
}
}  // namespace detail

/// Meshing (see the file comment) with its report: returns a new mesh of patches that cover the
/// input faces exactly, triangles and convex quads cut into grids whose edges are at most
/// max_edge long and whose patches have at most max_area (by RRV's rule, area_segments), other
/// faces into convex patches within grid cells of those sizes (a piece under half a cell merged
/// into a neighbour, so within two cells); conforming unless options.conforming is false (each
/// face by itself: T-junctions where neighbours differ), where coincident input vertices
/// (within 1e-9 of the scene's size) are merged first so that faces meeting along a geometric
/// edge share the new vertices too. Unless options.cut_intersections is false, faces are first
/// cut where other faces cross them, and the pieces inside closed solids left out
/// (intersect.hpp). Children keep their parent's data (E, R, material, surface), orientation
/// and, interpolated, lightmap UVs. With both limits 0 triangles and convex quads stay as they
/// are, other faces become their convex pieces. Checks that the patches (with the pieces left
/// out) cover every face (conservation.hpp). Throws Error for a negative or non-finite option,
/// a face that intersects itself (naming it), when more than max_faces would result, or if the
/// check fails. Cost: O(output size + n log n).
template <SpectrumType S>
Subdivided<S> subdivide_with_report(const Mesh<S>& mesh, const SubdivisionOptions& options = {}) {
    Subdivided<S> out;
    out.report.input_faces = mesh.n_faces();
    const bool limits = detail::subdivides(options);
    std::optional<CutMesh<S>> cut;
    if (options.cut_intersections) {
        cut = cut_intersections(mesh, options.planarity_tolerance);
        out.report.intersections = cut->report;
        if (!cut->changed()) cut.reset();
    }
    const Mesh<S>& in = cut ? cut->mesh : mesh;
    if (!cut && !limits && detail::only_triangles_and_convex_quads(mesh)) {
        out.mesh = mesh;
        out.report.patches = mesh.n_faces();
        return out;
    }
    const detail::SubdivisionPlan plan = detail::plan_subdivision(in, options);
    if (plan.too_many || plan.faces > double(options.max_faces))
        throw Error("subdivision: max edge " + std::to_string(options.max_edge) + " and max area " +
                    std::to_string(options.max_area) + " would make " +
                    std::to_string(static_cast<long long>(plan.faces)) + " patches (more than " +
                    std::to_string(options.max_faces) + ")");
    const detail::Welded& w = plan.welded;
    detail::PatchSoup soup =
        detail::SubdivisionBuilder<S>(w, plan.splits, plan.polygons, plan.polygon_of).build();
    // Conforming: along every carrier; else only along the lines inside polygons.
    const auto first = static_cast<std::uint32_t>(options.conforming ? 0 : plan.splits.id.size());
    out.report.conforming_points = detail::make_conforming(soup, w.eps, first);
    for (std::size_t f = 0; f < w.face.size(); ++f) out.report.polygons += w.polygon[f] ? 1 : 0;
    if (cut) {
        detail::check_cut_cover(soup, *cut, options, out.report);
        out.report.dropped_faces = cut->dropped;
        for (std::size_t f : w.dropped) out.report.dropped_faces.push_back(cut->input_face[f]);
        std::sort(out.report.dropped_faces.begin(), out.report.dropped_faces.end());
    } else {
        detail::check_input_cover(soup, plan, mesh.n_faces(), options, out.report);
        out.report.dropped_faces = w.dropped;
    }
    out.report.patches = soup.faces.size();
    out.mesh = detail::soup_mesh(in, soup);
    return out;
}

/// Subdivision without its report (see subdivide_with_report).
template <SpectrumType S>
Mesh<S> subdivide(const Mesh<S>& mesh, const SubdivisionOptions& options = {}) {
    return subdivide_with_report(mesh, options).mesh;
}

}  // namespace radiosity
