#pragma once
/// @file tree.hpp  The eight-wide bounding volume hierarchy and its traversals, whatever its
/// leaves hold: nodes of eight single-precision child boxes, tested four at a time with SIMD
/// (Dammertz, Hanika & Keller 2008, "Shallow bounding volume hierarchies"; Wald et al. 2014,
/// Embree), a ray's walk through them front to back by the slab test (Kay & Kajiya 1986) with
/// boxes padded so that no box the exact ray enters is missed (compare Ize 2013, "Robust BVH ray
/// traversal"), and a walk of the boxes that a predicate accepts. The leaf test is passed in:
/// geometry/bvh.hpp tests triangles (geometry/bvh/triangle.hpp); geometry/bvh/build.hpp makes
/// the nodes.

#include <radiosity/config.hpp>
#include <radiosity/detail/float4.hpp>
#include <radiosity/geometry/vec.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace radiosity {

/// Children per node. Eight beat four (and sixteen) in bench_bvh: a ray's walk to its first
/// leaf is a chain of dependent loads, and wider nodes make the tree shallower.
inline constexpr int bvh_width = 8;

namespace detail {

/// The build stops splitting at this depth; the traversal stacks are sized for it.
inline constexpr int bvh_max_depth = 64;

/// The largest |coordinate|, or infinity if one is not finite (NaN would slip through max).
inline double max_coordinate(const Vec3& v) {
    const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    return std::isfinite(v.x + v.y + v.z) ? m : std::numeric_limits<double>::infinity();
}

/// The float after f towards +inf (up = 1) or -inf (up = -1), for f not NaN nor the infinity
/// it moves towards: std::nextafter by stepping the bits (whose order is that of the
/// magnitudes), inline, as the library call cost a tenth of a ray's setup.
inline float next_float(float f, int up) {
    if (f == 0.0f) return std::numeric_limits<float>::denorm_min() * static_cast<float>(up);
    const auto bits = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>((f > 0.0f) == (up > 0) ? bits + 1 : bits - 1);
}

/// Smallest float >= x (x itself if it is a float): a bound that is never too tight.
inline float float_above(double x) {
    const auto f = static_cast<float>(x);
    return f < x ? next_float(f, 1) : f;
}

/// Largest float <= x.
inline float float_below(double x) {
    const auto f = static_cast<float>(x);
    return f > x ? next_float(f, -1) : f;
}

/// An axis-aligned box in double precision; empty (lo > hi) until grown.
struct Box {
    Vec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
    void grow(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    /// Half the surface area (what the SAH compares); 0 for an empty box.
    double half_area() const {
        const Vec3 d = hi - lo;
        return d.x < 0.0 ? 0.0 : d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

}  // namespace detail

/// A node of the eight-wide tree, laid out for the SIMD slab test: box[2a][k] and box[2a + 1][k]
/// are the low and high faces of child k along axis a, in single precision rounded outwards
/// (the child's double box always lies inside). Child k is a leaf with items [first, first +
/// count) if count > 0, else the inner node nodes[first]. An unused slot has an empty box (low
/// +inf, high -inf) that no ray enters and no box overlaps. 256 bytes.
struct alignas(64) BvhNode {
    std::array<std::array<float, bvh_width>, 6> box;
    std::array<std::uint32_t, bvh_width> first{}, count{};
    BvhNode() {
        constexpr float inf = std::numeric_limits<float>::infinity();
        for (int a = 0; a < 3; ++a) {
            box[2 * a].fill(inf);
            box[2 * a + 1].fill(-inf);
        }
    }
    /// Sets child k's box to b, rounded outwards to floats.
    void set_box(int k, const detail::Box& b) {
        constexpr float inf = std::numeric_limits<float>::infinity();
        for (int a = 0; a < 3; ++a) {
            box[2 * a][k] = std::nextafter(static_cast<float>(glm::value_ptr(b.lo)[a]), -inf);
            box[2 * a + 1][k] = std::nextafter(static_cast<float>(glm::value_ptr(b.hi)[a]), inf);
        }
    }
    /// Low (side 0) or high (side 1) corner of child k's box.
    Vec3 corner(int k, int side) const {
        return Vec3(box[side][k], box[2 + side][k], box[4 + side][k]);
    }
};

namespace detail {

/// What the slab test of a node's boxes needs of a ray, in single precision, computed once per
/// ray. The ray is tested against each box grown by a margin `pad` on every side, where pad is
/// 2^-18 (scene scale + |origin|): far more than the rounding of the origin, of 1 / d and of
/// the slab arithmetic (a few 2^-24 of the same magnitudes), so a box that the exact ray
/// enters is never missed (compare Ize 2013, "Robust BVH ray traversal"). The padding costs
/// nothing: it is folded into two shifted origins, one for the near and one for the far
/// faces. Where d_a = 0 the slab distances are +-inf, or NaN for a face through the shifted
/// origin, which vmin / vmax ignore (the ray then counts as inside that slab).
struct RayBoxes {
    Float4 inv[3], near_origin[3], far_origin[3], t0, defer, last;
    std::array<int, 3> near_face, far_face;  // rows of BvhNode::box
    /// The ray o + t d from t_min (t_min_below, a float <= t_min); boxes entered at or before
    /// `defer_to` are ordered last. R is scene scale + |origin|. (Taking 1 / d on the major
    /// axis from the shear's sz, to save a division, measured no faster.)
    RayBoxes(const Vec3& o, const Vec3& d, float t_min_below, double R, float defer_to) {
        const double pad = 0x1p-18 * R;
        for (int a = 0; a < 3; ++a) {
            const double da = glm::value_ptr(d)[a], oa = glm::value_ptr(o)[a];
            const bool negative = std::signbit(da);
            const double shift = negative ? -pad : pad;
            inv[a] = Float4::splat(static_cast<float>(1.0 / da));
            near_origin[a] = Float4::splat(static_cast<float>(oa + shift));
            far_origin[a] = Float4::splat(static_cast<float>(oa - shift));
            near_face[a] = 2 * a + (negative ? 1 : 0);
            far_face[a] = 2 * a + (negative ? 0 : 1);
        }
        t0 = Float4::splat(t_min_below);
        defer = Float4::splat(defer_to);
        last = Float4::splat(std::numeric_limits<float>::infinity());
    }

    /// Slab test (Kay & Kajiya 1986) of the child boxes of a node for t in [t0, t1], four at a
    /// time: returns a mask of the children entered, and in `order` their entry distances
    /// (lower bounds of the exact ones), or +inf for boxes entered at or before `defer`.
    int enter(const BvhNode& node, float t1, float* order) const {
        int mask = 0;
        for (int h = 0; h < bvh_width; h += 4) {
            Float4 near = t0, far = Float4::splat(t1);
            for (int a = 0; a < 3; ++a) {
                const Float4 n = Float4::load(node.box[near_face[a]].data() + h) - near_origin[a];
                const Float4 f = Float4::load(node.box[far_face[a]].data() + h) - far_origin[a];
                near = vmax(n * inv[a], near);  // argument order: a NaN slab is ignored
                far = vmin(f * inv[a], far);
            }
            where_at_most(near, defer, last).store(order + h);
            mask |= less_equal_mask(near, far) << h;
        }
        return mask;
    }
};

/// A subtree still to visit: an inner node (count 0) or a leaf's item range, with its order
/// key: a lower bound of the distance at which the ray enters its box, or +inf for a box
/// deferred (see RayBoxes::enter).
struct BvhEntry {
    std::uint32_t first, count;
    float t;
};

}  // namespace detail

/// The eight-wide tree (see BvhNode): its nodes, nodes[0] the root, and two walks through them
/// that call a leaf test passed in on the item ranges [first, first + count) of the leaves they
/// reach. Which items a range holds is the caller's (the BVH's triangles, laid out leaf by
/// leaf). Walks are O(log n) expected for a ray, O(what the predicate accepts) for a box walk.
class BvhTree {
  public:
    /// Deep enough for any tree: the build stops splitting at depth bvh_max_depth, and each node
    /// on the path pushes at most bvh_width - 1 siblings.
    static constexpr std::size_t stack_size = (bvh_width - 1) * detail::bvh_max_depth + bvh_width;

    BvhTree() = default;
    /// The tree of these nodes (made by build_bvh_nodes, geometry/bvh/build.hpp).
    explicit BvhTree(std::vector<BvhNode> nodes) : nodes_(std::move(nodes)) {}

    std::size_t node_count() const { return nodes_.size(); }      ///< nodes, root included
    const std::vector<BvhNode>& nodes() const { return nodes_; }  ///< nodes[0] is the root

    /// The leaves that a ray enters (ray: RayBoxes from t_start), walked with an explicit stack:
    /// leaf(first, count) tests a leaf's items and returns true to stop the walk. far_key()
    /// gives the far end of the ray as a float, read again after each leaf. With `closest`,
    /// children are visited near to far and subtrees entered beyond far_key() dropped (a
    /// closest-hit query shrinks it as it finds hits); without, the nearest child is taken first
    /// and the rest pushed as they come (an occlusion query stops at any hit). Returns true if
    /// stopped. `closest` is a template argument so that each query compiles to its own loop.
    template <bool closest, class FarKey, class Leaf>
    bool traverse(const detail::RayBoxes& ray, float t_start, FarKey&& far_key, Leaf&& leaf) const {
        if (nodes_.empty()) return false;
        std::array<detail::BvhEntry, stack_size> stack;
        std::size_t top = 0;
        stack[top++] = {0, 0, t_start};
        while (top > 0) {
            detail::BvhEntry e = stack[--top];
            const float limit = far_key();
            // Keys are distances unless deferring, and only closest hits prune by distance.
            if ((closest && e.t > limit) || !descend<closest>(e, ray, limit, stack, top)) continue;
            if (leaf(e.first, e.count)) return true;
        }
        return false;
    }

    /// The leaves under the boxes that enter(lo, hi) accepts, from the root down: a child box is
    /// opened (or its leaf tested by leaf(first, count), which returns true to stop) only where
    /// enter accepts it, so a predicate that rejects a box prunes its whole subtree. Boxes are
    /// those of BvhNode, rounded outwards to floats. Returns true if stopped.
    template <class Enter, class Leaf>
    bool any_leaf(Enter&& enter, Leaf&& leaf) const {
        if (nodes_.empty()) return false;
        std::array<std::uint32_t, stack_size> stack;
        std::size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            RADIOSITY_ASSERT(top + bvh_width <= stack_size);
            const BvhNode& node = nodes_[stack[--top]];
            for (int k = 0; k < bvh_width; ++k) {
                const Vec3 lo = node.corner(k, 0), hi = node.corner(k, 1);
                if (!(lo.x <= hi.x) || !enter(lo, hi)) continue;  // an unused slot, or rejected
                if (node.count[k] == 0)
                    stack[top++] = node.first[k];
                else if (leaf(node.first[k], node.count[k]))
                    return true;
            }
        }
        return false;
    }

  private:
    /// From inner node e, walks down towards the child box of least key that the ray enters
    /// until e is a leaf, pushing the other children entered: if `sorted`, larger keys first,
    /// so smaller ones are popped first; else as they come.
    /// Returns false if some inner node on the way has no child entered.
    template <bool sorted>
    bool descend(detail::BvhEntry& e, const detail::RayBoxes& ray, float t1,
                 std::array<detail::BvhEntry, stack_size>& stack, std::size_t& top) const {
        while (e.count == 0) {
            RADIOSITY_ASSERT(top + bvh_width <= stack_size);
            const BvhNode& node = nodes_[e.first];
            alignas(16) std::array<float, bvh_width> key;
            unsigned mask = static_cast<unsigned>(ray.enter(node, t1, key.data()));
            if (mask == 0) return false;
            auto child = [&](int k) {
                return detail::BvhEntry{node.first[k], node.count[k], key[k]};
            };
            // One or two children entered, without branches on which (they would mispredict):
            // with one, k1 = k0 and the store above the stack top is dropped.
            const int k0 = std::countr_zero(mask);
            mask &= mask - 1;
            const int k1 = mask != 0 ? std::countr_zero(mask) : k0;
            const bool two = mask != 0;
            mask &= mask - 1;
            const bool swap = key[k1] < key[k0];
            stack[top] = child(swap ? k0 : k1);
            top += two ? 1 : 0;
            e = child(swap ? k1 : k0);
            if (mask == 0) continue;
            if constexpr (sorted) {  // three or more: keep [base, top) sorted
                const std::size_t base = top - 1;
                stack[top++] = e;
                for (; mask != 0; mask &= mask - 1) {
                    const detail::BvhEntry c = child(std::countr_zero(mask));
                    std::size_t j = top++;
                    for (; j > base && stack[j - 1].t < c.t; --j) stack[j] = stack[j - 1];
                    stack[j] = c;
                }
                e = stack[--top];
            } else {
                // Keep the nearest as e and push the rest as they come. For occlusion rays in
                // bench_bvh, sorting them visited 2.5% fewer leaves, but the sort's
                // data-dependent branches mispredict, and the rays were 3% slower.
                for (; mask != 0; mask &= mask - 1) {
                    const detail::BvhEntry c = child(std::countr_zero(mask));
                    const bool closer = c.t < e.t;
                    stack[top++] = closer ? e : c;
                    e = closer ? c : e;
                }
            }
        }
        return true;
    }

    std::vector<BvhNode> nodes_;
};

}  // namespace radiosity
