#pragma once
/// @file build.hpp  Building the eight-wide tree of geometry/bvh/tree.hpp over any primitives
/// given by their boxes and centroids: a binary tree by the binned surface area heuristic (Wald
/// 2007, "On fast construction of SAH-based bounding volume hierarchies"), then collapsed into
/// eight-wide nodes by pulling every node's descendants up (Dammertz, Hanika & Keller 2008).
/// O(n log n) time, O(n) memory.

#include <radiosity/config.hpp>
#include <radiosity/detail/parallel.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/bvh/tree.hpp>
#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace radiosity {

/// Settings of the BVH build.
struct BvhOptions {
    int bins = 16;          ///< candidate split planes per axis of the binned SAH
    int max_leaf_size = 4;  ///< a node with this many triangles or fewer may become a leaf
    /// Cost of visiting a node, relative to testing one block of four triangles (the filter
    /// tests four at once). In bench_bvh, 2 was as fast as any value from 0.5 to 4, and 1 slower.
    double traversal_cost = 2.0;
};

/// The eight-wide nodes over n primitives, and the order of the primitives: a leaf's range
/// [first, first + count) holds primitives order[first] ... order[first + count - 1].
struct BvhNodes {
    std::vector<BvhNode> nodes;        ///< nodes[0] is the root; empty for no primitives
    std::vector<std::uint32_t> order;  ///< primitive indices, leaf by leaf
};

namespace detail {

/// A node of the binary build tree: its box; a leaf's primitive range, or for an inner node
/// the index of its second child (the first follows its parent).
struct BuildNode {
    Box box;
    std::uint32_t first = 0;
    std::uint32_t count = 0;  // 0 for an inner node
};

/// A candidate split: primitives whose centroids fall in bins < bin along axis go left.
struct Split {
    int axis = -1;
    int bin = 0;
    double cost = std::numeric_limits<double>::infinity();
};

/// SAH cost of testing n primitives in a leaf, in blocks of four: the BVH's single-precision
/// filter tests four triangles at once (as Embree's builders count four-triangle leaves).
inline double leaf_blocks(std::uint32_t n) {
    return static_cast<double>((n + 3) / 4);
}

/// Runs f on one thread of a new OpenMP team, whose other threads take the tasks it makes
/// (both); on the calling thread alone without OpenMP.
template <class F>
void with_tasks(F&& f) {
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel
#pragma omp single
#endif
    f();
}

/// Runs a as an OpenMP task and b on this thread, and returns when both are done; one after
/// the other without OpenMP. Inside with_tasks, another thread of the team takes a.
template <class A, class B>
void both(A&& a, B&& b) {
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp task shared(a)
#endif
    a();
    b();
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp taskwait
#endif
}

/// The binned SAH build of the binary tree (Wald 2007): at each node, the centroids are sorted
/// into bins along each axis, the bins swept from both sides accumulating boxes and counts, and
/// the cheapest plane kept, unless testing every block of the node as a leaf is cheaper.
class BinnedSahBuild {
  public:
    BinnedSahBuild(std::span<const Box> boxes, std::span<const Vec3> centres,
                   const BvhOptions& options)
        : boxes_(boxes), centres_(centres), options_(options), order_(boxes.size()) {
        RADIOSITY_ASSERT(boxes.size() == centres.size());
        for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<std::uint32_t>(k);
    }

    /// The binary tree, nodes[0] its root (primitives must be non-empty). The two halves of a
    /// large node are built at once by two threads (subtree), with the nodes and the leaf
    /// order that build_node alone gives.
    std::vector<BuildNode> run() {
        RADIOSITY_ASSERT(!order_.empty());
        const auto n = static_cast<std::uint32_t>(order_.size());
        if (n < parallel_subtree || thread_count() < 2) return plain(0, n, 0);
        std::vector<BuildNode> nodes;
        with_tasks([&] { nodes = subtree(0, n, 0); });
        return nodes;
    }
    /// The primitives in leaf order (after run).
    std::vector<std::uint32_t>& order() { return order_; }

  private:
    /// Nodes of at least this many primitives have their two halves built by two threads.
    static constexpr std::uint32_t parallel_subtree = 1u << 15;

    /// The nodes build_node makes for primitives [first, first + count) at `depth`, numbered
    /// from 0 (the subtree's root): a large node's halves as two OpenMP tasks, each into its
    /// own vector, then joined as build_node lays them out (the root, its first child's
    /// subtree, its second's), every inner node's second-child index moved by where its
    /// subtree lands. Each task partitions only its own range of order_.
    std::vector<BuildNode> subtree(std::uint32_t first, std::uint32_t count, int depth) {
        if (count < parallel_subtree) return plain(first, count, depth);
        std::vector<BuildNode> nodes(1);
        const std::uint32_t mid = split_node(nodes[0], first, count, depth);
        if (nodes[0].count > 0) return nodes;  // a leaf after all
        std::vector<BuildNode> left, right;
        both([&] { left = subtree(first, mid - first, depth + 1); },
             [&] { right = subtree(mid, first + count - mid, depth + 1); });
        const auto join = [&nodes](const std::vector<BuildNode>& part) {
            const auto at = static_cast<std::uint32_t>(nodes.size());
            for (BuildNode b : part) {
                if (b.count == 0) b.first += at;  // an inner node's second child
                nodes.push_back(b);
            }
            return at;
        };
        join(left);
        nodes[0].first = join(right);
        return nodes;
    }

    /// The nodes of build_node's plain recursion over primitives [first, first + count) at
    /// `depth`, numbered from 0.
    std::vector<BuildNode> plain(std::uint32_t first, std::uint32_t count, int depth) {
        std::vector<BuildNode> nodes;
        nodes.reserve(2 * std::size_t(count));
        nodes.push_back({});
        build_node(nodes, 0, first, count, depth);
        return nodes;
    }

    const Box& box_of(std::uint32_t k) const { return boxes_[order_[k]]; }
    const Vec3& centre_of(std::uint32_t k) const { return centres_[order_[k]]; }

    /// Builds node `index` over primitives [first, first + count): a leaf when it is small
    /// enough, when no split beats testing every block, or at depth bvh_max_depth; else two
    /// children split at the best binned SAH plane. Recursion depth is O(log n) for sane scenes.
    void build_node(std::vector<BuildNode>& nodes, std::size_t index, std::uint32_t first,
                    std::uint32_t count, int depth) {
        const std::uint32_t mid = split_node(nodes[index], first, count, depth);
        if (nodes[index].count > 0) return;
        nodes.push_back({});  // first child right after its parent
        build_node(nodes, index + 1, first, mid - first, depth + 1);
        nodes[index].first = static_cast<std::uint32_t>(nodes.size());
        nodes.push_back({});
        build_node(nodes, nodes[index].first, mid, first + count - mid, depth + 1);
    }

    /// Sets `node` over primitives [first, first + count): a leaf (count > 0) when it is small
    /// enough, when no split beats testing every block, or at depth bvh_max_depth; else an inner
    /// node (count 0) whose primitives are partitioned at the best binned SAH plane. Returns
    /// where the second half starts.
    std::uint32_t split_node(BuildNode& node, std::uint32_t first, std::uint32_t count, int depth) {
        Box box, centres;
        for (std::uint32_t k = first; k < first + count; ++k) {
            box.grow(box_of(k));
            centres.grow(centre_of(k));
        }
        node = {box, first, count};  // a leaf unless split below
        if (count <= static_cast<std::uint32_t>(options_.max_leaf_size) || depth >= bvh_max_depth)
            return first;  // small enough for a leaf: no split to look for
        const Split s = best_split(first, count, centres, box.half_area());
        if (s.axis < 0) return first;
        if (!(s.cost < leaf_blocks(count)) && count <= 16) return first;  // the leaf is cheaper
        const std::uint32_t mid = partition(first, count, centres, s);
        if (mid == first || mid == first + count) return first;
        node.count = 0;
        return mid;
    }

    /// Moves the primitives of [first, first + count) left of the split first; returns where
    /// the right ones start.
    std::uint32_t partition(std::uint32_t first, std::uint32_t count, const Box& centres,
                            const Split& s) {
        const auto begin = order_.begin() + first;
        const auto middle = std::partition(begin, begin + count, [&](std::uint32_t primitive) {
            return bin_of(centres_[primitive], centres, s.axis) < s.bin;
        });
        return static_cast<std::uint32_t>(middle - order_.begin());
    }

    int bin_of(const Vec3& c, const Box& centres, int axis) const {
        const double lo = centres.lo[axis], extent = centres.hi[axis] - lo;
        const int b = static_cast<int>(options_.bins * (c[axis] - lo) / extent);
        return std::clamp(b, 0, options_.bins - 1);
    }

    /// The cheapest binned SAH plane over the three axes: cost = traversal + sum over both
    /// sides of (area ratio x blocks of four). parent_area is the half area of the node's box.
    Split best_split(std::uint32_t first, std::uint32_t count, const Box& centres,
                     double parent_area) const {
        Split best;
        if (!(parent_area > 0.0)) return best;
        // The bins of all three axes in one pass over the primitives (one read of each box).
        const std::size_t nb = static_cast<std::size_t>(options_.bins);
        std::vector<Box> bin_box(3 * nb);
        std::vector<std::uint32_t> bin_count(3 * nb, 0);
        std::array<bool, 3> spread{};
        for (int axis = 0; axis < 3; ++axis) spread[axis] = centres.hi[axis] > centres.lo[axis];
        for (std::uint32_t k = first; k < first + count; ++k) {
            const Box& b = box_of(k);
            const Vec3& c = centre_of(k);
            for (int axis = 0; axis < 3; ++axis) {
                if (!spread[axis]) continue;
                const std::size_t at =
                    std::size_t(axis) * nb + std::size_t(bin_of(c, centres, axis));
                bin_box[at].grow(b);
                ++bin_count[at];
            }
        }
        for (int axis = 0; axis < 3; ++axis)
            if (spread[axis])
                best_split_along(axis, {bin_box.data() + axis * nb, nb},
                                 {bin_count.data() + axis * nb, nb}, count, parent_area, best);
        return best;
    }

    /// best_split along one axis, from its bins: sweep them from the right to get each plane's
    /// right-side cost, then from the left, keeping a plane cheaper than `best`.
    void best_split_along(int axis, std::span<const Box> bin_box,
                          std::span<const std::uint32_t> bin_count, std::uint32_t count,
                          double parent_area, Split& best) const {
        const std::size_t nb = bin_box.size();
        std::vector<double> right_cost(nb, 0.0);
        Box acc;
        std::uint32_t n = 0;
        for (std::size_t b = nb - 1; b > 0; --b) {
            acc.grow(bin_box[b]);
            n += bin_count[b];
            right_cost[b] = acc.half_area() * leaf_blocks(n);
        }
        acc = Box{};
        n = 0;
        for (std::size_t b = 1; b < nb; ++b) {
            acc.grow(bin_box[b - 1]);
            n += bin_count[b - 1];
            const double cost = options_.traversal_cost +
                                (acc.half_area() * leaf_blocks(n) + right_cost[b]) / parent_area;
            if (n > 0 && n < count && cost < best.cost) best = {axis, static_cast<int>(b), cost};
        }
    }

    std::span<const Box> boxes_;
    std::span<const Vec3> centres_;
    BvhOptions options_;
    std::vector<std::uint32_t> order_;
};

/// Makes an eight-wide node from inner binary node `index` into `out`: start from its two
/// children and keep replacing the inner child of largest surface area by its two children
/// until there are bvh_width (the largest box is the likeliest to be entered, so opening it
/// saves the most box tests). Returns the new node's index; depth never grows, so it stays
/// within bvh_max_depth.
inline std::uint32_t collapse(const std::vector<BuildNode>& binary, std::uint32_t index,
                              std::vector<BvhNode>& out) {
    std::array<std::uint32_t, bvh_width> child{index + 1, binary[index].first};
    std::size_t n = 2;
    while (n < bvh_width) {
        std::size_t widest = n;
        double area = -1.0;
        for (std::size_t k = 0; k < n; ++k) {
            const BuildNode& c = binary[child[k]];
            if (c.count == 0 && c.box.half_area() > area) {
                widest = k;
                area = c.box.half_area();
            }
        }
        if (widest == n) break;  // only leaves left
        const std::uint32_t open = child[widest];
        child[widest] = open + 1;
        child[n++] = binary[open].first;
    }
    const auto self = static_cast<std::uint32_t>(out.size());
    out.emplace_back();
    for (std::size_t k = 0; k < n; ++k) {
        const BuildNode& c = binary[child[k]];
        // Recursion may reallocate out: write through the index, not a reference.
        const std::uint32_t first = c.count > 0 ? c.first : collapse(binary, child[k], out);
        out[self].set_box(static_cast<int>(k), c.box);
        out[self].first[k] = first;
        out[self].count[k] = c.count;
    }
    return self;
}

}  // namespace detail

/// The eight-wide tree over primitives with these boxes and centroids (see the file comment):
/// the binary binned-SAH tree, collapsed. Throws Error for fewer than 2 bins or a leaf size
/// below 1. Cost: O(n log n).
inline BvhNodes build_bvh_nodes(std::span<const detail::Box> boxes, std::span<const Vec3> centres,
                                const BvhOptions& options = {}) {
    if (options.bins < 2 || options.max_leaf_size < 1)
        throw Error("bvh: need at least 2 bins and a leaf size of at least 1");
    BvhNodes result;
    if (boxes.empty()) return result;
    detail::BinnedSahBuild build(boxes, centres, options);
    const std::vector<detail::BuildNode> binary = build.run();
    result.order = std::move(build.order());
    result.nodes.reserve(binary.size() / 2 + 1);
    if (binary[0].count > 0) {  // a single leaf: one node with one used slot
        result.nodes.emplace_back();
        result.nodes[0].set_box(0, binary[0].box);
        result.nodes[0].first[0] = binary[0].first;
        result.nodes[0].count[0] = binary[0].count;
    } else {
        detail::collapse(binary, 0, result.nodes);
    }
    return result;
}

}  // namespace radiosity
