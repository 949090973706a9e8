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
inline LinkGroups group_links(const std::vector<Link>& links) {
    LinkGroups g;
    for (std::size_t i = 0; i < links.size(); ++i)
        if (i == 0 || links[i].receiver != links[i - 1].receiver) {
            if (i > 0) g.begin.push_back(i);
            g.receivers.push_back(links[i].receiver);
        }
    if (!links.empty()) g.begin.push_back(links.size());
    return g;
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

    /// Gives nodes [from, h.size()) their parent's values (new children of a split element).
    void extend(const Hierarchy& h, std::size_t from) {
        const std::size_t n = h.size();
        for (auto* v : {&E, &rho, &B, &H}) v->resize(n * K, 0.0);
        rho_max.resize(n, 0.0);
        B_max.resize(n, 0.0);
        exposure.resize(n, 1.0);
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
};

/// Gather: H_r = sum over r's links of T_rs V_rs B_s, receivers in parallel, each summing its
/// links in their sorted order (the same sums for any thread count). Cost: O(links).
template <std::size_t K>
void gather_links(const std::vector<Link>& links, const LinkGroups& g, NodeValues<K>& v) {
    std::fill(v.H.begin(), v.H.end(), 0.0);
    const auto groups = static_cast<std::int64_t>(g.receivers.size());
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 64) if (links.size() > 20000)
#endif
    for (std::int64_t gi = 0; gi < groups; ++gi) {
        std::array<double, K> acc{};
        for (std::size_t i = g.begin[std::size_t(gi)]; i < g.begin[std::size_t(gi) + 1]; ++i) {
            const Link& l = links[i];
            const double t = double(l.coefficient) * double(l.visibility);
            for (std::size_t k = 0; k < K; ++k) acc[k] += t * v.B[l.source * K + k];
        }
        const NodeId r = g.receivers[std::size_t(gi)];
        for (std::size_t k = 0; k < K; ++k) v.H[r * K + k] = acc[k];
    }
}

/// The irradiance of the exposed part of node i from its own links, h = H / e (0 where nothing
/// of the node is exposed: its links' rays all end in what hides it).
template <std::size_t K>
double exposed_irradiance(const NodeValues<K>& v, std::size_t i, std::size_t k) {
    return v.exposure[i] > 0.0 ? v.H[i * K + k] / v.exposure[i] : 0.0;
}

/// Push-pull (the file comment): the exposed irradiance h of every ancestor added down to the
/// leaves (push, ids increasing: parents come first), B = E + rho h at each leaf, then B
/// pulled up as the exposed-area-weighted mean of the children (ids decreasing; the plain area
/// mean where no child is exposed). Returns the largest change of a leaf's B (every band).
/// Sequential and in a fixed order. Cost: O(nodes).
template <std::size_t K>
double push_pull(const Hierarchy& h, NodeValues<K>& v, std::vector<double>& total) {
    const std::size_t n = h.size();
    total.resize(n * K);
    double change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const NodeId p = h.parent[i];
        for (std::size_t k = 0; k < K; ++k)
            total[i * K + k] =
                exposed_irradiance(v, i, k) + (p == no_node ? 0.0 : total[p * K + k]);
        if (!h.is_leaf(static_cast<NodeId>(i))) continue;
        for (std::size_t k = 0; k < K; ++k) {  // B = E + rho H
            const double b = v.E[i * K + k] + v.rho[i * K + k] * total[i * K + k];
            change = std::max(change, std::abs(b - v.B[i * K + k]));
            v.B[i * K + k] = b;
        }
    }
    for (std::size_t i = n; i-- > 0;) {
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
        } else {
            for (std::size_t k = 0; k < K; ++k) bmax = std::max(bmax, v.B[i * K + k]);
        }
        v.B_max[i] = bmax;  // the brightest leaf below: what the node's mean B may hide
    }
    return change;
}

/// The sum of T V over each group's links (a row of the operator the links define), in the
/// groups' order.
inline std::vector<double> link_rows(const std::vector<Link>& links, const LinkGroups& g) {
    std::vector<double> row(g.receivers.size(), 0.0);
    for (std::size_t gi = 0; gi < row.size(); ++gi)
        for (std::size_t i = g.begin[gi]; i < g.begin[gi + 1]; ++i)
            row[gi] += double(links[i].coefficient) * double(links[i].visibility);
    return row;
}

/// q = max over leaves of rho_max times the sum of T V / e over the links of the leaf and of
/// all its ancestors (`row`: per node, link_rows scattered, 0 for nodes without links; e the
/// node's exposure, as push_pull divides): ||R F||_inf of the operator the links define, the
/// contraction bound of the stopping rule. Cost: O(nodes).
template <std::size_t K>
double hierarchy_contraction(const Hierarchy& h, std::vector<double> row, const NodeValues<K>& v) {
    double q = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        row[i] = v.exposure[i] > 0.0 ? row[i] / v.exposure[i] : 0.0;
        if (h.parent[i] != no_node) row[i] += row[h.parent[i]];
        if (h.is_leaf(static_cast<NodeId>(i))) q = std::max(q, v.rho_max[i] * row[i]);
    }
    return q;
}

}  // namespace radiosity
