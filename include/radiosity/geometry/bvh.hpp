#pragma once
/// @file bvh.hpp  A bounding volume hierarchy over the scene's triangles for visibility rays:
/// the eight-wide tree and its traversal (geometry/bvh/tree.hpp; Dammertz et al. 2008, Wald et
/// al. 2014), built by the binned surface area heuristic and collapsed (geometry/bvh/build.hpp;
/// Wald 2007), with leaves of triangles tested four at a time by a single-precision filter and
/// exactly by the watertight test (geometry/bvh/triangle.hpp; Woop, Benthin & Wald 2013):
/// any-hit (occlusion) and closest-hit queries, and a walk of the triangles in accepted boxes.
/// It models Visibility and PairCulling. Include this header; the three others are its parts.

#include <radiosity/concepts.hpp>
#include <radiosity/config.hpp>
#include <radiosity/geometry/bvh/build.hpp>
#include <radiosity/geometry/bvh/tree.hpp>
#include <radiosity/geometry/bvh/triangle.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace radiosity {

/// The closest hit of a ray: distance along the (unnormalised) direction, the patch hit, and
/// the barycentric coordinates of the hit point in its triangle.
struct Hit {
    double t = 0.0;           ///< hit point = origin + t * direction
    std::uint32_t patch = 0;  ///< patch the triangle belongs to
    double u = 0.0, v = 0.0;  ///< barycentrics of vertices 1 and 2 of the triangle
};

/// An eight-wide BVH over triangles, each tagged with the patch it belongs to: a binary
/// binned-SAH tree (Wald 2007) with every node's descendants pulled up until it has eight
/// children (Dammertz, Hanika & Keller 2008: "Shallow bounding volume hierarchies"), whose
/// single-precision boxes a SIMD slab test handles four at a time. Leaves hold up to four
/// triangles (the default max_leaf_size), tested at once in single precision by a filter whose
/// error bound is proven, so that only the triangles it cannot decide go to the exact test: the
/// watertight test (Woop et al. 2013) in double precision, through which rays never slip at
/// shared edges. Answers are exactly those of that double test. Build: O(n log n) time, O(n)
/// memory. Queries: O(log n) expected.
class Bvh {
  public:
    Bvh() = default;
    /// Builds over the patches of a table, fan-triangulating each polygon (fan_triangles).
    /// Throws Error for fewer than 2 bins or a leaf size below 1.
    explicit Bvh(const PatchTable& patches, BvhOptions options = {})
        : triangles_(fan_triangles(patches)) {
        build(options);
    }

    std::size_t triangle_count() const { return triangle_count_; }  ///< triangles held
    std::size_t node_count() const { return tree_.node_count(); }   ///< eight-wide nodes

    /// Visibility: true if the open segment p -> q (endpoints excluded by segment_margin)
    /// hits a triangle of any patch other than a and b. Any hit ends the search.
    bool occluded(const Vec3& p, const Vec3& q, std::uint32_t a, std::uint32_t b) const {
        auto stop = [](const PatchTriangle&, double, double, double) { return true; };  // any hit
        return traverse<true>(p, q - p, segment_margin, 1.0 - segment_margin, stop, nullptr,
                              {a, b});
    }

    /// Closest hit of the ray origin + t direction with t in (t_min, t_max), if any, on the
    /// triangles of any patch other than `skip` (t_min may be negative: a hit just behind the
    /// origin, where a ray leaves a face pressed against another).
    std::optional<Hit> intersect(const Vec3& origin, const Vec3& direction, double t_min = 0.0,
                                 double t_max = std::numeric_limits<double>::infinity(),
                                 std::uint32_t skip = no_patch) const {
        std::optional<Hit> best;
        double far = t_max;
        traverse(origin, direction, t_min, far,
                 [&](const PatchTriangle& tri, double t, double u, double v) {
                     if (t < far) {
                         far = t;
                         best = Hit{t, tri.patch, u, v};
                     }
                     return false;
                 },
                 &far, {skip, skip});
        return best;
    }

    /// PairCulling: the triangles under the boxes that enter(lo, hi) accepts (BvhTree::any_leaf),
    /// each passed to test(triangle) until one returns true; returns whether one did. A
    /// predicate that rejects a box prunes everything in it. Cost: O(log n + what it accepts).
    template <class Enter, class Test>
    bool any_triangle(Enter&& enter, Test&& test) const {
        return tree_.any_leaf(enter, [&](std::uint32_t first, std::uint32_t count) {
            for (std::uint32_t k = first; k < first + count; ++k)
                if (test(triangles_[k])) return true;
            return false;
        });
    }

    /// PairCulling: how far a box that any_triangle passes to enter may reach beyond what it holds,
    /// in any direction (boxes are rounded outwards to floats): 4 float epsilons of the largest
    /// coordinate, more than the 1.5 ulps per coordinate, times sqrt(3) for a diagonal.
    double box_slack() const { return 4.0 * std::numeric_limits<float>::epsilon() * scale_; }

  private:
    /// Builds the tree over triangles_, then lays the triangles out leaf by leaf in blocks.
    void build(const BvhOptions& options) {
        scale_ = 0.0;
        std::vector<detail::Box> boxes(triangles_.size());
        std::vector<Vec3> centres(triangles_.size());
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            const auto& v = triangles_[t].v;
            for (const Vec3& p : v) {
                boxes[t].grow(p);
                scale_ = std::max(scale_, detail::max_coordinate(p));
            }
            centres[t] = (v[0] + v[1] + v[2]) / 3.0;
        }
        BvhNodes built = build_bvh_nodes(boxes, centres, options);
        if (built.nodes.empty()) return;
        lay_out_blocks(built);
        tree_ = BvhTree(std::move(built.nodes));
    }

    /// Lays every leaf's triangles out from a multiple of four (padding with copies that no
    /// query reads, as the leaf's count excludes them), so that triangle k is lane k % 4 of
    /// block k / 4, and fills the single-precision blocks and the axis planes.
    void lay_out_blocks(BvhNodes& built) {
        triangle_count_ = triangles_.size();
        std::vector<PatchTriangle> laid_out;
        laid_out.reserve(triangles_.size() + triangles_.size() / 2 + 4);
        for (BvhNode& node : built.nodes)
            for (int k = 0; k < bvh_width; ++k) {
                if (node.count[k] == 0) continue;
                const auto first = static_cast<std::uint32_t>(laid_out.size());
                for (std::uint32_t t = 0; t < node.count[k]; ++t)
                    laid_out.push_back(triangles_[built.order[node.first[k] + t]]);
                while (laid_out.size() % 4 != 0) laid_out.push_back(laid_out.back());
                node.first[k] = first;
            }
        triangles_ = std::move(laid_out);
        RADIOSITY_ASSERT(triangles_.size() % 4 == 0);
        blocks_.assign(triangles_.size() / 4, {});
        planes_.resize(triangles_.size());
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            blocks_[t / 4].set(t % 4, triangles_[t]);
            planes_[t] = detail::AxisPlane::of(triangles_[t]);
        }
        block_planes_.resize(blocks_.size());
        for (std::size_t k = 0; k < blocks_.size(); ++k) block_planes_[k] = shared_plane(k);
    }

    /// The axis plane of all four lanes of block k, if they share one.
    detail::AxisPlane shared_plane(std::size_t k) const {
        const detail::AxisPlane& p = planes_[4 * k];
        for (std::size_t lane = 1; lane < 4; ++lane)
            if (planes_[4 * k + lane].axis != p.axis || planes_[4 * k + lane].at != p.at) return {};
        return p;
    }

    /// What a ray query knows of its ray: the exact ray (origin, shear, range), its padded box
    /// test, its filter, the patches it skips, and the axes along which it does not move.
    struct RayQuery {
        Vec3 o;
        ShearedRay sheared;
        double t0, t1;
        float t0_below;  // a float <= t0, where the walk starts
        detail::RayBoxes boxes;
        detail::FilterRay filter;
        std::array<std::uint32_t, 2> skip;
        unsigned flat;
    };

    /// The ray o + t d for t in (t0, t1), set up once for the walk and the leaf tests.
    RayQuery prepare_ray(const Vec3& o, const Vec3& d, double t0, double t1, bool any_hit,
                         std::array<std::uint32_t, 2> skip) const {
        const ShearedRay sheared(d);
        // An occlusion ray starts on a surface. The boxes around its origin hold that surface and
        // its neighbours, which the ray leaves rather than crosses: try them last. (In bench_bvh
        // this visits a quarter fewer leaves.) A closest hit needs the plain near-to-far order.
        // (NaN defers nothing: no comparison with it holds.)
        const float t0_below = detail::float_below(t0);
        const float defer = any_hit ? t0_below : std::numeric_limits<float>::quiet_NaN();
        const double R = scale_ + detail::max_coordinate(o);
        // Axes along which the ray does not move: a triangle lying in a plane across one of them
        // through the origin contains the ray, which the filter cannot tell from a hit on its
        // edge (rays between patches of one wall meet dozens of such triangles).
        const unsigned flat =
            (d.x == 0.0 ? 1u : 0u) | (d.y == 0.0 ? 2u : 0u) | (d.z == 0.0 ? 4u : 0u);
        return {o,
                sheared,
                t0,
                t1,
                t0_below,
                detail::RayBoxes(o, d, t0_below, R, defer),
                detail::FilterRay(o, sheared, R, t0, t1),
                skip,
                flat};
    }

    /// The leaf test of a ray query: the triangles [first, first + count), block by block. A
    /// block lying in a plane that contains the ray is skipped at once; the filter rejects the
    /// lanes it can, and with `any_hit` a lane it proves hit (of a patch not skipped) ends the
    /// search without the double test; the remaining lanes go to the watertight test and, if
    /// hit within (t0, far), to visit(triangle, t, u, v), which returns true to stop.
    template <bool any_hit, class Visit>
    bool test_leaf(const RayQuery& q, std::uint32_t first, std::uint32_t count, Visit& visit,
                   const double* t_far) const {
        RADIOSITY_ASSERT(first % 4 == 0 && count > 0);  // leaves start a block (lay_out_blocks)
        auto skipped = [&](const detail::TriangleBlock& block, int lane) {
            return block.patch[lane] == q.skip[0] || block.patch[lane] == q.skip[1];
        };
        for (std::uint32_t at = first; at < first + count; at += 4) {
            // A ray along a wall meets its blocks by the dozen: skip each at once.
            if (q.flat != 0 && block_planes_[at / 4].contains_ray(q.o, q.flat)) continue;
            const detail::TriangleBlock& block = blocks_[at / 4];
            const std::uint32_t left = first + count - at;
            const unsigned valid = left >= 4 ? 15u : (1u << left) - 1;
            const detail::Lanes lanes = detail::candidates(block, q.filter);
            unsigned mask = lanes.maybe & valid;
            if constexpr (any_hit) {
                for (unsigned sure = lanes.sure & valid; sure != 0; sure &= sure - 1)
                    if (!skipped(block, std::countr_zero(sure))) return true;
                mask &= ~lanes.sure;
            }
            for (; mask != 0; mask &= mask - 1) {
                const int lane = std::countr_zero(mask);
                if (skipped(block, lane) ||
                    (q.flat != 0 && planes_[at + lane].contains_ray(q.o, q.flat)))
                    continue;
                const PatchTriangle& tri = triangles_[at + lane];
                double t, u, v;
                const double far = any_hit || !t_far ? q.t1 : *t_far;
                if (hit_triangle(tri, q.o, q.sheared, q.t0, far, t, u, v) && visit(tri, t, u, v))
                    return true;
            }
        }
        return false;
    }

    /// A ray query through the tree (BvhTree::traverse) with the triangle leaf test above:
    /// visit(triangle, t, u, v) is called for hits on triangles of patches other than those in
    /// `skip`, and returns true to stop. If `t_far` is given, it is re-read after each hit
    /// (closest-hit queries shrink it and drop subtrees entered beyond it). With `any_hit`, a
    /// triangle that the filter proves hit ends the search without the double test (nor a call
    /// of visit); it ignores t_far. Returns true if stopped.
    template <bool any_hit = false, class Visit>
    bool traverse(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit,
                  const double* t_far = nullptr,
                  std::array<std::uint32_t, 2> skip = {no_patch, no_patch}) const {
        if (tree_.node_count() == 0 || d == Vec3(0.0)) return false;
        const RayQuery q = prepare_ray(o, d, t0, t1, any_hit, skip);
        if constexpr (any_hit) {  // the far end stays t1: no t_far to read back
            const float t1_above = detail::float_above(t1);
            auto far_key = [t1_above] { return t1_above; };
            auto leaf = [&](std::uint32_t first, std::uint32_t count) {
                return test_leaf<true>(q, first, count, visit, nullptr);
            };
            return tree_.traverse<false>(q.boxes, q.t0_below, far_key, leaf);
        } else {
            const float t1_above = detail::float_above(t1);
            auto far_key = [&] { return t_far ? detail::float_above(*t_far) : t1_above; };
            auto leaf = [&](std::uint32_t first, std::uint32_t count) {
                return test_leaf<false>(q, first, count, visit, t_far);
            };
            return tree_.traverse<true>(q.boxes, q.t0_below, far_key, leaf);
        }
    }

    static constexpr std::uint32_t no_patch = std::numeric_limits<std::uint32_t>::max();

    std::vector<PatchTriangle> triangles_;         // leaf by leaf, each leaf from a multiple of 4
    std::vector<detail::TriangleBlock> blocks_;    // triangles_ in fours, single precision
    std::vector<detail::AxisPlane> planes_;        // of each of triangles_
    std::vector<detail::AxisPlane> block_planes_;  // of all four lanes of each block, if shared
    std::size_t triangle_count_ = 0;
    BvhTree tree_;
    double scale_ = 0.0;  // largest coordinate magnitude of any vertex
};

static_assert(Visibility<Bvh>);
static_assert(PairCulling<Bvh>);

}  // namespace radiosity
