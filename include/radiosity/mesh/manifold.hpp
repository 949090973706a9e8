#pragma once
/// @file manifold.hpp  Making a polygon soup into an oriented 2-manifold with boundary before it
/// goes into OpenMesh: a half-edge mesh cannot hold an edge shared by three faces, two faces
/// that disagree on an edge's direction, or two fans of faces meeting at one vertex (a
/// "bow-tie"), and OpenMesh's add_face may even abort on some of those. Scenes from files have
/// all of them, so faces and vertices are split here, where it is cheap and always works.

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

namespace radiosity {

/// Faces over vertex indices after make_manifold: vertices at or beyond the input count are
/// copies, and origin[v] names the input vertex each output vertex stands for.
struct ManifoldFaces {
    std::vector<std::vector<std::uint32_t>> faces;  ///< the faces, in input order
    std::vector<std::uint32_t> origin;              ///< input vertex of every output vertex
};

/// Splits vertices so that the faces form an oriented 2-manifold with boundary: (1) a face that
/// would add a third face to an edge, or run along an edge in the same direction as a face
/// already there, gets its own copies of its vertices; (2) at every vertex, the faces around it
/// are grouped into fans connected through shared edges, and each fan after the first gets its
/// own copy of the vertex. Faces must have distinct vertices. Cost: O(corners log corners).
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
    std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& f : faces) {
        bool fits = true;
        for (std::size_t k = 0; k < f.size() && fits; ++k) {
            const std::uint32_t a = f[k], b = f[(k + 1) % f.size()];
            const auto key = std::minmax(a, b);
            fits = !directed.count({a, b}) && uses[{key.first, key.second}] < 2;
        }
        std::vector<std::uint32_t> g = f;
        if (fits) {
            for (std::size_t k = 0; k < f.size(); ++k) {
                const std::uint32_t a = f[k], b = f[(k + 1) % f.size()];
                directed.insert({a, b});
                const auto key = std::minmax(a, b);
                ++uses[{key.first, key.second}];
            }
        } else {
            for (auto& v : g) v = copy_of(v);
        }
        out.faces.push_back(std::move(g));
    }
    // (2) Fans: union the faces around each vertex that share an edge at it.
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> around(out.origin.size());
    for (std::size_t f = 0; f < out.faces.size(); ++f)
        for (std::size_t k = 0; k < out.faces[f].size(); ++k)
            around[out.faces[f][k]].push_back({f, k});
    for (std::uint32_t v = 0; v < around.size(); ++v) {
        const auto& ring = around[v];
        if (ring.size() < 2) continue;
        std::vector<std::size_t> group(ring.size());
        std::iota(group.begin(), group.end(), std::size_t{0});
        auto find = [&](std::size_t x) {
            while (group[x] != x) x = group[x] = group[group[x]];
            return x;
        };
        std::map<std::uint32_t, std::size_t> by_neighbour;  // other end of an edge at v -> face
        for (std::size_t r = 0; r < ring.size(); ++r) {
            const auto& f = out.faces[ring[r].first];
            const std::size_t k = ring[r].second, n = f.size();
            for (std::uint32_t w : {f[(k + 1) % n], f[(k + n - 1) % n]}) {
                auto [it, fresh] = by_neighbour.try_emplace(w, r);
                if (!fresh) group[find(r)] = find(it->second);
            }
        }
        std::map<std::size_t, std::uint32_t> vertex_of;  // fan root -> vertex for that fan
        for (std::size_t r = 0; r < ring.size(); ++r) {
            const std::size_t root = find(r);
            auto [it, fresh] = vertex_of.try_emplace(root, v);
            if (fresh && vertex_of.size() > 1) it->second = copy_of(v);
            out.faces[ring[r].first][ring[r].second] = it->second;
        }
    }
    return out;
}

}  // namespace radiosity
