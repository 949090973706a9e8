#pragma once
/// @file bake.hpp  Baking a shaded mesh into a lightmap: every texel whose square touches a
/// triangle in UV space (conservative rasterisation: Hasselgren, Akenine-Moeller & Ohlsson 2005,
/// "Conservative Rasterization", GPU Gems 2, ch. 42) takes the vertex-interpolated radiosity at
/// its point on the surface - the texel centre if a triangle covers it, else the nearest point of
/// the nearest triangle, so thin triangles are never lost. Texels whose point lies inside or
/// behind geometry (most of a few rays from it hit back faces) are refilled from valid
/// neighbours; then dilation grows every chart into its gutter, never over a valid texel and
/// never from another chart. Everything per texel is seeded from its index: the result does not
/// depend on the thread count.

#include <radiosity/error.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/shading/image.hpp>
#include <radiosity/shading/shaded_mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace radiosity {

/// What a texel of a baked lightmap holds.
enum class TexelState : std::uint8_t {
    empty,    ///< no triangle touches it and dilation did not reach it (black)
    surface,  ///< the radiosity at its point on a surface
    inside,   ///< its point lies inside or behind geometry; refilled from valid neighbours
    dilated,  ///< gutter texel filled from its chart by dilation
};

/// Settings of the bake.
struct BakeOptions {
    int inside_rays = 16;          ///< rays per texel for the inside-geometry test (0: no test)
    double inside_fraction = 0.5;  ///< inside if more of its rays than this hit back faces
    int dilation = 2;              ///< texels each chart grows into its gutter
    std::uint64_t seed = 1;        ///< base seed of the per-texel ray directions
};

/// A baked lightmap: linear radiant exitance B per texel (row 0 on top, as UVs have it), what
/// each texel holds and the chart (connected island of texels) it belongs to.
struct Lightmap {
    Image image;                        ///< B per texel (RGB); io/image.hpp writes it
    std::vector<TexelState> state;      ///< per texel
    std::vector<std::uint32_t> island;  ///< per texel: its chart's island, or no_island
    static constexpr std::uint32_t no_island = UINT32_MAX;  ///< island of an empty texel

    /// Index of texel (x, y).
    std::size_t index(int x, int y) const { return std::size_t(y) * image.width + x; }
    /// Number of texels in the given state.
    std::size_t count(TexelState s) const {
        return static_cast<std::size_t>(std::count(state.begin(), state.end(), s));
    }
};

namespace detail {

/// The best triangle point found for a texel: squared distance (texels) from the texel centre
/// to the triangle (0 if the centre is covered), the triangle, and the point's barycentrics.
struct TexelHit {
    double distance2 = std::numeric_limits<double>::infinity();
    std::uint32_t triangle = 0;
    glm::dvec3 weight{0.0};
};

/// Nearest point to p on the segment a-b, as the parameter s in [0, 1] along it.
inline double nearest_on_segment(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) {
    const glm::dvec2 d = b - a;
    const double len2 = glm::dot(d, d);
    return len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
}

/// The point of triangle t (texel coordinates) nearest to p: barycentrics and squared distance.
/// Inside (edge functions of one sign, Pineda 1988) the point is p itself; outside, the
/// nearest point of the three edges.
/// area is cross2(t[1] - t[0], t[2] - t[0]), twice the signed area, computed once per triangle.
inline TexelHit nearest_point(const std::array<glm::dvec2, 3>& t, double area,
                              const glm::dvec2& p) {
    const double w0 = cross2(t[2] - t[1], p - t[1]), w1 = cross2(t[0] - t[2], p - t[2]),
                 w2 = cross2(t[1] - t[0], p - t[0]);
    TexelHit hit;
    if (area != 0.0 && w0 * area >= 0.0 && w1 * area >= 0.0 && w2 * area >= 0.0) {
        hit.distance2 = 0.0;
        hit.weight = glm::dvec3(w0, w1, w2) / area;
        return hit;
    }
    for (int e = 0; e < 3; ++e) {
        const int a = e, b = (e + 1) % 3;
        const double s = nearest_on_segment(t[a], t[b], p);
        const glm::dvec2 q = t[a] + s * (t[b] - t[a]);
        const double d2 = glm::dot(p - q, p - q);
        if (d2 < hit.distance2) {
            hit.distance2 = d2;
            hit.weight = glm::dvec3(0.0);
            hit.weight[a] = 1.0 - s;
            hit.weight[b] = s;
        }
    }
    return hit;
}

/// Whether the texel square [x, x+1] x [y, y+1] touches triangle t: the separating-axis test
/// with the triangle's edge normals (the box's own axes are covered by the caller's bounding
/// box). A degenerate triangle is a segment: the square must straddle its line.
inline bool square_touches(const std::array<glm::dvec2, 3>& t, double area, double x, double y) {
    const std::array<glm::dvec2, 4> corner{glm::dvec2(x, y), glm::dvec2(x + 1, y),
                                           glm::dvec2(x, y + 1), glm::dvec2(x + 1, y + 1)};
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 a = t[e], d = t[(e + 1) % 3] - a;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const auto& c : corner) {
            const double f = cross2(d, c - a);
            lo = std::min(lo, f);
            hi = std::max(hi, f);
        }
        if (area > 0.0 ? hi < 0.0 : area < 0.0 ? lo > 0.0 : (lo > 0.0 || hi < 0.0)) return false;
    }
    return true;
}

/// Conservative rasterisation of every triangle in UV space: for each texel, the nearest
/// triangle point (ties go to the lower triangle index, so the result is deterministic).
inline std::vector<TexelHit> cover_texels(const ShadedMesh& mesh, int width, int height) {
    std::vector<TexelHit> best(std::size_t(width) * height);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        std::array<glm::dvec2, 3> t;
        for (int k = 0; k < 3; ++k)
            t[k] = glm::dvec2(mesh.uvs[mesh.triangles[i][k]]) * glm::dvec2(width, height);
        const double area = cross2(t[1] - t[0], t[2] - t[0]);  // twice the signed area
        const glm::dvec2 lo = glm::min(t[0], glm::min(t[1], t[2])),
                         hi = glm::max(t[0], glm::max(t[1], t[2]));
        const int x0 = std::max(0, int(std::floor(lo.x)) - (std::floor(lo.x) == lo.x ? 1 : 0)),
                  y0 = std::max(0, int(std::floor(lo.y)) - (std::floor(lo.y) == lo.y ? 1 : 0));
        const int x1 = std::min(width - 1, int(std::floor(hi.x))),
                  y1 = std::min(height - 1, int(std::floor(hi.y)));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                if (!square_touches(t, area, x, y)) continue;
                TexelHit h = nearest_point(t, area, glm::dvec2(x + 0.5, y + 0.5));
                h.triangle = static_cast<std::uint32_t>(i);
                TexelHit& b = best[std::size_t(y) * width + x];
                if (h.distance2 < b.distance2) b = h;
            }
    }
    return best;
}

/// Calls visit(j) for each of the (up to) 8 neighbours j of texel i in a w x h map, row by row.
template <class Visit>
void for_each_neighbour(int w, int h, std::size_t i, Visit&& visit) {
    const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx != 0 || dy != 0) && nx >= 0 && ny >= 0 && nx < w && ny < h)
                visit(std::size_t(ny) * std::size_t(w) + std::size_t(nx));
        }
}

/// Labels the 8-connected islands of covered texels (one per chart when charts are apart),
/// numbered in scan order. Flood fill with an explicit stack.
inline void label_islands(Lightmap& lm) {
    const int w = lm.image.width, h = lm.image.height;
    std::uint32_t next = 0;
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < lm.state.size(); ++start) {
        if (lm.state[start] == TexelState::empty || lm.island[start] != Lightmap::no_island)
            continue;
        lm.island[start] = next;
        stack.push_back(start);
        while (!stack.empty()) {
            const std::size_t i = stack.back();
            stack.pop_back();
            for_each_neighbour(w, h, i, [&](std::size_t j) {
                if (lm.state[j] == TexelState::empty || lm.island[j] != Lightmap::no_island) return;
                lm.island[j] = next;
                stack.push_back(j);
            });
        }
        ++next;
    }
}

/// Whether the point p of a surface with unit normal n is inside or behind geometry: of `rays`
/// cosine-distributed, stratified rays from just above it, more than `fraction` hit the back of
/// a triangle (a point in open space sees only front faces, or nothing).
inline bool inside_geometry(const Bvh& bvh, const PatchTable& triangles, const Vec3& p,
                            const Vec3& n, double offset, const BakeOptions& o,
                            std::uint64_t seed) {
    const Vec3 a = std::abs(n.x) > 0.5 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    const Vec3 t = glm::normalize(glm::cross(a, n)), b = glm::cross(n, t);
    const Vec3 origin = p + offset * n;
    Rng rng(seed);
    const double need = o.inside_fraction * o.inside_rays;  // inside if back > need
    int back = 0;
    for (int r = 0; r < o.inside_rays; ++r) {
        // Stop as soon as the remaining rays cannot change the verdict (the same verdict as
        // casting all of them, for about half the rays).
        if (back > need) return true;
        if (back + (o.inside_rays - r) <= need) return false;
        // Malley's method: uniform on the disc (stratified in radius^2), lifted to the hemisphere.
        const double u = (r + rng.uniform()) / o.inside_rays,
                     phi = 2.0 * std::numbers::pi * rng.uniform();
        const double s = std::sqrt(u);
        const Vec3 d = s * std::cos(phi) * t + s * std::sin(phi) * b + std::sqrt(1.0 - u) * n;
        const auto hit = bvh.intersect(origin, d);
        if (hit && glm::dot(d, triangles.normal(hit->patch)) > 0.0) ++back;
    }
    return back > need;
}

/// Growth of a fill or a dilation, ring by ring, for at most `passes` rings: in each ring, every
/// texel for which `want` holds and which has neighbours already holding light takes the mean
/// of those of them in the lowest-numbered island, and joins that island. A ring is decided on
/// the light of the rings before it, so the order within a ring is irrelevant; only the
/// frontier is visited, so the cost is O(texels filled), not O(rings x atlas).
template <class Want>
void grow(Lightmap& lm, std::vector<bool>& has_light, Want want, TexelState now, int passes) {
    const int w = lm.image.width, h = lm.image.height;
    auto neighbours = [w, h](std::size_t i, auto&& visit) { for_each_neighbour(w, h, i, visit); };
    std::vector<bool> queued(has_light.size(), false);
    std::vector<std::size_t> frontier;
    auto enqueue = [&](std::size_t j) {
        if (!has_light[j] && !queued[j] && want(j)) {
            queued[j] = true;
            frontier.push_back(j);
        }
    };
    for (std::size_t i = 0; i < has_light.size(); ++i)
        if (has_light[i]) neighbours(i, enqueue);
    std::vector<std::pair<std::size_t, std::pair<glm::vec3, std::uint32_t>>> fills;
    for (int pass = 0; pass < passes && !frontier.empty(); ++pass) {
        fills.clear();
        for (std::size_t i : frontier) {
            std::uint32_t island = Lightmap::no_island;
            neighbours(i, [&](std::size_t j) {
                if (has_light[j]) island = std::min(island, lm.island[j]);
            });
            glm::vec3 sum(0.0f);
            int n = 0;
            neighbours(i, [&](std::size_t j) {
                if (has_light[j] && lm.island[j] == island) {
                    sum += lm.image.pixels[j];
                    ++n;
                }
            });
            fills.push_back({i, {sum / float(n), island}});
        }
        frontier.clear();
        for (const auto& [i, f] : fills) {
            lm.image.pixels[i] = f.first;
            lm.island[i] = f.second;
            lm.state[i] = now;
            has_light[i] = true;
        }
        for (const auto& fill : fills) neighbours(fill.first, enqueue);
    }
}

/// Evaluates every covered texel: the interpolated radiosity and point, and the inside test.
inline void shade_texels(Lightmap& lm, const ShadedMesh& mesh, const std::vector<TexelHit>& hits,
                         const BakeOptions& o) {
    PatchTable triangles;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        triangles.add(
            std::array<Vec3, 3>{mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]},
            "bake: triangle " + std::to_string(i));
    }
    const Bvh bvh = o.inside_rays > 0 ? Bvh(triangles) : Bvh();
    Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double offset = 1e-5 * glm::length(hi - lo);  // off the surface, not through a wall
    const auto n = static_cast<std::ptrdiff_t>(hits.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 256)
#endif
    for (std::ptrdiff_t k = 0; k < n; ++k) {
        const auto i = static_cast<std::size_t>(k);
        const TexelHit& hit = hits[i];
        if (!std::isfinite(hit.distance2)) continue;
        const auto& t = mesh.triangles[hit.triangle];
        const glm::dvec3 w = hit.weight;
        glm::dvec3 c(0.0), p(0.0);
        for (int v = 0; v < 3; ++v) {
            c += w[v] * glm::dvec3(mesh.colours[t[v]]);
            p += w[v] * mesh.positions[t[v]];
        }
        lm.image.pixels[i] = glm::vec3(c);
        const bool inside =
            o.inside_rays > 0 && inside_geometry(bvh, triangles, p, triangles.normal(hit.triangle),
                                                 offset, o, splitmix64(o.seed ^ splitmix64(i)));
        lm.state[i] = inside ? TexelState::inside : TexelState::surface;
    }
}

}  // namespace detail

/// Bakes the vertex-interpolated radiosity of a shaded mesh with lightmap UVs into a width x
/// height lightmap (see the file comment). Throws Error if the mesh has no UVs, a UV is not a
/// finite number, a triangle has zero area, or the options are out of range.
/// Cost: O(triangles + texels x inside_rays x log triangles).
inline Lightmap bake_lightmap(const ShadedMesh& mesh, int width, int height,
                              const BakeOptions& options = {}) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw Error("bake: lightmap size must be in [1, 16384], not " + std::to_string(width) +
                    " x " + std::to_string(height));
    if (mesh.uvs.size() != mesh.positions.size()) throw Error("bake: the mesh has no lightmap UVs");
    for (std::size_t v = 0; v < mesh.uvs.size(); ++v)
        if (!std::isfinite(mesh.uvs[v].x) || !std::isfinite(mesh.uvs[v].y))
            throw Error("bake: the UV of vertex " + std::to_string(v) + " is not a finite number");
    if (options.inside_rays < 0 || options.inside_rays > 1024 || options.dilation < 0 ||
        options.dilation > 256 ||
        !(options.inside_fraction >= 0.0 && options.inside_fraction < 1.0))
        throw Error(
            "bake: inside_rays must be in [0, 1024], dilation in [0, 256] and "
            "inside_fraction in [0, 1)");
    Lightmap lm;
    const std::size_t texels = std::size_t(width) * height;
    lm.image = Image{width, height, std::vector<glm::vec3>(texels, glm::vec3(0.0f))};
    lm.state.assign(texels, TexelState::empty);
    lm.island.assign(texels, Lightmap::no_island);
    detail::shade_texels(lm, mesh, detail::cover_texels(mesh, width, height), options);
    detail::label_islands(lm);
    // Texels inside geometry take the light of their valid neighbours, ring by ring.
    std::vector<bool> has_light(texels);
    for (std::size_t i = 0; i < texels; ++i) has_light[i] = lm.state[i] == TexelState::surface;
    auto inside = [&](std::size_t i) { return lm.state[i] == TexelState::inside; };
    detail::grow(lm, has_light, inside, TexelState::inside, width + height);
    // Dilation: the gutter takes the light of its own chart only.
    for (std::size_t i = 0; i < texels; ++i) has_light[i] = lm.state[i] != TexelState::empty;
    auto empty = [&](std::size_t i) { return lm.state[i] == TexelState::empty; };
    detail::grow(lm, has_light, empty, TexelState::dilated, options.dilation);
    return lm;
}

}  // namespace radiosity
