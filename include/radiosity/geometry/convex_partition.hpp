#pragma once
/// @file convex_partition.hpp  A triangulated polygon cut into convex pieces by Hertel &
/// Mehlhorn's rule (1983): remove every diagonal whose removal leaves both its end corners convex.
/// The pieces are at most four times as many as the fewest convex pieces possible (and a convex
/// polygon stays one piece); boundary and cut edges are never removed. Longer diagonals go first,
/// so the cuts that remain are short ones. Corners of exactly 180 degrees count as convex.

#include <radiosity/geometry/predicates.hpp>
#include <radiosity/geometry/triangulate.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace radiosity {

/// An edge of a convex piece: its kind and, for a free edge (a diagonal between two pieces), a
/// number that the two pieces share.
struct PieceEdge {
    EdgeKind kind = EdgeKind::free;
    std::uint32_t diagonal = Triangulation::none;
};

/// Convex pieces of a triangulated region.
struct ConvexPartition {
    /// Each piece's corners (indices into the triangulation's points), counter-clockwise.
    std::vector<std::vector<std::uint32_t>> pieces;
    /// edges[p][k]: the edge of piece p from corner k to corner k + 1.
    std::vector<std::vector<PieceEdge>> edges;
    /// The triangles of each piece.
    std::vector<std::vector<std::uint32_t>> triangles;
    /// The kept diagonals' end points, by diagonal number.
    std::vector<std::array<std::uint32_t, 2>> diagonals;
};

namespace detail {

/// The edges at each vertex of a triangulation, counter-clockwise: for a vertex on the boundary
/// from its outgoing boundary edge to its incoming one, else all the way round.
class VertexRings {
  public:
    struct Entry {
        std::uint32_t to;
        EdgeKind kind;
        bool kept = true;
        std::uint32_t prev = 0, next = 0;  // neighbouring kept entries in this ring
    };

    explicit VertexRings(const Triangulation& t) : ring_(t.points.size()) {
        constexpr std::uint32_t none = Triangulation::none;
        std::vector<std::uint32_t> first(t.points.size(), none);  // a wedge (3 t + k) at each
        for (std::uint32_t tri = 0; tri < t.triangles.size(); ++tri)
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t v = t.triangles[tri][k];
                // The wedge after the outgoing boundary edge comes first.
                if (first[v] == none || t.neighbours[tri][k] == none) first[v] = 3 * tri + k;
            }
        for (std::uint32_t v = 0; v < t.points.size(); ++v) {
            if (first[v] == none) continue;
            std::uint32_t w = first[v];
            auto& r = ring_[v];
            r.push_back({t.triangles[w / 3][(w % 3 + 1) % 3], t.kinds[w / 3][w % 3]});
            for (;;) {
                const std::uint32_t tri = w / 3, k = w % 3, back = (k + 2) % 3;
                r.push_back({t.triangles[tri][back], t.kinds[tri][back]});
                const std::uint32_t u = t.neighbours[tri][back];
                if (u == none) break;
                const std::uint32_t j = static_cast<std::uint32_t>(
                    std::find(t.triangles[u].begin(), t.triangles[u].end(), v) -
                    t.triangles[u].begin());
                w = 3 * u + j;
                if (w == first[v]) {  // all the way round: the last entry repeats the first
                    r.pop_back();
                    circular_.push_back(v);
                    break;
                }
            }
            const auto m = static_cast<std::uint32_t>(r.size());
            for (std::uint32_t i = 0; i < m; ++i) {
                r[i].prev = (i + m - 1) % m;
                r[i].next = (i + 1) % m;
                at_[key(v, r[i].to)] = i;
            }
        }
    }

    std::vector<Entry>& ring(std::uint32_t v) { return ring_[v]; }
    std::uint32_t position(std::uint32_t v, std::uint32_t to) const { return at_.at(key(v, to)); }

    /// Removes edge v - to from both rings.
    void remove(std::uint32_t v, std::uint32_t to) {
        unlink(v, position(v, to));
        unlink(to, position(to, v));
    }

  private:
    static std::uint64_t key(std::uint32_t a, std::uint32_t b) {
        return (std::uint64_t{a} << 32) | b;
    }
    void unlink(std::uint32_t v, std::uint32_t i) {
        auto& r = ring_[v];
        r[i].kept = false;
        r[r[i].prev].next = r[i].next;
        r[r[i].next].prev = r[i].prev;
    }

    std::vector<std::vector<Entry>> ring_;
    std::vector<std::uint32_t> circular_;
    std::unordered_map<std::uint64_t, std::uint32_t> at_;
};

/// Walks the boundary of each group of triangles (the pieces) along the kept edges: after a -> b
/// comes b -> the kept edge before b -> a in b's ring, the next one clockwise.
template <class Find>
ConvexPartition trace_pieces(const Triangulation& t, VertexRings& rings, Find& find) {
    constexpr std::uint32_t none = Triangulation::none;
    ConvexPartition out;
    std::vector<std::uint32_t> piece(t.triangles.size(), none);
    for (std::uint32_t tri = 0; tri < t.triangles.size(); ++tri) {
        std::uint32_t& p = piece[find(tri)];
        if (p == none) {
            p = static_cast<std::uint32_t>(out.triangles.size());
            out.triangles.emplace_back();
        }
        out.triangles[p].push_back(tri);
    }
    std::unordered_map<std::uint64_t, std::uint32_t> number;  // kept diagonal -> its number
    out.pieces.resize(out.triangles.size());
    out.edges.resize(out.triangles.size());
    for (std::uint32_t p = 0; p < out.triangles.size(); ++p) {
        std::uint32_t a = none, b = none;  // a kept edge of the piece, the piece on its left
        for (std::uint32_t tri : out.triangles[p])
            for (std::uint32_t k = 0; k < 3 && a == none; ++k) {
                const std::uint32_t x = t.triangles[tri][k], y = t.triangles[tri][(k + 1) % 3];
                if (rings.ring(x)[rings.position(x, y)].kept) {
                    a = x;
                    b = y;
                }
            }
        const std::uint32_t a0 = a, b0 = b;
        do {
            const auto& e = rings.ring(a)[rings.position(a, b)];
            PieceEdge edge{e.kind, none};
            if (e.kind == EdgeKind::free) {
                const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
                auto [it, fresh] =
                    number.try_emplace(key, static_cast<std::uint32_t>(out.diagonals.size()));
                if (fresh) out.diagonals.push_back({std::min(a, b), std::max(a, b)});
                edge.diagonal = it->second;
            }
            out.pieces[p].push_back(a);
            out.edges[p].push_back(edge);
            auto& r = rings.ring(b);
            const std::uint32_t c = r[r[rings.position(b, a)].prev].to;
            a = b;
            b = c;
        } while (a != a0 || b != b0);
    }
    return out;
}

}  // namespace detail

/// The convex pieces of a triangulated region (Hertel & Mehlhorn 1983; see the file comment).
/// Cost: O(n log n) for n triangles (the sort of the diagonals), O(1) per removal.
inline ConvexPartition convex_partition(const Triangulation& t) {
    constexpr std::uint32_t none = Triangulation::none;
    detail::VertexRings rings(t);
    const auto& P = t.points;
    // The diagonals: free edges between two triangles, each once, longest first.
    struct Diagonal {
        std::uint32_t a, b, t1, t2;
        double length2;
    };
    std::vector<Diagonal> diagonals;
    for (std::uint32_t tri = 0; tri < t.triangles.size(); ++tri)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t u = t.neighbours[tri][k];
            if (u == none || u < tri || t.kinds[tri][k] != EdgeKind::free) continue;
            const std::uint32_t a = t.triangles[tri][k], b = t.triangles[tri][(k + 1) % 3];
            const Vec2 d = P[b] - P[a];
            diagonals.push_back({a, b, tri, u, glm::dot(d, d)});
        }
    std::stable_sort(diagonals.begin(), diagonals.end(),
                     [](const Diagonal& x, const Diagonal& y) { return x.length2 > y.length2; });
    // Convex at v once edge v - to is gone: the kept edges on either side of it turn left by at
    // most 180 degrees (and are two different edges, so that no crack is left).
    auto convex_without = [&](std::uint32_t v, std::uint32_t to) {
        auto& r = rings.ring(v);
        const auto& e = r[rings.position(v, to)];
        if (e.prev == e.next) return false;
        const Vec2 &x = P[v], &a = P[r[e.prev].to], &b = P[r[e.next].to];
        const int o = orient2d(x, a, b);
        return o > 0 || (o == 0 && glm::dot(a - x, b - x) < 0.0);
    };
    std::vector<std::uint32_t> group(t.triangles.size());
    std::iota(group.begin(), group.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (group[x] != x) x = group[x] = group[group[x]];
        return x;
    };
    for (const Diagonal& d : diagonals) {
        if (!convex_without(d.a, d.b) || !convex_without(d.b, d.a)) continue;
        rings.remove(d.a, d.b);
        const std::uint32_t x = find(d.t1), y = find(d.t2);
        group[std::max(x, y)] = std::min(x, y);
    }
    return detail::trace_pieces(t, rings, find);
}

}  // namespace radiosity
