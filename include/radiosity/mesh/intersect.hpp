#pragma once
/// @file intersect.hpp  Faces cut where other faces cross them, before patches are made, so
/// that no patch straddles another surface (a patch is lit, or not, as a whole from its
/// centroid); and the pieces hidden inside a closed solid left out of the solve. Game levels
/// and RRV scenes are full of props pushed into walls and floors, and of lamp barrels run
/// through their globes.
///
/// Candidate pairs come from a BVH over the faces' boxes, never all pairs. Two faces cross
/// when each has corners strictly on both sides of the other's plane; then, as in Moller's
/// (1997) triangle-triangle test, each face meets the line where the two planes meet in
/// intervals (one for a convex face, more for a concave one), found from its edges' sign
/// changes, and where the intervals of the two faces overlap is a segment on both. Corners
/// within a millionth of the scene's size of the other plane count as on it, so faces that
/// merely meet (a wall on a floor, a block standing on it, one face's edge on the other) or
/// lie in one plane are not cut. A crossing point on an edge is computed once from that edge
/// and the other plane, so that the faces on either side of the edge share it. Each cut face
/// is then triangulated with its segments as constraints (the constrained Delaunay
/// triangulation, Chew 1989, geometry/triangulate.hpp) and merged into convex pieces (Hertel &
/// Mehlhorn 1983), none of which crosses a segment.
///
/// A piece whose interior point lies inside a closed solid other than its own object
/// (mesh/solid.hpp), one that its object crosses, is where no light can reach: it is left out,
/// and counted with its area, so that the meshing's check still finds each input face covered
/// exactly, by its kept patches and its left-out pieces together.

#include <radiosity/error.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/convex_partition.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/triangulate.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/mesh/conservation.hpp>
#include <radiosity/mesh/corner_uv.hpp>
#include <radiosity/mesh/manifold.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/solid.hpp>
#include <radiosity/mesh/weld.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace radiosity {

/// What cutting intersecting faces did.
struct IntersectionReport {
    std::size_t crossing_pairs = 0;  ///< pairs of faces that cross each other
    std::size_t cut_faces = 0;       ///< input faces split along where others cross them
    std::size_t pieces = 0;          ///< pieces the cut faces became, kept and left out
    /// Pieces (or whole faces) left out: inside a closed solid that their object crosses.
    std::size_t left_out = 0;
    double left_out_area = 0.0;  ///< their total area
    /// Crossed faces kept whole: not planar (beyond the planarity tolerance: their pieces
    /// would not lie in one plane), or refused by the triangulation.
    std::size_t failed_faces = 0;
    /// Pieces dropped as slivers: under 1e-12 of their face's area, made where segments meet
    /// within rounding of each other.
    std::size_t slivers = 0;
};

/// A mesh with its intersecting faces cut (see the file comment), and what the meshing's check
/// needs to find every input face covered: the input faces over welded vertices and the pieces
/// left out.
template <SpectrumType S>
struct CutMesh {
    Mesh<S> mesh;                                  ///< kept pieces and the faces nothing cut
    std::vector<std::size_t> input_face;           ///< the input face of each face of mesh
    std::vector<std::vector<Vec3>> input_polygon;  ///< input faces, welded (empty: no area)
    std::vector<std::vector<Vec3>> left_out;       ///< the pieces left out
    std::vector<std::size_t> left_out_face;        ///< the input face of each
    std::vector<std::size_t> dropped;              ///< input faces of no area once welded
    IntersectionReport report;                     ///< counts
    /// Whether anything was cut or left out (if not, mesh is not filled: use the input).
    bool changed() const { return report.cut_faces > 0 || report.left_out > 0; }
};

namespace detail {

/// The input faces over welded vertices, each with its plane (Newell's normal through the
/// corners' mean) and a frame in it.
struct CutInput {
    std::vector<Vec3> point;                       // by vertex; only welded ids are used
    std::vector<std::vector<std::uint32_t>> face;  // welded corners, none twice in a row
    std::vector<std::vector<glm::vec2>> uv;        // per corner, or empty
    std::vector<Vec3> origin, normal, u, v;        // plane and frame of each face
    std::vector<std::array<Vec3, 2>> box;          // bounds of each face
    double eps = 0.0;                              // the welding distance: points closer are one
    double tol = 0.0;                              // corners closer than this to a plane lie on it
};

template <class M>
CutInput cut_input(const M& mesh) {
    const MeshWeld weld = weld_mesh(mesh);
    CutInput in;
    in.point = weld.point;
    in.eps = 1e-9 * weld.diagonal;
    in.tol = 1e-6 * weld.diagonal;
    for (auto f : mesh.faces()) {
        std::vector<std::uint32_t> all, c;
        for (auto v : mesh.fv_range(f))
            all.push_back(static_cast<std::uint32_t>(weld.group[std::size_t(v.idx())]));
        const std::vector<glm::vec2> all_uv = corner_uvs(mesh, f);
        std::vector<glm::vec2> uv;
        std::vector<Vec3> p;
        for (std::size_t k = 0; k < all.size(); ++k)
            if (all[k] != all[(k + 1) % all.size()]) {
                c.push_back(all[k]);
                p.push_back(in.point[all[k]]);
                if (!all_uv.empty()) uv.push_back(all_uv[k]);
            }
        Vec3 n = p.size() >= 3 ? local_newell(p) : Vec3(0.0);
        if (!(glm::length(n) > 0.0)) c.clear(), p.clear(), n = Vec3(0, 0, 1);
        Vec3 o(0.0), lo(std::numeric_limits<double>::max()), hi(-lo);
        for (const Vec3& x : p) o += x, lo = glm::min(lo, x), hi = glm::max(hi, x);
        in.origin.push_back(p.empty() ? o : o / double(p.size()));
        in.normal.push_back(glm::normalize(n));
        Vec3 u, v;
        orthonormal_basis(in.normal.back(), u, v);
        in.u.push_back(u);
        in.v.push_back(v);
        in.box.push_back({lo, hi});
        in.face.push_back(std::move(c));
        in.uv.push_back(std::move(uv));
    }
    return in;
}

/// Point x in face f's frame.
inline Vec2 face_xy(const CutInput& in, std::uint32_t f, const Vec3& x) {
    return {glm::dot(x - in.origin[f], in.u[f]), glm::dot(x - in.origin[f], in.v[f])};
}

/// Pairs (a, b), a < b, of faces whose boxes (grown by tol) overlap, from a BVH over the faces.
/// Cost: O(n log n + pairs).
inline std::vector<std::pair<std::uint32_t, std::uint32_t>> candidate_pairs(const CutInput& in) {
    PatchTable table;
    std::vector<std::uint32_t> face_of;
    for (std::size_t f = 0; f < in.face.size(); ++f) {
        if (in.face[f].empty()) continue;
        std::vector<Vec3> p;
        for (std::uint32_t v : in.face[f]) p.push_back(in.point[v]);
        if (!(polygon_area(p) > 0.0)) continue;
        table.add(p);
        face_of.push_back(static_cast<std::uint32_t>(f));
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if (table.size() < 2) return pairs;
    const Bvh bvh(table);
    const Vec3 grow(in.tol + bvh.box_slack());
    std::vector<std::uint32_t> found;
    for (std::uint32_t a : face_of) {
        const Vec3 lo = in.box[a][0] - grow, hi = in.box[a][1] + grow;
        auto overlaps = [&](const Vec3& l, const Vec3& h) {
            return glm::all(glm::lessThanEqual(l, hi)) && glm::all(glm::lessThanEqual(lo, h));
        };
        found.clear();
        bvh.any_triangle(overlaps, [&](const PatchTriangle& t) {
            const std::uint32_t b = face_of[t.patch];
            if (b > a && overlaps(in.box[b][0], in.box[b][1])) found.push_back(b);
            return false;
        });
        std::sort(found.begin(), found.end());
        found.erase(std::unique(found.begin(), found.end()), found.end());
        for (std::uint32_t b : found) pairs.emplace_back(a, b);
    }
    return pairs;
}

/// Where a face meets the line of two planes: an end of one of its intervals there.
struct LineEnd {
    double t = 0.0;           // position along the line
    std::uint32_t point = 0;  // the point
    int edge = -1;            // on the face's edge from corner `edge` (-1: a corner or inside)
    double s = 0.0;           // parameter along that edge
};

/// The segments cut into one face: pairs of points, and the points on its own edges.
struct FaceCuts {
    std::vector<std::array<std::uint32_t, 2>> segments;
    std::vector<std::tuple<int, double, std::uint32_t>> on_edge;  // edge, parameter, point
};

/// Finds the crossing segments of face pairs (see the file comment): points are shared, by
/// vertex, or by (edge, plane) for a crossing point. Faces that share a corner are taken not
/// to cross (they meet there).
class Crossings {
  public:
    explicit Crossings(CutInput& in) : in_(in), cuts_(in.face.size()) {}

    /// The segments where faces a and b cross, added to both; false if they do not cross.
    bool cross(std::uint32_t a, std::uint32_t b) {
        // Neighbours meet at their shared corners; where they are not planar (a twisted strip
        // of quads), their best-fit planes would make them seem to cross there.
        for (std::uint32_t c : in_.face[a])
            if (std::find(in_.face[b].begin(), in_.face[b].end(), c) != in_.face[b].end())
                return false;
        std::vector<double> da, db;
        std::vector<int> sa, sb;
        if (!sides(a, b, da, sa) || !sides(b, a, db, sb)) return false;
        const Vec3 dir = glm::normalize(glm::cross(in_.normal[a], in_.normal[b]));
        if (!std::isfinite(dir.x)) return false;
        const auto ia = intervals(a, b, da, sa, dir), ib = intervals(b, a, db, sb, dir);
        bool any = false;
        for (const auto& x : ia)
            for (const auto& y : ib)
                if (std::min(x[1].t, y[1].t) - std::max(x[0].t, y[0].t) > in_.tol) {
                    add(a, x, y);
                    add(b, y, x);
                    any = true;
                }
        return any;
    }

    const std::vector<FaceCuts>& cuts() const { return cuts_; }

  private:
    /// Signed distances of face f's corners from g's plane, and their signs (0 within tol).
    /// True if f has corners strictly on both sides.
    bool sides(std::uint32_t f, std::uint32_t g, std::vector<double>& d, std::vector<int>& s) {
        bool below = false, above = false;
        for (std::uint32_t c : in_.face[f]) {
            d.push_back(glm::dot(in_.point[c] - in_.origin[g], in_.normal[g]));
            s.push_back(d.back() > in_.tol ? 1 : d.back() < -in_.tol ? -1 : 0);
            below = below || s.back() < 0;
            above = above || s.back() > 0;
        }
        return below && above;
    }

    /// The point where edge p - q crosses g's plane, computed from the edge's lower vertex
    /// whichever face asks (so both faces of the edge get the same point).
    std::uint32_t edge_point(std::uint32_t p, std::uint32_t q, double dp, double dq,
                             std::uint32_t g) {
        if (p > q) std::swap(p, q), std::swap(dp, dq);
        auto [it, fresh] =
            on_plane_.try_emplace({p, q, g}, static_cast<std::uint32_t>(in_.point.size()));
        if (fresh)
            in_.point.push_back(in_.point[p] + (in_.point[q] - in_.point[p]) * (dp / (dp - dq)));
        return it->second;
    }

    /// The intervals in which face f meets the line (direction dir) of its and g's planes: its
    /// edges' sign changes, sorted along the line and paired. A corner on the plane counts as
    /// above it (a symbolic shift of the plane), so a corner touching it adds nothing.
    std::vector<std::array<LineEnd, 2>> intervals(std::uint32_t f, std::uint32_t g,
                                                  const std::vector<double>& d,
                                                  const std::vector<int>& s, const Vec3& dir) {
        const auto& c = in_.face[f];
        std::vector<LineEnd> ends;
        for (std::size_t k = 0; k < c.size(); ++k) {
            const std::size_t j = (k + 1) % c.size();
            if ((s[k] < 0) == (s[j] < 0)) continue;
            LineEnd e;
            if (s[k] == 0 || s[j] == 0) {
                e.point = c[s[k] == 0 ? k : j];
            } else {
                e.point = edge_point(c[k], c[j], d[k], d[j], g);
                e.edge = static_cast<int>(k);
                e.s = d[k] / (d[k] - d[j]);
            }
            e.t = glm::dot(in_.point[e.point], dir);
            ends.push_back(e);
        }
        std::sort(ends.begin(), ends.end(),
                  [](const LineEnd& x, const LineEnd& y) { return x.t < y.t; });
        std::vector<std::array<LineEnd, 2>> out;
        for (std::size_t k = 0; k + 1 < ends.size(); k += 2) out.push_back({ends[k], ends[k + 1]});
        return out;
    }

    /// Adds to face f the overlap of its interval x with the other face's interval y: each end
    /// is x's (on f's boundary) unless y's lies farther in by more than tol (inside f).
    void add(std::uint32_t f, const std::array<LineEnd, 2>& x, const std::array<LineEnd, 2>& y) {
        LineEnd lo = x[0], hi = x[1];
        if (y[0].t > x[0].t + in_.tol) lo = {y[0].t, y[0].point, -1, 0.0};
        if (y[1].t < x[1].t - in_.tol) hi = {y[1].t, y[1].point, -1, 0.0};
        FaceCuts& fc = cuts_[f];
        fc.segments.push_back({lo.point, hi.point});
        for (const LineEnd& e : {lo, hi})
            if (e.edge >= 0) fc.on_edge.emplace_back(e.edge, e.s, e.point);
    }

    CutInput& in_;
    std::vector<FaceCuts> cuts_;
    std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> on_plane_;
};

/// A piece of a face: its corners (point ids) and their UVs.
struct Piece {
    std::uint32_t face = 0;
    std::vector<std::uint32_t> corners;
    std::vector<glm::vec2> uv;  // per corner, or empty
};

/// The UV at point q (in face f's frame) by the barycentric coordinates of the triangle of
/// the face's corners that holds it (the one it lies least outside of, for rounding).
inline glm::vec2 uv_at(const std::vector<Vec2>& corner, const Triangulation& t,
                       const std::vector<glm::vec2>& uv, const Vec2& q) {
    double best = -std::numeric_limits<double>::max();
    glm::dvec2 out(uv[0]);
    for (const auto& v : t.triangles) {
        const Vec2 &a = corner[v[0]], &b = corner[v[1]], &c = corner[v[2]];
        const double d = cross2(b - a, c - a);
        const std::array<double, 3> l{cross2(b - q, c - q) / d, cross2(c - q, a - q) / d,
                                      cross2(a - q, b - q) / d};
        if (const double m = std::min({l[0], l[1], l[2]}); m > best) {
            best = m;
            out = l[0] * glm::dvec2(uv[v[0]]) + l[1] * glm::dvec2(uv[v[1]]) +
                  l[2] * glm::dvec2(uv[v[2]]);
        }
    }
    return glm::vec2(out);
}

/// The cut points on face f's edges: those found there, and the segments' other ends that lie
/// on an edge up to eps (another face's edge crossing f's plane just at f's edge), which the
/// triangulation would otherwise find touching the boundary.
inline std::vector<std::tuple<int, double, std::uint32_t>> boundary_points(const CutInput& in,
                                                                           std::uint32_t f,
                                                                           const FaceCuts& cuts) {
    const auto& c = in.face[f];
    auto on = cuts.on_edge;
    for (const auto& sgm : cuts.segments)
        for (std::uint32_t p : sgm) {
            if (std::find(c.begin(), c.end(), p) != c.end() ||
                std::any_of(on.begin(), on.end(),
                            [&](const auto& e) { return std::get<2>(e) == p; }))
                continue;
            const Vec2 x = face_xy(in, f, in.point[p]);
            for (std::size_t k = 0; k < c.size(); ++k) {
                const Vec2 a = face_xy(in, f, in.point[c[k]]),
                           b = face_xy(in, f, in.point[c[(k + 1) % c.size()]]);
                const double t = glm::dot(x - a, b - a) / glm::dot(b - a, b - a);
                if (t > 0.0 && t < 1.0 &&
                    (orient2d(a, b, x) == 0 || glm::distance(a + t * (b - a), x) <= in.eps)) {
                    on.emplace_back(static_cast<int>(k), t, p);
                    break;
                }
            }
        }
    return on;
}

/// The boundary loop and constraints of cut face f in its frame: its corners with the cut
/// points on its edges in order, and the segments; points closer than eps are one (the first:
/// corners come first). id receives the point id of each point of the input.
inline TriangulationInput cut_outline(const CutInput& in, std::uint32_t f, const FaceCuts& cuts,
                                      std::vector<std::uint32_t>& id) {
    const auto& c = in.face[f];
    std::vector<std::uint32_t> local, loop;  // point id of each local point; the loop over them
    std::unordered_map<std::uint32_t, std::uint32_t> index;
    auto add = [&](std::uint32_t p) {
        auto [it, fresh] = index.try_emplace(p, static_cast<std::uint32_t>(local.size()));
        if (fresh) local.push_back(p);
        return it->second;
    };
    const auto on_edge = boundary_points(in, f, cuts);
    for (std::size_t k = 0; k < c.size(); ++k) {
        loop.push_back(add(c[k]));
        std::vector<std::pair<double, std::uint32_t>> on;
        for (const auto& [e, s, p] : on_edge)
            if (e == static_cast<int>(k)) on.emplace_back(s, p);
        std::sort(on.begin(), on.end());
        for (const auto& sp : on) loop.push_back(add(sp.second));
    }
    for (const auto& sgm : cuts.segments) add(sgm[0]), add(sgm[1]);
    std::vector<Vec2> xy;
    for (std::uint32_t p : local) xy.push_back(face_xy(in, f, in.point[p]));
    DisjointSets same(local.size());
    std::vector<std::uint32_t> by_x(local.size());
    std::iota(by_x.begin(), by_x.end(), 0u);
    std::sort(by_x.begin(), by_x.end(), [&](auto a, auto b) { return xy[a].x < xy[b].x; });
    for (std::size_t i = 0; i < by_x.size(); ++i)
        for (std::size_t j = i + 1; j < by_x.size() && xy[by_x[j]].x - xy[by_x[i]].x <= in.eps; ++j)
            if (glm::distance(xy[by_x[i]], xy[by_x[j]]) <= in.eps) same.unite(by_x[i], by_x[j]);
    TriangulationInput t;
    t.exact_delaunay = false;  // the pieces' cover is what matters, not the best angles
    std::vector<std::uint32_t> compact(local.size(), UINT32_MAX);
    auto at = [&](std::uint32_t l) {
        const std::size_t r = same.find(l);
        if (compact[r] == UINT32_MAX) {
            compact[r] = static_cast<std::uint32_t>(t.points.size());
            t.points.push_back(xy[r]);
            id.push_back(local[r]);
        }
        return compact[r];
    };
    t.loops.emplace_back();
    for (std::uint32_t l : loop)
        if (const std::uint32_t k = at(l); t.loops[0].empty() || t.loops[0].back() != k)
            t.loops[0].push_back(k);
    while (t.loops[0].size() > 1 && t.loops[0].back() == t.loops[0].front()) t.loops[0].pop_back();
    for (const auto& sgm : cuts.segments)
        if (std::array<std::uint32_t, 2> e{at(index[sgm[0]]), at(index[sgm[1]])}; e[0] != e[1])
            t.cuts.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
    std::sort(t.cuts.begin(), t.cuts.end());
    t.cuts.erase(std::unique(t.cuts.begin(), t.cuts.end()), t.cuts.end());
    return t;
}

/// Lightmap UVs of the pieces' corners: a corner's own, else interpolated in the face.
inline void piece_uvs(const CutInput& in, std::uint32_t f, const Triangulation& t,
                      const ConvexPartition& parts, const std::vector<std::uint32_t>& id,
                      std::vector<Piece>& pieces) {
    const auto& c = in.face[f];
    TriangulationInput whole;
    whole.exact_delaunay = false;
    whole.loops.emplace_back();
    for (std::uint32_t k = 0; k < c.size(); ++k) {
        whole.points.push_back(face_xy(in, f, in.point[c[k]]));
        whole.loops[0].push_back(k);
    }
    const Triangulation corners = triangulate(whole);
    for (std::size_t p = 0; p < pieces.size(); ++p)
        for (std::uint32_t k : parts.pieces[p]) {
            const auto it = std::find(c.begin(), c.end(), id[k]);
            pieces[p].uv.push_back(it != c.end()
                                       ? in.uv[f][std::size_t(it - c.begin())]
                                       : uv_at(whole.points, corners, in.uv[f], t.points[k]));
        }
}

/// Re-triangulates cut face f with its segments as constraints (cut_outline) and returns its
/// convex pieces. Points where segments cross are lifted from the face's plane, or are the
/// point they fall within eps of (a segment ending on another one, up to rounding, makes
/// one); a sliver left with no area to speak of (under 1e-12 of the face's) is dropped and
/// counted. Throws Error where the triangulation refuses the outline.
inline std::vector<Piece> cut_face(CutInput& in, std::uint32_t f, const FaceCuts& cuts,
                                   std::size_t& slivers) {
    std::vector<std::uint32_t> id;
    const TriangulationInput outline = cut_outline(in, f, cuts, id);
    const Triangulation t = triangulate(outline, "cutting face " + std::to_string(f));
    const std::size_t n = outline.points.size();
    for (std::size_t k = n; k < t.points.size(); ++k) {
        std::size_t near = n;
        for (std::size_t j = 0; j < n && near == n; ++j)
            if (glm::distance(t.points[j], t.points[k]) <= in.eps) near = j;
        id.push_back(near < n ? id[near] : static_cast<std::uint32_t>(in.point.size()));
        if (near == n)
            in.point.push_back(in.origin[f] + t.points[k].x * in.u[f] + t.points[k].y * in.v[f]);
    }
    double whole = 0.0;
    for (const auto& tri : t.triangles)
        whole += cross2(t.points[tri[1]] - t.points[tri[0]], t.points[tri[2]] - t.points[tri[0]]);
    ConvexPartition parts = convex_partition(t);
    std::vector<Piece> out;
    ConvexPartition kept;
    for (const auto& corners : parts.pieces) {
        Piece piece{f, {}, {}};
        std::vector<std::uint32_t> at;
        for (std::uint32_t k : corners)
            if (piece.corners.empty() || piece.corners.back() != id[k])
                piece.corners.push_back(id[k]), at.push_back(k);
        while (piece.corners.size() > 1 && piece.corners.back() == piece.corners.front())
            piece.corners.pop_back(), at.pop_back();
        double area = 0.0;
        for (std::size_t k = 1; k + 1 < at.size(); ++k)
            area +=
                cross2(t.points[at[k]] - t.points[at[0]], t.points[at[k + 1]] - t.points[at[0]]);
        if (piece.corners.size() < 3 || !(area > 1e-12 * whole)) {
            ++slivers;
            continue;
        }
        out.push_back(std::move(piece));
        kept.pieces.push_back(std::move(at));
    }
    if (!in.uv[f].empty()) piece_uvs(in, f, t, kept, id, out);
    return out;
}

/// The triangles of polygon p (normal n), counter-clockwise about n: a fan if it is convex,
/// else its constrained Delaunay triangulation.
inline void polygon_triangles(std::span<const Vec3> p, const Vec3& n,
                              std::vector<std::array<Vec3, 3>>& out) {
    if (turns_left_about(p, n)) {
        for (std::size_t k = 1; k + 1 < p.size(); ++k) out.push_back({p[0], p[k], p[k + 1]});
        return;
    }
    Vec3 u, v;
    for (const auto& t : triangulate(in_plane(p, n, u, v)).triangles)
        out.push_back({p[t[0]], p[t[1]], p[t[2]]});
}

/// Which pieces lie inside a closed solid (solid.hpp) that their object crosses: each piece's
/// interior point against each such solid. Cost: O(n log n) per solid built, three ray
/// queries per piece of an object that crosses one.
inline std::vector<char> hidden_pieces(
    const CutInput& in, const std::vector<Piece>& pieces,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& crossing) {
    const Objects objects = find_objects(in.face, in.point.size());
    const std::size_t n = objects.closed.size();
    std::vector<std::set<std::uint32_t>> solids(n);  // closed objects each object crosses
    for (const auto& [a, b] : crossing) {
        const std::uint32_t oa = objects.of_face[a], ob = objects.of_face[b];
        if (oa == ob) continue;
        if (objects.closed[ob]) solids[oa].insert(ob);
        if (objects.closed[oa]) solids[ob].insert(oa);
    }
    std::vector<std::vector<std::uint32_t>> faces_of(n);
    for (std::uint32_t f = 0; f < in.face.size(); ++f)
        if (!in.face[f].empty()) faces_of[objects.of_face[f]].push_back(f);
    std::map<std::uint32_t, SolidTest> tests;
    auto test = [&](std::uint32_t o) -> const SolidTest& {
        if (auto it = tests.find(o); it != tests.end()) return it->second;
        std::vector<std::array<Vec3, 3>> triangles;
        for (std::uint32_t f : faces_of[o]) {
            std::vector<Vec3> p;
            for (std::uint32_t c : in.face[f]) p.push_back(in.point[c]);
            polygon_triangles(p, in.normal[f], triangles);
        }
        return tests.emplace(o, SolidTest(triangles)).first->second;
    };
    std::vector<char> hidden(pieces.size(), 0);
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const auto& around = solids[objects.of_face[pieces[i].face]];
        if (around.empty()) continue;
        std::vector<Vec3> p;
        for (std::uint32_t c : pieces[i].corners) p.push_back(in.point[c]);
        const Vec3 x = interior_point(p, in.normal[pieces[i].face]);
        for (std::uint32_t o : around)
            if (test(o).contains(x)) {
                hidden[i] = 1;
                break;
            }
    }
    return hidden;
}

/// The kept pieces as a mesh, each with the data of its input face; points no piece uses are
/// left out, and what a half-edge mesh cannot hold is split first (make_manifold).
template <SpectrumType S>
Mesh<S> pieces_mesh(const Mesh<S>& mesh, const CutInput& in, const std::vector<Piece>& kept) {
    std::vector<std::uint32_t> number(in.point.size(), UINT32_MAX), point;
    std::vector<std::vector<std::uint32_t>> faces;
    for (const Piece& p : kept) {
        faces.emplace_back();
        for (std::uint32_t c : p.corners) {
            if (number[c] == UINT32_MAX) {
                number[c] = static_cast<std::uint32_t>(point.size());
                point.push_back(c);
            }
            faces.back().push_back(number[c]);
        }
    }
    const ManifoldFaces m = make_manifold(faces, point.size());
    Mesh<S> out;
    add_manifold_faces(
        out, m, [&](std::uint32_t o) -> const Vec3& { return in.point[point[o]]; },
        [&](std::size_t f, auto h, const auto& c) {
            out.data(h) = mesh.data(typename Mesh<S>::FaceHandle(static_cast<int>(kept[f].face)));
            if (!kept[f].uv.empty()) set_face_uvs(out, h, c, kept[f].uv);
        },
        [&](std::size_t f) {
            return "cutting intersections: could not add a piece of face " +
                   std::to_string(kept[f].face);
        });
    return out;
}

}  // namespace detail

/// Cuts the faces of a mesh where other faces cross them and leaves out the pieces inside
/// closed solids (see the file comment). Faces that nothing crosses, or that only touch, stay
/// as they are, and so do faces whose corners lie farther than planarity_tolerance of their
/// size from a plane (subdivide's warning threshold); if nothing is cut or left out, the
/// result's mesh is empty (use the input).
/// Cost: O(n log n) for the candidate pairs, O(k log k) per cut face of k segments, and three
/// ray queries per face of an object that crosses a closed solid.
template <SpectrumType S>
CutMesh<S> cut_intersections(const Mesh<S>& mesh, double planarity_tolerance = 1e-5) {
    CutMesh<S> out;
    detail::CutInput in = detail::cut_input(mesh);
    for (std::size_t f = 0; f < in.face.size(); ++f) {
        out.input_polygon.emplace_back();
        for (std::uint32_t c : in.face[f]) out.input_polygon.back().push_back(in.point[c]);
        if (in.face[f].empty()) out.dropped.push_back(f);
    }
    detail::Crossings crossings(in);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> crossing;
    for (const auto& [a, b] : detail::candidate_pairs(in))
        if (crossings.cross(a, b)) crossing.emplace_back(a, b);
    out.report.crossing_pairs = crossing.size();
    if (crossing.empty()) return out;
    std::vector<detail::Piece> pieces;
    for (std::uint32_t f = 0; f < in.face.size(); ++f) {
        if (in.face[f].empty()) continue;
        const detail::FaceCuts& cuts = crossings.cuts()[f];
        if (!cuts.segments.empty() &&
            detail::non_planarity(out.input_polygon[f]) > planarity_tolerance)
            ++out.report.failed_faces;
        else if (!cuts.segments.empty())
            try {
                std::vector<detail::Piece> p = detail::cut_face(in, f, cuts, out.report.slivers);
                ++out.report.cut_faces;
                out.report.pieces += p.size();
                pieces.insert(pieces.end(), p.begin(), p.end());
                continue;
            } catch (const Error&) {
                ++out.report.failed_faces;  // kept whole: a patch may straddle the crossing
            }
        pieces.push_back({f, in.face[f], in.uv[f]});
    }
    const std::vector<char> hidden = detail::hidden_pieces(in, pieces, crossing);
    std::vector<detail::Piece> kept;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        if (!hidden[i]) {
            kept.push_back(pieces[i]);
            out.input_face.push_back(pieces[i].face);
            continue;
        }
        std::vector<Vec3> p;
        for (std::uint32_t c : pieces[i].corners) p.push_back(in.point[c]);
        ++out.report.left_out;
        out.report.left_out_area += polygon_area(p);
        out.left_out.push_back(std::move(p));
        out.left_out_face.push_back(pieces[i].face);
    }
    if (out.changed()) out.mesh = detail::pieces_mesh(mesh, in, kept);
    return out;
}

}  // namespace radiosity
