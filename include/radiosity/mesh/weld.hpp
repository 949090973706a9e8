#pragma once
/// @file weld.hpp  Merging coincident vertices ("welding"): scenes from files often repeat a
/// vertex once per face (separate quads of one wall, polygon soups), and both the conforming
/// subdivision and the lightmap charts need to know which faces really share an edge.

#include <radiosity/geometry/vec.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <unordered_map>
#include <vector>

namespace radiosity {

namespace detail {

/// Union-find with path halving (Tarjan 1975), for merging vertices and edge classes.
class DisjointSets {
  public:
    explicit DisjointSets(std::size_t n) : parent_(n) {
        std::iota(parent_.begin(), parent_.end(), std::size_t{0});
    }
    std::size_t find(std::size_t x) {
        while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
        return x;
    }
    void unite(std::size_t a, std::size_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // deterministic representative
    }

  private:
    std::vector<std::size_t> parent_;
};

/// Hash of a cell of a uniform 3-D grid: splitmix64's finaliser (Steele et al. 2014) over the
/// coordinates. Cell coordinates of a regular mesh are multiples of one large number, which
/// plain multiply-and-xor hashes map to few buckets.
struct CellHash {
    static std::uint64_t mix(std::uint64_t z) {
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
        std::uint64_t h = 0;
        for (std::int64_t x : c) h = mix(h ^ static_cast<std::uint64_t>(x));
        return static_cast<std::size_t>(h);
    }
};

}  // namespace detail

/// Groups points closer than eps (transitively) and returns, for each point, the smallest index
/// in its group. Points go into a hash grid of cells 2 eps wide, so each is compared only with
/// the points of the (at most 8) cells its eps-ball touches, and close pairs are joined by
/// union-find: O(n) expected, even for a wall where thousands of vertices share a coordinate
/// (a sweep along one axis would compare them all with each other). eps = 0 merges equal points.
inline std::vector<std::size_t> weld_points(std::span<const Vec3> p, double eps) {
    const std::size_t n = p.size();
    const double cell = eps > 0.0 ? 2.0 * eps : 1.0;
    auto cell_of = [&](const Vec3& x) {
        return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(x.x / cell)),
                                           static_cast<std::int64_t>(std::floor(x.y / cell)),
                                           static_cast<std::int64_t>(std::floor(x.z / cell))};
    };
    // Each cell keeps its last point; next[v] links to the cell's point before v.
    constexpr std::uint32_t end = std::numeric_limits<std::uint32_t>::max();
    std::unordered_map<std::array<std::int64_t, 3>, std::uint32_t, detail::CellHash> grid;
    grid.reserve(n);
    std::vector<std::uint32_t> next(n, end);
    detail::DisjointSets sets(n);
    for (std::size_t v = 0; v < n; ++v) {
        const auto c0 = cell_of(p[v] - eps), c1 = cell_of(p[v] + eps);
        for (std::int64_t x = c0[0]; x <= c1[0]; ++x)
            for (std::int64_t y = c0[1]; y <= c1[1]; ++y)
                for (std::int64_t z = c0[2]; z <= c1[2]; ++z) {
                    const auto it = grid.find({x, y, z});
                    if (it == grid.end()) continue;
                    for (std::uint32_t u = it->second; u != end; u = next[u])
                        if (glm::distance(p[u], p[v]) <= eps) sets.unite(u, v);
                }
        auto [it, fresh] = grid.try_emplace(cell_of(p[v]), static_cast<std::uint32_t>(v));
        if (!fresh) {
            next[v] = it->second;
            it->second = static_cast<std::uint32_t>(v);
        }
    }
    std::vector<std::size_t> group(n);
    for (std::size_t v = 0; v < n; ++v) group[v] = sets.find(v);
    return group;
}

/// A mesh's vertices welded: their points (by vertex index), the diagonal of their bounding box,
/// and for each vertex its group's smallest index, merging vertices within 1e-9 of the diagonal
/// (weld_points). What the subdivision and the lightmap charts both start from.
struct MeshWeld {
    std::vector<Vec3> point;
    std::vector<std::size_t> group;
    double diagonal = 0.0;
};

/// Welds the vertices of an OpenMesh mesh (see MeshWeld). O(n) expected.
template <class M>
MeshWeld weld_mesh(const M& mesh) {
    MeshWeld w;
    w.point.resize(mesh.n_vertices());
    Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (auto v : mesh.vertices()) {
        const auto& q = mesh.point(v);
        const Vec3 x(q[0], q[1], q[2]);
        w.point[static_cast<std::size_t>(v.idx())] = x;
        lo = glm::min(lo, x);
        hi = glm::max(hi, x);
    }
    w.diagonal = w.point.empty() ? 0.0 : glm::length(hi - lo);
    w.group = weld_points(w.point, 1e-9 * w.diagonal);
    return w;
}

}  // namespace radiosity
