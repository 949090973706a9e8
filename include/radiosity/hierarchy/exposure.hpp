#pragma once
/// @file exposure.hpp  How much of each element is exposed: the share of its area from which
/// the scene can be seen at all, as opposed to the part hidden inside a solid or pressed against
/// another face (a floor under a block, a ceiling where a pillar meets it, a lamp's globe inside
/// its shade). A coarse link averages its transfer over the whole receiver, the hidden part
/// included, and a coarse source's radiosity is a mean over its whole area; pushed and pulled
/// by area alone, the hidden parts take light they never see and dim the light their nodes
/// send, a leak that a room of reflectance 0.9 multiplies about tenfold (room3 lost 5%). So the
/// hierarchy works with the exposed part of each node (gather.hpp): its irradiance per unit of
/// exposed area going down, its radiosity as the exposed parts' mean going up.
///
/// A sample point is hidden if every ray of a few cosine-weighted ones from it first meets the
/// back of a face (it lies inside a closed solid) or meets a face in contact (within eps: two
/// faces pressed together); a ray that meets a face's front, or nothing (an open scene), shows
/// the point exposed. Exposure is a pure function of the element and the seed: the streams are
/// seeded by the node's key, so the values never depend on threads, ranks or when they are
/// computed (a resumed solve finds the same ones).
///
/// The same rays tell whether a leaf is enclosed (element_enclosed): whether faces' fronts cover
/// the whole hemisphere above its exposed part, so that its form factors to all it sees sum to
/// 1, the row sum to which the sweeps scale its links' (gather.hpp: scale_row_sums).

#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/hierarchy/links.hpp>
#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

namespace radiosity {

/// Rays cast from a sample point before it is called hidden: one that sees a front face or
/// open space settles it exposed, so an exposed point costs one ray nearly always.
inline constexpr int exposure_rays_per_point = 4;

/// An element that its first sample points find partly hidden is sampled again on a jittered
/// grid of exposure_strata x exposure_strata points, and its exposure is their share: the
/// exposed part's irradiance is H / e, and the noise of an estimate of e biases 1 / e upwards
/// (Jensen's inequality; with 16 independent points about 6% for e = 1/2), which a partly hidden
/// element would re-emit as light it never received. Stratified, the error comes only from the
/// strata that the hidden part's edge crosses (about k of the k^2 for a straight edge): for
/// e = 1/2, a variance of about k / (4 k^4) = 5e-4 with k = 8 (256 independent points: 1e-3),
/// which biases 1 / e by under 0.5%. (polygon_point maps the unit square to the element
/// preserving area, so equal cells of the square are equal parts of the element.)
inline constexpr int exposure_strata = 8;

/// What the rays from an element's points need: its normal and two tangents (the frame of the
/// cosine-weighted directions), its root (which the rays skip), the distance within which a
/// face is in contact, and its polygon.
struct ElementFrame {
    Vec3 normal, t1, t2;
    std::uint32_t own;
    double eps;
    std::span<const Vec3> polygon;
};

/// The frame of element n.
inline ElementFrame element_frame(const Hierarchy& h, NodeId n) {
    const Vec3 nrm = h.normal[n];
    const Vec3 t1 = glm::normalize(std::abs(nrm.x) < 0.9 ? glm::cross(nrm, Vec3(1, 0, 0))
                                                         : glm::cross(nrm, Vec3(0, 1, 0)));
    return {nrm,
            t1,
            glm::cross(nrm, t1),
            h.root_of(n),
            1e-9 * (h.radius[0] + glm::length(h.centre[0]) + 1.0),
            h.polygon(n)};
}

/// The cosine-weighted direction about frame f's normal of the point (a, phi) of the unit disc
/// in polar form (r^2 = a), by Malley's method: a uniform point of the disc, lifted to the
/// hemisphere, is a direction of density cos(theta) / pi.
inline Vec3 cosine_direction(const ElementFrame& f, double a, double phi) {
    return std::sqrt(a) * (std::cos(phi) * f.t1 + std::sin(phi) * f.t2) +
           std::sqrt(1.0 - a) * f.normal;
}

/// Whether the scene is seen from point x of the element of frame f: up to
/// exposure_rays_per_point cosine-weighted rays, the first that meets a face's front or nothing
/// settling it. Contact: a face within f.eps of x along the ray (either side, the own root
/// skipped) is pressed against it, and no light comes between. If the point is exposed and one
/// of its rays met something other than a face's front (nothing, a back, a face in contact),
/// *open is set: the point is not enclosed (element_enclosed).
inline bool point_exposed(const Hierarchy& h, const Bvh& bvh, const Vec3& x, const ElementFrame& f,
                          Rng& rng, bool* open = nullptr) {
    bool missed_front = false;
    for (int k = 0; k < exposure_rays_per_point; ++k) {
        const double a = rng.uniform();
        const Vec3 d = cosine_direction(f, a, 2.0 * std::numbers::pi * rng.uniform());
        const auto hit =
            bvh.intersect(x, d, -f.eps, std::numeric_limits<double>::infinity(), f.own);
        const bool front = hit && hit->t > f.eps && glm::dot(h.roots.normal(hit->patch), d) < 0.0;
        if (!hit || front) {
            if (open != nullptr && (!hit || missed_front)) *open = true;
            return true;
        }
        missed_front = true;
    }
    return false;
}

/// Exposure of element n in [0, 1]: the share of sample points, uniform in area, from which
/// the scene is seen (point_exposed): `points` independent ones, and where they disagree (the
/// element is partly hidden) the share of exposure_strata^2 jittered ones instead. *open is set
/// if a ray from an exposed point met anything but a face's front: the element is then not
/// enclosed (element_enclosed), whose test it spares. Seeded by the node's key and `seed`.
/// Cost: about `points` closest-hit queries for an exposed element, 4 x that for a hidden one,
/// and 64 more points for one partly hidden (a wall where a pillar meets it).
inline double element_exposure(const Hierarchy& h, const Bvh& bvh, NodeId n, int points,
                               std::uint64_t seed, bool* open = nullptr) {
    Rng rng(splitmix64(seed ^ (0x5eedull << 40) ^ splitmix64(h.key[n])));
    const ElementFrame f = element_frame(h, n);
    int seen = 0;
    for (int p = 0; p < points; ++p) {
        const double u = rng.uniform();
        const Vec3 x = detail::polygon_point(f.polygon, u, rng.uniform());
        seen += point_exposed(h, bvh, x, f, rng, open) ? 1 : 0;
    }
    if (seen == 0 || seen == points) return double(seen) / double(points);
    constexpr int k = exposure_strata;
    seen = 0;
    for (int i = 0; i < k * k; ++i) {  // cell (i / k, i % k) of the unit square, jittered
        const double u = (i / k + rng.uniform()) / k, v = (i % k + rng.uniform()) / k;
        const Vec3 x = detail::polygon_point(f.polygon, u, v);
        seen += point_exposed(h, bvh, x, f, rng, open) ? 1 : 0;
    }
    return double(seen) / double(k * k);
}

/// Whether element n is enclosed: whether faces' fronts cover the whole hemisphere above its
/// exposed part, so that its visible row sum, sum_j F_nj over the faces it sees, is 1 (as in a
/// closed room), by Malley's method: k x k points on a jittered grid over the element
/// (k = round(sqrt(rays)), at most 16), each with one cosine-weighted ray from a jittered grid
/// of k x k directions shuffled against the points (as link_visibility pairs its strata); the
/// element is enclosed if every ray from an exposed point meets a face's front. A point whose
/// ray meets anything else is tested for exposure (point_exposed), and a hidden one (inside a
/// solid, pressed against a face) does not count: what is tested is the exposed part's, as the
/// links' row sums are (gather.hpp). Only the verdict "enclosed" is used, not the share of the
/// rays that meet a front: that share is exact where it is 1, but elsewhere it scatters by
/// sqrt((1 - r) / (r k^2)) about the row sum r (a square beside another, r = 0.11: 35% with 64
/// rays), more than the links' row sums are off. An element whose row sum is just below 1
/// passes for enclosed with probability r^(k^2) (0.98 and 64 rays: 27%), and its row sum is
/// then taken 2% high. Seeded by the node's key and `seed`. Returns false where no point is
/// exposed. Cost: up to k^2 closest-hit queries, and 4 more for a hidden point; an element in
/// open space stops at its first ray that meets nothing.
inline bool element_enclosed(const Hierarchy& h, const Bvh& bvh, NodeId n, int rays,
                             std::uint64_t seed) {
    Rng rng(splitmix64(seed ^ (0x7011ull << 40) ^ splitmix64(h.key[n])));
    const int k = strata_side(rays);
    const auto strata = shuffled_strata(k, rng);
    const ElementFrame f = element_frame(h, n);
    bool exposed = false;
    for (int i = 0; i < k * k; ++i) {
        const int j = strata[std::size_t(i)];
        const double u = (i / k + rng.uniform()) / k, v = (i % k + rng.uniform()) / k;
        const Vec3 x = detail::polygon_point(f.polygon, u, v);
        // The direction from stratum j of the disc in polar form: (r^2, angle) on a k x k grid.
        const double a = (j / k + rng.uniform()) / k;
        const Vec3 d = cosine_direction(f, a, 2.0 * std::numbers::pi * (j % k + rng.uniform()) / k);
        const auto hit =
            bvh.intersect(x, d, -f.eps, std::numeric_limits<double>::infinity(), f.own);
        if (hit && hit->t > f.eps && glm::dot(h.roots.normal(hit->patch), d) < 0.0) {
            exposed = true;  // a front: the point sees the scene
        } else if (point_exposed(h, bvh, x, f, rng)) {
            return false;  // open space or a back, seen from an exposed point
        }
    }
    return exposed;
}

/// element_enclosed of each element of `nodes` (1 or 0), in their order, in parallel; an element
/// whose exposure test found it open (`open`, per node id, if not empty) is not enclosed without
/// more rays. Cost: their rays; in an open scene exposure finds most elements open (the Cornell
/// box as a million triangles: 765,000 of its 1,026,732 leaves).
inline std::vector<std::uint8_t> elements_enclosed(const Hierarchy& h, const Bvh& bvh, int rays,
                                                   std::uint64_t seed,
                                                   std::span<const NodeId> nodes,
                                                   std::span<const std::uint8_t> open = {}) {
    std::vector<std::uint8_t> out(nodes.size(), 0);
    const auto count = static_cast<std::int64_t>(nodes.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64)
#endif
    for (std::int64_t i = 0; i < count; ++i) {
        const NodeId n = nodes[std::size_t(i)];
        if (open.empty() || !open[n]) out[std::size_t(i)] = element_enclosed(h, bvh, n, rays, seed);
    }
    return out;
}

/// Sets the exposure of every node with children to the area-weighted mean of its children's,
/// bottom up (children have larger ids than their parent), so that exposed area adds up the
/// tree. Leaves keep theirs. Cost: O(nodes).
inline void mean_exposure(const Hierarchy& h, std::vector<double>& exposure) {
    for (std::size_t i = h.size(); i-- > 0;) {
        if (h.is_leaf(NodeId(i))) continue;
        double sum = 0.0;
        for (NodeId c = h.first_child[i]; c < h.first_child[i] + h.child_count[i]; ++c)
            sum += h.area[c] * exposure[c];
        exposure[i] = sum / h.area[i];
    }
}

/// What the exposure test finds of an element: its exposure, and whether a ray from an exposed
/// point met anything but a face's front (then it is not enclosed).
struct ElementExposure {
    double share = 1.0;
    std::uint8_t open = 0;
};

/// element_exposure of each element of `nodes`, in their order, in parallel. Cost: their rays.
inline std::vector<ElementExposure> element_exposures(const Hierarchy& h, const Bvh& bvh,
                                                      int points, std::uint64_t seed,
                                                      std::span<const NodeId> nodes) {
    std::vector<ElementExposure> out(nodes.size());
    const auto count = static_cast<std::int64_t>(nodes.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64)
#endif
    for (std::int64_t i = 0; i < count; ++i) {
        bool open = false;
        ElementExposure& e = out[std::size_t(i)];
        e.share = element_exposure(h, bvh, nodes[std::size_t(i)], points, seed, &open);
        e.open = open ? 1 : 0;
    }
    return out;
}

}  // namespace radiosity
