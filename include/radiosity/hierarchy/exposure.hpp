#pragma once
/// @file exposure.hpp  How much of each input face is exposed, for the push of a cluster's
/// irradiance. A cluster gathers the right energy (its links are sampled over its true faces),
/// but the isotropic push of Sillion 1995 hands it to every face below alike: faces hidden from
/// the room (a floor under a block, the inside of a crevice) then take light they never see and
/// send it nowhere, and a closed room loses several per cent of its light. So the push is
/// weighted by exposure: the share of cosine-weighted rays from a face whose first hit is not a
/// back face (what a hidden face sees is the inside of what hides it). Energy is kept: a
/// cluster's children share its irradiance in proportion to area times exposure.

#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/hierarchy/links.hpp>
#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace radiosity {

/// Exposure of every root in [0, 1] from `rays` cosine-weighted rays (Malley's method) from
/// uniform points of the root: the share whose first hit, if any, is a front face. Seeded by
/// the root's index; roots in parallel. Only roots [first, last) if given (a rank's share; the
/// others stay 1). Cost: rays x roots closest-hit queries.
inline std::vector<double> root_exposure(const Hierarchy& h, const Bvh& bvh, int rays,
                                         std::uint64_t seed, std::size_t first = 0,
                                         std::size_t last = std::size_t(-1)) {
    const auto n = static_cast<std::int64_t>(std::min(last, h.roots.size()));
    std::vector<double> out(h.roots.size(), 1.0);
    const double t_min = 1e-9 * (h.radius[0] + 1.0);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 256)
#endif
    for (std::int64_t i = std::int64_t(first); i < n; ++i) {
        const auto r = static_cast<std::size_t>(i);
        Rng rng(splitmix64(seed ^ (0x5eedull << 40) ^ r));
        const Vec3 nrm = h.roots.normal(r);
        const Vec3 t1 = glm::normalize(std::abs(nrm.x) < 0.9 ? glm::cross(nrm, Vec3(1, 0, 0))
                                                             : glm::cross(nrm, Vec3(0, 1, 0)));
        const Vec3 t2 = glm::cross(nrm, t1);
        int open = 0;
        for (int k = 0; k < rays; ++k) {
            const double u = rng.uniform();
            const Vec3 x = detail::polygon_point(h.roots.polygon(r), u, rng.uniform());
            const double a = rng.uniform(), phi = 2.0 * std::numbers::pi * rng.uniform();
            const Vec3 d =
                std::sqrt(a) * (std::cos(phi) * t1 + std::sin(phi) * t2) + std::sqrt(1.0 - a) * nrm;
            const auto hit = bvh.intersect(x, d, t_min);
            open += !hit || glm::dot(h.roots.normal(hit->patch), d) < 0.0 ? 1 : 0;
        }
        out[r] = double(open) / double(rays);
    }
    return out;
}

/// The push weights of the nodes: for a child of a cluster, its exposure over the cluster's
/// (exposure of a node: the area-weighted mean of its roots'); 1 below the roots, whose
/// children share their root's exposure, and where a cluster is wholly hidden.
inline std::vector<double> push_weights(const Hierarchy& h, const std::vector<double>& exposure) {
    std::vector<double> e(h.size(), 0.0), w(h.size(), 1.0);
    for (std::size_t i = h.size(); i-- > 0;) {
        if (!h.is_cluster(NodeId(i))) {
            e[i] = exposure[h.root_of(NodeId(i))];
            continue;
        }
        double sum = 0.0;
        for (NodeId c = h.first_child[i]; c < h.first_child[i] + h.child_count[i]; ++c)
            sum += h.area[c] * e[c];
        e[i] = sum / h.area[i];
    }
    for (std::size_t i = 0; i < h.size(); ++i) {
        const NodeId p = h.parent[i];
        if (p != no_node && h.is_cluster(p) && e[p] > 0.0) w[i] = e[i] / e[p];
    }
    return w;
}

}  // namespace radiosity
