#pragma once
/// @file hierarchical.hpp  Hierarchical radiosity with clustering, the library's path for large
/// scenes: no n x n matrix, links between elements and clusters at whatever level is accurate
/// enough (Hanrahan, Salzman & Aupperle 1991), starting from the self-link of the cluster of the
/// whole scene (Smits, Arvo & Greenberg 1994; Sillion 1995). Multigridding: a few passes at
/// coarser thresholds (16x apart), each refined against the B of the pass before, then refine ->
/// gather -> push-pull at the final threshold until no link splits and B has converged.
/// The leaves are the result's patches (leaves.hpp). Memory: O(elements + links).
/// The loop itself, spread over ranks (HierarchicalOptions::communicator) and checkpointed
/// (HierarchicalOptions::checkpoint), is solve_loop.hpp's.

#include <radiosity/error.hpp>
#include <radiosity/form_factor/budget.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/hierarchy/exposure.hpp>
#include <radiosity/hierarchy/gather.hpp>
#include <radiosity/hierarchy/leaves.hpp>
#include <radiosity/hierarchy/options.hpp>
#include <radiosity/hierarchy/refine.hpp>
#include <radiosity/hierarchy/solve_loop.hpp>
#include <radiosity/mesh/corner_uv.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/session.hpp>
#include <radiosity/solver/system.hpp>

#include <array>
#include <chrono>
#include <limits>
#include <cmath>
#include <string>
#include <vector>

namespace radiosity {

/// The result of a hierarchical solve: the leaves as a patch mesh with B, and the reports.
template <SpectrumType S>
struct HierarchicalResult {
    Mesh<S> mesh;   ///< one face per leaf, B set
    Report report;  ///< iterations (sweeps), error bound, converged, time
    HierarchyReport hierarchy;
};

namespace detail {

/// Root elements of a patch mesh: triangles and quads as they are, larger (convex) polygons as
/// their fan triangles; each with the face it came from.
template <SpectrumType S>
Hierarchy hierarchy_of(const Mesh<S>& mesh) {
    PatchTable roots;
    std::vector<std::uint32_t> surface;
    std::vector<std::array<Vec3, 4>> uvs;  // per root, if the mesh has lightmap UVs
    const bool with_uv = has_corner_uvs(mesh);
    auto add = [&](std::span<const Vec3> p, std::span<const glm::vec2> uv, auto f) {
        roots.add(p, "face " + std::to_string(f.idx()));
        surface.push_back(static_cast<std::uint32_t>(f.idx()));
        if (!with_uv) return;
        std::array<Vec3, 4> u{};
        for (std::size_t k = 0; k < p.size(); ++k) u[k] = Vec3(uv[k].x, uv[k].y, 0.0);
        uvs.push_back(u);
    };
    for (auto f : mesh.faces()) {
        const std::vector<Vec3> p = face_polygon(mesh, f);
        std::vector<glm::vec2> uv = corner_uvs(mesh, f);
        if (!with_uv) uv.assign(p.size(), glm::vec2(0.0f));
        if (p.size() <= 4) {
            add(p, uv, f);
            continue;
        }
        for (std::size_t k = 1; k + 1 < p.size(); ++k) {
            const std::array<Vec3, 3> t{p[0], p[k], p[k + 1]};
            const std::array<glm::vec2, 3> tu{uv[0], uv[k], uv[k + 1]};
            if (polygon_area(t) > 0.0) add(t, tu, f);  // not collinear corners along an edge
        }
    }
    return build_hierarchy(std::move(roots), std::move(surface), uvs);
}

}  // namespace detail

/// Solves B = E + R F B on a patch mesh by hierarchical radiosity with clustering (see the file
/// comment): its faces are the roots, the result's faces the leaves. `tolerance` bounds the
/// error of B for the final links relative to the largest reflected radiosity B - E
/// (stopping.hpp), so never looser than the other solvers' ||B - B*|| / ||B*|| (session.hpp); 0
/// max_iterations: the guard from what the tolerance needs. Throws Error if the hierarchy would
/// pass options.max_bytes, and Cancelled if the progress callback stops the refinement; a
/// cancelled solve returns its leaves with report.cancelled. Visibility: a Bvh over the roots.
template <SpectrumType S>
HierarchicalResult<S> solve_hierarchical(const Mesh<S>& patches, const HierarchicalOptions& o = {},
                                         double tolerance = 1e-4, std::size_t max_iterations = 0,
                                         const ProgressCallback& progress = {}) {
    constexpr std::size_t K = band_count<S>;
    const auto t0 = std::chrono::steady_clock::now();
    if (!(o.link_error > 0.0) || !std::isfinite(o.link_error))
        throw Error("hierarchical radiosity: link error must be a positive number");
    if (!(o.min_area >= 0.0) || !std::isfinite(o.min_area))
        throw Error("hierarchical radiosity: minimum area must be a non-negative number");
    if (o.rays < 1) throw Error("hierarchical radiosity: need at least 1 ray per link");
    if (o.cluster_samples < 1)
        throw Error("hierarchical radiosity: need at least 1 sample per link with a cluster");
    if (o.enclosure_rays < 0 || o.enclosure_rays > 256)
        throw Error("hierarchical radiosity: enclosure rays must be between 0 and 256");
    if (o.exposure_samples < 0)
        throw Error("hierarchical radiosity: exposure samples must not be negative");
    if (!(o.shadow_factor > 0.0) || !std::isfinite(o.shadow_factor))
        throw Error("hierarchical radiosity: the shadow factor must be a positive number");
    if (!(o.coarse_factor >= 1.0) || !std::isfinite(o.coarse_factor))
        throw Error("hierarchical radiosity: the coarse passes' factor must be at least 1");
    detail::HierarchySolve<K> solve(detail::hierarchy_of(patches), o);
    solve.set_materials([&](std::uint32_t face, double* E, double* rho) {
        const auto& d = patches.data(patches.face_handle(static_cast<int>(face)));
        for (std::size_t k = 0; k < K; ++k) {
            E[k] = band(d.emission, k);
            rho[k] = band(d.reflectance, k);
        }
    });
    const Bvh scene(solve.hierarchy().roots);
    if (o.exposure_samples > 0 || o.enclosure_rays > 0)
        solve.set_exposure(scene, o.exposure_samples, o.seed);
    HierarchicalResult<S> result;
    result.report = solve.run(scene, tolerance, max_iterations, progress, result.hierarchy);
    const Hierarchy& h = solve.hierarchy();
    const LeafPolygons leaves = leaf_polygons(h);
    std::vector<S> B(leaves.leaf.size());
    for (std::size_t f = 0; f < B.size(); ++f)
        for (std::size_t k = 0; k < K; ++k)
            set_band(B[f], k, static_cast<float>(solve.values().mean_radiosity(leaves.leaf[f], k)));
    result.mesh = leaf_mesh<S>(h, leaves, patches, B);
    HierarchyReport& r = result.hierarchy;
    r.input_faces = patches.n_faces();
    r.roots = h.roots.size();
    for (NodeId n = 0; n < h.size(); ++n) (h.is_cluster(n) ? r.clusters : r.elements) += 1;
    r.leaves = leaves.leaf.size();
    r.bytes = solve.bytes();
    result.report.seconds = detail::seconds_since(t0);
    return result;
}

}  // namespace radiosity
