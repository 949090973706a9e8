#pragma once
/// @file stopping.hpp  What the hierarchical sweeps stop by (solve_loop.hpp): a contraction q of
/// their operator and the norm it holds in, so that q / (1 - q) times a sweep's change bounds
/// the error of B (StoppingRule, solver/session.hpp), and the size the error is relative to.
///
/// The sweeps apply B -> E + M B at the leaves, with M = R s G: gather and push (G, what a leaf
/// receives per unit of B at every leaf, its links' estimated transfers), the row scales s
/// (scale_row_sums, gather.hpp) and the reflectances R. M is nonnegative. Its max norm
/// ||M||_inf = max_i rho_i s_i g_i is a contraction bound wherever every row sum is below
/// 1 / rho, as exact form factors' are. Sampled ones scatter past it at a few leaves (the Cornell
/// box's few faces at link error 3e-7: ||M||_inf = 1.03); then the max norm gives no bound at
/// all, though the sweeps contract well (by about 0.65 a sweep there).
///
/// A weighted max norm does. For weights w > 0, ||x||_w = max_i |x_i| / w_i, and a nonnegative M
/// has ||M||_w = max_i (M w)_i / w_i. That is at least M's spectral radius for every w, and
/// equal to it at its Perron vector (the Collatz-Wielandt formula; Varga, Matrix Iterative
/// Analysis, ch. 2, nonnegative matrices). The power iteration w_k+1 = M w_k, from w_0 = 1, moves w
/// towards that vector, so ||M||_w falls from ||M||_inf towards the radius: the few heavy rows gain
/// weight, and their ratio (M w)_i / w_i drops to what their sources send them. Any w gives a
/// true bound, so the solve keeps the smallest it meets in a few steps, each one sweep.
///
/// A band's operator R_k s G is at most rho_max s G entry by entry, so one w and one q, taken for
/// rho_max (the largest reflectance of each leaf over the bands), serve every band.

#include <radiosity/hierarchy/gather.hpp>
#include <radiosity/hierarchy/nodes.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace radiosity {

/// A weighted max norm in which the sweeps contract (the file comment): per node the weight w
/// of the norm ||x||_w = max over leaves i of |x_i| / w_i (1 at the largest; only leaves'
/// count), and q = ||M||_w. Empty weights: the plain max norm, w = 1.
struct ContractionNorm {
    std::vector<double> weight;  ///< per node (leaves'), or empty: the max norm
    double q = 1.0;              ///< ||M||_w: a bound on the sweeps' contraction where below 1
};

/// Power steps towards the Perron vector that solve_loop.hpp tries at most, each one sweep:
/// room3's two passes settle in 6 and 3, the Cornell box's few faces at link error 3e-7 in 8.
inline constexpr int contraction_power_steps = 12;

/// Weights of leaves that M sends nothing to (black, or unlinked: their B never changes) and of
/// those it sends very little are raised to this share of the largest, so that every weight is
/// positive; (M w)_i / w_i stays a true ratio there, only a smaller one.
inline constexpr double contraction_weight_floor = 1e-6;

/// y = (M x) at the leaves from `total` (push's irradiance per leaf for a B of x, the same in
/// every band): rho_max s total, 0 at other nodes. Cost: O(nodes).
template <std::size_t K>
std::vector<double> leaf_rows(const Hierarchy& h, const NodeValues<K>& v,
                              const std::vector<double>& total) {
    std::vector<double> y(h.size(), 0.0);
    for (std::size_t i = 0; i < h.size(); ++i)
        if (h.is_leaf(static_cast<NodeId>(i))) y[i] = v.rho_max[i] * v.row_scale[i] * total[i * K];
    return y;
}

/// ||M||_w = max over leaves of (M w)_i / w_i, given y = M w (leaf_rows). Cost: O(nodes).
inline double weighted_norm(const Hierarchy& h, const std::vector<double>& y,
                            const std::vector<double>& w) {
    double q = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i)
        if (h.is_leaf(static_cast<NodeId>(i))) q = std::max(q, y[i] / w[i]);
    return q;
}

/// The next weights of the power iteration: y scaled so that its largest leaf is 1, each leaf at
/// least contraction_weight_floor (0 at other nodes). Empty if y is 0 at every leaf (M = 0: no
/// leaf reflects anything, and the sweeps are done after one). Cost: O(nodes).
inline std::vector<double> next_weights(const Hierarchy& h, std::vector<double> y) {
    double top = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i)
        if (h.is_leaf(static_cast<NodeId>(i))) top = std::max(top, y[i]);
    if (!(top > 0.0)) return {};
    for (std::size_t i = 0; i < h.size(); ++i)
        y[i] = h.is_leaf(static_cast<NodeId>(i)) ? std::max(y[i] / top, contraction_weight_floor)
                                                 : 0.0;
    return y;
}

/// Where ||M||_inf = `row_norm` >= 1, the weighted norm (the file comment): power steps from
/// w = M 1 (`rows`: leaf_rows of the row sums), each calling apply(w) for M w (one sweep, E left
/// out), keeping the w of the smallest ||M||_w met. Stops once ||M||_w is below 1 and falls by
/// less than 1% a step, or after contraction_power_steps; {empty, row_norm} if no w does better.
/// (On a periodic M, light that only goes back and forth between two sets of leaves, the power
/// steps oscillate and may find nothing better: the bound is then no worse than the max norm's.)
/// Cost: up to contraction_power_steps calls of apply.
template <class Apply>
ContractionNorm weigh_contraction(const Hierarchy& h, std::vector<double> rows, double row_norm,
                                  Apply&& apply) {
    ContractionNorm best{{}, row_norm};
    std::vector<double> w = next_weights(h, std::move(rows));
    double last = row_norm;
    for (int step = 0; step < contraction_power_steps && !w.empty(); ++step) {
        std::vector<double> y = apply(w);  // M w
        const double q = weighted_norm(h, y, w);
        const bool settled = q < 1.0 && q > 0.99 * last;
        last = q;
        if (q < best.q) best = ContractionNorm{std::move(w), q};  // (w is replaced next)
        if (settled) break;
        w = next_weights(h, std::move(y));
    }
    return best;
}

/// The size a hierarchical solve's error is relative to: the largest reflected radiosity
/// B - E of any leaf and band (never more than ||B||_inf). The error lies in the reflected light
/// alone (E is exact), and a lamp 216 times brighter than the walls (the Cornell box's) made a
/// tolerance of 1e-4 of ||B|| one of 2% of the walls. Cost: O(nodes).
template <std::size_t K>
double reflected_size(const Hierarchy& h, const NodeValues<K>& v) {
    double size = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        if (!h.is_leaf(static_cast<NodeId>(i))) continue;
        for (std::size_t k = 0; k < K; ++k) size = std::max(size, v.B[i * K + k] - v.E[i * K + k]);
    }
    return size;
}

}  // namespace radiosity
