#pragma once
/// @file refine.hpp  The refinement of hierarchical radiosity: BF refinement (Hanrahan, Salzman &
/// Aupperle 1991) of links between elements and clusters, from the one self-link of the top
/// cluster (Smits, Arvo & Greenberg 1994; Sillion 1995). A link whose estimated transfer
/// rho_r B_s T_rs A_r, times the share (r_r + r_s) / d of the distance the pair spans, exceeds
/// the threshold is replaced by links of the children of its larger node; it stays where
/// neither can be split (an element at the minimum area). Breadth first,
/// links judged in parallel and nodes split in a fixed order, so the hierarchy never depends on
/// the number of threads.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/parallel.hpp>
#include <radiosity/hierarchy/links.hpp>
#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace radiosity {

/// What the refinement oracle needs of the current solution, per node: the largest rho (of a
/// receiver) and B (of a source) of any leaf below it, over all bands.
struct OracleInputs {
    std::span<const double> rho_max;  ///< per node
    std::span<const double> B_max;    ///< per node
};

/// Settings of the refinement (set from HierarchicalOptions).
struct RefineSettings {
    double threshold = 0.0;    ///< absolute power: refine while the oracle's estimate exceeds it
    double min_area = 0.0;     ///< elements split only into children of at least this area
    int max_depth = 24;        ///< deepest element level below a root
    int rays = 4;              ///< visibility rays per link between two elements
    int cluster_samples = 16;  ///< sample pairs (and rays) per link with a cluster
    std::uint64_t seed = 1;    ///< base of every link's random stream
};

namespace detail {

/// Whether node n may be split: a cluster always; an element if its children keep at least the
/// minimum area and it is above the deepest level.
inline bool splittable(const Hierarchy& h, NodeId n, const RefineSettings& s) {
    if (h.is_cluster(n)) return true;
    return h.area[n] * 0.25 >= s.min_area && h.depth[n] < s.max_depth;
}

/// The oracle's verdict on a link.
enum class Verdict : std::uint8_t { keep, receiver, source, self };

/// BF refinement's oracle (Hanrahan et al. 1991), weighted by how much the transfer can vary
/// over the pair: rho_r B_s T A_r (radius_r + radius_s) / d, with T the transfer without
/// visibility (its bound where the estimate fails); above the threshold the larger splittable
/// node (by bounding radius) is split. A cluster's self-link is always split.
inline Verdict judge(const Hierarchy& h, const Link& l, const OracleInputs& in,
                     const RefineSettings& s) {
    const NodeId r = l.receiver, src = l.source;
    if (r == src) return Verdict::self;
    // The oracle must not see the link's own random estimates (its sampled transfer, its
    // visibility): links whose rays happened to say "little" would then stay while the others
    // are refined and drawn again, a selection that biases the kept links low. Elements: the
    // analytic coefficient; a cluster: the isotropic estimate, or its bound where that fails.
    double T = l.coefficient;
    if (h.is_cluster(r) || h.is_cluster(src)) {  // O(1) for a cluster
        const Transfer t = transfer(h, r, src);
        T = t.unreliable ? t.bound : t.coefficient;
    }
    // How much the transfer varies over the pair: the share of the distance that the two
    // nodes span, (radius_r + radius_s) / d, at most 1 (overlapping, or touching). A link is
    // wrong for its receiver's parts (which inherit its mean) and its source's by about that
    // share of what it carries.
    const double d = glm::length(h.centre[src] - h.centre[r]);
    const double reach = h.radius[r] + h.radius[src];
    const double spread = d > reach ? reach / d : 1.0;
    const double power = in.rho_max[r] * in.B_max[src] * T * h.area[r] * spread;
    if (!(power > s.threshold)) return Verdict::keep;
    const bool sr = splittable(h, r, s), ss = splittable(h, src, s);
    if (sr && (!ss || h.radius[r] >= h.radius[src])) return Verdict::receiver;
    if (ss) return Verdict::source;
    return Verdict::keep;
}

/// Children of node n, splitting a leaf element first (appending its children).
inline std::pair<NodeId, NodeId> children_of(Hierarchy& h, NodeId n) {
    if (h.is_leaf(n)) split_element(h, n);
    return {h.first_child[n], h.first_child[n] + h.child_count[n]};
}

/// Carries out the verdicts on the frontier's links in their order: kept links go to `done`,
/// split ones give the (receiver, source) pairs of their children's links to `fresh` (a
/// cluster's self-link: every pair of its children, a child cluster's own self-link included,
/// an element's not: a flat element does not see itself). Returns the links split.
inline std::size_t apply_verdicts(Hierarchy& h, const std::vector<Link>& frontier,
                                  const std::vector<Verdict>& verdict, std::vector<Link>& done,
                                  std::vector<std::pair<NodeId, NodeId>>& fresh) {
    std::size_t splits = 0;
    for (std::size_t i = 0; i < frontier.size(); ++i) {
        const Link& l = frontier[i];
        switch (verdict[i]) {
            case Verdict::keep:
                done.push_back(l);
                continue;
            case Verdict::receiver: {
                const auto [b, e] = children_of(h, l.receiver);
                for (NodeId c = b; c < e; ++c) fresh.emplace_back(c, l.source);
                break;
            }
            case Verdict::source: {
                const auto [b, e] = children_of(h, l.source);
                for (NodeId c = b; c < e; ++c) fresh.emplace_back(l.receiver, c);
                break;
            }
            case Verdict::self: {
                const auto [b, e] = children_of(h, l.receiver);
                for (NodeId x = b; x < e; ++x)
                    for (NodeId y = b; y < e; ++y)
                        if (x != y || h.is_cluster(x)) fresh.emplace_back(x, y);
                break;
            }
        }
        ++splits;
    }
    return splits;
}

}  // namespace detail

/// Evaluates a new link: its transfer and, if it carries anything, its visibility (between
/// elements: the analytic coefficient and link_visibility; with a cluster: sampled_transfer).
/// A link between nodes that exchange nothing comes back with visibility -1, to be dropped.
template <Visibility V>
Link evaluate_link(const Hierarchy& h, const V& scene, NodeId r, NodeId s,
                   const RefineSettings& settings) {
    if (r == s) return {r, s, 0.0f, 1.0f};
    const Transfer t = transfer(h, r, s);
    Link l{r, s, static_cast<float>(t.coefficient), 1.0f};
    if (h.is_cluster(r) || h.is_cluster(s)) {
        // Sampled wherever the nodes may exchange anything, overlapping ones included: the
        // isotropic estimate is only the oracle's (a link left at 0 would lose what it carries).
        if (t.coefficient == 0.0 && !t.unreliable) return {r, s, 0.0f, -1.0f};  // drop
        const SampledTransfer st =
            sampled_transfer(h, scene, r, s, settings.cluster_samples, settings.seed);
        l.coefficient = static_cast<float>(st.coefficient);
        l.visibility = static_cast<float>(st.visibility);
        if (st.coefficient == 0.0 && !t.unreliable) l.visibility = -1.0f;  // nothing: drop
    } else if (t.coefficient > 0.0) {
        l.visibility =
            static_cast<float>(link_visibility(h, scene, r, s, settings.rays, settings.seed));
    } else {
        l.visibility = -1.0f;  // the two elements do not face each other: drop
    }
    return l;
}

/// Called as nodes are made, so that the caller can extend its per-node arrays: new nodes are
/// [from, h.size()).
using NodesAdded = std::function<void(std::size_t from)>;

/// One refinement pass over all links at this threshold: every link judged (in parallel), the
/// ones to split replaced by their children's links (nodes split in link order), the new links
/// evaluated (in parallel) and judged in turn, until no link splits. Returns the links, sorted
/// by receiver then source (the order of every gather), and the number of links split.
/// on_nodes(from) is called after nodes are appended; `in` must then cover them (the caller
/// gives new elements their parent's values). Cost: O(links made) transfers and rays.
template <Visibility V>
std::size_t refine_links(Hierarchy& h, const V& scene, std::vector<Link>& links,
                         const RefineSettings& s, const std::function<OracleInputs()>& inputs,
                         const NodesAdded& on_nodes, const ProgressCallback& progress) {
    std::vector<Link> done;
    done.reserve(links.size());
    std::vector<Link> frontier = std::move(links);
    std::size_t splits = 0;
    std::vector<detail::Verdict> verdict;
    while (!frontier.empty()) {
        const OracleInputs in = inputs();
        verdict.assign(frontier.size(), detail::Verdict::keep);
        const auto count = static_cast<std::int64_t>(frontier.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 256)
#endif
        for (std::int64_t i = 0; i < count; ++i)
            verdict[std::size_t(i)] = detail::judge(h, frontier[std::size_t(i)], in, s);
        // Split in link order, one thread: node ids then follow the links, not the schedule.
        const std::size_t before = h.size();
        std::vector<std::pair<NodeId, NodeId>> fresh;
        splits += detail::apply_verdicts(h, frontier, verdict, done, fresh);
        if (h.size() > before) on_nodes(before);
        frontier.assign(fresh.size(), Link{});
        const auto n_fresh = static_cast<std::int64_t>(fresh.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64)
#endif
        for (std::int64_t i = 0; i < n_fresh; ++i) {
            const auto [r, src] = fresh[std::size_t(i)];
            frontier[std::size_t(i)] = evaluate_link(h, scene, r, src, s);
        }
        std::erase_if(frontier, [](const Link& l) { return l.visibility < 0.0f; });
        const double settled = double(done.size()) / double(done.size() + frontier.size() + 1);
        if (!detail::report(progress, "refine", settled)) throw Cancelled();
    }
    std::sort(done.begin(), done.end(), [](const Link& a, const Link& b) {
        return a.receiver < b.receiver || (a.receiver == b.receiver && a.source < b.source);
    });
    links = std::move(done);
    return splits;
}

}  // namespace radiosity
