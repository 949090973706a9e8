#pragma once
/// @file polygon_patches.hpp  One planar polygon, of any shape and number of vertices, cut into
/// convex patches of a target size that cover it exactly: its constrained Delaunay triangulation
/// (geometry/triangulate.hpp) is merged into convex pieces (Hertel & Mehlhorn 1983,
/// geometry/convex_partition.hpp), and each piece is clipped by the cells of one grid over the
/// polygon (a convex piece clipped by a rectangle stays convex, Sutherland & Hodgman 1974). A
/// piece that covers less than half of its cell is merged into a neighbouring piece of the same
/// convex piece C across a cell side: with rectangles A and B whose union is a rectangle,
/// (A n C) u (B n C) = (A u B) n C, which is convex again. So a disk given as a 10,000-gon
/// becomes about as many patches as a square of its area, not 10,000 slivers.
///
/// Every point is made once, under a key that says where it lies (a corner, the crossing of an
/// edge, diagonal or grid line with a grid line), so pieces on both sides of a diagonal or grid
/// line share their points; and every patch edge records the line it lies on (its carrier), from
/// which the subdivision inserts the points of the neighbours (no T-junctions). Patches are
/// convex to within the snap distance (a corner of a nearly collinear run may turn that little
/// the wrong way); they cover the polygon exactly.

#include <radiosity/error.hpp>
#include <radiosity/geometry/convex_partition.hpp>
#include <radiosity/geometry/predicates.hpp>
#include <radiosity/geometry/triangulate.hpp>
#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace radiosity {

/// Settings of polygon_patches.
struct PolygonPatchOptions {
    double max_edge = 0.0;     ///< grid cells no wider or taller than this; 0: no limit
    double max_area = 0.0;     ///< grid cells of at most this area (square-ish); 0: no limit
    double merge_below = 0.5;  ///< pieces covering less than this share of a cell are merged
    /// An inner grid line within this share of a cell of a corner is moved onto the corner,
    /// so that no strip thinner than that forms between the line and the corner's edges.
    double move_lines = 0.1;
    double snap = 0.0;  ///< a point within this distance of a grid line counts as on it
};

/// The line a patch edge lies on: an edge of the polygon (from its corner `index` to the next),
/// a diagonal of the convex partition, a grid line x = x_lines[index] or y = y_lines[index].
struct Carrier {
    enum Kind : std::uint8_t { edge, diagonal, grid_x, grid_y } kind;
    std::uint32_t index;
    auto operator<=>(const Carrier&) const = default;
};

/// A point of the patches and where it lies.
struct PatchPoint {
    enum Kind : std::uint8_t {
        corner,    ///< the polygon's corner `index`
        crossing,  ///< on `carrier` (an edge or diagonal) at parameter t from its first point
        grid       ///< a grid corner inside the polygon
    } kind;
    std::uint32_t index = 0;  ///< the corner, for a corner
    Carrier carrier{};        ///< for a crossing
    double t = 0.0;           ///< for a crossing: from the edge's corner or the diagonal's first
    Vec2 xy;                  ///< in the polygon's coordinates
};

/// A polygon cut into convex patches (see the file comment).
struct PolygonPatches {
    std::vector<PatchPoint> points;
    std::vector<std::vector<std::uint32_t>> patches;  ///< counter-clockwise, into points
    std::vector<std::vector<Carrier>> carriers;  ///< carriers[p][k]: edge from corner k to k + 1
    std::vector<std::uint32_t> piece;            ///< the convex piece each patch lies in
    Triangulation triangulation;                 ///< of the polygon
    ConvexPartition partition;                   ///< of the triangulation
    std::vector<double> x_lines, y_lines;        ///< the grid
    double cell_area = 0.0;                      ///< of one grid cell
};

namespace detail {

/// The cells of the grid along one axis over [lo, hi]: lines lo + i (hi - lo) / k, k the fewest
/// cells no longer than max_edge and no longer than sqrt(max_area) (square cells of at most that
/// area), 1 when both are 0.
inline std::vector<double> grid_lines(double lo, double hi, double max_edge, double max_area) {
    const double w = hi - lo;
    double k = 1.0;
    if (max_edge > 0.0) k = std::max(k, std::ceil(w / max_edge - 1e-9));
    if (max_area > 0.0) k = std::max(k, std::ceil(w / std::sqrt(max_area) - 1e-9));
    const auto n = static_cast<std::size_t>(k);
    std::vector<double> x(n + 1);
    for (std::size_t i = 0; i <= n; ++i) x[i] = lo + w * (double(i) / double(n));
    x[0] = lo;
    x[n] = hi;
    return x;
}

/// Moves each inner line of a grid onto the nearest of the coordinates c within `share` of a
/// cell of it (the lines stay in order: they move by less than half a cell).
inline void move_lines_onto(std::vector<double>& lines, std::span<const double> c, double share) {
    if (lines.size() < 3) return;
    const double reach = share * (lines.back() - lines.front()) / double(lines.size() - 1);
    std::vector<double> best(lines.size(), reach), to(lines);
    for (double x : c) {
        const auto i = std::lower_bound(lines.begin() + 1, lines.end() - 1, x) - lines.begin();
        for (auto j : {i - 1, i})
            if (j >= 1 && j + 1 < static_cast<std::ptrdiff_t>(lines.size()) &&
                std::abs(x - lines[std::size_t(j)]) < best[std::size_t(j)]) {
                best[std::size_t(j)] = std::abs(x - lines[std::size_t(j)]);
                to[std::size_t(j)] = x;
            }
    }
    lines = std::move(to);
}

/// The cutter of one polygon (see the file comment).
class PolygonCutter {
  public:
    /// A corner of a piece and the carrier of its edge to the next corner.
    struct Corner {
        std::uint32_t point;
        Carrier out;
    };
    using Piece = std::vector<Corner>;

    PolygonCutter(PolygonPatches& r, double snap) : r_(r), snap_{snap, snap} {}

    /// The point of polygon corner k.
    std::uint32_t corner(std::uint32_t k) {
        return point({0, k, 0}, [&] {
            PatchPoint p{PatchPoint::corner, 0, {}, 0.0, {}};
            p.index = k;
            p.xy = r_.triangulation.points[k];
            return p;
        });
    }

    /// Which side of line `axis` = value a point is on: -1, +1, or 0 within snap of it.
    int side(std::uint32_t point, int axis, double value) const {
        const double c = r_.points[point].xy[axis], d = snap_[std::size_t(axis)];
        return c < value - d ? -1 : c > value + d ? 1 : 0;
    }
    /// The snap distance across lines of an axis.
    double snap(int axis) const { return snap_[std::size_t(axis)]; }

    /// Splits a convex piece by grid line `line` of `axis` (0: x = x_lines[line], 1: y) into
    /// the parts below and above it (empty where nothing lies strictly on that side; a piece
    /// wholly within snap of the line goes above). Corners within snap of the line count as on
    /// it; a run of them belongs, with the edges between them, to the part of the side before
    /// the run, and the other part takes the run's last corner only, where it re-enters: so the
    /// two parts meet along one chord and share no edge.
    std::pair<Piece, Piece> split(const Piece& piece, int axis, std::uint32_t line) {
        const double value = axis == 0 ? r_.x_lines[line] : r_.y_lines[line];
        const Carrier along{axis == 0 ? Carrier::grid_x : Carrier::grid_y, line};
        const std::size_t m = piece.size();
        std::vector<int> s(m);
        for (std::size_t k = 0; k < m; ++k) s[k] = side(piece[k].point, axis, value);
        const auto strict = std::find_if(s.begin(), s.end(), [](int x) { return x != 0; });
        if (strict == s.end()) return {Piece{}, piece};
        const auto start = static_cast<std::size_t>(strict - s.begin());
        Piece part[2];
        for (int half = 0; half < 2; ++half) {
            const int keep = half == 0 ? -1 : 1;  // the strict side this part keeps
            if (std::find(s.begin(), s.end(), keep) == s.end()) continue;
            Piece& out = part[half];
            int before = 0;  // the side of the last strict corner passed
            for (std::size_t step = 0; step < m; ++step) {
                const std::size_t k = (start + step) % m, n = (k + 1) % m;
                if (s[k] != 0) {
                    before = s[k];
                    if (s[k] == keep) out.push_back(piece[k]);
                    if (s[n] == -s[k])  // edge k crosses the line
                        out.push_back({crossing(piece[k].out, axis, line),
                                       s[k] == keep ? along : piece[k].out});
                    continue;
                }
                const bool last = s[n] != 0;  // of its run
                if (before == keep)
                    out.push_back({piece[k].point, last && s[n] == -keep ? along : piece[k].out});
                else if (last && s[n] == keep)
                    out.push_back(piece[k]);  // where the part re-enters
            }
        }
        return {std::move(part[0]), std::move(part[1])};
    }

    /// Twice the signed area of a piece, from its first corner (for accuracy).
    double area2(const Piece& piece) const {
        double a = 0.0;
        const Vec2 o = r_.points[piece[0].point].xy;
        for (std::size_t k = 1; k + 1 < piece.size(); ++k)
            a += cross2(r_.points[piece[k].point].xy - o, r_.points[piece[k + 1].point].xy - o);
        return a;
    }

    PolygonPatches& result() { return r_; }

  private:
    template <class Make>
    std::uint32_t point(std::array<std::uint32_t, 3> key, Make&& make) {
        auto [it, fresh] = keys_.try_emplace(key, static_cast<std::uint32_t>(r_.points.size()));
        if (fresh) r_.points.push_back(make());
        return it->second;
    }

    /// The point where carrier c meets grid line `line` of `axis`, computed from c's own end
    /// points so that every piece along c finds the same one.
    std::uint32_t crossing(Carrier c, int axis, std::uint32_t line) {
        const std::uint32_t code = (static_cast<std::uint32_t>(c.kind) << 1) | std::uint32_t(axis);
        return point({code + 1, c.index, line}, [&] {
            const double value = axis == 0 ? r_.x_lines[line] : r_.y_lines[line];
            PatchPoint p{PatchPoint::crossing, 0, {}, 0.0, {}};
            if (c.kind == Carrier::grid_x || c.kind == Carrier::grid_y) {  // a grid corner
                p.kind = PatchPoint::grid;
                p.xy = c.kind == Carrier::grid_x ? Vec2(r_.x_lines[c.index], value)
                                                 : Vec2(value, r_.y_lines[c.index]);
                return p;
            }
            const auto [a, b] = ends(c);
            const Vec2 &A = r_.triangulation.points[a], &B = r_.triangulation.points[b];
            const double t = std::clamp((value - A[axis]) / (B[axis] - A[axis]), 0.0, 1.0);
            p.carrier = c;
            p.t = t;
            p.xy = A + t * (B - A);
            p.xy[axis] = value;
            return p;
        });
    }

    /// The end points of an edge or diagonal carrier, in the order its parameter runs.
    std::array<std::uint32_t, 2> ends(Carrier c) const {
        if (c.kind == Carrier::edge) {
            const auto n = static_cast<std::uint32_t>(r_.triangulation.points.size());
            return {c.index, (c.index + 1) % n};
        }
        return r_.partition.diagonals[c.index];
    }

    PolygonPatches& r_;
    std::array<double, 2> snap_;
    std::map<std::array<std::uint32_t, 3>, std::uint32_t> keys_;
};

/// The cells a convex piece covers along one axis: [first, last], from its extent (less snap).
inline std::array<std::uint32_t, 2> cell_range(const std::vector<double>& lines, double lo,
                                               double hi, double snap) {
    const auto last_cell = static_cast<std::ptrdiff_t>(lines.size()) - 2;
    auto cell_of = [&](double x) {  // the cell whose lines hold x, the lower one on a line
        const auto i = std::upper_bound(lines.begin(), lines.end(), x) - lines.begin() - 1;
        return static_cast<std::uint32_t>(std::clamp<std::ptrdiff_t>(i, 0, last_cell));
    };
    const std::uint32_t a = cell_of(lo + snap), b = cell_of(std::max(lo + snap, hi - snap));
    return {a, std::max(a, b)};
}

/// Cuts convex pieces into their grid cells, then merges neighbours (see the file comment) and
/// writes the patches into the result.
class CellMerger {
  public:
    using Piece = PolygonCutter::Piece;

    CellMerger(PolygonCutter& cut, const PolygonPatchOptions& o) : cut_(cut), o_(o) {}

    /// Cuts convex piece C (number `piece`) into the cells it covers.
    void cut(const Piece& C, std::uint32_t piece) {
        const PolygonPatches& r = cut_.result();
        Vec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const auto& c : C) {
            lo = glm::min(lo, r.points[c.point].xy);
            hi = glm::max(hi, r.points[c.point].xy);
        }
        const auto xs = cell_range(r.x_lines, lo.x, hi.x, cut_.snap(0));
        ys_ = cell_range(r.y_lines, lo.y, hi.y, cut_.snap(1));
        piece_ = piece;
        columns(C, xs[0], xs[1]);
    }

    /// Merges (first the pieces of one cell whose union is convex, then each piece below
    /// merge_below of a cell into its largest neighbour) and writes the patches.
    void finish() {
        for (std::size_t p = 0; p < cells_.size(); ++p) add_edges(p);
        for (std::size_t p = 0; p < cells_.size(); ++p)  // whole cells cut by diagonals
            for (bool merged = true; merged && cells_[p].alive;) {
                merged = false;
                for (std::size_t q : neighbours(p))
                    if (same_cells(p, q) && merge(p, q)) {
                        merged = true;
                        break;
                    }
            }
        const double small = o_.merge_below * cut_.result().cell_area;
        std::set<std::pair<double, std::size_t>> queue;
        for (std::size_t c = 0; c < cells_.size(); ++c)
            if (cells_[c].alive && cells_[c].area < small) queue.insert({cells_[c].area, c});
        while (!queue.empty()) {  // smallest first, into the largest neighbour that fits
            const std::size_t p = queue.begin()->second;
            queue.erase(queue.begin());
            std::vector<std::size_t> by_area = neighbours(p);
            std::stable_sort(by_area.begin(), by_area.end(), [&](std::size_t a, std::size_t b) {
                return cells_[a].area > cells_[b].area;
            });
            for (std::size_t q : by_area) {
                const double before = cells_[q].area;
                if (!merge(p, q)) continue;
                queue.erase({before, q});
                if (cells_[q].area < small) queue.insert({cells_[q].area, q});
                break;
            }
        }
        write();
    }

  private:
    struct Cell {
        Piece poly;
        std::uint32_t i0, i1, j0, j1;  // the grid cells it covers
        double area;
        std::uint32_t piece;  // the convex piece it came from (the first, once merged)
        bool alive = true;
    };

    /// Recursive bisection by the middle line: O(|C| log cells) rather than O(|C| cells).
    void columns(const Piece& P, std::uint32_t i0, std::uint32_t i1) {
        if (i0 == i1) return rows(P, i0, ys_[0], ys_[1]);
        const std::uint32_t mid = (i0 + i1 + 1) / 2;
        auto [below, above] = cut_.split(P, 0, mid);
        if (!below.empty()) columns(below, i0, mid - 1);
        if (!above.empty()) columns(above, mid, i1);
    }

    void rows(const Piece& P, std::uint32_t i, std::uint32_t j0, std::uint32_t j1) {
        if (j0 == j1) {
            const double a = 0.5 * cut_.area2(P);
            if (a > 0.0) cells_.push_back({P, i, i, j0, j0, a, piece_});
            return;  // else a piece only touching the cell (within snap)
        }
        const std::uint32_t mid = (j0 + j1 + 1) / 2;
        auto [below, above] = cut_.split(P, 1, mid);
        if (!below.empty()) rows(below, i, j0, mid - 1);
        if (!above.empty()) rows(above, i, mid, j1);
    }

    static std::uint64_t key(std::uint32_t a, std::uint32_t b) {
        return (std::uint64_t{a} << 32) | b;
    }
    void add_edges(std::size_t p) {
        const Piece& poly = cells_[p].poly;
        for (std::size_t k = 0; k < poly.size(); ++k)
            edge_[key(poly[k].point, poly[(k + 1) % poly.size()].point)] = p;
    }
    void remove_edges(std::size_t p) {
        const Piece& poly = cells_[p].poly;
        for (std::size_t k = 0; k < poly.size(); ++k)
            edge_.erase(key(poly[k].point, poly[(k + 1) % poly.size()].point));
    }
    /// The pieces across an edge of p, each once, in the order of p's edges.
    std::vector<std::size_t> neighbours(std::size_t p) const {
        std::vector<std::size_t> out;
        const Piece& poly = cells_[p].poly;
        for (std::size_t k = 0; k < poly.size(); ++k) {
            const auto it = edge_.find(key(poly[(k + 1) % poly.size()].point, poly[k].point));
            if (it != edge_.end() && std::find(out.begin(), out.end(), it->second) == out.end())
                out.push_back(it->second);
        }
        return out;
    }
    bool same_cells(std::size_t p, std::size_t q) const {
        const Cell &a = cells_[p], &b = cells_[q];
        return a.i0 == b.i0 && a.i1 == b.i1 && a.j0 == b.j0 && a.j1 == b.j1;
    }

    /// Merges p into q if they share a chain of edges, their union is convex and it spans at
    /// most `span` x `span` cells; false otherwise.
    bool merge(std::size_t p, std::size_t q, std::uint32_t span = 2) {
        Piece u;
        if (!union_of(p, q, span, u)) return false;
        commit(p, q, std::move(u));
        return true;
    }

    /// The union of p and q into u, if they share a chain of edges, it is convex and spans at
    /// most span x span cells: p from the chain's end round to its start, then q round to the
    /// end (the chain's inner points, which only p and q use, go).
    bool union_of(std::size_t p, std::size_t q, std::uint32_t span, Piece& u) const {
        const Cell &a = cells_[p], &b = cells_[q];
        if (std::max(a.i1, b.i1) - std::min(a.i0, b.i0) >= span ||
            std::max(a.j1, b.j1) - std::min(a.j0, b.j0) >= span)
            return false;
        const std::size_t m = a.poly.size();
        auto shared = [&](std::size_t k) {  // edge k of p is an edge of q
            const auto it = edge_.find(key(a.poly[(k + 1) % m].point, a.poly[k].point));
            return it != edge_.end() && it->second == q;
        };
        std::size_t s = m;  // first shared edge of the chain
        for (std::size_t k = 0; k < m && s == m; ++k)
            if (shared(k) && !shared((k + m - 1) % m)) s = k;
        if (s == m) return false;
        std::size_t e = s;  // one past the chain's last edge
        while (shared(e % m)) ++e;
        const std::uint32_t start = a.poly[s].point, end = a.poly[e % m].point;
        u.clear();
        for (std::size_t k = e; k <= s + m; ++k) u.push_back(a.poly[k % m]);
        const std::size_t n = b.poly.size();
        std::size_t j = 0;
        while (b.poly[j].point != start) ++j;
        u.back().out = b.poly[j].out;  // from the chain's start into q
        for (std::size_t k = (j + 1) % n; b.poly[k].point != end; k = (k + 1) % n)
            u.push_back(b.poly[k]);
        return convex_at(u, 0) && convex_at(u, s + m - e);
    }

    void commit(std::size_t p, std::size_t q, Piece u) {
        Cell &a = cells_[p], &b = cells_[q];
        remove_edges(p);
        remove_edges(q);
        b.poly = std::move(u);
        b.i0 = std::min(a.i0, b.i0);
        b.i1 = std::max(a.i1, b.i1);
        b.j0 = std::min(a.j0, b.j0);
        b.j1 = std::max(a.j1, b.j1);
        b.area += a.area;
        b.piece = std::min(a.piece, b.piece);
        a.alive = false;
        add_edges(q);
    }

    /// Whether the corner k of u turns left by at most 180 degrees, or right by so little that
    /// it lies within snap of the line through its neighbours (a corner of a nearly collinear
    /// run: merging there keeps the cover exact, as gluing moves no point, and spares a sliver
    /// pinned by a corner that is reflex by rounding). Where both its edges lie on one carrier
    /// the corner is straight by construction (a crossing point is only within rounding of the
    /// line it was computed on).
    bool convex_at(const Piece& u, std::size_t k) const {
        const auto& P = cut_.result().points;
        const std::size_t m = u.size(), before = (k + m - 1) % m;
        if (u[before].out == u[k].out) return true;
        const Vec2 &x = P[u[k].point].xy, &a = P[u[before].point].xy,
                   &b = P[u[(k + 1) % m].point].xy;
        const int o = orient2d(a, x, b);
        if (o > 0 || (o == 0 && glm::dot(a - x, b - x) < 0.0)) return true;
        const double base = glm::length(b - a);
        return glm::dot(x - a, b - x) > 0.0 && std::abs(cross2(x - a, b - a)) <= o_.snap * base;
    }

    void write() {
        PolygonPatches& r = cut_.result();
        std::vector<std::size_t> order;
        for (std::size_t c = 0; c < cells_.size(); ++c)
            if (cells_[c].alive) order.push_back(c);
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return std::tuple(cells_[a].j0, cells_[a].i0, cells_[a].piece) <
                   std::tuple(cells_[b].j0, cells_[b].i0, cells_[b].piece);
        });
        for (std::size_t c : order) {
            std::vector<std::uint32_t> corners;
            std::vector<Carrier> carriers;
            for (const auto& k : cells_[c].poly) {
                corners.push_back(k.point);
                carriers.push_back(k.out);
            }
            r.patches.push_back(std::move(corners));
            r.carriers.push_back(std::move(carriers));
            r.piece.push_back(cells_[c].piece);
        }
    }

    PolygonCutter& cut_;
    const PolygonPatchOptions& o_;
    std::vector<Cell> cells_;
    std::unordered_map<std::uint64_t, std::size_t> edge_;  // directed edge -> its piece
    std::array<std::uint32_t, 2> ys_{};
    std::uint32_t piece_ = 0;
};

}  // namespace detail

/// Cuts a simple polygon (counter-clockwise, in its own plane's coordinates) into convex patches
/// that cover it exactly (see the file comment). Throws Error, beginning with `what`, for a
/// polygon that is not simple or not counter-clockwise. Cost: O(n log n) for the triangulation
/// and partition, O(|C| log k + k) to cut a convex piece C over k cells.
inline PolygonPatches polygon_patches(std::span<const Vec2> polygon,
                                      const PolygonPatchOptions& options = {},
                                      const std::string& what = "polygon") {
    PolygonPatches r;
    const auto n = static_cast<std::uint32_t>(polygon.size());
    TriangulationInput in;
    in.points.assign(polygon.begin(), polygon.end());
    in.loops.emplace_back(n);
    for (std::uint32_t k = 0; k < n; ++k) in.loops[0][k] = k;
    r.triangulation = triangulate(in, what);
    double area2 = 0.0;
    for (std::uint32_t k = 1; k + 1 < n; ++k)
        area2 += cross2(polygon[k] - polygon[0], polygon[k + 1] - polygon[0]);
    if (!(area2 > 0.0)) throw Error(what + ": the polygon is not counter-clockwise");
    r.partition = convex_partition(r.triangulation);
    Vec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec2& p : polygon) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    r.x_lines = detail::grid_lines(lo.x, hi.x, options.max_edge, options.max_area);
    r.y_lines = detail::grid_lines(lo.y, hi.y, options.max_edge, options.max_area);
    r.cell_area =
        (hi.x - lo.x) / double(r.x_lines.size() - 1) * (hi.y - lo.y) / double(r.y_lines.size() - 1);
    std::vector<double> xs, ys;
    for (const Vec2& q : polygon) {
        xs.push_back(q.x);
        ys.push_back(q.y);
    }
    detail::move_lines_onto(r.x_lines, xs, options.move_lines);
    detail::move_lines_onto(r.y_lines, ys, options.move_lines);
    detail::PolygonCutter cut(r, options.snap);
    detail::CellMerger cells(cut, options);
    for (std::uint32_t p = 0; p < r.partition.pieces.size(); ++p) {
        detail::PolygonCutter::Piece C;
        const auto& corners = r.partition.pieces[p];
        for (std::size_t k = 0; k < corners.size(); ++k) {
            const PieceEdge& e = r.partition.edges[p][k];
            if (e.kind == EdgeKind::cut)
                throw Error(what + ": cuts are not supported by polygon_patches");
            const Carrier c = e.kind == EdgeKind::boundary ? Carrier{Carrier::edge, corners[k]}
                                                           : Carrier{Carrier::diagonal, e.diagonal};
            C.push_back({cut.corner(corners[k]), c});
        }
        cells.cut(C, p);
    }
    cells.finish();
    return r;
}

}  // namespace radiosity
