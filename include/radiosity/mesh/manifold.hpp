#pragma once
/// @file manifold.hpp  Making a polygon soup into an oriented 2-manifold with boundary before it
/// goes into OpenMesh: a half-edge mesh cannot hold an edge shared by three faces, two faces
/// that disagree on an edge's direction, or two fans of faces meeting at one vertex (a
/// "bow-tie"), and OpenMesh's add_face may even abort on some of those. Scenes from files have
/// all of them, so faces and vertices are split here, where it is cheap and always works.

#include <radiosity/config.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

namespace radiosity {

/// Faces over vertex indices after make_manifold: vertices at or beyond the input count are
/// copies, and origin[v] names the input vertex each output vertex stands for.
struct ManifoldFaces {
    std::vector<std::vector<std::uint32_t>> faces;  ///< the faces, in input order
    std::vector<std::uint32_t> origin;              ///< input vertex of every output vertex
};

namespace detail {

/// Lists of items per vertex in flat storage (compressed rows): vertex v's row holds up to
/// capacity[v] items, of which the first filled(v) are pushed so far. Rows are sized by a
/// first count, so filling them never allocates; a million-face soup made a million small
/// vectors (and, in the std::set and std::map this replaced, millions of tree nodes), and was
/// a fifth of loading it.
template <class Item>
class VertexRows {
  public:
    /// Empty rows of capacity[v] items each.
    explicit VertexRows(const std::vector<std::size_t>& capacity)
        : begin_(capacity.size() + 1, 0), filled_(capacity.size(), 0) {
        for (std::size_t v = 0; v < capacity.size(); ++v) begin_[v + 1] = begin_[v] + capacity[v];
        item_.resize(begin_.back());
    }
    std::size_t rows() const { return filled_.size(); }  ///< vertices
    /// Appends x to row v (within its capacity); returns where it went.
    Item& push(std::size_t v, const Item& x) {
        RADIOSITY_ASSERT(begin_[v] + filled_[v] < begin_[v + 1]);
        return item_[begin_[v] + filled_[v]++] = x;
    }
    std::span<Item> row(std::size_t v) { return {item_.data() + begin_[v], filled_[v]}; }
    std::span<const Item> row(std::size_t v) const {
        return {item_.data() + begin_[v], filled_[v]};
    }

  private:
    std::vector<std::size_t> begin_;
    std::vector<std::uint32_t> filled_;
    std::vector<Item> item_;
};

/// The edges of the faces kept so far by make_manifold's first step, each undirected edge in
/// the row of its lower vertex: its other vertex, how many faces use it, and which directions
/// they run (bit 0: low to high, bit 1: high to low). Rows hold every edge that could be there
/// (a vertex's row is sized by its corners), and are searched linearly: a vertex has a handful
/// of edges.
class EdgeUses {
  public:
    /// Room for the edges of `faces` over `vertex_count` vertices.
    EdgeUses(const std::vector<std::vector<std::uint32_t>>& faces, std::size_t vertex_count)
        : rows_(edge_capacity(faces, vertex_count)) {}

    /// Whether a face may run from a to b: no kept face runs that way and fewer than two use it.
    bool fits(std::uint32_t a, std::uint32_t b) {
        const Edge* e = find(a, b);
        return e == nullptr || (e->uses < 2 && (e->directions & direction(a, b)) == 0);
    }
    /// Records a kept face's edge from a to b.
    void add(std::uint32_t a, std::uint32_t b) {
        Edge* e = find(a, b);
        if (e == nullptr) e = &rows_.push(std::min(a, b), {std::max(a, b), 0, 0});
        ++e->uses;
        e->directions |= direction(a, b);
    }

  private:
    struct Edge {
        std::uint32_t other = 0;
        std::uint8_t uses = 0, directions = 0;
    };
    static std::uint8_t direction(std::uint32_t a, std::uint32_t b) { return a < b ? 1 : 2; }
    static std::vector<std::size_t> edge_capacity(
        const std::vector<std::vector<std::uint32_t>>& faces, std::size_t vertex_count) {
        std::vector<std::size_t> capacity(vertex_count, 0);
        for (const auto& f : faces)
            for (std::size_t k = 0; k < f.size(); ++k)
                ++capacity[std::min(f[k], f[(k + 1) % f.size()])];
        return capacity;
    }
    Edge* find(std::uint32_t a, std::uint32_t b) {
        const std::uint32_t high = std::max(a, b);
        for (Edge& e : rows_.row(std::min(a, b)))
            if (e.other == high) return &e;
        return nullptr;
    }

    VertexRows<Edge> rows_;
};

/// The fans of faces around one vertex: `ring` lists the (face, corner) pairs at the vertex,
/// and two of them share a fan when their faces share an edge at it, directly or through
/// others. Writes each ring entry's fan as the index of the fan's first entry in ring order
/// into `fan` (union-find over the entries, uniting those that name the same vertex as a
/// neighbour: sorting the (neighbour, entry) pairs puts those side by side). `scratch` is
/// reused between vertices.
inline void fans_around(const std::vector<std::vector<std::uint32_t>>& faces,
                        std::span<const std::pair<std::uint32_t, std::uint32_t>> ring,
                        std::vector<std::uint32_t>& fan,
                        std::vector<std::pair<std::uint32_t, std::uint32_t>>& scratch) {
    const auto size = static_cast<std::uint32_t>(ring.size());
    fan.resize(size);
    std::iota(fan.begin(), fan.end(), std::uint32_t{0});
    auto find = [&](std::uint32_t x) {
        while (fan[x] != x) x = fan[x] = fan[fan[x]];
        return x;
    };
    scratch.clear();
    for (std::uint32_t r = 0; r < size; ++r) {
        const auto& f = faces[ring[r].first];
        const std::size_t k = ring[r].second, n = f.size();
        scratch.push_back({f[(k + 1) % n], r});
        scratch.push_back({f[(k + n - 1) % n], r});
    }
    std::sort(scratch.begin(), scratch.end());
    for (std::size_t i = 1; i < scratch.size(); ++i)
        if (scratch[i].first == scratch[i - 1].first) {
            // The root of a fan is its first entry in ring order: union by the smaller root.
            const std::uint32_t a = find(scratch[i].second), b = find(scratch[i - 1].second);
            fan[std::max(a, b)] = std::min(a, b);
        }
    for (std::uint32_t r = 0; r < size; ++r) fan[r] = find(r);
}

}  // namespace detail

/// Splits vertices so that the faces form an oriented 2-manifold with boundary: (1) a face that
/// would add a third face to an edge, or run along an edge in the same direction as a face
/// already there, gets its own copies of its vertices; (2) at every vertex, the faces around it
/// are grouped into fans connected through shared edges, and each fan after the first (in the
/// order of the faces) gets its own copy of the vertex. Faces must have distinct vertices.
/// Edges and rings are kept in flat rows per vertex (detail::EdgeUses, detail::VertexRows);
/// tests/test_manifold.cpp keeps the plain version, with a std::map per edge and per ring,
/// and holds the two to the same output. Cost: O(corners log corners).
inline ManifoldFaces make_manifold(const std::vector<std::vector<std::uint32_t>>& faces,
                                   std::size_t vertex_count) {
    ManifoldFaces out;
    out.origin.resize(vertex_count);
    std::iota(out.origin.begin(), out.origin.end(), std::uint32_t{0});
    auto copy_of = [&](std::uint32_t v) {
        out.origin.push_back(out.origin[v]);
        return static_cast<std::uint32_t>(out.origin.size() - 1);
    };
    // (1) Edges: each directed edge once, each undirected edge at most twice.
    detail::EdgeUses edges(faces, vertex_count);
    out.faces.reserve(faces.size());
    for (const auto& f : faces) {
        bool fits = true;
        for (std::size_t k = 0; k < f.size() && fits; ++k)
            fits = edges.fits(f[k], f[(k + 1) % f.size()]);
        std::vector<std::uint32_t> g = f;
        if (fits)
            for (std::size_t k = 0; k < f.size(); ++k) edges.add(f[k], f[(k + 1) % f.size()]);
        else
            for (auto& v : g) v = copy_of(v);
        out.faces.push_back(std::move(g));
    }
    // (2) Fans: the (face, corner) pairs around each vertex, in face order, then each fan after
    // the first onto a copy of the vertex.
    std::vector<std::size_t> corners(out.origin.size(), 0);
    for (const auto& f : out.faces)
        for (const std::uint32_t v : f) ++corners[v];
    detail::VertexRows<std::pair<std::uint32_t, std::uint32_t>> around(corners);
    for (std::size_t f = 0; f < out.faces.size(); ++f)
        for (std::size_t k = 0; k < out.faces[f].size(); ++k)
            around.push(out.faces[f][k], {std::uint32_t(f), std::uint32_t(k)});
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> fan, vertex_of;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> scratch;
    const auto vertices = static_cast<std::uint32_t>(around.rows());
    for (std::uint32_t v = 0; v < vertices; ++v) {
        const auto ring = std::as_const(around).row(v);
        if (ring.size() < 2) continue;
        detail::fans_around(out.faces, ring, fan, scratch);
        vertex_of.assign(ring.size(), none);  // per fan (by its first entry): the vertex it takes
        bool first = true;
        for (std::size_t r = 0; r < ring.size(); ++r) {
            std::uint32_t& mine = vertex_of[fan[r]];
            if (mine == none) {
                mine = first ? v : copy_of(v);
                first = false;
            }
            out.faces[ring[r].first][ring[r].second] = mine;
        }
    }
    return out;
}

}  // namespace radiosity
