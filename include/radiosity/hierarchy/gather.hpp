#pragma once
/// @file gather.hpp  One iteration of hierarchical radiosity over fixed links (Hanrahan, Salzman
/// & Aupperle 1991): gather, every receiver summing B_s T_rs V_rs over its links into its
/// irradiance H_r; push-pull, each node's H handed down to its leaves (a cluster's evenly to its
/// surfaces, as an isotropic receiver does; Sillion 1995), B = E + rho H at the leaves, and B
/// pulled back up as area-weighted means. Jacobi in form, so every receiver is independent.

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
    /// The share of its parent's irradiance a node takes per unit area in the push: exposure
    /// weights (exposure.hpp) below clusters, 1 below elements.
    std::vector<double> push;

    /// Gives nodes [from, h.size()) their parent's values (new children of a split element).
    void extend(const Hierarchy& h, std::size_t from) {
        const std::size_t n = h.size();
        for (auto* v : {&E, &rho, &B, &H}) v->resize(n * K, 0.0);
        rho_max.resize(n, 0.0);
        B_max.resize(n, 0.0);
        push.resize(n, 1.0);
        for (std::size_t i = from; i < n; ++i) {
            const NodeId p = h.parent[i];
            for (std::size_t k = 0; k < K; ++k) {
                E[i * K + k] = E[p * K + k];
                rho[i * K + k] = rho[p * K + k];
                B[i * K + k] = B[p * K + k];
            }
            rho_max[i] = rho_max[p];
            B_max[i] = B_max[p];
        }
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

/// Push-pull: the irradiance of every ancestor added down to the leaves (push, ids increasing:
/// parents come first; below a cluster weighted by exposure, v.push), B = E + rho H_total at
/// each leaf, then B pulled up as area-weighted means
/// of the children (ids decreasing). Returns the largest change of a leaf's B (every band).
/// Sequential and in a fixed order. Cost: O(nodes).
template <std::size_t K>
double push_pull(const Hierarchy& h, NodeValues<K>& v, std::vector<double>& total) {
    const std::size_t n = h.size();
    total.resize(n * K);
    double change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const NodeId p = h.parent[i];
        for (std::size_t k = 0; k < K; ++k)
            total[i * K + k] = v.H[i * K + k] + (p == no_node ? 0.0 : v.push[i] * total[p * K + k]);
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
            std::array<double, K> sum{};
            double area = 0.0;
            for (NodeId c = h.first_child[i]; c < h.first_child[i] + h.child_count[i]; ++c) {
                for (std::size_t k = 0; k < K; ++k) sum[k] += h.area[c] * v.B[c * K + k];
                area += h.area[c];
                bmax = std::max(bmax, v.B_max[c]);
            }
            for (std::size_t k = 0; k < K; ++k) v.B[i * K + k] = sum[k] / area;
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

/// q = max over leaves of rho_max times the sum of T V over the links of the leaf and of all
/// its ancestors (`row`: per node, link_rows scattered, 0 for nodes without links):
/// ||R F||_inf of the operator the links define, the contraction bound of the stopping rule.
/// Cost: O(nodes).
template <std::size_t K>
double hierarchy_contraction(const Hierarchy& h, std::vector<double> row, const NodeValues<K>& v) {
    double q = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        if (h.parent[i] != no_node) row[i] += row[h.parent[i]];
        if (h.is_leaf(static_cast<NodeId>(i))) q = std::max(q, v.rho_max[i] * row[i]);
    }
    return q;
}

}  // namespace radiosity
