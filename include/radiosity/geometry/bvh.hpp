#pragma once
/// @file bvh.hpp  A bounding volume hierarchy over the scene's triangles for visibility rays:
/// binned surface-area-heuristic build (Wald 2007), a watertight ray-triangle test (Woop,
/// Benthin & Wald 2013), any-hit (occlusion) and closest-hit queries. It models Visibility.

#include <radiosity/concepts.hpp>
#include <radiosity/error.hpp>
#include <radiosity/geometry/vec.hpp>

#include <glm/gtc/type_ptr.hpp>
#include <radiosity/mesh/patch_table.hpp>

#include <algorithm>
#include <array>
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
    int bins = 16;                ///< candidate split planes per axis of the binned SAH
    int max_leaf_size = 4;        ///< a node with this many triangles or fewer may become a leaf
    double traversal_cost = 1.0;  ///< cost of visiting a node, relative to one triangle test
};

/// The closest hit of a ray: distance along the (unnormalised) direction, the patch hit, and
/// the barycentric coordinates of the hit point in its triangle.
struct Hit {
    double t = 0.0;           ///< hit point = origin + t * direction
    std::uint32_t patch = 0;  ///< patch the triangle belongs to
    double u = 0.0, v = 0.0;  ///< barycentrics of vertices 1 and 2 of the triangle
};

/// A binary BVH over triangles, each tagged with the patch it belongs to (Wald 2007: binned SAH;
/// Woop et al. 2013: watertight triangle test, so rays never slip through shared edges).
/// Build: O(n log n) time, O(n) memory. Queries: O(log n) expected.
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

    std::size_t triangle_count() const { return triangles_.size(); }  ///< triangles held
    std::size_t node_count() const { return nodes_.size(); }          ///< nodes of the tree

    /// Visibility: true if the open segment p -> q (endpoints excluded by a relative margin)
    /// hits a triangle of any patch other than a and b. Any hit ends the search.
    bool occluded(const Vec3& p, const Vec3& q, std::uint32_t a, std::uint32_t b) const {
        constexpr double margin = 1e-9;
        bool hit = false;
        traverse(p, q - p, margin, 1.0 - margin, [&](const Triangle& tri, double, double, double) {
            if (tri.patch == a || tri.patch == b) return false;
            hit = true;
            return true;  // stop: any hit will do
        });
        return hit;
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
        std::array<std::uint32_t, 128> stack;
        std::size_t top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const std::uint32_t index = stack[--top];
            const Node& node = nodes_[index];
            if (!overlaps(Vec3(node.box.lo[0], node.box.lo[1], node.box.lo[2]),
                          Vec3(node.box.hi[0], node.box.hi[1], node.box.hi[2])))
                continue;
            if (node.count == 0) {
                stack[top++] = index + 1;
                stack[top++] = node.first;
                continue;
            }
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                const Triangle& t = triangles_[k];
                if (t.patch == a || t.patch == b) continue;
                if (!overlaps(glm::min(glm::min(t.v[0], t.v[1]), t.v[2]),
                              glm::max(glm::max(t.v[0], t.v[1]), t.v[2])))
                    continue;
                if (!behind(t, plane_a) && !behind(t, plane_b)) return true;
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
    /// A box in single precision, rounded outwards so it always contains the double box: half
    /// the memory traffic of doubles during traversal, and never a missed triangle.
    struct FloatBox {
        std::array<float, 3> lo{}, hi{};
        FloatBox() = default;
        explicit FloatBox(const Box& b) {
            constexpr float inf = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::nextafter(static_cast<float>(b.lo[a]), -inf);
                hi[a] = std::nextafter(static_cast<float>(b.hi[a]), inf);
            }
        }
    };
    /// A node: its box; for a leaf, its triangle range; for an inner node, its second child
    /// (the first child always follows its parent in the array).
    struct Node {
        FloatBox box;
        std::uint32_t first = 0;  // leaf: first triangle; inner: index of the second child
        std::uint32_t count = 0;  // leaf: triangle count; 0 for an inner node
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

    void build() {
        nodes_.clear();
        if (triangles_.empty()) return;
        nodes_.reserve(2 * triangles_.size());
        nodes_.push_back({});
        build_node(0, 0, static_cast<std::uint32_t>(triangles_.size()));
    }

    /// Builds node `index` over triangles [first, first + count): find the best binned SAH split
    /// (cost = traversal + sum over children of area ratio x triangles), or make a leaf when no
    /// split beats testing every triangle. Recursion depth is O(log n) for sane scenes and at
    /// most 64 levels, after which a node becomes a leaf.
    void build_node(std::size_t index, std::uint32_t first, std::uint32_t count, int depth = 0) {
        Box box, centres;
        for (std::uint32_t k = first; k < first + count; ++k) {
            box.grow(triangle_box(k));
            centres.grow(centroid(k));
        }
        nodes_[index].box = FloatBox(box);
        const Split s = best_split(first, count, centres);
        if (count <= static_cast<std::uint32_t>(options_.max_leaf_size) || s.axis < 0 ||
            depth >= 64)
            return make_leaf(index, first, count);
        // SAH: splitting must beat testing every triangle here (the leaf cost is count).
        if (!(s.cost < static_cast<double>(count)) && count <= 16)
            return make_leaf(index, first, count);
        const auto mid = static_cast<std::uint32_t>(
            std::partition(triangles_.begin() + first, triangles_.begin() + first + count,
                           [&](const Triangle& t) {
                               return bin_of((t.v[0] + t.v[1] + t.v[2]) / 3.0, centres, s.axis) <
                                      s.bin;
                           }) -
            triangles_.begin());
        if (mid == first || mid == first + count) return make_leaf(index, first, count);
        nodes_.push_back({});  // first child right after its parent
        build_node(index + 1, first, mid - first, depth + 1);
        nodes_[index].first = static_cast<std::uint32_t>(nodes_.size());
        nodes_.push_back({});
        build_node(nodes_[index].first, mid, first + count - mid, depth + 1);
    }

    void make_leaf(std::size_t index, std::uint32_t first, std::uint32_t count) {
        nodes_[index].first = first;
        nodes_[index].count = count;
    }

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
    Split best_split(std::uint32_t first, std::uint32_t count, const Box& centres) const {
        Split best;
        const std::size_t nb = static_cast<std::size_t>(options_.bins);
        const double parent_area = [&] {
            Box b;
            for (std::uint32_t k = first; k < first + count; ++k) b.grow(triangle_box(k));
            return b.half_area();
        }();
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
                right_cost[b] = acc.half_area() * n;
            }
            acc = Box{};
            n = 0;
            for (std::size_t b = 1; b < nb; ++b) {
                acc.grow(bin_box[b - 1]);
                n += bin_count[b - 1];
                const double cost =
                    options_.traversal_cost + (acc.half_area() * n + right_cost[b]) / parent_area;
                if (n > 0 && n < count && cost < best.cost)
                    best = {axis, static_cast<int>(b), cost};
            }
        }
        return best;
    }

    /// What the slab test needs of a ray, computed once per ray.
    struct RaySlabs {
        std::array<double, 3> inv, o_inv;
        std::array<bool, 3> negative;
        RaySlabs(const Vec3& o, const Vec3& d) {
            for (int a = 0; a < 3; ++a) {
                const double da = glm::value_ptr(d)[a];
                inv[a] = da != 0.0 ? 1.0 / da : std::copysign(1e200, da);
                o_inv[a] = glm::value_ptr(o)[a] * inv[a];
                negative[a] = inv[a] < 0.0;
            }
        }
    };

    /// Slab test of a ray against a box (Kay & Kajiya 1986) with precomputed reciprocal
    /// direction; returns the entry distance, or infinity for a miss. Components are read
    /// through plain arrays: glm's operator[] branches on the index.
    static double enter(const FloatBox& b, const RaySlabs& r, double t0, double t1) {
        for (int a = 0; a < 3; ++a) {
            // The near and far faces of the slab are known from the direction's sign, so no
            // swap: t = face * (1 / d) - o / d.
            const double near = (r.negative[a] ? b.hi[a] : b.lo[a]) * r.inv[a] - r.o_inv[a];
            const double far = (r.negative[a] ? b.lo[a] : b.hi[a]) * r.inv[a] - r.o_inv[a];
            t0 = near > t0 ? near : t0;
            t1 = far < t1 ? far : t1;
        }
        return t0 <= t1 * (1.0 + 1e-12) ? t0 : std::numeric_limits<double>::infinity();
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

    /// Front-to-back traversal with an explicit stack; visit(triangle, t, u, v) returns true to
    /// stop. If `t_far` is given, it is re-read after each hit (closest-hit queries shrink it).
    template <class Visit>
    void traverse(const Vec3& o, const Vec3& d, double t0, double t1, Visit&& visit,
                  const double* t_far = nullptr) const {
        if (nodes_.empty() || d == Vec3(0.0)) return;
        const ShearedRay sheared(d);
        const RaySlabs slabs(o, d);
        constexpr double miss = std::numeric_limits<double>::infinity();
        // Each stack entry is a node whose box the ray enters, with its entry distance (a
        // closest-hit query drops it once a nearer hit is known); boxes are tested once, at
        // the parent, so both children are compared and the nearer is visited first.
        struct Entry {
            std::uint32_t node;
            double t;
        };
        std::array<Entry, 128> stack;
        std::size_t top = 0;
        const double root = enter(nodes_[0].box, slabs, t0, t1);
        if (root == miss) return;
        stack[top++] = {0, root};
        while (top > 0) {
            const Entry e = stack[--top];
            const double limit = t_far ? *t_far : t1;
            if (e.t > limit) continue;
            const Node& node = nodes_[e.node];
            if (node.count > 0) {
                for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                    double t, u, v;
                    if (hit_triangle(triangles_[k], o, sheared, t0, t_far ? *t_far : t1, t, u, v) &&
                        visit(triangles_[k], t, u, v))
                        return;
                }
                continue;
            }
            const std::uint32_t left = e.node + 1, right = node.first;
            const double tl = enter(nodes_[left].box, slabs, t0, limit);
            const double tr = enter(nodes_[right].box, slabs, t0, limit);
            if (tl <= tr) {  // push the farther child first, so the nearer is visited first
                if (tr != miss) stack[top++] = {right, tr};
                if (tl != miss) stack[top++] = {left, tl};
            } else {
                if (tl != miss) stack[top++] = {left, tl};
                stack[top++] = {right, tr};
            }
        }
    }

    BvhOptions options_;
    std::vector<Triangle> triangles_;
    std::vector<Node> nodes_;
};

static_assert(Visibility<Bvh>);

}  // namespace radiosity
