#pragma once
/// @file conforming.hpp  Patches made conforming along the lines their edges lie on: where a
/// patch edge has a point of a neighbour strictly inside it (a T-junction), the point becomes a
/// vertex of the patch too. A convex patch stays convex (the new corner is straight), and the
/// mesh is then a proper cell complex: every edge is shared by matching vertices or lies on the
/// boundary, so smooth shading has no cracks. Each patch edge names its carrier (an input edge,
/// or a line inside one input face: a diagonal or grid line of its cutting) and the parameters
/// of its ends along it; points of one carrier closer than a tolerance are one point.

#include <radiosity/geometry/vec.hpp>

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <utility>
#include <vector>

namespace radiosity::detail {

/// Where a patch edge lies: carrier `carrier` (none: inside a face, where nothing can meet it)
/// from parameter ta (its first corner) to tb.
struct EdgeOn {
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    std::uint32_t carrier = none;
    double ta = 0.0, tb = 0.0;
};

/// Patches as a polygon soup over shared points, with the carrier of every edge.
struct PatchSoup {
    std::vector<Vec3> points;
    std::vector<std::vector<std::uint32_t>> faces;
    std::vector<std::size_t> parent;          // the input face of each patch
    std::vector<std::vector<glm::vec2>> uvs;  // per corner, or empty
    std::vector<std::vector<EdgeOn>> on;      // per edge (from corner k to k + 1)
    std::vector<double> carrier_length;       // scene units per unit of a carrier's parameter
    std::uint32_t add_carrier(double length) {
        carrier_length.push_back(length);
        return static_cast<std::uint32_t>(carrier_length.size() - 1);
    }
};

/// Makes the soup conforming (see the file comment): first points of one carrier within `eps`
/// of each other (in scene units along it) become the first of them, then every edge takes the
/// points of its carrier strictly between its ends, in order, with UVs interpolated along the
/// edge. Only carriers at or above `first_carrier` are used (so that input edges can be left
/// out when faces are split each by itself). Returns the number of points inserted. Cost:
/// O(E log E) for E patch edges on carriers.
inline std::size_t make_conforming(PatchSoup& s, double eps, std::uint32_t first_carrier = 0) {
    constexpr std::uint32_t none = EdgeOn::none;
    const std::size_t nc = s.carrier_length.size();
    std::vector<std::vector<std::pair<double, std::uint32_t>>> along(nc);
    for (std::size_t f = 0; f < s.faces.size(); ++f)
        for (std::size_t k = 0; k < s.faces[f].size(); ++k) {
            const EdgeOn& e = s.on[f][k];
            if (e.carrier == none || e.carrier < first_carrier) continue;
            along[e.carrier].push_back({e.ta, s.faces[f][k]});
            along[e.carrier].push_back({e.tb, s.faces[f][(k + 1) % s.faces[f].size()]});
        }
    std::vector<std::uint32_t> same(s.points.size());
    std::iota(same.begin(), same.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (same[x] != x) x = same[x] = same[same[x]];
        return x;
    };
    for (std::size_t c = 0; c < nc; ++c) {
        auto& list = along[c];
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        const double tol = eps / std::max(s.carrier_length[c], 1e-300);
        for (std::size_t k = 1; k < list.size(); ++k)  // near points: one point, the first
            if (list[k].first - list[k - 1].first <= tol) {
                const std::uint32_t a = find(list[k - 1].second), b = find(list[k].second);
                if (a != b) same[std::max(a, b)] = std::min(a, b);
            }
    }
    std::size_t inserted = 0;
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
        const auto& v = s.faces[f];
        const bool uv = !s.uvs[f].empty();
        std::vector<std::uint32_t> out;
        std::vector<glm::vec2> out_uv;
        std::vector<EdgeOn> out_on;
        for (std::size_t k = 0; k < v.size(); ++k) {
            const EdgeOn& e = s.on[f][k];
            out.push_back(find(v[k]));
            if (uv) out_uv.push_back(s.uvs[f][k]);
            out_on.push_back(e);
            if (e.carrier == none || e.carrier < first_carrier) continue;
            const auto& list = along[e.carrier];
            const std::uint32_t a = find(v[k]), b = find(v[(k + 1) % v.size()]);
            const double lo = std::min(e.ta, e.tb), hi = std::max(e.ta, e.tb);
            auto first = std::upper_bound(list.begin(), list.end(),
                                          std::pair(lo, std::numeric_limits<std::uint32_t>::max()));
            auto last = std::lower_bound(list.begin(), list.end(), std::pair(hi, 0u));
            std::vector<std::pair<double, std::uint32_t>> between(first, last);
            if (e.ta > e.tb) std::reverse(between.begin(), between.end());
            for (const auto& [t, p] : between) {
                const std::uint32_t q = find(p);
                if (q == a || q == b || q == out.back()) continue;
                out_on.back().tb = t;  // the edge so far ends here; the rest starts here
                out_on.push_back({e.carrier, t, e.tb});
                out.push_back(q);
                if (uv) {
                    const double w = (t - e.ta) / (e.tb - e.ta);
                    const glm::vec2 a_uv = s.uvs[f][k], b_uv = s.uvs[f][(k + 1) % v.size()];
                    out_uv.push_back(a_uv + static_cast<float>(w) * (b_uv - a_uv));
                }
                ++inserted;
            }
        }
        // Points made one may leave a corner twice in a row: drop the empty edge between.
        std::vector<std::uint32_t> v2;
        std::vector<glm::vec2> uv2;
        std::vector<EdgeOn> on2;
        for (std::size_t k = 0; k < out.size(); ++k) {
            if (out[k] == out[(k + 1) % out.size()]) continue;
            v2.push_back(out[k]);
            if (uv) uv2.push_back(out_uv[k]);
            on2.push_back(out_on[k]);
        }
        s.faces[f] = std::move(v2);
        if (uv) s.uvs[f] = std::move(uv2);
        s.on[f] = std::move(on2);
    }
    return inserted;
}

}  // namespace radiosity::detail
