#pragma once
/// @file bvh.hpp  A bounding volume hierarchy over the scene's triangles for visibility rays:
/// binned surface-area-heuristic build (Wald 2007) collapsed into an eight-wide tree whose
/// child boxes are tested four at a time (Dammertz et al. 2008; Wald et al. 2014, Embree), a
/// watertight ray-triangle test (Woop, Benthin & Wald 2013), any-hit (occlusion) and
/// closest-hit queries. It models Visibility.

#include <radiosity/concepts.hpp>
#include <radiosity/detail/float4.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/vec.hpp>

#include <glm/gtc/type_ptr.hpp>
#include <radiosity/geometry/patch_table.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace radiosity {

/// Something that answers "is the segment p -> q blocked?": `v.occluded(p, q, a, b)` is true if
/// the open segment between p and q meets any surface other than patches a and b (the patches
/// the segment starts and ends on, which must not block it). Must be const and thread-safe.
template <class V>
concept Visibility = requires(const V& v, const Vec3& p, const Vec3& q, std::uint32_t a,
                              std::uint32_t b) {
    { v.occluded(p, q, a, b) } -> std::convertible_to<bool>;
};

/// Settings of the BVH build.
struct BvhOptions {
    int bins = 16;          ///< candidate split planes per axis of the binned SAH
    int max_leaf_size = 4;  ///< a node with this many triangles or fewer may become a leaf
    /// Cost of visiting a node, relative to testing one block of four triangles (the filter
    /// tests four at once). In bench_bvh, 2 was as fast as any value from 0.5 to 4, and 1 slower.
    double traversal_cost = 2.0;
};

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
/// triangles (the default
/// max_leaf_size), tested at once in single precision by a filter whose error bound is proven,
/// so that only the triangles it cannot decide go to the exact test: the watertight test (Woop
/// et al. 2013) in double precision, through which rays never slip at shared edges. Answers are
/// exactly those of that double test. Build: O(n log n) time, O(n) memory. Queries: O(log n)
/// expected.
class Bvh {
  public:
    Bvh() = default;
    /// Builds over the patches of a table, fan-triangulating each polygon.
    explicit Bvh(const PatchTable& patches, BvhOptions options = {}) : options_(options) {
        if (options_.bins < 2 || options_.max_leaf_size < 1)
            throw Error("bvh: need at least 2 bins and a leaf size of at least 1");
        for (std::size_t i = 0; i < patches.size(); ++i) {
            const auto p = patches.polygon(i);
            for (std::size_t k = 1; k + 1 < p.size(); ++k)
                triangles_.push_back({{p[0], p[k], p[k + 1]}, static_cast<std::uint32_t>(i)});
        }
        build();
    }

    std::size_t triangle_count() const { return triangle_count_; }  ///< triangles held
    std::size_t node_count() const { return nodes_.size(); }        ///< eight-wide nodes

    /// Visibility: true if the open segment p -> q (endpoints excluded by a relative margin)
    /// hits a triangle of any patch other than a and b. Any hit ends the search.
    bool occluded(const Vec3& p, const Vec3& q, std::uint32_t a, std::uint32_t b) const {
        constexpr double margin = 1e-9;
        auto stop = [](const Triangle&, double, double, double) { return true; };  // any hit
        return traverse<true>(p, q - p, margin, 1.0 - margin, stop, nullptr, {a, b});
    }

    /// True if some triangle of a patch other than a and b might block a segment from the front
    /// of plane A to the front of plane B inside the box [lo, hi]: its bounding box reaches into
    /// the box's interior and it is not entirely behind (or on) either plane. A conservative
    /// test: false proves that every such segment is free, so two patches inside the box that
    /// face each other see each other without any ray (the walls around them lie on the box's
    /// faces or behind the patches' planes). Planes are (point, unit normal); eps is a length.
    /// Cost: O(log n + what reaches into the box).
    bool may_block(const Vec3& lo, const Vec3& hi, std::uint32_t a, std::uint32_t b,
                   const std::array<Vec3, 2>& plane_a, const std::array<Vec3, 2>& plane_b,
                   double eps) const {
        if (nodes_.empty()) return false;
        auto overlaps = [&](const Vec3& l, const Vec3& h) {
            return l.x < hi.x && h.x > lo.x && l.y < hi.y && h.y > lo.y && l.z < hi.z && h.z > lo.z;
        };
        auto behind = [&](const Triangle& t, const std::array<Vec3, 2>& plane) {
            for (const Vec3& v : t.v)
                if (glm::dot(v - plane[0], plane[1]) > eps) return false;
            return true;
        };
        auto blocks = [&](std::uint32_t first, std::uint32_t count) {
            for (std::uint32_t k = first; k < first + count; ++k) {
                const Triangle& t = triangles_[k];
                if (t.patch == a || t.patch == b) continue;
                if (!overlaps(glm::min(glm::min(t.v[0], t.v[1]), t.v[2]),
                              glm::max(glm::max(t.v[0], t.v[1]), t.v[2])))
                    continue;
                if (!behind(t, plane_a) && !behind(t, plane_b)) return true;
            }
            return false;
        };
        // A whole node on or behind either plane holds nothing that could block: without this,
        // a pair on a floor of n patches visits every floor leaf under its box (their boxes,
        // rounded outwards to floats, reach just above the floor), and a row costs O(n^2). The
        // margin covers that rounding; a triangle within it of a plane lies flat on the plane.
        const double margin = eps + 4.0 * std::numeric_limits<float>::epsilon() * scale_;
        auto box_behind = [&](const Vec3& l, const Vec3& h, const std::array<Vec3, 2>& plane) {
            const Vec3 centre = 0.5 * (l + h), half = 0.5 * (h - l);
            return glm::dot(centre - plane[0], plane[1]) + glm::dot(half, glm::abs(plane[1])) <=
                   margin;
        };
        std::array<std::uint32_t, stack_size> stack;
        std::size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            for (int k = 0; k < width; ++k) {
                const Vec3 l = node.corner(k, 0), h = node.corner(k, 1);
                if (!overlaps(l, h) || box_behind(l, h, plane_a) || box_behind(l, h, plane_b))
                    continue;
                if (node.count[k] == 0)
                    stack[top++] = node.first[k];
                else if (blocks(node.first[k], node.count[k]))
                    return true;
            }
        }
        return false;
    }

    /// Closest hit of the ray origin + t direction with t in (t_min, t_max), if any.
    std::optional<Hit> intersect(const Vec3& origin, const Vec3& direction, double t_min = 0.0,
                                 double t_max = std::numeric_limits<double>::infinity()) const {
        std::optional<Hit> best;
        double far = t_max;
        traverse(
            origin, direction, t_min, far,
            [&](const Triangle& tri, double t, double u, double v) {
                if (t < far) {
                    far = t;
                    best = Hit{t, tri.patch, u, v};
                }
                return false;
            },
            &far);
        return best;
    }

  private:
    /// Children per node. Eight beat four (and sixteen) in bench_bvh: a ray's walk to its first
    /// leaf is a chain of dependent loads, and wider nodes make the tree shallower.
    static constexpr int width = 8;
    // Deep enough for any tree: the build stops splitting at depth 64, and each node on the
    // path pushes at most width - 1 siblings.
    static constexpr std::size_t stack_size = (width - 1) * 64 + width;

    struct Triangle {
        std::array<Vec3, 3> v;
        std::uint32_t patch;
    };
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
        double half_area() const {
            const Vec3 d = hi - lo;
            return d.x < 0.0 ? 0.0 : d.x * d.y + d.y * d.z + d.z * d.x;
        }
    };
    /// A node of the binary build tree: its box; a leaf's triangle range, or for an inner node
    /// the index of its second child (the first follows its parent).
    struct BuildNode {
        Box box;
        std::uint32_t first = 0;
        std::uint32_t count = 0;  // 0 for an inner node
    };
    /// A node, laid out for the SIMD slab test: box[2a][k] and box[2a + 1][k] are the
    /// low and high faces of child k along axis a, in single precision rounded outwards (the
    /// child's double box always lies inside). Child k is a leaf with triangles [first, first +
    /// count) if count > 0, else the inner node nodes_[first]. An unused slot has an empty
    /// box (low +inf, high -inf) that no ray enters and no box overlaps. 256 bytes.
    struct alignas(64) Node {
        std::array<std::array<float, width>, 6> box;
        std::array<std::uint32_t, width> first{}, count{};
        Node() {
            constexpr float inf = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a) {
                box[2 * a].fill(inf);
                box[2 * a + 1].fill(-inf);
            }
        }
        void set_box(int k, const Box& b) {
            constexpr float inf = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a) {
                box[2 * a][k] = std::nextafter(static_cast<float>(glm::value_ptr(b.lo)[a]), -inf);
                box[2 * a + 1][k] =
                    std::nextafter(static_cast<float>(glm::value_ptr(b.hi)[a]), inf);
            }
        }
        /// Low (side 0) or high (side 1) corner of child k's box.
        Vec3 corner(int k, int side) const {
            return Vec3(box[side][k], box[2 + side][k], box[4 + side][k]);
        }
    };

    /// Four consecutive triangles in single precision, lane by lane (v[4 * (3 * vertex + axis) +
    /// lane]) with their patches: what the SIMD filter of the triangle test reads. One flat
    /// array, so that the filter reaches a vertex's row from its axis's row by a constant
    /// offset (12 floats), which frees registers. 160 bytes.
    struct alignas(16) TriangleBlock {
        std::array<float, 36> v{};
        std::array<std::uint32_t, 4> patch{};
        void set(std::size_t lane, const Triangle& t) {
            for (std::size_t i = 0; i < 3; ++i)
                for (std::size_t a = 0; a < 3; ++a)
                    v[4 * (3 * i + a) + lane] = static_cast<float>(glm::value_ptr(t.v[i])[a]);
            patch[lane] = t.patch;
        }
    };

    /// The plane x_axis = at in which a triangle lies, if it lies in one (all three vertices
    /// with exactly that coordinate; axis 3 if none). A ray with d_axis = 0 and o_axis = at
    /// lies in that plane, and the watertight test then surely misses: in its sheared frame
    /// every vertex projects to exactly 0 (or NaN) along the axis, so U, V and W are all zero
    /// (det = 0) or NaN (t = NaN). Lets the search skip these without the double test.
    struct AxisPlane {
        double at = 0.0;
        std::uint32_t axis = 3;
        static AxisPlane of(const Triangle& t) {
            for (std::uint32_t a = 0; a < 3; ++a)
                if (t.v[0][a] == t.v[1][a] && t.v[0][a] == t.v[2][a]) return {t.v[0][a], a};
            return {};
        }
    };

    Box triangle_box(std::size_t t) const {
        Box b;
        for (const Vec3& p : triangles_[t].v) b.grow(p);
        return b;
    }
    Vec3 centroid(std::size_t t) const {
        const auto& v = triangles_[t].v;
        return (v[0] + v[1] + v[2]) / 3.0;
    }

    /// Builds the binary SAH tree, then collapses it into eight-wide nodes.
    void build() {
        nodes_.clear();
        scale_ = 0.0;
        for (const Triangle& t : triangles_)
            for (const Vec3& v : t.v) scale_ = std::max(scale_, max_abs(v));
        if (triangles_.empty()) return;
        std::vector<BuildNode> binary;
        binary.reserve(2 * triangles_.size());
        binary.push_back({});
        build_node(binary, 0, 0, static_cast<std::uint32_t>(triangles_.size()));
        nodes_.reserve(binary.size() / 2 + 1);
        if (binary[0].count > 0) {  // a single leaf: one node with one used slot
            nodes_.emplace_back();
            nodes_[0].set_box(0, binary[0].box);
            nodes_[0].first[0] = binary[0].first;
            nodes_[0].count[0] = binary[0].count;
        } else {
            collapse(binary, 0);
        }
        make_blocks();
    }

    /// Lays every leaf's triangles out from a multiple of four (padding with copies that no
    /// query reads, as the leaf's count excludes them), so that triangle k is lane k % 4 of
    /// block k / 4, and fills the single-precision blocks.
    void make_blocks() {
        triangle_count_ = triangles_.size();
        std::vector<Triangle> laid_out;
        laid_out.reserve(triangles_.size() + triangles_.size() / 2 + 4);
        for (Node& node : nodes_)
            for (int k = 0; k < width; ++k) {
                if (node.count[k] == 0) continue;
                const auto first = static_cast<std::uint32_t>(laid_out.size());
                for (std::uint32_t t = 0; t < node.count[k]; ++t)
                    laid_out.push_back(triangles_[node.first[k] + t]);
                while (laid_out.size() % 4 != 0) laid_out.push_back(laid_out.back());
                node.first[k] = first;
            }
        triangles_ = std::move(laid_out);
        blocks_.assign(triangles_.size() / 4, {});
        planes_.resize(triangles_.size());
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            blocks_[t / 4].set(t % 4, triangles_[t]);
            planes_[t] = AxisPlane::of(triangles_[t]);
        }
        block_planes_.resize(blocks_.size());
        for (std::size_t k = 0; k < blocks_.size(); ++k) {
            const AxisPlane& p = planes_[4 * k];
            bool same = true;
            for (std::size_t lane = 1; lane < 4; ++lane)
                same = same && planes_[4 * k + lane].axis == p.axis &&
                       planes_[4 * k + lane].at == p.at;
            block_planes_[k] = same ? p : AxisPlane{};
        }
    }

    /// Builds node `index` over triangles [first, first + count): find the best binned SAH split
    /// (cost = traversal + sum over children of area ratio x blocks of four triangles, as in
    /// Embree's builders for four-triangle leaves), or make a leaf when no split beats testing
    /// every block. Recursion depth is O(log n) for sane scenes and at most 64 levels, after
    /// which a node becomes a leaf.
    void build_node(std::vector<BuildNode>& nodes, std::size_t index, std::uint32_t first,
                    std::uint32_t count, int depth = 0) {
        Box box, centres;
        for (std::uint32_t k = first; k < first + count; ++k) {
            box.grow(triangle_box(k));
            centres.grow(centroid(k));
        }
        nodes[index].box = box;
        nodes[index].first = first;
        nodes[index].count = count;  // a leaf unless split below
        // Small enough for a leaf: no split to look for.
        if (count <= static_cast<std::uint32_t>(options_.max_leaf_size) || depth >= 64) return;
        const Split s = best_split(first, count, centres, box.half_area());
        if (s.axis < 0) return;
        // SAH: splitting must beat testing every block here.
        if (!(s.cost < blocks(count)) && count <= 16) return;
        const auto mid = static_cast<std::uint32_t>(
            std::partition(triangles_.begin() + first, triangles_.begin() + first + count,
                           [&](const Triangle& t) {
                               return bin_of((t.v[0] + t.v[1] + t.v[2]) / 3.0, centres, s.axis) <
                                      s.bin;
                           }) -
            triangles_.begin());
        if (mid == first || mid == first + count) return;
        nodes[index].count = 0;
        nodes.push_back({});  // first child right after its parent
        build_node(nodes, index + 1, first, mid - first, depth + 1);
        nodes[index].first = static_cast<std::uint32_t>(nodes.size());
        nodes.push_back({});
        build_node(nodes, nodes[index].first, mid, first + count - mid, depth + 1);
    }

    /// Makes a node from inner binary node `index`: start from its two children and keep
    /// replacing the inner child of largest surface area by its two children until there are
    /// `width` (the largest box is the likeliest to be entered, so opening it saves the most
    /// box tests). Returns the new node's index; depth never grows, so it stays within 64.
    std::uint32_t collapse(const std::vector<BuildNode>& binary, std::uint32_t index) {
        std::array<std::uint32_t, width> child{index + 1, binary[index].first};
        std::size_t n = 2;
        while (n < width) {
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
        const auto self = static_cast<std::uint32_t>(nodes_.size());
        nodes_.emplace_back();
        for (std::size_t k = 0; k < n; ++k) {
            const BuildNode& c = binary[child[k]];
            // Recursion may reallocate nodes_: write through the index, not a reference.
            const std::uint32_t first = c.count > 0 ? c.first : collapse(binary, child[k]);
            nodes_[self].set_box(static_cast<int>(k), c.box);
            nodes_[self].first[k] = first;
            nodes_[self].count[k] = c.count;
        }
        return self;
    }

    /// Cost of testing n triangles, in blocks: the filter tests four at once.
    static double blocks(std::uint32_t n) { return static_cast<double>((n + 3) / 4); }

    struct Split {
        int axis = -1;
        int bin = 0;  // triangles in bins < bin go left
        double cost = std::numeric_limits<double>::infinity();
    };

    int bin_of(const Vec3& c, const Box& centres, int axis) const {
        const double lo = centres.lo[axis], extent = centres.hi[axis] - lo;
        const int b = static_cast<int>(options_.bins * (c[axis] - lo) / extent);
        return std::clamp(b, 0, options_.bins - 1);
    }

    /// Binned SAH (Wald 2007): sort centroids into bins along each axis, sweep the bins from
    /// both sides accumulating boxes and counts, and keep the cheapest plane.
    /// parent_area is the half area of the node's box.
    Split best_split(std::uint32_t first, std::uint32_t count, const Box& centres,
                     double parent_area) const {
        Split best;
        const std::size_t nb = static_cast<std::size_t>(options_.bins);
        if (!(parent_area > 0.0)) return best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(centres.hi[axis] > centres.lo[axis])) continue;
            std::vector<Box> bin_box(nb);
            std::vector<std::uint32_t> bin_count(nb, 0);
            for (std::uint32_t k = first; k < first + count; ++k) {
                const auto b = static_cast<std::size_t>(bin_of(centroid(k), centres, axis));
                bin_box[b].grow(triangle_box(k));
                ++bin_count[b];
            }
            std::vector<double> right_cost(nb, 0.0);
            Box acc;
            std::uint32_t n = 0;
            for (std::size_t b = nb - 1; b > 0; --b) {
                acc.grow(bin_box[b]);
                n += bin_count[b];
                right_cost[b] = acc.half_area() * blocks(n);
            }
            acc = Box{};
            n = 0;
            for (std::size_t b = 1; b < nb; ++b) {
                acc.grow(bin_box[b - 1]);
                n += bin_count[b - 1];
                const double cost = options_.traversal_cost +
                                    (acc.half_area() * blocks(n) + right_cost[b]) / parent_area;
                if (n > 0 && n < count && cost < best.cost)
                    best = {axis, static_cast<int>(b), cost};
            }
        }
        return best;
    }

    /// The largest |coordinate|, or infinity if one is not finite (NaN would slip through max).
    static double max_abs(const Vec3& v) {
        const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        return std::isfinite(v.x + v.y + v.z) ? m : std::numeric_limits<double>::infinity();
    }
    /// Smallest float >= x (x itself if it is a float): a bound that is never too tight.
    static float float_above(double x) {
        const auto f = static_cast<float>(x);
        return f < x ? next_float(f, 1) : f;
    }
    /// Largest float <= x.
    static float float_below(double x) {
        const auto f = static_cast<float>(x);
        return f > x ? next_float(f, -1) : f;
    }
    /// The float after f towards +inf (up = 1) or -inf (up = -1), for f not NaN nor the infinity
    /// it moves towards: std::nextafter by stepping the bits (whose order is that of the
    /// magnitudes), inline, as the library call cost a tenth of a ray's setup.
    static float next_float(float f, int up) {
        if (f == 0.0f) return std::numeric_limits<float>::denorm_min() * static_cast<float>(up);
        const auto bits = std::bit_cast<std::uint32_t>(f);
        return std::bit_cast<float>((f > 0.0f) == (up > 0) ? bits + 1 : bits - 1);
    }

    /// The watertight ray-triangle test (Woop, Benthin & Wald 2013): shear the triangle into the
    /// ray's frame, where the ray is the z axis, and test the signs of the 2-D edge functions.
    /// Edges shared by two triangles give the same edge function with opposite sign, so a ray
    /// through an edge hits at least one of them.
    struct ShearedRay {
        int kx, ky, kz;
        double sx, sy, sz;
        explicit ShearedRay(const Vec3& dir) {
            const Vec3 a = glm::abs(dir);
            const double* d = glm::value_ptr(dir);
            kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
            kx = (kz + 1) % 3;
            ky = (kx + 1) % 3;
            if (d[kz] < 0.0) std::swap(kx, ky);  // keep the winding
            sx = d[kx] / d[kz];
            sy = d[ky] / d[kz];
            sz = 1.0 / d[kz];
        }
    };

    /// What the slab test of a node's boxes needs of a ray, in single precision, computed once per
    /// ray. The ray is tested against each box grown by a margin `pad` on every side, where pad is
    /// 2^-18 (scene scale + |origin|): far more than the rounding of the origin, of 1 / d and of
    /// the slab arithmetic (a few 2^-24 of the same magnitudes), so a box that the exact ray
    /// enters is never missed (compare Ize 2013, "Robust BVH ray traversal"). The padding costs
    /// nothing: it is folded into two shifted origins, one for the near and one for the far
    /// faces. Where d_a = 0 the slab distances are +-inf, or NaN for a face through the shifted
    /// origin, which vmin / vmax ignore (the ray then counts as inside that slab).
    struct RayBoxes {
        detail::Float4 inv[3], near_origin[3], far_origin[3], t0, defer, last;
        std::array<int, 3> near_face, far_face;  // rows of Node::box
        /// The ray o + t d from t_min (t_min_below, a float <= t_min); boxes entered at or before
        /// `defer_to` are ordered last. R is scene scale + |origin|. (Taking 1 / d on the major
        /// axis from the shear's sz, to save a division, measured no faster.)
        RayBoxes(const Vec3& o, const Vec3& d, float t_min_below, double R, float defer_to) {
            const double pad = 0x1p-18 * R;
            for (int a = 0; a < 3; ++a) {
                const double da = glm::value_ptr(d)[a], oa = glm::value_ptr(o)[a];
                const bool negative = std::signbit(da);
                const double shift = negative ? -pad : pad;
                inv[a] = detail::Float4::splat(static_cast<float>(1.0 / da));
                near_origin[a] = detail::Float4::splat(static_cast<float>(oa + shift));
                far_origin[a] = detail::Float4::splat(static_cast<float>(oa - shift));
                near_face[a] = 2 * a + (negative ? 1 : 0);
                far_face[a] = 2 * a + (negative ? 0 : 1);
            }
            t0 = detail::Float4::splat(t_min_below);
            defer = detail::Float4::splat(defer_to);
            last = detail::Float4::splat(std::numeric_limits<float>::infinity());
        }

        /// Slab test (Kay & Kajiya 1986) of the child boxes of a node for t in [t0, t1], four at a
        /// time: returns a mask of the children entered, and in `order` their entry distances
        /// (lower bounds of the exact ones), or +inf for boxes entered at or before `defer`.
        int enter(const Node& node, float t1, float* order) const {
            using detail::Float4;
            int mask = 0;
            for (int h = 0; h < width; h += 4) {
                Float4 near = t0, far = Float4::splat(t1);
                for (int a = 0; a < 3; ++a) {
                    const Float4 n =
                        Float4::load(node.box[near_face[a]].data() + h) - near_origin[a];
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

    static bool hit_triangle(const Triangle& tri, const Vec3& o, const ShearedRay& r, double t0,
                             double t1, double& t, double& u, double& v) {
        const Vec3 dA = tri.v[0] - o, dB = tri.v[1] - o, dC = tri.v[2] - o;
        const double *A = glm::value_ptr(dA), *B = glm::value_ptr(dB), *C = glm::value_ptr(dC);
        const double ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
        const double bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
        const double cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
        const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
        if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
        const double det = U + V + W;
        if (det == 0.0) return false;
        const double T = r.sz * (U * A[r.kz] + V * B[r.kz] + W * C[r.kz]);
        t = T / det;
        if (!(t > t0 && t < t1)) return false;
        u = V / det;
        v = W / det;
        return true;
    }

    /// What the SIMD filter of the triangle test needs of a ray, in single precision: the
    /// origin, the shear of ShearedRay, the error bound, and the range of t in which every
    /// vertex must lie for a sure hit (see candidates).
    struct FilterRay {
        // The origin's coordinates along the sheared frame's axes kx, ky, kz, and those axes'
        // offsets into TriangleBlock::v.
        detail::Float4 ox, oy, oz, sx, sy, sz, bound_scale, bound_floor, t_low, t_high;
        std::size_t fx, fy, fz;
        /// R is scene scale + |origin|.
        FilterRay(const Vec3& o, const ShearedRay& r, double R, double t0, double t1)
            : fx(4 * static_cast<std::size_t>(r.kx)),
              fy(4 * static_cast<std::size_t>(r.ky)),
              fz(4 * static_cast<std::size_t>(r.kz)) {
            using detail::Float4;
            ox = Float4::splat(static_cast<float>(glm::value_ptr(o)[r.kx]));
            oy = Float4::splat(static_cast<float>(glm::value_ptr(o)[r.ky]));
            oz = Float4::splat(static_cast<float>(glm::value_ptr(o)[r.kz]));
            sx = Float4::splat(static_cast<float>(r.sx));
            sy = Float4::splat(static_cast<float>(r.sy));
            // R bounds every coordinate of vertices and origin. Far outside float's comfortable
            // range the bound below could fail (overflow, subnormals, NaN): then reject nothing
            // and prove nothing. Within it, every value in candidates is finite.
            const bool sane =
                R > 1e-15 && R < 1e15 && std::abs(r.sz) < 1e30 && std::isfinite(r.sx + r.sy);
            const double inf = std::numeric_limits<double>::infinity();
            bound_scale = Float4::splat(static_cast<float>(sane ? 0x1p-18 * R : inf));
            bound_floor = Float4::splat(static_cast<float>(0x1p-16 * R));
            sz = Float4::splat(static_cast<float>(r.sz));
            const double margin = 0x1p-20 * (R * std::abs(r.sz) + 1.0);
            t_low = Float4::splat(static_cast<float>(sane ? t0 + margin : inf));
            t_high = Float4::splat(static_cast<float>(t1 - margin));
        }
    };

    /// Lanes of a block: those the exact test might hit, and those it surely hits.
    struct Lanes {
        unsigned maybe, sure;
    };

    /// Which triangles of a block the exact (double) test might hit, and which it surely hits:
    /// Woop's sheared edge functions U, V, W for four triangles at once in single precision.
    /// A triangle is rejected only when one edge function is surely negative and another surely
    /// positive, i.e. beyond the rounding error; it is surely hit when all three are surely of
    /// one sign and the t of each vertex (the hit's t is their convex combination) lies surely
    /// inside (t0, t1). With u = 2^-24 and R a bound on every coordinate of vertices and
    /// origin, each sheared coordinate (ax ... cy) is off by at most 16 u R after rounding
    /// vertices, origin, shear and arithmetic, and is at most 4R; so U is off by at most
    /// 24 u R M + 512 u^2 R^2, where M is the sum of the six magnitudes. The bound used,
    /// 64 u R (M + 2^-16 R), is more than twice that even with M taken from the rounded values.
    /// A vertex's t is off by at most 4 u R |sz| + 2.1 u; the margin used is 16 u (R |sz| + 1).
    /// So the filter never contradicts the double test, and answers are exactly its answers.
    static Lanes candidates(const TriangleBlock& b, const FilterRay& r) {
        using detail::Float4;
        std::array<Float4, 3> px, py, t;
        const float *row_x = b.v.data() + r.fx, *row_y = b.v.data() + r.fy,
                    *row_z = b.v.data() + r.fz;
        for (std::size_t i = 0; i < 3; ++i) {
            const Float4 x = Float4::load(row_x + 12 * i) - r.ox;
            const Float4 y = Float4::load(row_y + 12 * i) - r.oy;
            const Float4 z = Float4::load(row_z + 12 * i) - r.oz;
            px[i] = x - r.sx * z;
            py[i] = y - r.sy * z;
            t[i] = z * r.sz;
        }
        const Float4 U = px[2] * py[1] - py[2] * px[1];
        const Float4 V = px[0] * py[2] - py[0] * px[2];
        const Float4 W = px[1] * py[0] - py[1] * px[0];
        const Float4 M =
            vabs(px[0]) + vabs(py[0]) + vabs(px[1]) + vabs(py[1]) + vabs(px[2]) + vabs(py[2]);
        const Float4 bound = r.bound_scale * (M + r.bound_floor);
        const Float4 minus = Float4::splat(0.0f) - bound;
        // Only the smallest and largest of U, V, W matter (and of the vertices' t). No NaN can
        // arise while the filter is on (see FilterRay), so min / max drop none; while it is off,
        // the bound is +inf or NaN and every lane is a candidate, none sure.
        const Float4 low = vmin(vmin(U, V), W), high = vmax(vmax(U, V), W);
        const int some_negative = less_mask(low, minus), some_positive = less_mask(bound, high);
        const int all_one_sign = less_mask(bound, low) | less_mask(high, minus);
        const int inside = less_mask(r.t_low, vmin(vmin(t[0], t[1]), t[2])) &
                           less_mask(vmax(vmax(t[0], t[1]), t[2]), r.t_high);
        return {static_cast<unsigned>(~(some_negative & some_positive)) & 15u,
                static_cast<unsigned>(all_one_sign & inside)};
    }

    /// A subtree still to visit: an inner node (count 0) or a leaf's triangle range, with its
    /// order key: a lower bound of the distance at which the ray enters its box, or +inf for a
    /// box deferred (see RayBoxes::enter).
    struct Entry {
        std::uint32_t first, count;
        float t;
    };

    /// From inner node e, walks down towards the child box of least key that the ray enters
    /// until e is a leaf, pushing the other children entered: if `sorted`, larger keys first,
    /// so smaller ones are popped first; else as they come.
    /// Returns false if some inner node on the way has no child entered.
    template <bool sorted>
    bool descend(Entry& e, const RayBoxes& ray, float t1, std::array<Entry, stack_size>& stack,
                 std::size_t& top) const {
        while (e.count == 0) {
            const Node& node = nodes_[e.first];
            alignas(16) std::array<float, width> key;
            unsigned mask = static_cast<unsigned>(ray.enter(node, t1, key.data()));
            if (mask == 0) return false;
            auto child = [&](int k) { return Entry{node.first[k], node.count[k], key[k]}; };
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
                    const Entry c = child(std::countr_zero(mask));
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
                    const Entry c = child(std::countr_zero(mask));
                    const bool closer = c.t < e.t;
                    stack[top++] = closer ? e : c;
                    e = closer ? c : e;
                }
            }
        }
        return true;
    }

    /// Front-to-back traversal with an explicit stack; visit(triangle, t, u, v) is called for
    /// hits on triangles of patches other than those in `skip`, and returns true to stop. If
    /// `t_far` is given, it is re-read after each hit (closest-hit queries shrink it and drop
    /// subtrees entered beyond it). With `any_hit`, a triangle that the filter proves hit ends
    /// the search without the double test (nor a call of visit); it ignores t_far. Returns true
    /// if stopped. any_hit is a template argument so that each query compiles to its own loop,
    /// without the other's branches.
    template <bool any_hit = false, class Visit>
    bool traverse(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit,
                  const double* t_far = nullptr,
                  std::array<std::uint32_t, 2> skip = {no_patch, no_patch}) const {
        if constexpr (any_hit) t_far = nullptr;
        if (nodes_.empty() || d == Vec3(0.0)) return false;
        const ShearedRay sheared(d);
        // An occlusion ray starts on a surface. The boxes around its origin hold that surface and
        // its neighbours, which the ray leaves rather than crosses: try them last. (In bench_bvh
        // this visits a quarter fewer leaves.) A closest hit needs the plain near-to-far order.
        // (NaN defers nothing: no comparison with it holds.)
        const float t0_below = float_below(t0);
        const float defer = any_hit ? t0_below : std::numeric_limits<float>::quiet_NaN();
        const double R = scale_ + max_abs(o);
        const RayBoxes ray(o, d, t0_below, R, defer);
        const FilterRay filter(o, sheared, R, t0, t1);
        std::array<Entry, stack_size> stack;
        std::size_t top = 0;
        stack[top++] = {0, 0, t0_below};
        auto skipped = [&](const TriangleBlock& block, int lane) {
            return block.patch[lane] == skip[0] || block.patch[lane] == skip[1];
        };
        // Axes along which the ray does not move: a triangle lying in a plane across one of them
        // through the origin contains the ray, which the filter cannot tell from a hit on its
        // edge (rays between patches of one wall meet dozens of such triangles).
        const unsigned flat =
            (d.x == 0.0 ? 1u : 0u) | (d.y == 0.0 ? 2u : 0u) | (d.z == 0.0 ? 4u : 0u);
        auto in_ray_plane = [&](const AxisPlane& plane) {
            return plane.axis < 3 && ((flat >> plane.axis) & 1u) != 0 &&
                   plane.at == glm::value_ptr(o)[plane.axis];
        };
        const float t1_above = float_above(t1);
        while (top > 0) {
            Entry e = stack[--top];
            const float limit = t_far ? float_above(*t_far) : t1_above;
            // Keys are distances unless deferring, and only closest hits (t_far) prune by distance.
            if ((t_far && e.t > limit) || !descend<!any_hit>(e, ray, limit, stack, top)) continue;
            for (std::uint32_t first = e.first; first < e.first + e.count; first += 4) {
                // A ray along a wall meets its blocks by the dozen: skip each at once.
                if (flat != 0 && in_ray_plane(block_planes_[first / 4])) continue;
                const TriangleBlock& block = blocks_[first / 4];
                const std::uint32_t left = e.first + e.count - first;
                const unsigned valid = left >= 4 ? 15u : (1u << left) - 1;
                const Lanes lanes = candidates(block, filter);
                unsigned mask = lanes.maybe & valid;
                if constexpr (any_hit) {
                    for (unsigned sure = lanes.sure & valid; sure != 0; sure &= sure - 1)
                        if (!skipped(block, std::countr_zero(sure))) return true;
                    mask &= ~lanes.sure;
                }
                for (; mask != 0; mask &= mask - 1) {
                    const int lane = std::countr_zero(mask);
                    if (skipped(block, lane) || (flat != 0 && in_ray_plane(planes_[first + lane])))
                        continue;
                    const Triangle& tri = triangles_[first + lane];
                    double t, u, v;
                    if (hit_triangle(tri, o, sheared, t0, t_far ? *t_far : t1, t, u, v) &&
                        visit(tri, t, u, v))
                        return true;
                }
            }
        }
        return false;
    }

    static constexpr std::uint32_t no_patch = std::numeric_limits<std::uint32_t>::max();

    BvhOptions options_;
    std::vector<Triangle> triangles_;      // leaf by leaf, each leaf from a multiple of 4
    std::vector<TriangleBlock> blocks_;    // triangles_ in fours, single precision
    std::vector<AxisPlane> planes_;        // of each of triangles_
    std::vector<AxisPlane> block_planes_;  // of all four lanes of each block, if they share one
    std::size_t triangle_count_ = 0;
    std::vector<Node> nodes_;  // nodes_[0] is the root
    double scale_ = 0.0;       // largest coordinate magnitude of any vertex
};

static_assert(Visibility<Bvh>);

}  // namespace radiosity
