#pragma once
/// @file refine.hpp  The refinement of hierarchical radiosity: BF refinement (Hanrahan, Salzman &
/// Aupperle 1991) of links between elements and clusters, from the one self-link of the top
/// cluster (Smits, Arvo & Greenberg 1994; Sillion 1995). A link whose estimated transfer
/// rho_r B_s T_rs A_r, times the share (r_r + r_s) / d of the distance the pair spans, exceeds
/// the threshold is replaced by links of the children of its larger node; it stays where
/// neither can be split (an element at the minimum area). Breadth first, links judged in
/// parallel and elements split in increasing id order, so the hierarchy never depends on the
/// number of threads or ranks. A new link is judged on its unoccluded transfer alone; its rays
/// are cast only once the oracle keeps it, and one they find partly visible is judged again on
/// its whole transfer (a shadow boundary crosses it). With several ranks each judges the links
/// of the receivers it owns (distributed/partition.hpp), every rank splits alike, and each
/// round's transfers and rays are shared out in equal shares of rays among all ranks.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/parallel.hpp>
#include <radiosity/distributed/communicator.hpp>
#include <radiosity/distributed/partition.hpp>
#include <radiosity/error.hpp>
#include <radiosity/hierarchy/links.hpp>
#include <radiosity/hierarchy/nodes.hpp>
#include <radiosity/progress.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
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
    double threshold = 0.0;      ///< absolute power: refine while the oracle's estimate exceeds it
    double min_area = 0.0;       ///< elements split only into children of at least this area
    int max_depth = 24;          ///< deepest element level below a root
    int rays = 4;                ///< visibility rays per link between two elements
    int cluster_samples = 4;     ///< sample pairs (and rays) per link with a cluster
    double shadow_factor = 4.0;  ///< partly visible links: the threshold divided by this
    std::uint64_t seed = 1;      ///< base of every link's random stream
};

namespace detail {

/// Seconds since t0 (wall clock).
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// A link to be made: its receiver and source (trivially copyable, so it can travel between
/// ranks as it is).
struct NodePair {
    NodeId receiver, source;
};

/// Whether node n may be split: a cluster always; an element if its children keep at least the
/// minimum area and it is above the deepest level.
inline bool splittable(const Hierarchy& h, NodeId n, const RefineSettings& s) {
    if (h.is_cluster(n)) return true;
    return h.area[n] * 0.25 >= s.min_area && h.depth[n] < s.max_depth;
}

/// Whether a link could be replaced by finer ones: either end may be split.
inline bool splits_further(const Hierarchy& h, const Link& l, const RefineSettings& s) {
    return splittable(h, l.receiver, s) || splittable(h, l.source, s);
}

/// The oracle's verdict on a link.
enum class Verdict : std::uint8_t { keep, receiver, source, self };

/// BF refinement's oracle (Hanrahan et al. 1991), weighted by how much the transfer can vary
/// over the pair: rho_r B_s T A_r (radius_r + radius_s) / d, with T the transfer without
/// visibility (a cluster's by the oriented model; its bound where the estimate fails), and
/// without the weight (all of rho_r B_s T A_r) for a link partly visible or with a mixed
/// cluster at an end; above the threshold the larger splittable
/// node (by bounding radius) is split, or the receiver of a partly visible link. A cluster's
/// self-link is always split.
inline Verdict judge(const Hierarchy& h, const Link& l, const OracleInputs& in,
                     const RefineSettings& s) {
    const NodeId r = l.receiver, src = l.source;
    if (r == src) return Verdict::self;
    // The oracle must not weigh by the link's own random estimates (its sampled transfer, its
    // visibility): links whose rays happened to say "little" would then stay while the others
    // are refined and drawn again, a selection that biases the kept links low. Elements: the
    // analytic coefficient; a cluster: the oriented estimate, or its bound where that fails.
    double T = l.coefficient;
    if (h.is_cluster(r) || h.is_cluster(src)) {  // O(1) for a cluster
        const Transfer t = transfer(h, r, src, Accuracy::full, ClusterModel::oriented);
        T = t.unreliable ? t.bound : t.coefficient;
    }
    // How much the transfer varies over the pair: the share of the distance that the two
    // nodes span, (radius_r + radius_s) / d, at most 1 (overlapping, or touching). A link is
    // wrong for its receiver's parts (which inherit its mean) and its source's by about that
    // share of what it carries.
    const double d = glm::length(h.centre[src] - h.centre[r]);
    const double reach = h.radius[r] + h.radius[src];
    // A link whose rays found it partly visible has a shadow boundary across the pair: the
    // visible fraction, pushed down alike to every part of the receiver, is then wrong for each
    // part by up to all it carries (Hanrahan et al. 1991 refine such links further), so it is
    // judged on its whole unoccluded transfer against a threshold shadow_factor times lower.
    // Only "partly": the rays' verdict is used as a flag, never as a weight, so the kept links
    // are not chosen by how little their rays saw.
    const bool partly_visible = l.visibility > 0.0f && l.visibility < 1.0f;
    // A link with a mixed cluster at an end divides its light among the cluster's orientation
    // classes by the shares its few samples saw (ClassShares): a class's share is off by a good
    // part of what the link carries however far apart the nodes are, so it too is judged on
    // all it carries. (The Cornell box as 340,000 triangles, seed 1: its worst surface went
    // from 9.3% to 4.4% off the converged few faces, for 5% more links; room3: 5% more links.)
    const bool mixed_end = h.mixed(r) || h.mixed(src);
    const double spread = partly_visible || mixed_end || d <= reach ? 1.0 : reach / d;
    const double shadow = partly_visible ? s.shadow_factor : 1.0;
    const double power = in.rho_max[r] * in.B_max[src] * T * h.area[r] * spread * shadow;
    if (!(power > s.threshold)) return Verdict::keep;
    // Which end to split: the larger (Hanrahan et al. 1991), as its size bounds how much the
    // transfer varies over the pair; but a shadow boundary that crosses the pair is drawn on
    // the receiver, so a partly visible link splits its receiver first. Splitting the source
    // instead leaves a coarse receiver under finer and finer sources, every one of them partly
    // visible, whose mean then goes down alike to the lit and the shadowed parts of the
    // receiver (room3: the per-material means moved toward the reference walk's, the table's
    // excess halved, for no more links).
    const bool sr = splittable(h, r, s), ss = splittable(h, src, s);
    if (sr && (!ss || partly_visible || h.radius[r] >= h.radius[src])) return Verdict::receiver;
    if (ss) return Verdict::source;
    return Verdict::keep;
}

/// The leaf element that a verdict splits, if any (clusters have their children already).
inline NodeId node_to_split(const Hierarchy& h, const Link& l, Verdict v) {
    const NodeId n = v == Verdict::source ? l.source : l.receiver;
    if (v == Verdict::keep || h.is_cluster(n) || !h.is_leaf(n)) return no_node;
    return n;
}

/// Carries out one verdict whose nodes are already split: a kept link goes to `done`, a split
/// one gives the (receiver, source) pairs of its children's links to `fresh` (a cluster's
/// self-link: every pair of its children, a child cluster's own self-link included, an
/// element's not: a flat element does not see itself), only those whose receiver `mine`
/// accepts. Returns whether the link was split.
template <class Mine>
bool apply_verdict(const Hierarchy& h, const Link& l, Verdict v, std::vector<Link>& done,
                   std::vector<NodePair>& fresh, const Mine& mine) {
    const auto children = [&](NodeId n) {
        RADIOSITY_ASSERT(!h.is_leaf(n));
        return std::pair<NodeId, NodeId>{h.first_child[n], h.first_child[n] + h.child_count[n]};
    };
    switch (v) {
        case Verdict::keep:
            done.push_back(l);
            return false;
        case Verdict::receiver: {
            const auto [b, e] = children(l.receiver);
            for (NodeId c = b; c < e; ++c)
                if (mine(c)) fresh.emplace_back(c, l.source);
            return true;
        }
        case Verdict::source: {
            const auto [b, e] = children(l.source);
            for (NodeId c = b; c < e; ++c) fresh.emplace_back(l.receiver, c);
            return true;
        }
        case Verdict::self: {
            const auto [b, e] = children(l.receiver);
            for (NodeId x = b; x < e; ++x)
                if (mine(x))
                    for (NodeId y = b; y < e; ++y)
                        if (x != y || h.is_cluster(x)) fresh.emplace_back(x, y);
            return true;
        }
    }
    return false;
}

/// Whether carrying out verdict v on a link makes receivers that another rank owns: a split
/// cluster receiver whose children lie on either side of a cut (an element's children have its
/// root, and so its owner).
template <class Owner>
bool crosses_ranks(const Hierarchy& h, const Link& l, Verdict v, const Owner& owner) {
    if (v != Verdict::receiver && v != Verdict::self) return false;
    if (!h.is_cluster(l.receiver)) return false;
    const NodeId c = h.first_child[l.receiver];
    return owner(c) != owner(l.receiver) || owner(c + 1) != owner(l.receiver);
}

}  // namespace detail

/// The visibility of a link whose rays are not cast yet: a new link is judged on its unoccluded
/// transfer alone, so its rays (and a cluster link's samples) wait until the oracle keeps it;
/// a link split at once never casts any.
inline constexpr float unsampled = 2.0f;

/// The visibility of a pair whose transfer is not computed yet (what a round hands to
/// evaluate_shared along with the links to sample).
inline constexpr float unopened = -2.0f;

/// Opens a new link: its unoccluded transfer (transfer(): the analytic form factor between
/// elements, near ones by the 7-point estimate, the isotropic estimate with a cluster), which
/// is all the oracle looks at, and its visibility left unsampled. A pair that can exchange nothing
/// (elements not facing each other, a cluster wholly behind an element) comes back with visibility
/// -1, to be dropped.
inline Link open_link(const Hierarchy& h, NodeId r, NodeId s) {
    if (r == s) return {r, s, 0.0f, unsampled};  // a self-link: the oracle always splits it
    const Transfer t = transfer(h, r, s, Accuracy::estimate);
    // A cluster link is sampled wherever the nodes may exchange anything, overlapping ones
    // included: the isotropic estimate is only the oracle's.
    const bool nothing = h.is_cluster(r) || h.is_cluster(s) ? t.coefficient == 0.0 && !t.unreliable
                                                            : !(t.coefficient > 0.0);
    return {r, s, static_cast<float>(t.coefficient), nothing ? -1.0f : unsampled};
}

/// Samples a kept link: between two elements its full analytic transfer (Accuracy::full) and its
/// visibility from link_visibility's rays, or with a cluster both the coefficient and the
/// visibility from sampled_transfer. Seeded from the pair alone. A link whose samples happen to
/// find nothing is kept all the same (with T = 0): the next pass judges it again and may refine it,
/// whereas a dropped link would take its pair's light out of the solve for good (with 4 samples
/// that dimmed room3 by 2%). A link with class shares (has_class_shares) appends them to
/// `shares`, if given: the sweeps take them from there rather than sample them again.
template <Visibility V>
Link sample_link(const Hierarchy& h, const V& scene, Link l, const RefineSettings& settings,
                 std::vector<ClassShares>* shares = nullptr) {
    const NodeId r = l.receiver, s = l.source;
    if (r == s) {  // a self-link carries nothing itself (the oracle always splits it)
        l.visibility = 1.0f;
    } else if (h.is_cluster(r) || h.is_cluster(s)) {
        const SampledTransfer st =
            sampled_transfer(h, scene, r, s, settings.cluster_samples, settings.seed);
        l.coefficient = static_cast<float>(st.coefficient);
        l.visibility = static_cast<float>(st.visibility);
        if (shares != nullptr && has_class_shares(h, l))
            shares->push_back({r, s, in_255ths(st.facing), in_255ths(st.sending)});
    } else {
        // The transfer it was judged on is the estimate; a kept link carries the full one
        // (the same number but for near pairs that need the quadrature).
        if (detail::full_differs(h, r, s))
            l.coefficient = static_cast<float>(transfer(h, r, s, Accuracy::full).coefficient);
        l.visibility =
            static_cast<float>(link_visibility(h, scene, r, s, settings.rays, settings.seed));
    }
    return l;
}

/// Called as nodes are made, so that the caller can extend its per-node arrays: new nodes are
/// [from, h.size()).
using NodesAdded = std::function<void(std::size_t from)>;

/// Where a refinement pass stands between two rounds: this rank's settled links and the links
/// still to be judged; what a checkpoint taken inside a pass holds.
struct RefineRound {
    LinkVector done;            ///< kept links
    LinkVector frontier;        ///< evaluated links to be judged next round
    std::uint64_t splits = 0;   ///< links split in this pass so far (all ranks)
    std::uint64_t settled = 0;  ///< links settled so far (all ranks), for progress
    std::uint64_t open = 1;     ///< links in every rank's frontier (0: the pass is done)
};

/// What a distributed refinement needs: the ranks, who owns which receiver, the per-position
/// cost it measures for the next partition, and the log of every element split (all ranks').
struct RefineShare {
    Communicator& comm;
    const Partition& partition;
    std::vector<std::uint64_t>& cost;  ///< per position of the cluster order: work measured
    std::vector<NodeId>& split_log;    ///< elements split, in the order they were split
    double compute_seconds = 0.0;      ///< time judging and evaluating (no waiting on others)
    /// Where the class shares of the links this rank samples go (sample_link), if anywhere.
    std::vector<ClassShares>* shares = nullptr;
    /// Most links this rank may hold in a round (settled, to be judged, and the round's new
    /// ones): past it the refinement stops with an Error instead of exhausting the memory.
    std::size_t max_links = std::size_t(-1);
};

/// Called after every round; returns false to stop the pass (it then throws Cancelled).
using RoundDone = std::function<bool(const RefineRound&)>;

namespace detail {

/// A link whose split makes receivers on other ranks, with its verdict, sent to every rank.
struct SharedSplit {
    Link link;
    std::uint32_t verdict;
};

/// The work of a task of evaluate_shared, in rays: opening a pair, one (its transfer);
/// sampling a link, a cluster's sample pairs or an element pair's rays.
inline std::uint64_t evaluation_cost(const Hierarchy& h, const Link& task,
                                     const RefineSettings& s) {
    if (task.visibility == unopened) return 1;
    const bool cluster = h.is_cluster(task.receiver) || h.is_cluster(task.source);
    return std::uint64_t(cluster ? s.cluster_samples : s.rays);
}

/// Carries out one task: opens a pair (open_link) or samples a kept link (sample_link, its
/// class shares to `shares`).
template <Visibility V>
Link evaluate_task(const Hierarchy& h, const V& scene, const Link& task, const RefineSettings& s,
                   std::vector<ClassShares>* shares) {
    if (task.visibility == unopened) return open_link(h, task.receiver, task.source);
    RADIOSITY_ASSERT(task.visibility == unsampled);
    return sample_link(h, scene, task, s, shares);
}

/// Carries out tasks (evaluate_task) with this rank's threads into `links` (resized to the
/// tasks'): the plain loop. The class shares of the sampled links go to `shares` if given,
/// each thread's after the loop (in no fixed order: they are looked up by pair).
template <Visibility V>
void evaluate_tasks(const Hierarchy& h, const V& scene, const LinkVector& tasks,
                    const RefineSettings& s, LinkVector& links,
                    std::vector<ClassShares>* shares = nullptr) {
    links.resize(tasks.size());
    const auto threads = static_cast<std::size_t>(thread_count());
    std::vector<std::vector<ClassShares>> per_thread(shares != nullptr ? threads : 0);
    const auto n = static_cast<std::int64_t>(tasks.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64)
#endif
    for (std::int64_t i = 0; i < n; ++i)
        links[std::size_t(i)] =
            evaluate_task(h, scene, tasks[std::size_t(i)], s,
                          shares ? &per_thread[std::size_t(thread_index())] : nullptr);
    if (shares != nullptr)
        for (const auto& part : per_thread) shares->insert(shares->end(), part.begin(), part.end());
}

/// Carries out this rank's tasks of the round (the pairs to open, the kept links to sample)
/// with the work shared evenly among the ranks: what each rank has is one piece of a list in
/// rank order, which is cut into equal shares of rays (evaluation_cost); each rank carries out
/// its share and sends the links back to the ranks they came from (two all-to-alls, the tasks
/// there and the links back, in the order sent). Without it, a rank whose receivers made more
/// of the round's work than its share keeps the others waiting at the round's end. A link is a
/// function of its pair alone (its rays are seeded from the pair), so it has the same bits
/// whichever rank evaluates it. The links come back in `links`, in the order of `tasks`.
template <Visibility V>
void evaluate_shared(const Hierarchy& h, const V& scene, const LinkVector& tasks,
                     const RefineSettings& s, RefineShare& share, LinkVector& links) {
    Communicator& comm = share.comm;
    if (comm.size() == 1) {
        const auto t0 = std::chrono::steady_clock::now();
        evaluate_tasks(h, scene, tasks, s, links, share.shares);
        share.compute_seconds += seconds_since(t0);
        return;
    }
    // Where this rank's tasks start in the list of every rank's, counted in rays.
    std::uint64_t mine = 0;
    for (const Link& t : tasks) mine += evaluation_cost(h, t, s);
    const std::vector<std::uint64_t> work = all_gather(comm, std::vector<std::uint64_t>{mine});
    std::uint64_t at = 0, total = 0;
    for (std::size_t q = 0; q < work.size(); ++q) {
        if (q < std::size_t(comm.rank())) at += work[q];
        total += work[q];
    }
    // A task goes to the rank whose share holds its first ray: rank floor(at P / total).
    const auto ranks = std::uint64_t(comm.size());
    std::vector<LinkVector> send(ranks);
    for (const Link& t : tasks) {
        send[std::min(ranks - 1, at * ranks / std::max<std::uint64_t>(total, 1))].push_back(t);
        at += evaluation_cost(h, t, s);
    }
    std::vector<std::size_t> from;
    const LinkVector came = all_to_all(comm, send, &from);
    const auto t0 = std::chrono::steady_clock::now();
    evaluate_tasks(h, scene, came, s, links, share.shares);  // (shares of others' links too)
    share.compute_seconds += seconds_since(t0);
    // Back to the ranks that sent them, each in the order it sent them.
    std::vector<LinkVector> back(ranks);
    for (std::size_t q = 0, k = 0; q < ranks; k += from[q], ++q)
        back[q].assign(links.begin() + std::ptrdiff_t(k),
                       links.begin() + std::ptrdiff_t(k + from[q]));
    links = all_to_all(comm, back);
}

/// A round's links are carried out in blocks of this many, in parallel, each block's output
/// kept apart and the outputs joined in block order: the same lists, in the same order, for any
/// number of threads. (One thread alone, these loops over a million links were a fifth of
/// room3's refinement, with the other core waiting.)
inline constexpr std::size_t round_block = 4096;

/// Runs body(k, begin, end) for each block k of [0, n) of round_block items, blocks shared
/// among threads. body must write only block k's own output.
template <class Body>
void for_each_block(std::size_t n, Body&& body) {
    const auto blocks = static_cast<std::int64_t>((n + round_block - 1) / round_block);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 1)
#endif
    for (std::int64_t k = 0; k < blocks; ++k) {
        const std::size_t begin = std::size_t(k) * round_block;
        body(std::size_t(k), begin, std::min(n, begin + round_block));
    }
}

/// What one block of a round's links gives: links to sample (kept, not sampled yet), pairs to
/// open (each a Link marked unopened), links to judge again, settled links, and splits made.
struct RoundBlock {
    std::vector<Link> to_sample, to_open, to_judge, settled;
    std::vector<NodePair> fresh;  // scratch: the block's new pairs
    std::uint64_t splits = 0;
};

/// Appends the `part` of every block to `out`, in block order.
inline void join_blocks(std::vector<RoundBlock>& blocks, std::size_t count,
                        std::vector<Link> RoundBlock::*part, LinkVector& out) {
    std::size_t size = out.size();
    for (std::size_t k = 0; k < count; ++k) size += (blocks[k].*part).size();
    if (size > out.capacity()) out.reserve(std::max(size, 2 * out.capacity()));  // amortised
    for (std::size_t k = 0; k < count; ++k)
        out.insert(out.end(), (blocks[k].*part).begin(), (blocks[k].*part).end());
}

/// The working vectors of a pass's rounds, kept from one round to the next: fresh ones each
/// round cost more than their contents (page faults and copies as they grow from nothing).
struct RoundBuffers {
    std::vector<Verdict> verdict;    ///< per frontier link
    std::vector<char> crosses;       ///< per frontier link: its split makes other ranks' receivers
    std::vector<NodeId> to_split;    ///< elements to split this round
    std::vector<RoundBlock> blocks;  ///< per block of round_block links
    LinkVector tasks;                ///< kept links to sample, then pairs to open
    LinkVector evaluated;            ///< the tasks carried out
};

/// Carries out this rank's verdicts on the frontier (those whose splits stay on this rank;
/// apply_verdict), in parallel blocks: b.tasks gets the kept links still unsampled, then the
/// new pairs to open, in frontier order; `done` the kept links already sampled. Returns the
/// links split; throws if the links would pass max_links.
inline std::uint64_t carry_out_verdicts(const Hierarchy& h, const LinkVector& frontier,
                                        RoundBuffers& b, LinkVector& done, std::size_t max_links) {
    const std::size_t blocks = (frontier.size() + round_block - 1) / round_block;
    if (b.blocks.size() < blocks) b.blocks.resize(blocks);
    const auto anything = [](NodeId) { return true; };
    for_each_block(frontier.size(), [&](std::size_t k, std::size_t begin, std::size_t end) {
        RoundBlock& o = b.blocks[k];
        o.to_sample.clear(), o.to_open.clear(), o.settled.clear(), o.fresh.clear();
        o.splits = 0;
        for (std::size_t i = begin; i < end; ++i)
            if (!b.crosses[i])
                o.splits +=
                    apply_verdict(h, frontier[i], b.verdict[i], o.to_sample, o.fresh, anything);
        // Kept links already sampled are settled; the rest wait for their rays.
        std::erase_if(o.to_sample, [&](const Link& l) {
            if (l.visibility == unsampled) return false;
            o.settled.push_back(l);
            return true;
        });
        for (const NodePair& p : o.fresh)
            o.to_open.push_back({p.receiver, p.source, 0.0f, unopened});
    });
    std::uint64_t splits = 0;
    std::size_t links = done.size();
    for (std::size_t k = 0; k < blocks; ++k) {
        const RoundBlock& o = b.blocks[k];
        splits += o.splits;
        links += o.to_sample.size() + o.to_open.size() + o.settled.size();
    }
    if (links > max_links)
        throw Error("hierarchical radiosity: the refinement would hold more than " +
                    std::to_string(max_links) + " links, past the memory limit; raise " +
                    "--link-error or --min-area, or the limit (--max-memory)");
    b.tasks.clear();
    join_blocks(b.blocks, blocks, &RoundBlock::to_sample, b.tasks);
    join_blocks(b.blocks, blocks, &RoundBlock::to_open, b.tasks);
    join_blocks(b.blocks, blocks, &RoundBlock::settled, done);
    return splits;
}

/// Sorts the round's evaluated links, in parallel blocks and in their order: opened links go to
/// the next round's frontier, and so do sampled ones that their rays found partly visible
/// (judge refines those further); the rest are settled in `done`; pairs that exchange nothing
/// are dropped.
inline void settle_evaluated(const Hierarchy& h, const RefineSettings& s, RoundBuffers& b,
                             LinkVector& frontier, LinkVector& done) {
    const LinkVector& evaluated = b.evaluated;
    const std::size_t blocks = (evaluated.size() + round_block - 1) / round_block;
    if (b.blocks.size() < blocks) b.blocks.resize(blocks);
    for_each_block(evaluated.size(), [&](std::size_t k, std::size_t begin, std::size_t end) {
        RoundBlock& o = b.blocks[k];
        o.to_judge.clear(), o.settled.clear();
        for (std::size_t i = begin; i < end; ++i) {
            const Link& l = evaluated[i];
            if (l.visibility < 0.0f) continue;  // exchanges nothing: dropped
            const bool judged_again =
                l.visibility == unsampled ||
                (l.visibility > 0.0f && l.visibility < 1.0f && splits_further(h, l, s));
            (judged_again ? o.to_judge : o.settled).push_back(l);
        }
    });
    frontier.clear();
    join_blocks(b.blocks, blocks, &RoundBlock::to_judge, frontier);
    join_blocks(b.blocks, blocks, &RoundBlock::settled, done);
}

/// One round of a pass: judge this rank's frontier; split, on every rank alike and in
/// increasing id order, every element that any rank's verdicts split (so node ids never depend
/// on the ranks or threads); carry out the verdicts; then, the round's work shared evenly among
/// the ranks (evaluate_shared), open the new links of this rank's receivers (their transfers:
/// the next round's frontier) and sample the kept links that are not sampled yet (settled).
/// Rays are cast only for links the oracle keeps: most links of a pass are split as soon as
/// they are judged. Three all-gathers (the splits, the links that cross ranks, the work), two
/// all-to-alls and one reduction.
template <Visibility V>
void refine_round(Hierarchy& h, const V& scene, RefineRound& round, const RefineSettings& s,
                  const OracleInputs& in, const NodesAdded& on_nodes, RefineShare& share,
                  RoundBuffers& b) {
    const int me = share.comm.rank();
    const auto owner = [&](NodeId n) { return share.partition.owner(h, n); };
    LinkVector& frontier = round.frontier;
    std::vector<Verdict>& verdict = b.verdict;
    verdict.assign(frontier.size(), Verdict::keep);
    const auto t0 = std::chrono::steady_clock::now();
    const auto count = static_cast<std::int64_t>(frontier.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 256)
#endif
    for (std::int64_t i = 0; i < count; ++i)
        verdict[std::size_t(i)] = judge(h, frontier[std::size_t(i)], in, s);
    share.compute_seconds += seconds_since(t0);
    std::vector<NodeId>& to_split = b.to_split;
    to_split.clear();
    std::vector<SharedSplit> shared;
    b.crosses.assign(frontier.size(), 0);
    const bool ranks = share.comm.size() > 1;  // (one rank owns every receiver)
    for (std::size_t i = 0; i < frontier.size(); ++i) {
        if (const NodeId n = node_to_split(h, frontier[i], verdict[i]); n != no_node)
            to_split.push_back(n);
        b.crosses[i] = ranks && crosses_ranks(h, frontier[i], verdict[i], owner);
        if (b.crosses[i]) shared.push_back({frontier[i], std::uint32_t(verdict[i])});
    }
    to_split = all_gather(share.comm, to_split);
    std::sort(to_split.begin(), to_split.end());
    to_split.erase(std::unique(to_split.begin(), to_split.end()), to_split.end());
    const std::size_t before = h.size();
    for (const NodeId n : to_split) {
        split_element(h, n);
        share.split_log.push_back(n);
    }
    if (h.size() > before) on_nodes(before);
    shared = all_gather(share.comm, shared);
    // The round's tasks: the kept links still unsampled, then the new pairs to open (this
    // rank's verdicts', then those of the splits shared by every rank, each rank taking its
    // receivers).
    const std::uint64_t splits = carry_out_verdicts(h, frontier, b, round.done, share.max_links);
    std::vector<NodePair> fresh;
    std::vector<Link> unused;
    const auto ours = [&](NodeId n) { return owner(n) == me; };
    for (const SharedSplit& x : shared)
        apply_verdict(h, x.link, Verdict(x.verdict), unused, fresh, ours);
    for (const NodePair& p : fresh) b.tasks.push_back({p.receiver, p.source, 0.0f, unopened});
    if (ranks)  // the work, where the next partition will weigh it (one rank has no other)
        for (const Link& t : b.tasks)
            share.cost[h.member_begin[t.receiver]] += evaluation_cost(h, t, s);
    evaluate_shared(h, scene, b.tasks, s, share, b.evaluated);
    settle_evaluated(h, s, b, frontier, round.done);
    std::array<std::uint64_t, 3> totals{splits, frontier.size(), round.done.size()};
    share.comm.sum_in_place(totals);
    round.splits += totals[0] + shared.size();
    round.open = totals[1];
    round.settled = totals[2];
}

}  // namespace detail

/// One refinement pass over all links at this threshold, continuing `round` (a fresh pass:
/// every link in its frontier): rounds of judging, splitting and evaluating
/// (detail::refine_round) until no rank has a link left to judge. Leaves this rank's links in
/// round.done, sorted by receiver then source (the order of every gather). on_nodes(from) is
/// called after nodes are appended; `inputs` must then cover them. After each round
/// round_done(round) may take a checkpoint or stop the pass (Cancelled). Cost: O(links made)
/// transfers and rays, split over the ranks.
template <Visibility V>
void refine_links(Hierarchy& h, const V& scene, RefineRound& round, const RefineSettings& s,
                  const std::function<OracleInputs()>& inputs, const NodesAdded& on_nodes,
                  RefineShare& share, const RoundDone& round_done) {
    detail::RoundBuffers buffers;
    while (round.open > 0) {
        detail::refine_round(h, scene, round, s, inputs(), on_nodes, share, buffers);
        if (round_done && !round_done(round)) throw Cancelled();
    }
    sort_links(round.done);
}

}  // namespace radiosity
