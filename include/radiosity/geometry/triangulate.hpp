#pragma once
/// @file triangulate.hpp  Constrained Delaunay triangulation of planar polygons (Chew 1989;
/// Lee & Lin 1986): the triangles cover the polygon exactly, every polygon edge is an edge of the
/// triangulation, and no other edge could be flipped to raise the smallest angle (each is locally
/// Delaunay: no vertex it can see lies inside the circle through either triangle). Of all
/// triangulations of the polygon it has the largest smallest angle, so it makes no sliver the
/// polygon does not force. Besides the boundary loops it takes constraint segments inside (cuts,
/// such as the lines along which other faces cross a face), which become edges too.
///
/// Incremental: the points go one by one into a Delaunay triangulation inside a large enclosing
/// triangle (Lawson 1977's flips after each insertion, point location by a visibility walk,
/// Devillers, Pion & Teillaud 2002); then each constraint is inserted by removing the triangles it
/// crosses and retriangulating the two pseudo-polygons on either side (Anglada 1997); the
/// triangles outside the boundary loops (by parity across boundary edges) are dropped. All
/// decisions use the exact predicates of predicates.hpp, so a polygon with collinear runs or
/// many nearly cocircular vertices (a finely sampled circle) is handled like any other.
/// Boundary edges that cross, touch or overlap are refused with an Error naming them.

#include <radiosity/error.hpp>
#include <radiosity/geometry/predicates.hpp>
#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace radiosity {

/// What an edge of a triangulation is: a free (Delaunay) edge, on a boundary loop, or on a cut.
enum class EdgeKind : std::uint8_t { free = 0, boundary = 1, cut = 2 };

/// The input of a constrained triangulation.
struct TriangulationInput {
    std::vector<Vec2> points;                        ///< the vertices
    std::vector<std::vector<std::uint32_t>> loops;   ///< boundary loops over points: the outer
                                                     ///< counter-clockwise, holes clockwise
    std::vector<std::array<std::uint32_t, 2>> cuts;  ///< constraint segments inside the polygon
    /// false: flip only where the floating-point in-circle test is certain: the same cover,
    /// every free edge Delaunay up to rounding (points within rounding of one circle may keep
    /// either diagonal); about 6 times faster for a 10,000-gon, whose corners all lie so.
    bool exact_delaunay = true;
};

/// A constrained Delaunay triangulation of the region inside the loops.
struct Triangulation {
    /// The input points, then the points where cuts crossed each other or a boundary edge.
    std::vector<Vec2> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise
    /// neighbours[t][k]: the triangle across edge k (from corner k to corner k + 1), or `none`
    /// where that edge is on a boundary loop.
    std::vector<std::array<std::uint32_t, 3>> neighbours;
    std::vector<std::array<EdgeKind, 3>> kinds;  ///< the kind of edge k of each triangle
    /// For each point after the input ones: the two constraints (index into the loops' edges,
    /// numbered loop by loop, then the cuts) whose crossing made it.
    std::vector<std::array<std::uint32_t, 2>> crossing;
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
};

namespace detail {

/// The incremental constrained Delaunay triangulation (see the file comment).
class Cdt {
  public:
    static constexpr std::uint32_t none = Triangulation::none;

    /// The triangulation's state: its points (input, the enclosing triangle's three, then
    /// crossings) and triangles with their neighbours and edge kinds.
    struct Tri {
        std::array<std::uint32_t, 3> v;
        std::array<std::uint32_t, 3> nb{none, none, none};  // across edge k: v[k] -> v[k+1]
        std::array<EdgeKind, 3> kind{EdgeKind::free, EdgeKind::free, EdgeKind::free};
        std::array<std::uint32_t, 3> id{none, none, none};  // the constraint on each edge
        bool dead = false;
    };

    Cdt(std::vector<Vec2> points, std::string what, bool exact = true)
        : p_(std::move(points)), what_(std::move(what)), exact_(exact) {
        input_ = static_cast<std::uint32_t>(p_.size());
        enclose();
    }

    /// Inserts input point i; throws if it coincides with a point inserted before.
    void insert_input_point(std::uint32_t i) {
        const std::uint32_t at = insert_point(i);
        if (at != i)
            throw Error(what_ + ": vertices " + std::to_string(at) + " and " + std::to_string(i) +
                        " coincide (the polygon touches itself)");
    }

    /// Inserts the constraint a - b of the given kind; id numbers it for messages and crossings.
    void insert_constraint(std::uint32_t a, std::uint32_t b, EdgeKind kind, std::uint32_t id) {
        std::vector<std::array<std::uint32_t, 2>> work{{a, b}};
        while (!work.empty()) {
            const auto [u, w] = work.back();
            work.pop_back();
            if (u != w) insert_piece(u, w, kind, id, work);
        }
    }

    /// The triangles inside the boundary loops, renumbered (see Triangulation).
    Triangulation result() const;

  private:
    // --- basic operations -------------------------------------------------------------------

    static std::uint32_t next(std::uint32_t k) { return k == 2 ? 0 : k + 1; }
    static std::uint32_t prev(std::uint32_t k) { return k == 0 ? 2 : k - 1; }

    int orient(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
        return orient2d(p_[a], p_[b], p_[c]);
    }

    std::uint32_t new_tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        std::uint32_t t;
        if (!free_.empty()) {
            t = free_.back();
            free_.pop_back();
            t_[t] = Tri{};
        } else {
            t = static_cast<std::uint32_t>(t_.size());
            t_.emplace_back();
        }
        t_[t].v = {a, b, c};
        for (std::uint32_t v : {a, b, c}) vt_[v] = t;
        last_ = t;
        return t;
    }

    void kill(std::uint32_t t) {
        t_[t].dead = true;
        free_.push_back(t);
    }

    /// The index k of edge a -> b in triangle t, or 3.
    std::uint32_t edge_of(std::uint32_t t, std::uint32_t a, std::uint32_t b) const {
        for (std::uint32_t k = 0; k < 3; ++k)
            if (t_[t].v[k] == a && t_[t].v[next(k)] == b) return k;
        return 3;
    }

    /// Makes edge k of t and the matching edge of u (its reverse) neighbours, with one kind and
    /// constraint id.
    void link(std::uint32_t t, std::uint32_t k, std::uint32_t u, EdgeKind kind,
              std::uint32_t id = none) {
        t_[t].nb[k] = u;
        t_[t].kind[k] = kind;
        t_[t].id[k] = id;
        if (u == none) return;
        const std::uint32_t j = edge_of(u, t_[t].v[next(k)], t_[t].v[k]);
        t_[u].nb[j] = t;
        t_[u].kind[j] = kind;
        t_[u].id[j] = id;
    }

    /// A triangle that contains the point, far enough out that all points are well inside.
    void enclose() {
        Vec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (const Vec2& q : p_) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        if (p_.empty()) lo = hi = Vec2(0.0);
        const Vec2 c = 0.5 * (lo + hi);
        const double r =
            std::max({hi.x - lo.x, hi.y - lo.y, 1e-300}) * 16.0 + std::abs(c.x) + std::abs(c.y);
        const auto s = static_cast<std::uint32_t>(p_.size());
        p_.push_back(c + Vec2(-2.0 * r, -r));
        p_.push_back(c + Vec2(2.0 * r, -r));
        p_.push_back(c + Vec2(0.0, 2.0 * r));
        vt_.assign(p_.size(), none);
        new_tri(s, s + 1, s + 2);
    }

    /// Where point q lies: in triangle t (strictly), on its edge k, or at its vertex k. A
    /// visibility walk from the last triangle made: step across an edge that has q on its far
    /// side, starting the edge scan at a varying corner (a deterministic xorshift), which
    /// terminates on Delaunay triangulations (Devillers, Pion & Teillaud 2002).
    struct Location {
        std::uint32_t tri, index;
        enum { inside, edge, vertex } where;
    };
    Location locate(const Vec2& q) {
        std::uint32_t t = last_;
        if (t_[t].dead) t = first_live();
        // A guard: points within rounding of one circle leave the triangulation Delaunay only up
        // to rounding, where a walk could in principle circle; then every triangle is tried.
        for (std::size_t steps = 0;; ++steps) {
            if (steps > 4 * t_.size() + 16) {
                t = scan(q);
                break;
            }
            rng_ ^= rng_ << 13;
            rng_ ^= rng_ >> 7;
            rng_ ^= rng_ << 17;
            const std::uint32_t start = static_cast<std::uint32_t>(rng_ % 3);
            std::uint32_t step = 3;
            for (std::uint32_t s = 0; s < 3 && step == 3; ++s) {
                const std::uint32_t k = (start + s) % 3;
                if (orient2d(p_[t_[t].v[k]], p_[t_[t].v[next(k)]], q) < 0) step = k;
            }
            if (step == 3) break;
            t = t_[t].nb[step];
        }
        int zeros = 0;
        std::uint32_t on = 0;
        for (std::uint32_t k = 0; k < 3; ++k) {
            if (p_[t_[t].v[k]] == q) return {t, k, Location::vertex};
            if (orient2d(p_[t_[t].v[k]], p_[t_[t].v[next(k)]], q) == 0) {
                ++zeros;
                on = k;
            }
        }
        return zeros == 0 ? Location{t, 0, Location::inside} : Location{t, on, Location::edge};
    }

    /// A live triangle that contains q (on its boundary or inside), by trying all.
    std::uint32_t scan(const Vec2& q) const {
        for (std::uint32_t t = 0; t < t_.size(); ++t)
            if (!t_[t].dead && orient2d(p_[t_[t].v[0]], p_[t_[t].v[1]], q) >= 0 &&
                orient2d(p_[t_[t].v[1]], p_[t_[t].v[2]], q) >= 0 &&
                orient2d(p_[t_[t].v[2]], p_[t_[t].v[0]], q) >= 0)
                return t;
        return first_live();
    }

    std::uint32_t first_live() const {
        for (std::uint32_t t = 0; t < t_.size(); ++t)
            if (!t_[t].dead) return t;
        return none;
    }

    /// Inserts point i (Lawson 1977): split the triangle or edge it falls in, then flip the
    /// edges opposite it that are not locally Delaunay. Returns the vertex now at its position
    /// (i, or an earlier point equal to it).
    std::uint32_t insert_point(std::uint32_t i) {
        const Location at = locate(p_[i]);
        if (at.where == Location::vertex) return t_[at.tri].v[at.index];
        std::vector<std::uint32_t> around;  // the new triangles, each with i at corner 0
        if (at.where == Location::inside)
            split_triangle(at.tri, i, around);
        else
            split_edge(at.tri, at.index, i, around);
        legalize(i, around);
        return i;
    }

    /// Triangle t = (a, b, c) becomes (i, a, b), (i, b, c), (i, c, a).
    void split_triangle(std::uint32_t t, std::uint32_t i, std::vector<std::uint32_t>& out) {
        const Tri old = t_[t];
        kill(t);
        std::array<std::uint32_t, 3> n;
        for (std::uint32_t k = 0; k < 3; ++k) n[k] = new_tri(i, old.v[k], old.v[next(k)]);
        for (std::uint32_t k = 0; k < 3; ++k) {
            link(n[k], 1, old.nb[k], old.kind[k], old.id[k]);  // the old edge v[k] -> v[k+1]
            link(n[k], 2, n[next(k)], EdgeKind::free);         // v[k+1] -> i, with n[k+1]
            out.push_back(n[k]);
        }
    }

    /// Edge k of t (a -> b) and the triangle across it, if any, split at point i on the edge:
    /// the pieces a - i and i - b keep the edge's kind.
    void split_edge(std::uint32_t t, std::uint32_t k, std::uint32_t i,
                    std::vector<std::uint32_t>& out) {
        const Tri a_side = t_[t];
        const std::uint32_t a = a_side.v[k], b = a_side.v[next(k)], c = a_side.v[prev(k)];
        const EdgeKind kind = a_side.kind[k];
        const std::uint32_t id = a_side.id[k], u = a_side.nb[k];
        kill(t);
        // t = (a, b, c) -> (i, b, c), (i, c, a)
        const std::uint32_t t1 = new_tri(i, b, c), t2 = new_tri(i, c, a);
        link(t1, 1, a_side.nb[next(k)], a_side.kind[next(k)], a_side.id[next(k)]);
        link(t2, 1, a_side.nb[prev(k)], a_side.kind[prev(k)], a_side.id[prev(k)]);
        link(t1, 2, t2, EdgeKind::free);
        out.push_back(t1);
        out.push_back(t2);
        if (u == none) {
            t_[t1].kind[0] = t_[t2].kind[2] = kind;
            t_[t1].id[0] = t_[t2].id[2] = id;
            return;
        }
        const Tri b_side = t_[u];
        const std::uint32_t j = edge_of(u, b, a), d = b_side.v[prev(j)];
        kill(u);
        // u = (b, a, d) -> (i, a, d), (i, d, b)
        const std::uint32_t u1 = new_tri(i, a, d), u2 = new_tri(i, d, b);
        link(u1, 1, b_side.nb[next(j)], b_side.kind[next(j)], b_side.id[next(j)]);
        link(u2, 1, b_side.nb[prev(j)], b_side.kind[prev(j)], b_side.id[prev(j)]);
        link(u1, 2, u2, EdgeKind::free);
        link(t1, 0, u2, kind, id);  // i -> b against b -> i
        link(t2, 2, u1, kind, id);  // a -> i against i -> a
        out.push_back(u1);
        out.push_back(u2);
    }

    /// Flips, while any is left, the free edges opposite point i that fail the in-circle test.
    /// Each triangle in `stack` has i at corner 0, so its edge 1 is the one opposite i.
    void legalize(std::uint32_t i, std::vector<std::uint32_t>& stack) {
        while (!stack.empty()) {
            const std::uint32_t t = stack.back();
            stack.pop_back();
            if (t_[t].dead || t_[t].v[0] != i) continue;
            const std::uint32_t u = t_[t].nb[1];
            if (u == none || t_[t].kind[1] != EdgeKind::free) continue;
            const std::uint32_t j = edge_of(u, t_[t].v[2], t_[t].v[1]);
            const std::uint32_t d = t_[u].v[prev(j)];
            // Exact, or only where floating point is certain (each such flip is a true
            // improvement, so this ends too, Lawson 1977; near-cocircular points keep theirs).
            const Vec2 &a = p_[t_[t].v[0]], &b = p_[t_[t].v[1]], &c = p_[t_[t].v[2]];
            if ((exact_ ? incircle(a, b, c, p_[d]) : incircle_certain(a, b, c, p_[d])) <= 0)
                continue;
            const auto [x, y] = flip(t, 1);
            stack.push_back(x);
            stack.push_back(y);
        }
    }

    /// Flips edge k of t: (a, b, c) and (b, a, d) across a -> b become (c, a, d) and (c, d, b),
    /// each with c at corner 0 (so that, c being the point being inserted, edge 1 faces away).
    std::pair<std::uint32_t, std::uint32_t> flip(std::uint32_t t, std::uint32_t k) {
        const Tri x = t_[t];
        const std::uint32_t u = x.nb[k];
        const Tri y = t_[u];
        const std::uint32_t a = x.v[k], b = x.v[next(k)], c = x.v[prev(k)];
        const std::uint32_t j = edge_of(u, b, a), d = y.v[prev(j)];
        kill(t);
        kill(u);
        const std::uint32_t n1 = new_tri(c, a, d), n2 = new_tri(c, d, b);
        link(n1, 0, x.nb[prev(k)], x.kind[prev(k)], x.id[prev(k)]);  // c -> a
        link(n1, 1, y.nb[next(j)], y.kind[next(j)], y.id[next(j)]);  // a -> d
        link(n2, 1, y.nb[prev(j)], y.kind[prev(j)], y.id[prev(j)]);  // d -> b
        link(n2, 2, x.nb[next(k)], x.kind[next(k)], x.id[next(k)]);  // b -> c
        link(n1, 2, n2, EdgeKind::free);                             // d -> c against c -> d
        return {n1, n2};
    }

    // --- constraints --------------------------------------------------------------------------

    /// The triangles around vertex a, in no particular order.
    std::vector<std::uint32_t> star(std::uint32_t a) const {
        std::vector<std::uint32_t> out;
        const std::uint32_t t0 = vt_[a];
        // Rotate counter-clockwise, then, if a boundary of the live region stops us, clockwise.
        std::uint32_t t = t0;
        do {
            out.push_back(t);
            const std::uint32_t k = index_of(t, a);
            t = t_[t].nb[prev(k)];  // across the edge into a
        } while (t != none && t != t0);
        if (t == none) {
            t = t_[t0].nb[index_of(t0, a)];
            while (t != none) {
                out.push_back(t);
                t = t_[t].nb[index_of(t, a)];
            }
        }
        return out;
    }

    std::uint32_t index_of(std::uint32_t t, std::uint32_t v) const {
        return t_[t].v[0] == v ? 0 : t_[t].v[1] == v ? 1 : 2;
    }

    std::string constraint_name(std::uint32_t id) const {
        return (id < boundary_edges_ ? "boundary edge " : "cut ") +
               std::to_string(id < boundary_edges_ ? id : id - boundary_edges_);
    }

    /// Inserts the part a - b of constraint `id`; pushes the rest onto `work` when a vertex lies
    /// on it or it crosses another constraint (split there).
    void insert_piece(std::uint32_t a, std::uint32_t b, EdgeKind kind, std::uint32_t id,
                      std::vector<std::array<std::uint32_t, 2>>& work);

    /// Makes the triangles of the pseudo-polygon x, chain..., y (the chain on the left of x -> y)
    /// (Anglada 1997): the chain vertex c whose circle with x, y holds no other chain vertex
    /// makes triangle (x, y, c); the two sides recurse. O(k^2) for k chain vertices.
    void fill(std::uint32_t x, std::uint32_t y, const std::uint32_t* chain, std::size_t m,
              std::vector<std::uint32_t>& made) {
        if (m == 0) return;
        std::size_t best = 0;
        for (std::size_t k = 1; k < m; ++k)
            if (incircle(p_[x], p_[y], p_[chain[best]], p_[chain[k]]) > 0) best = k;
        made.push_back(new_tri(x, y, chain[best]));
        fill(x, chain[best], chain, best, made);
        fill(chain[best], y, chain + best + 1, m - best - 1, made);
    }

    std::vector<Vec2> p_;
    std::string what_;
    bool exact_ = true;
    std::uint32_t input_ = 0;

  public:
    std::uint32_t boundary_edges_ = 0;  ///< constraint ids below this are boundary edges
    /// For each crossing point (after the input and the enclosing triangle's points): its two
    /// constraints.
    std::vector<std::array<std::uint32_t, 2>> crossing_;

  private:
    std::vector<Tri> t_;
    std::vector<std::uint32_t> free_;
    std::vector<std::uint32_t> vt_;  // a triangle at each vertex
    std::uint32_t last_ = 0;
    std::uint64_t rng_ = 0x9e3779b97f4a7c15ull;
};

inline void Cdt::insert_piece(std::uint32_t a, std::uint32_t b, EdgeKind kind, std::uint32_t id,
                              std::vector<std::array<std::uint32_t, 2>>& work) {
    auto on_segment = [&](std::uint32_t v) {  // v strictly between a and b, collinear
        if (kind == EdgeKind::boundary && v < input_)
            throw Error(what_ + ": vertex " + std::to_string(v) + " lies on " +
                        constraint_name(id) + " (the polygon touches itself)");
        work.push_back({v, b});
        work.push_back({a, v});
    };
    // Step 1: the edge may be there already, or a vertex next to a may lie on a - b; else find
    // the triangle at a whose far edge a - b crosses.
    std::uint32_t t = none, p = none, q = none;
    for (std::uint32_t s : star(a)) {
        const std::uint32_t k = index_of(s, a);
        const std::uint32_t v1 = t_[s].v[next(k)], v2 = t_[s].v[prev(k)];
        if (v1 == b || v2 == b) {  // the edge exists: mark it on both sides
            const std::uint32_t e = v1 == b ? k : prev(k);
            if (t_[s].kind[e] == EdgeKind::boundary && kind == EdgeKind::boundary)
                throw Error(what_ + ": " + constraint_name(id) +
                            " runs along another boundary edge (the polygon overlaps itself)");
            if (t_[s].kind[e] != EdgeKind::boundary) link(s, e, t_[s].nb[e], kind, id);
            return;
        }
        for (std::uint32_t v : {v1, v2})
            if (orient(a, b, v) == 0 && glm::dot(p_[v] - p_[a], p_[b] - p_[a]) > 0.0) {
                on_segment(v);
                return;
            }
        if (orient(a, v1, b) > 0 && orient(a, v2, b) < 0) {
            t = s;
            p = v1;  // on the right of a -> b
            q = v2;  // on the left
        }
    }
    if (t == none) throw Error(what_ + ": could not insert " + constraint_name(id));
    // Step 2: walk through the triangles a - b crosses, collecting the vertices on each side.
    std::vector<std::uint32_t> crossed{t}, left{q}, right{p};
    for (;;) {
        const std::uint32_t k = edge_of(t, p, q);
        if (t_[t].kind[k] != EdgeKind::free) {  // a constraint crosses: split both there
            const std::uint32_t other = t_[t].id[k];
            if (kind == EdgeKind::boundary && t_[t].kind[k] == EdgeKind::boundary)
                throw Error(what_ + ": " + constraint_name(id) + " crosses " +
                            constraint_name(other) + " (the polygon intersects itself)");
            const Vec2 &A = p_[a], &B = p_[b], &P = p_[p], &Q = p_[q];
            const double s = cross2(P - A, Q - P) / cross2(B - A, Q - P);
            const auto x = static_cast<std::uint32_t>(p_.size());
            p_.push_back(A + std::clamp(s, 0.0, 1.0) * (B - A));
            vt_.push_back(none);
            crossing_.push_back({id, other});
            std::vector<std::uint32_t> around;
            split_edge(t, k, x, around);
            legalize(x, around);
            work.push_back({x, b});
            work.push_back({a, x});
            return;
        }
        const std::uint32_t u = t_[t].nb[k];
        const std::uint32_t r = t_[u].v[prev(edge_of(u, q, p))];
        crossed.push_back(u);
        t = u;
        if (r == b) break;
        const int o = orient(a, b, r);
        if (o == 0) {
            on_segment(r);
            return;
        }
        if (o > 0) {
            left.push_back(r);
            q = r;
        } else {
            right.push_back(r);
            p = r;
        }
    }
    // Step 3: remember the outer edges of the crossed triangles, remove them, fill both sides.
    struct Outer {
        std::uint32_t from, to, across;
        EdgeKind kind;
        std::uint32_t id;
    };
    std::vector<Outer> outer;
    auto is_crossed = [&](std::uint32_t x) {
        return std::find(crossed.begin(), crossed.end(), x) != crossed.end();
    };
    for (std::uint32_t c : crossed)
        for (std::uint32_t k = 0; k < 3; ++k)
            if (t_[c].nb[k] == none || !is_crossed(t_[c].nb[k]))
                outer.push_back(
                    {t_[c].v[k], t_[c].v[next(k)], t_[c].nb[k], t_[c].kind[k], t_[c].id[k]});
    for (std::uint32_t c : crossed) kill(c);
    std::vector<std::uint32_t> made;
    fill(a, b, left.data(), left.size(), made);
    std::reverse(right.begin(), right.end());
    fill(b, a, right.data(), right.size(), made);
    // Link the new triangles with each other and with the outside.
    std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> half;
    auto key = [](std::uint32_t x, std::uint32_t y) { return (std::uint64_t{x} << 32) | y; };
    for (std::uint32_t m : made)
        for (std::uint32_t k = 0; k < 3; ++k) half[key(t_[m].v[k], t_[m].v[next(k)])] = {m, k};
    for (const Outer& o : outer) {
        const auto [m, k] = half.at(key(o.from, o.to));
        t_[m].nb[k] = o.across;
        t_[m].kind[k] = o.kind;
        t_[m].id[k] = o.id;
        if (o.across != none) {
            const std::uint32_t j = edge_of(o.across, o.to, o.from);
            t_[o.across].nb[j] = m;
        }
    }
    for (std::uint32_t m : made)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t x = t_[m].v[k], y = t_[m].v[next(k)];
            const auto it = half.find(key(y, x));
            if (it == half.end()) continue;
            t_[m].nb[k] = it->second.first;
            const bool constraint = (x == a && y == b) || (x == b && y == a);
            t_[m].kind[k] = constraint ? kind : EdgeKind::free;
            t_[m].id[k] = constraint ? id : none;
        }
}

inline Triangulation Cdt::result() const {
    // Parity across boundary edges, by a flood from a triangle at the enclosing triangle's
    // corner (outside every loop).
    std::vector<std::int8_t> inside(t_.size(), -1);
    std::vector<std::uint32_t> stack;
    auto corner = [&](std::uint32_t v) { return v >= input_ && v < input_ + 3; };
    for (std::uint32_t t = 0; t < t_.size() && stack.empty(); ++t)
        if (!t_[t].dead && (corner(t_[t].v[0]) || corner(t_[t].v[1]) || corner(t_[t].v[2]))) {
            inside[t] = 0;
            stack.push_back(t);
        }
    while (!stack.empty()) {
        const std::uint32_t t = stack.back();
        stack.pop_back();
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t u = t_[t].nb[k];
            if (u == none || inside[u] >= 0) continue;
            inside[u] = static_cast<std::int8_t>(inside[t] ^ (t_[t].kind[k] == EdgeKind::boundary));
            stack.push_back(u);
        }
    }
    Triangulation out;
    auto point = [&](std::uint32_t v) { return v < input_ ? v : v - 3; };  // drop the corners
    out.points.assign(p_.begin(), p_.begin() + input_);
    out.points.insert(out.points.end(), p_.begin() + input_ + 3, p_.end());
    out.crossing = crossing_;
    std::vector<std::uint32_t> number(t_.size(), none);
    for (std::uint32_t t = 0; t < t_.size(); ++t)
        if (!t_[t].dead && inside[t] == 1) {
            number[t] = static_cast<std::uint32_t>(out.triangles.size());
            out.triangles.push_back({point(t_[t].v[0]), point(t_[t].v[1]), point(t_[t].v[2])});
            out.kinds.push_back(t_[t].kind);
        }
    for (std::uint32_t t = 0; t < t_.size(); ++t)
        if (number[t] != none) {
            std::array<std::uint32_t, 3> nb;
            for (std::uint32_t k = 0; k < 3; ++k)
                nb[k] = t_[t].nb[k] == none ? none : number[t_[t].nb[k]];
            out.neighbours.push_back(nb);
        }
    return out;
}

}  // namespace detail

/// The constrained Delaunay triangulation of the region inside `in.loops`, with `in.cuts` as
/// edges too (see the file comment). Throws Error, beginning with `what` (say, "scene.obj: face
/// 12"), for a loop of fewer than 3 vertices, an index out of range, a point that is not finite,
/// two points at one place, or boundary edges that cross, touch or run along each other. Cuts
/// that cross each other or a boundary edge are split where they cross (a new point). Cost:
/// O(n log n) expected for n points in general position, O(k^2) more per constraint crossing k
/// triangles.
inline Triangulation triangulate(const TriangulationInput& in,
                                 const std::string& what = "polygon") {
    const auto n = static_cast<std::uint32_t>(in.points.size());
    for (std::uint32_t i = 0; i < n; ++i)
        if (!std::isfinite(in.points[i].x) || !std::isfinite(in.points[i].y))
            throw Error(what + ": point " + std::to_string(i) + " is not finite");
    for (const auto& loop : in.loops) {
        if (loop.size() < 3) throw Error(what + ": a boundary loop has fewer than 3 vertices");
        for (std::uint32_t v : loop)
            if (v >= n)
                throw Error(what + ": boundary vertex " + std::to_string(v) + " is missing");
    }
    for (const auto& c : in.cuts)
        if (c[0] >= n || c[1] >= n) throw Error(what + ": a cut's vertex is missing");
    detail::Cdt cdt(in.points, what, in.exact_delaunay);
    for (std::uint32_t i = 0; i < n; ++i) cdt.insert_input_point(i);
    std::uint32_t id = 0;
    for (const auto& loop : in.loops) id += static_cast<std::uint32_t>(loop.size());
    cdt.boundary_edges_ = id;
    id = 0;
    for (const auto& loop : in.loops)
        for (std::size_t k = 0; k < loop.size(); ++k)
            cdt.insert_constraint(loop[k], loop[(k + 1) % loop.size()], EdgeKind::boundary, id++);
    for (const auto& c : in.cuts) cdt.insert_constraint(c[0], c[1], EdgeKind::cut, id++);
    return cdt.result();
}

}  // namespace radiosity
