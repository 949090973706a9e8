#pragma once
/// @file hierarchical.hpp  Hierarchical radiosity with clustering, the library's path for large
/// scenes: no n x n matrix, links between elements and clusters at whatever level is accurate
/// enough (Hanrahan, Salzman & Aupperle 1991), starting from the self-link of the cluster of the
/// whole scene (Smits, Arvo & Greenberg 1994; Sillion 1995). Multigridding: a few passes at
/// coarser thresholds (4x apart), each refined against the B of the pass before, then refine ->
/// gather -> push-pull at the final threshold until no link splits and B has converged.
/// The leaves are the result's patches (leaves.hpp). Memory: O(elements + links).

#include <radiosity/error.hpp>
#include <radiosity/form_factor/budget.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/hierarchy/exposure.hpp>
#include <radiosity/hierarchy/gather.hpp>
#include <radiosity/hierarchy/leaves.hpp>
#include <radiosity/hierarchy/refine.hpp>
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

/// Settings of hierarchical radiosity.
struct HierarchicalOptions {
    /// BF refinement's threshold as a share of the scene's emitted power: a link is refined
    /// while it would move more than link_error times sum_i E_i A_i (rho_r B_s T_rs A_r).
    double link_error = 5e-5;
    /// Elements split only into children of at least this area; 0: the scene's area / 10^6.
    double min_area = 0.0;
    int rays = 4;              ///< visibility rays per link of two elements (a square number)
    int cluster_samples = 16;  ///< sample pairs, one ray each, per link with a cluster
    int max_depth = 24;        ///< deepest element level below an input face
    int coarse_passes = 3;     ///< multigrid passes before the final threshold (4x each)
    int max_final_passes = 2;  ///< refine -> solve rounds at the final threshold
    std::uint64_t seed = 1;    ///< base seed of the links' rays
    /// Rays per input face for its exposure, which weights a cluster's push (exposure.hpp);
    /// 0: the isotropic push, every face below a cluster alike.
    int exposure_rays = 16;
    /// Largest memory for nodes and links, in bytes; 0: half the physical memory. Refinement
    /// that would pass it stops with an Error naming what to change.
    std::size_t max_bytes = 0;
};

/// What the hierarchy holds at the end of a solve.
struct HierarchyReport {
    std::size_t input_faces = 0;  ///< faces of the patch mesh solved (the roots' sources)
    std::size_t roots = 0;        ///< root elements (faces, polygons split into triangles)
    std::size_t clusters = 0;     ///< cluster nodes
    std::size_t elements = 0;     ///< element nodes (roots and their descendants)
    std::size_t leaves = 0;       ///< leaf elements: the result's patches
    std::size_t links = 0;        ///< links at the end
    std::size_t bytes = 0;        ///< memory of nodes, values and links
    std::size_t passes = 0;       ///< refinement passes
    double refine_seconds = 0.0;  ///< time spent refining (transfers and rays)
    double solve_seconds = 0.0;   ///< time spent gathering and pushing-pulling
    /// Links per element.
    double links_per_element() const { return elements ? double(links) / double(elements) : 0.0; }
};

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
/// Seconds since t0 (wall clock).
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

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

/// The state of a hierarchical solve for K bands: the nodes, their values and the links.
template <std::size_t K>
class HierarchySolve {
  public:
    HierarchySolve(Hierarchy h, const HierarchicalOptions& o) : h_(std::move(h)), o_(o) {}

    /// Sets E and rho of every root (from its face, by callback) and the clusters' rho_max.
    template <class Material>
    void set_materials(Material&& material) {
        v_.extend(h_, h_.size());
        for (NodeId n = 0; n < h_.size(); ++n)
            if (!h_.is_cluster(n))
                material(h_.surface[h_.root_of(n)], &v_.E[n * K], &v_.rho[n * K]);
        for (std::size_t i = h_.size(); i-- > 0;) {
            double r = 0.0;
            if (h_.is_cluster(NodeId(i)))
                for (NodeId c = h_.first_child[i]; c < h_.first_child[i] + 2; ++c)
                    r = std::max(r, v_.rho_max[c]);
            else
                for (std::size_t k = 0; k < K; ++k) r = std::max(r, v_.rho[i * K + k]);
            v_.rho_max[i] = r;
            for (std::size_t k = 0; k < K; ++k) v_.B[i * K + k] = v_.E[i * K + k];
        }
        std::vector<double> scratch;
        std::fill(v_.H.begin(), v_.H.end(), 0.0);
        push_pull(h_, v_, scratch);  // B = E at the leaves, means above
        emitted_ = 0.0;
        for (NodeId n = 0; n < h_.size(); ++n)
            if (!h_.is_cluster(n)) {
                double e = 0.0;
                for (std::size_t k = 0; k < K; ++k) e = std::max(e, v_.E[n * K + k]);
                emitted_ += e * h_.area[n];
            }
    }

    /// Runs the passes (see the file comment) under `tolerance`.
    template <Visibility V>
    Report run(const V& scene, double tolerance, std::size_t max_iterations,
               const ProgressCallback& progress, HierarchyReport& hr) {
        Report report;
        report.solver = "hierarchical";
        RefineSettings s = settings();
        if (h_.size() > 1) links_.push_back({0, 0, 0.0f, 1.0f});  // the top cluster's self-link
        const int passes = o_.coarse_passes + o_.max_final_passes;
        for (int p = 0; p < passes; ++p) {
            const bool final = p >= o_.coarse_passes;
            s.threshold =
                o_.link_error * emitted_ * std::pow(4.0, final ? 0 : o_.coarse_passes - p);
            auto t0 = std::chrono::steady_clock::now();
            const std::size_t splits = refine(scene, s, progress);
            hr.refine_seconds += seconds_since(t0);
            ++hr.passes;
            t0 = std::chrono::steady_clock::now();
            const double pass_tolerance = final ? tolerance : std::max(tolerance, 1e-2);
            iterate(pass_tolerance, max_iterations, progress, report);
            hr.solve_seconds += seconds_since(t0);
            if (report.cancelled) break;
            if (final && splits == 0) break;
        }
        return report;
    }

    /// Weights the push below clusters by the roots' exposure (exposure.hpp).
    void set_exposure(const std::vector<double>& exposure) { v_.push = push_weights(h_, exposure); }

    const Hierarchy& hierarchy() const { return h_; }          ///< the nodes
    const std::vector<Link>& links() const { return links_; }  ///< the links, by receiver
    const NodeValues<K>& values() const { return v_; }         ///< E, rho, B, H per node
    /// Bytes of nodes, values and links.
    std::size_t bytes() const {
        return h_.bytes() + links_.capacity() * sizeof(Link) +
               h_.size() * (4 * K + 3) * sizeof(double);
    }

  private:
    RefineSettings settings() const {
        RefineSettings s;
        s.min_area = o_.min_area > 0.0 ? o_.min_area : h_.area[0] * 1e-6;
        s.max_depth = o_.max_depth;
        s.rays = o_.rays;
        s.cluster_samples = o_.cluster_samples;
        s.seed = o_.seed;
        return s;
    }

    template <Visibility V>
    std::size_t refine(const V& scene, const RefineSettings& s, const ProgressCallback& progress) {
        const std::size_t limit = o_.max_bytes ? o_.max_bytes : default_matrix_limit();
        auto inputs = [this] { return OracleInputs{v_.rho_max, v_.B_max}; };
        auto added = [this, limit](std::size_t from) {
            v_.extend(h_, from);
            if (bytes() > limit)
                throw Error("hierarchical radiosity: the hierarchy would need more than " +
                            std::to_string(limit / 1000000) + " MB (" + std::to_string(h_.size()) +
                            " nodes); raise --link-error or " +
                            "--min-area, or the limit (--max-memory)");
        };
        return refine_links(h_, scene, links_, s, inputs, added, progress);
    }

    /// Gather and push-pull until the bound on the error of B meets the tolerance. The bound
    /// is the sweeping solvers' (session.hpp), q / (1 - q) times the last change, with q the
    /// links' ||R F||_inf where that is below 1; where it is not (a small leaf under links
    /// averaged over a larger receiver can gather more than 1 per unit B), q is the largest of
    /// the last three observed contractions change_k / change_k-1, an estimate rather than a
    /// bound, which the guard backs (2 sweeps_needed + 10 at that q, at most 1000).
    void iterate(double tolerance, std::size_t cap, const ProgressCallback& progress,
                 Report& report) {
        const LinkGroups groups = group_links(links_);
        const double q_rows = hierarchy_contraction(h_, links_, v_);
        std::vector<double> total;
        std::array<double, 3> ratio{1.0, 1.0, 1.0};
        double previous = std::numeric_limits<double>::infinity(), first = 0.0;
        for (std::size_t it = 0;; ++it) {
            gather_links(links_, groups, v_);
            const double change = push_pull(h_, v_, total);
            ++report.iterations;
            ratio[it % 3] = previous > 0.0 && std::isfinite(previous) ? change / previous : 1.0;
            previous = change;
            const double q_seen = *std::max_element(ratio.begin(), ratio.end());
            const double q = q_rows < 1.0 ? q_rows : (it >= 3 ? q_seen : 1.0);
            const StoppingRule rule = StoppingRule::sweeps(tolerance, q, cap);
            const double size = v_.B_max[0];  // the top node's: the brightest leaf, ||B||_inf
            report.residual = size > 0.0 ? change / size : change;
            report.error_bound = rule.bound(change, size);
            report.converged = rule.met(report.error_bound);
            if (it == 0) first = report.error_bound;
            Progress pr{"solve", rule.fraction(first, report.error_bound), report.residual,
                        report.iterations};
            if (!detail::report(progress, pr)) {
                report.cancelled = true;
                return;
            }
            if (report.converged || it + 1 >= std::min<std::size_t>(rule.max_iterations, 1000))
                return;
        }
    }

    Hierarchy h_;
    HierarchicalOptions o_;
    NodeValues<K> v_;
    std::vector<Link> links_;
    double emitted_ = 0.0;
};

}  // namespace detail

/// Solves B = E + R F B on a patch mesh by hierarchical radiosity with clustering (see the file
/// comment): its faces are the roots, the result's faces the leaves. `tolerance` bounds the
/// relative error of B for the final links (as for the other solvers, session.hpp); 0
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
    detail::HierarchySolve<K> solve(detail::hierarchy_of(patches), o);
    solve.set_materials([&](std::uint32_t face, double* E, double* rho) {
        const auto& d = patches.data(patches.face_handle(static_cast<int>(face)));
        for (std::size_t k = 0; k < K; ++k) {
            E[k] = band(d.emission, k);
            rho[k] = band(d.reflectance, k);
        }
    });
    const Bvh scene(solve.hierarchy().roots);
    if (o.exposure_rays > 0)
        solve.set_exposure(root_exposure(solve.hierarchy(), scene, o.exposure_rays, o.seed));
    HierarchicalResult<S> result;
    result.report = solve.run(scene, tolerance, max_iterations, progress, result.hierarchy);
    const Hierarchy& h = solve.hierarchy();
    const LeafPolygons leaves = leaf_polygons(h);
    std::vector<S> B(leaves.leaf.size());
    for (std::size_t f = 0; f < B.size(); ++f)
        for (std::size_t k = 0; k < K; ++k)
            set_band(B[f], k, static_cast<float>(solve.values().B[leaves.leaf[f] * K + k]));
    result.mesh = leaf_mesh<S>(h, leaves, patches, B);
    HierarchyReport& r = result.hierarchy;
    r.input_faces = patches.n_faces();
    r.roots = h.roots.size();
    for (NodeId n = 0; n < h.size(); ++n) (h.is_cluster(n) ? r.clusters : r.elements) += 1;
    r.leaves = leaves.leaf.size();
    r.links = solve.links().size();
    r.bytes = solve.bytes();
    result.report.seconds = detail::seconds_since(t0);
    return result;
}

}  // namespace radiosity
