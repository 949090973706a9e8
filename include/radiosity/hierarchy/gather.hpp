#pragma once
/// @file gather.hpp  One iteration of hierarchical radiosity over fixed links (Hanrahan, Salzman
/// & Aupperle 1991): gather, every receiver summing B_s T_rs V_rs over its links into its
/// irradiance H_r; push-pull, each node's irradiance handed down to its leaves, B = E + rho H
/// at the leaves, and B pulled back up. Jacobi in form, so every receiver is independent.
///
/// Push and pull work with the exposed part of each node (exposure.hpp: the share e of its area
/// from which the scene is seen). A link's transfer is a mean over the whole receiver, hidden
/// part included, so the irradiance of the exposed part is h = H / e; it goes down to every
/// child alike (each child's exposed part sees what its parent's does), and at a leaf the
/// exposed part's radiosity is B = E + rho h. Going up, a node's radiosity is the mean of its
/// children's weighted by exposed area, A e: what the node sends, since its hidden part sends
/// nothing along any link. Energy is kept: a leaf's exposed part absorbs and re-emits all the
/// light its links bring. Below a cluster this is the push by exposure that the isotropic
/// cluster lacks (Sillion 1995 pushes to every face alike); below an element it is what keeps
/// a wall's hidden strip under a pillar from taking light and dimming the wall around it.
///
/// A cluster's faces need not face alike (a box's top and sides, a room's corner), and the
/// light a link brings falls on those that face its source. So a link into a cluster has the
/// shares of its light that the cluster's orientation classes took (ClassShares; nodes.hpp:
/// +x, -x, +y, -y, +z, -z, by its samples), and push-pull hands each class's light down to the
/// children in proportion to their exposed area in that class, S_c = sum of A e over their
/// faces of the class (`facing_area`): a box's top, lit from above, takes the light its sides
/// do not, and each class's light still reaches exactly the exposed faces of that class, so
/// energy is kept.
/// Flat clusters, and what a link does not split by class, go down by exposed area alone, as
/// in Sillion's isotropic cluster; at a root element the light becomes its scalar irradiance.

#include <radiosity/detail/parallel.hpp>
#include <radiosity/hierarchy/links.hpp>
#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace radiosity {

/// Links grouped by receiver (links sorted by receiver): the links of receiver
/// receivers[g] are links[begin[g] .. begin[g + 1]).
struct LinkGroups {
    std::vector<NodeId> receivers;
    std::vector<std::size_t> begin{0};
};

/// The groups of sorted links. Cost: O(links).
inline LinkGroups group_links(const LinkVector& links) {
    LinkGroups g;
    for (std::size_t i = 0; i < links.size(); ++i)
        if (i == 0 || links[i].receiver != links[i - 1].receiver) {
            if (i > 0) g.begin.push_back(i);
            g.receivers.push_back(links[i].receiver);
        }
    if (!links.empty()) g.begin.push_back(links.size());
    return g;
}

/// The nodes of a hierarchy level by level, the top node's level 0 and every other node's one
/// below its parent's: the order in which push-pull can share a sweep among threads, since a
/// node's push reads only what the level above left, and its pull only the level below.
struct NodeLevels {
    std::vector<NodeId> nodes;       ///< level after level, each level in increasing id
    std::vector<std::size_t> begin;  ///< where each level starts in nodes; one more than levels
};

/// The levels of h's nodes (parents have smaller ids than their children), by counting sort.
/// Cost: O(nodes).
inline NodeLevels node_levels(const Hierarchy& h) {
    std::vector<std::uint32_t> level(h.size(), 0);
    std::size_t levels = h.size() > 0 ? 1 : 0;
    for (std::size_t i = 1; i < h.size(); ++i) {
        level[i] = level[h.parent[i]] + 1;
        levels = std::max<std::size_t>(levels, level[i] + 1);
    }
    NodeLevels out;
    out.begin.assign(levels + 1, 0);
    for (const std::uint32_t l : level) ++out.begin[l + 1];
    for (std::size_t l = 0; l < levels; ++l) out.begin[l + 1] += out.begin[l];
    out.nodes.resize(h.size());
    std::vector<std::size_t> at(out.begin.begin(), out.begin.end() - 1);
    for (std::size_t i = 0; i < h.size(); ++i) out.nodes[at[level[i]]++] = NodeId(i);
    return out;
}

/// Nodes of a level from which push and pull share it among threads (a node's push or pull
/// takes tens of ns; a parallel region, a few µs). Room3's levels: 1, 2, 4, ... 4,096 clusters,
/// then its elements, 388 to 3,196 a level; shared from 1,024 on, push-pull kept the other
/// core waiting half as long as done in id order, from 256 on a fifth as long.
inline constexpr std::size_t parallel_level = 256;

/// Runs body(n) for every node n of `levels`, level after level (from the top, or from the
/// bottom if `upward`), the nodes of a level shared among threads where it has parallel_level
/// or more. body(n) must write only n's values (going down, also its children's) and read,
/// besides n's own, only those of the level done before.
template <class Body>
void for_each_level(const NodeLevels& levels, bool upward, Body&& body) {
    const std::size_t count = levels.begin.size() - 1;
    for (std::size_t step = 0; step < count; ++step) {
        const std::size_t l = upward ? count - 1 - step : step;
        const auto first = static_cast<std::int64_t>(levels.begin[l]);
        const auto last = static_cast<std::int64_t>(levels.begin[l + 1]);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(static) if (last - first >= std::int64_t(parallel_level))
#endif
        for (std::int64_t j = first; j < last; ++j) body(levels.nodes[std::size_t(j)]);
    }
}

/// Per-node radiometry of the hierarchy, K bands per node, node after node.
template <std::size_t K>
struct NodeValues {
    std::vector<double> E, rho;  ///< emission and reflectance (clusters: unused)
    std::vector<double> B;       ///< radiosity (clusters: area-weighted mean of their roots')
    std::vector<double> H;       ///< irradiance gathered over the node's own links
    /// The oracle's inputs: the largest rho and B of any leaf below the node (and any band).
    std::vector<double> rho_max, B_max;
    /// The share of the node's area that is exposed (exposure.hpp); 1 until measured.
    std::vector<double> exposure;
    /// Per top node (clusters and roots, Hierarchy::top_nodes): its index among the mixed
    /// clusters (Hierarchy::mixed), or no_node. Only those keep their light by orientation
    /// class: a cluster whose faces face alike has one class, all of its light.
    std::vector<NodeId> mixed;
    /// Per mixed cluster: of H, what each orientation class of its faces took (facing_classes
    /// values per band, class after class); the rest of H goes to every exposed face alike.
    std::vector<double> Hc;
    /// Per mixed cluster: the exposed area of its faces in each orientation class, S = sum of
    /// A e over the faces of the class (facing_areas; facing_area() for any top node).
    std::vector<double> S;
    /// Per mixed cluster: the mean radiosity of its exposed faces in each orientation class,
    /// weighted by their A e (facing_classes values per band, class after class; B where the
    /// class is empty): what a link sends from the faces of that class (pull_classes).
    std::vector<double> Bc;
    /// Per node: what push-pull multiplies a leaf's irradiance by (scale_row_sums): 1 over its
    /// links' row sum where it is enclosed (within row_scale_limit), else 1; held where the
    /// row sum is impossible.
    std::vector<double> row_scale;
    /// Per node: 1 where a leaf was found enclosed (exposure.hpp: element_enclosed), its
    /// visible row sum 1; else 0, and 0 until tested.
    std::vector<std::uint8_t> enclosed;

    /// Gives nodes [from, h.size()) their parent's values (new children of a split element).
    void extend(const Hierarchy& h, std::size_t from) {
        const std::size_t n = h.size();
        if (mixed.empty()) {  // the top nodes are all made at once, by build_hierarchy
            NodeId count = 0;
            mixed.resize(h.top_nodes(), no_node);
            for (NodeId i = 0; i < mixed.size(); ++i)
                if (h.mixed(i)) mixed[i] = count++;
            Hc.assign(std::size_t(count) * facing_classes * K, 0.0);
            Bc.assign(Hc.size(), 0.0);
            S.assign(std::size_t(count) * facing_classes, 0.0);
        }
        for (auto* v : {&E, &rho, &B, &H}) v->resize(n * K, 0.0);
        rho_max.resize(n, 0.0);
        B_max.resize(n, 0.0);
        exposure.resize(n, 1.0);
        row_scale.resize(n, 1.0);  // new nodes: 1 until the next pass's rows are measured
        enclosed.resize(n, 0);     // and not enclosed until a final pass's leaves are tested
        for (std::size_t i = from; i < n; ++i) {
            const NodeId p = h.parent[i];
            for (std::size_t k = 0; k < K; ++k) {
                E[i * K + k] = E[p * K + k];
                rho[i * K + k] = rho[p * K + k];
                B[i * K + k] = B[p * K + k];
            }
            rho_max[i] = rho_max[p];
            B_max[i] = B_max[p];
            exposure[i] = exposure[p];
        }
    }

    /// The mean radiosity over the whole of leaf n in band k, what a patch shows: the exposed
    /// part's B over the share e, the hidden part's emission alone over the rest.
    double mean_radiosity(NodeId n, std::size_t k) const {
        return E[n * K + k] + exposure[n] * (B[n * K + k] - E[n * K + k]);
    }

    /// Whether top node n is a mixed cluster.
    bool is_mixed(NodeId n) const { return n < mixed.size() && mixed[n] != no_node; }

    /// S of top node n in class d: a mixed cluster's from S; any other node has its faces in
    /// one class (Hierarchy::classes), whose S is its exposed area A e.
    double facing_area(const Hierarchy& h, NodeId n, std::size_t d) const {
        if (is_mixed(n)) return S[mixed[n] * facing_classes + d];
        return h.classes[n] == (1u << d) ? h.area[n] * exposure[n] : 0.0;
    }

    /// Zeroes H and Hc: every gather writes its receivers' and only those, so this is due
    /// whenever the links change.
    void clear_irradiance() {
        std::fill(H.begin(), H.end(), 0.0);
        std::fill(Hc.begin(), Hc.end(), 0.0);
    }
};

/// The class shares of a rank's links for its sweeps: `entries` (class_shares, in the links'
/// order), and for each group of LinkGroups where its entries begin (`begin`, one more than the
/// groups), so that a gather finds a link's shares by walking its receiver's entries along with
/// its links.
struct GroupShares {
    std::vector<ClassShares> entries;
    std::vector<std::size_t> begin{0};
};

/// Where each group's entries begin (entries: a subsequence of the sorted links, by
/// link_order). Cost: O(groups + entries).
inline GroupShares group_shares(const LinkGroups& g, std::vector<ClassShares> entries) {
    GroupShares out;
    out.begin.assign(g.receivers.size() + 1, entries.size());
    std::size_t e = 0;
    for (std::size_t gi = 0; gi < g.receivers.size(); ++gi) {
        while (e < entries.size() && entries[e].receiver < g.receivers[gi]) ++e;
        out.begin[gi] = e;
    }
    out.entries = std::move(entries);
    return out;
}

/// The radiosity that link l sends: its source's B, or, from a mixed cluster, the mean over the
/// orientation classes of the cluster's per-class radiosity Bc, weighted by the shares of the
/// link's light that each class sent (ClassShares::sending; x null: the link has none).
template <std::size_t K>
std::array<double, K> sent(const Link& l, const ClassShares* x, const NodeValues<K>& v) {
    std::array<double, K> b{};
    if (x == nullptr || !measured(x->sending)) {
        for (std::size_t k = 0; k < K; ++k) b[k] = v.B[l.source * K + k];
        return b;
    }
    const double* Bc = &v.Bc[std::size_t(v.mixed[l.source]) * facing_classes * K];
    for (std::size_t d = 0; d < facing_classes; ++d) {  // no branch on 0: they mispredict
        const double w = double(x->sending[d]) * (1.0 / 255.0);
        for (std::size_t k = 0; k < K; ++k) b[k] += w * Bc[d * K + k];
    }
    return b;
}

/// Gather: H_r = sum over r's links of T_rs V_rs B_s, receivers in parallel, each summing its
/// links in their sorted order (the same sums for any thread count); a mixed cluster receiver
/// also sums each link's light by the classes that took it (ClassShares::facing) into Hc, at
/// most S_d / A_r per unit radiosity from one link (the faces' irradiance at most the source's
/// radiosity; the rest of the link's light goes to every face alike). A link's shares are
/// the next of its group's entries if that names its source. Writes the
/// receivers' H and Hc only: the others' must be 0 (NodeValues::clear_irradiance, due when the
/// links change; a fill per sweep would write 300 MB at a million faces). Cost: O(links).
template <std::size_t K>
void gather_links(const Hierarchy& h, const LinkVector& links, const LinkGroups& g,
                  const GroupShares& shares, NodeValues<K>& v) {
    const auto groups = static_cast<std::int64_t>(g.receivers.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64) if (links.size() > 20000)
#endif
    for (std::int64_t gi = 0; gi < groups; ++gi) {
        const NodeId r = g.receivers[std::size_t(gi)];
        const bool cluster = v.is_mixed(r);
        std::array<double, K> acc{};
        std::array<double, facing_classes * K> by_class{};
        // The most one link can give a class per unit radiosity sent, S_d / A_r: its faces'
        // irradiance, A_r Hc_d / S_d after push_mixed, is at most the source's radiosity (their
        // visible form factor is at most 1). A few samples near the source can put more in a
        // class of little area; the excess stays in H, which goes to every face alike.
        std::array<double, facing_classes> cap{};
        if (cluster)
            for (std::size_t d = 0; d < facing_classes; ++d)
                cap[d] = v.S[v.mixed[r] * facing_classes + d] / h.area[r];
        std::size_t e = shares.begin[std::size_t(gi)];
        const std::size_t e_end = shares.begin[std::size_t(gi) + 1];
        for (std::size_t i = g.begin[std::size_t(gi)]; i < g.begin[std::size_t(gi) + 1]; ++i) {
            const Link& l = links[i];
            const ClassShares* x = nullptr;
            if (e < e_end && shares.entries[e].source == l.source) x = &shares.entries[e++];
            const double t = double(l.coefficient) * double(l.visibility);
            const std::array<double, K> b = sent(l, x, v);
            for (std::size_t k = 0; k < K; ++k) acc[k] += t * b[k];
            if (!cluster || x == nullptr || !measured(x->facing)) continue;
            for (std::size_t d = 0; d < facing_classes; ++d) {
                const double td = std::min(t * (double(x->facing[d]) * (1.0 / 255.0)), cap[d]);
                for (std::size_t k = 0; k < K; ++k) by_class[d * K + k] += td * b[k];
            }
        }
        for (std::size_t k = 0; k < K; ++k) v.H[r * K + k] = acc[k];
        if (cluster)
            std::copy(by_class.begin(), by_class.end(),
                      v.Hc.begin() + std::ptrdiff_t(v.mixed[r] * facing_classes * K));
    }
}

/// The irradiance of the exposed part of node i from its own links, h = H / e (0 where nothing
/// of the node is exposed: its links' rays all end in what hides it).
template <std::size_t K>
double exposed_irradiance(const NodeValues<K>& v, std::size_t i, std::size_t k) {
    return v.exposure[i] > 0.0 ? v.H[i * K + k] / v.exposure[i] : 0.0;
}

/// S of every mixed cluster (NodeValues::S), from its children's (facing_area), bottom up.
/// Due whenever the exposure changes. Cost: O(mixed clusters).
template <std::size_t K>
void facing_areas(const Hierarchy& h, NodeValues<K>& v) {
    for (std::size_t i = v.mixed.size(); i-- > 0;) {
        if (!v.is_mixed(NodeId(i))) continue;
        const NodeId a = h.first_child[i], b = a + 1;
        for (std::size_t d = 0; d < facing_classes; ++d)
            v.S[v.mixed[i] * facing_classes + d] = v.facing_area(h, a, d) + v.facing_area(h, b, d);
    }
}

/// The push through mixed cluster i: the light of each orientation class, its links' (A Hc)
/// and what its parent handed down (`down`, per mixed cluster), shared between its two children
/// by their exposed area in the class (S_c / S_i); what is not split by class by their exposed
/// area (A e). A mixed child keeps its share in `down`; any other (a cluster whose faces face
/// alike, or a root) takes it as the irradiance of its exposed part, into total.
template <std::size_t K>
void push_mixed(const Hierarchy& h, const NodeValues<K>& v, NodeId i, std::vector<double>& down,
                std::vector<double>& total) {
    constexpr std::size_t C = facing_classes;
    const std::size_t mi = v.mixed[i];
    const double exposed = h.area[i] * v.exposure[i];
    // The power of each class and band arriving at i, the rest (alike) last.
    std::array<double, (C + 1) * K> P{};
    for (std::size_t k = 0; k < K; ++k)
        P[C * K + k] = h.area[i] * v.H[i * K + k] + down[(mi * (C + 1) + C) * K + k];
    for (std::size_t d = 0; d < C; ++d)
        for (std::size_t k = 0; k < K; ++k) {
            const double own = h.area[i] * v.Hc[(mi * C + d) * K + k];
            P[d * K + k] = own + down[(mi * (C + 1) + d) * K + k];
            P[C * K + k] -= own;  // taken by class d
        }
    for (NodeId c = h.first_child[i]; c < h.first_child[i] + 2; ++c) {
        const double ec = h.area[c] * v.exposure[c];
        std::array<double, (C + 1) * K> mine{};
        if (exposed > 0.0)  // else nothing of i is exposed: nothing goes down
            for (std::size_t d = 0; d <= C; ++d) {
                const double Si = d < C ? v.S[mi * C + d] : 0.0;
                const double share = Si > 0.0 ? v.facing_area(h, c, d) / Si : ec / exposed;
                for (std::size_t k = 0; k < K; ++k) mine[d * K + k] = P[d * K + k] * share;
            }
        if (v.is_mixed(c)) {
            std::copy(mine.begin(), mine.end(),
                      down.begin() + std::ptrdiff_t(v.mixed[c] * (C + 1) * K));
            continue;
        }
        for (std::size_t k = 0; k < K; ++k) {
            double sum = 0.0;
            for (std::size_t d = 0; d <= C; ++d) sum += mine[d * K + k];
            total[c * K + k] = ec > 0.0 ? sum / ec : 0.0;
        }
    }
}

/// Bc of mixed cluster i from its children's (a child that is not mixed has one class, whose
/// radiosity is its B): the S-weighted mean per class, the cluster's B where the class is empty.
template <std::size_t K>
void pull_classes(const Hierarchy& h, NodeValues<K>& v, NodeId i) {
    constexpr std::size_t C = facing_classes;
    double* out = &v.Bc[std::size_t(v.mixed[i]) * C * K];
    for (std::size_t d = 0; d < C; ++d) {
        const double Si = v.S[v.mixed[i] * C + d];
        for (std::size_t k = 0; k < K; ++k) out[d * K + k] = Si > 0.0 ? 0.0 : v.B[i * K + k];
        if (!(Si > 0.0)) continue;
        for (NodeId c = h.first_child[i]; c < h.first_child[i] + 2; ++c) {
            const double w = v.facing_area(h, c, d) / Si;
            if (w == 0.0) continue;
            const double* bc =
                v.is_mixed(c) ? &v.Bc[(std::size_t(v.mixed[c]) * C + d) * K] : &v.B[c * K];
            for (std::size_t k = 0; k < K; ++k) out[d * K + k] += w * bc[k];
        }
    }
}

/// Pull at node i: its B the exposed-area-weighted mean of its children's (the plain area
/// mean where none is exposed), its Bc if it is a mixed cluster, and B_max the brightest leaf
/// below.
template <std::size_t K>
void pull_node(const Hierarchy& h, NodeValues<K>& v, std::size_t i) {
    double bmax = 0.0;
    if (!h.is_leaf(static_cast<NodeId>(i))) {
        std::array<double, K> sum{}, exposed{};
        double area = 0.0, exposed_area = 0.0;
        for (NodeId c = h.first_child[i]; c < h.first_child[i] + h.child_count[i]; ++c) {
            const double a = h.area[c], ae = h.area[c] * v.exposure[c];
            for (std::size_t k = 0; k < K; ++k) {
                sum[k] += a * v.B[c * K + k];
                exposed[k] += ae * v.B[c * K + k];
            }
            area += a;
            exposed_area += ae;
            bmax = std::max(bmax, v.B_max[c]);
        }
        for (std::size_t k = 0; k < K; ++k)
            v.B[i * K + k] = exposed_area > 0.0 ? exposed[k] / exposed_area : sum[k] / area;
        if (v.is_mixed(NodeId(i))) pull_classes(h, v, NodeId(i));
    } else {
        for (std::size_t k = 0; k < K; ++k) bmax = std::max(bmax, v.B[i * K + k]);
    }
    v.B_max[i] = bmax;  // the brightest leaf below: what the node's mean B may hide
}

/// Pull (pull_node at every node), children before parents: the plain order, ids decreasing;
/// with `levels`, level by level from the bottom, each level's nodes shared among threads
/// (for_each_level). Both give the same bits. Cost: O(nodes).
template <std::size_t K>
void pull(const Hierarchy& h, NodeValues<K>& v, const NodeLevels* levels = nullptr) {
    if (levels != nullptr) {
        for_each_level(*levels, true, [&](NodeId i) { pull_node(h, v, i); });
        return;
    }
    for (std::size_t i = h.size(); i-- > 0;) pull_node(h, v, i);
}

/// Push at node i (the file comment): a mixed cluster hands its light down by orientation
/// class (push_mixed, writing its children's `total` or `down`); any other node adds the
/// exposed irradiance h = H / e of its own links to what came down to it (from a mixed parent,
/// already in total; else its parent's total).
template <std::size_t K>
void push_node(const Hierarchy& h, const NodeValues<K>& v, std::size_t i,
               std::vector<double>& total, std::vector<double>& down) {
    if (v.is_mixed(NodeId(i))) {
        push_mixed(h, v, NodeId(i), down, total);
        return;
    }
    const NodeId p = h.parent[i];
    const bool from_mixed = p != no_node && v.is_mixed(p);  // total[i] set by push_mixed
    for (std::size_t k = 0; k < K; ++k) {
        const double above =
            p == no_node ? 0.0 : (from_mixed ? total[i * K + k] : total[p * K + k]);
        total[i * K + k] = above + exposed_irradiance(v, i, k);
    }
}

/// Push (push_node at every node), parents before children: the plain order, ids
/// increasing; with `levels`, level by level from the top, each level's nodes shared among
/// threads (for_each_level). Both give the same bits. Leaves `total`, per node and band, the
/// irradiance of its exposed part from its own links and all above it. Needs S current
/// (facing_areas). Cost: O(nodes).
template <std::size_t K>
void push(const Hierarchy& h, const NodeValues<K>& v, std::vector<double>& total,
          std::vector<double>& down, const NodeLevels* levels = nullptr) {
    const std::size_t n = h.size();
    total.resize(n * K);
    down.resize(v.S.size() / facing_classes * (facing_classes + 1) * K);
    if (v.is_mixed(0)) std::fill_n(down.begin(), (facing_classes + 1) * K, 0.0);  // the top's
    if (levels != nullptr) {
        for_each_level(*levels, false, [&](NodeId i) { push_node(h, v, i, total, down); });
        return;
    }
    for (std::size_t i = 0; i < n; ++i) push_node(h, v, i, total, down);
}

/// The largest of two changes of B, a NaN in either kept (std::max would drop it), so that
/// push_pull's caller sees a radiosity that is not finite.
inline double larger_change(double change, double moved) {
    return !(moved <= change) && !std::isnan(change) ? moved : change;
}

/// Push-pull: push, then at every leaf B = E + rho s h, with h its pushed irradiance (total)
/// and s its row_scale (scale_row_sums), then pull. Returns the largest
/// change of a leaf's B (every band; not finite where a B is not), in the max norm, or with
/// `weight` (per node) in the weighted one, max |change_i| / w_i (ContractionNorm,
/// stopping.hpp). In a fixed order, or with `levels` shared among threads (push, pull), with
/// the same bits. Cost: O(nodes).
template <std::size_t K>
double push_pull(const Hierarchy& h, NodeValues<K>& v, std::vector<double>& total,
                 std::vector<double>& down, const NodeLevels* levels = nullptr,
                 const std::vector<double>* weight = nullptr) {
    push(h, v, total, down, levels);
    const auto leaf = [&](std::size_t i, double change) {
        if (!h.is_leaf(static_cast<NodeId>(i))) return change;
        const double w = weight != nullptr ? (*weight)[i] : 1.0;
        for (std::size_t k = 0; k < K; ++k) {  // B = E + rho H
            const double b =
                v.E[i * K + k] + v.rho[i * K + k] * (v.row_scale[i] * total[i * K + k]);
            change = larger_change(change, std::abs(b - v.B[i * K + k]) / w);
            v.B[i * K + k] = b;
        }
        return change;
    };
    double change = 0.0;
    const auto n = static_cast<std::int64_t>(h.size());
    if (levels != nullptr && n >= std::int64_t(parallel_level)) {  // threads, as push's
        // Each thread's largest over a piece, then the pieces' in order: the same number.
        std::vector<double> piece(std::size_t(detail::thread_count()), 0.0);
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel
#endif
        {
            double mine = 0.0;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp for schedule(static)
#endif
            for (std::int64_t i = 0; i < n; ++i) mine = leaf(std::size_t(i), mine);
            piece[std::size_t(detail::thread_index())] = mine;
        }
        for (const double c : piece) change = larger_change(change, c);
    } else {
        for (std::size_t i = 0; i < h.size(); ++i) change = leaf(i, change);
    }
    pull(h, v, levels);
    return change;
}

/// push_pull with scratch of its own, S computed first (where the exposure may have changed).
template <std::size_t K>
double push_pull(const Hierarchy& h, NodeValues<K>& v, std::vector<double>& total) {
    std::vector<double> down;
    facing_areas(h, v);
    return push_pull(h, v, total, down);
}

/// What scale_row_sums found: the leaves scaled to a row sum of 1, those held, and
/// ||R G||_inf of the operator.
struct HeldRows {
    std::size_t scaled = 0;  ///< enclosed leaves whose irradiance was scaled to a row sum of 1
    std::size_t held = 0;    ///< leaves whose row sum was held to 1
    double norm = 0.0;       ///< max over leaves of rho_max g s: the sweeps' contraction
};

/// How far an enclosed leaf's irradiance is scaled: by at most this factor or its inverse. A
/// leaf whose links' row sum is off by more than that has lost (or gained) most of its light
/// to a few sampled links that saw little (or much), and a large scale would only magnify what
/// those few happened to see. (Room3's surfaces hardly notice: `bench_hierarchy surfaces 4`
/// puts every surface's median within 0.4% of what no limit gives, and within 0.8% of a limit
/// of 1.25.)
inline constexpr double row_scale_limit = 2.0;

/// The row scales s of the leaves. g = G 1 is a leaf's row sum in the sweeps' operator
/// B -> E + rho s G B (gather and push, leaf by leaf; `total`: what push leaves at each leaf
/// when every node and class sends B = 1, the same for every band).
///
/// Enclosed leaves are scaled to a row sum of 1. The form factors from a leaf's exposed part to
/// every face it sees sum to the share of its hemisphere that faces cover, sum_j F_ij = 1 in a
/// closed room: the identity that normalised form factors keep (a hemicube's delta form factors
/// sum to it). The links' g meets it only on average. Each link is exact on average over its
/// receiver, but a leaf inherits its ancestors' links, whose transfer falls off across them:
/// beside a shared edge a coarse link from the next wall carries its mean to a leaf that sees
/// that wall edge-on and gets nearly nothing from it (a furnace's edge leaf: g = 1.225), and
/// sampled links scatter g further. Rows too heavy at leaves that face each other across a
/// corner raise each other, bounce after bounce: a furnace of rho 0.9 came out 6.6% bright,
/// its edge strips 25%. Where the rays found a leaf enclosed (`enclosed`: element_enclosed, in
/// the final passes), s = 1 / g, within row_scale_limit: the links keep how the light is shared
/// among the sources, the identity says how much there is to share. Every furnace is then
/// exact leaf by leaf. A leaf that sees open space keeps s = 1: its row sum below 1 is known
/// only to the scatter of a few rays (element_enclosed).
///
/// Held. Where g is still impossible with `hold` (rho_max g s >= 1), s = 1 / g, the most any
/// leaf can gather: a cluster link's few samples beside a near face (F / p, with p the face's
/// small share of the area), divided by a small exposure, gave some leaves of the
/// million-triangle box at seed 3 a row sum of 4.6 / rho, and the sweeps ran away. Holding is
/// for sweeps that run away (HierarchySolve::runs_away); held in every pass, the unscaled rows
/// of room3, of reflectance up to 0.99, came out 2.4 to 5.6% below the dense solve.
/// Returns the leaves scaled and held, and max rho_max g s, the operator's ||R G||_inf.
/// Cost: O(nodes).
template <std::size_t K>
HeldRows scale_row_sums(const Hierarchy& h, NodeValues<K>& v, const std::vector<double>& total,
                        bool hold) {
    HeldRows out;
    for (std::size_t i = 0; i < h.size(); ++i) {
        v.row_scale[i] = 1.0;
        if (!h.is_leaf(static_cast<NodeId>(i))) continue;
        const double g = total[i * K];
        if (v.enclosed[i] && g > 0.0) {
            v.row_scale[i] = std::clamp(1.0 / g, 1.0 / row_scale_limit, row_scale_limit);
            ++out.scaled;
        }
        if (hold && v.rho_max[i] * g * v.row_scale[i] >= 1.0) {
            v.row_scale[i] = 1.0 / g;
            ++out.held;
        }
        out.norm = std::max(out.norm, v.rho_max[i] * g * v.row_scale[i]);
    }
    return out;
}

}  // namespace radiosity
