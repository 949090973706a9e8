#pragma once
/// @file analytic.hpp  Analytic form factors: the exact differential-area-to-polygon form factor
/// (Lambert's contour integral, Lambert 1760; Baum, Rushmeier & Winget 1989), integrated over the
/// receiving patch by adaptive triangle quadrature, so that area-to-area values reach the closed
/// forms of the heat-transfer literature.
///
/// Limitation, by design of the method: there is NO visibility. Every pair of patches that face
/// each other exchanges energy as if nothing stood between them, so the method is exact for
/// convex enclosures and unoccluded configurations, and wrong in scenes with occluders (such as
/// the blocks of the Cornell box). Use the hemicube or ray casting there, or set
/// AnalyticOptions::visibility_samples to multiply each value by a visible fraction from rays
/// (then the result is no longer exact where something is in the way, but it is consistent).

#include <radiosity/concepts.hpp>
#include <radiosity/config.hpp>
#include <radiosity/error.hpp>
#include <radiosity/form_factor/visibility.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/polygon.hpp>
#include <radiosity/geometry/sampling.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <numbers>
#include <span>
#include <vector>

namespace radiosity {

/// Settings of the analytic method.
struct AnalyticOptions {
    double tolerance = 1e-6;     ///< relative error aimed at in each area-to-area integral
    int max_depth = 10;          ///< deepest level of the adaptive quadrature (4^depth triangles)
    int visibility_samples = 0;  ///< rays per pair for a visible fraction; 0: no visibility
    int penumbra_samples = 256;  ///< rays for a pair whose first rays disagree (partly hidden)
    std::uint64_t seed = 1;      ///< seed of each pair's rays (with visibility_samples > 0)
};

namespace detail {

/// The angle atan2(y, x) in [0, pi] for y >= 0: what an edge subtends, from y = |a x b| and
/// x = a . b. The same value as std::atan2 to 1 ulp, at half its cost (glibc's saves and
/// restores the rounding mode on every call, and contour integrals are a quarter of a
/// hierarchical solve). Method: fold to the octant 0 <= t <= 1 (t = min / max of y, |x|), take
/// atan t as pi/4 + atan((t - 1) / (t + 1)) above 0.66, and there the rational minimax
/// approximation atan u = u + u z P(z) / Q(z), z = u^2, of degree 4 over 5 (the Cephes math
/// library's coefficients, Moshier 1989); unfold by pi/2 - angle and pi - angle. The plain
/// version is std::atan2(y, x).
inline double subtended_angle(double y, double x) {
    const double ax = std::abs(x);
    const bool steep = y > ax;  // the angle from the y axis is the smaller one
    const double num = steep ? ax : y, den = steep ? y : ax;
    if (!(den > 0.0)) return x < 0.0 ? std::numbers::pi : 0.0;
    const bool upper = num > 0.66 * den;
    const double u = upper ? (num - den) / (num + den) : num / den;
    const double z = u * u;
    // P and Q by Horner's rule, coefficients from z^4 (Q's leading 1) down to z^0.
    constexpr std::array<double, 5> p{-8.750608600031904122785e-1, -1.615753718733365076637e1,
                                      -7.500855792314704667340e1, -1.228866684490136173410e2,
                                      -6.485021904942025371773e1};
    constexpr std::array<double, 5> q{2.485846490142306297962e1, 1.650270098316988542046e2,
                                      4.328810604912902668951e2, 4.853903996359136964868e2,
                                      1.945506571482613964425e2};
    double P = p[0], Q = z + q[0];
    for (std::size_t k = 1; k < 5; ++k) {
        P = P * z + p[k];
        Q = Q * z + q[k];
    }
    // The doubles pi/4, pi/2 and pi lie below the true values by 3.06e-17, 6.12e-17 and
    // 1.22e-16: each is added to the small part first, so that the sum keeps those bits.
    double angle = u + u * (z * P / Q);
    if (upper) angle = (angle + 3.061616997868383e-17) + std::numbers::pi / 4;
    if (steep) angle = (6.123233995736766e-17 - angle) + std::numbers::pi / 2;
    return x < 0.0 ? (1.2246467991473532e-16 - angle) + std::numbers::pi : angle;
}

/// The contour sum of Lambert's formula for a polygon entirely on the front side of the
/// receiver's plane: sum_k gamma_k n . (r_k x r_k+1) / |r_k x r_k+1|, with r_k = v_k - x and
/// gamma_k the angle subtended by edge k. Negative when the polygon shows its front to x.
inline double contour_sum(const Vec3& x, const Vec3& n, std::span<const Vec3> poly) {
    double sum = 0.0;
    for (std::size_t k = 0; k < poly.size(); ++k) {
        const Vec3 a = poly[k] - x;
        const Vec3 b = poly[(k + 1) % poly.size()] - x;
        const Vec3 c = glm::cross(a, b);
        const double len = glm::length(c);
        if (len == 0.0) continue;  // x on the edge's line: the edge subtends no area
        const double gamma = subtended_angle(len, glm::dot(a, b));  // atan2(len, a . b)
        sum += gamma * glm::dot(n, c) / len;
    }
    return sum;
}

}  // namespace detail

/// Form factor from a differential area at x with unit normal n to a planar polygon (vertices
/// counter-clockwise about the polygon's front normal), by Lambert's contour integral
///   F_dA->P = -(1 / 2 pi) sum_k gamma_k n . unit(r_k x r_k+1)
/// after clipping the polygon to the horizon of x (the half-space in front of the receiver),
/// since the formula holds only for what lies above it. One-sided: a polygon seen from its back
/// gives 0 (the contour then runs the other way round and the sum changes sign). Cost: O(k).
inline double point_to_polygon(const Vec3& x, const Vec3& n, std::span<const Vec3> poly) {
    bool all_above = true, any_above = false;
    for (const Vec3& v : poly) {
        const bool above = glm::dot(v - x, n) > 0.0;
        all_above = all_above && above;
        any_above = any_above || above;
    }
    if (!any_above) return 0.0;
    double sum;
    if (all_above) {
        sum = detail::contour_sum(x, n, poly);
    } else {
        const ClippedPolygon<> clipped(poly, x, n);
        sum = detail::contour_sum(x, n, clipped.corners());
    }
    return std::max(0.0, -sum / (2.0 * std::numbers::pi));
}

namespace detail {

/// Degree-5, 7-point quadrature rule on a triangle (Dunavant 1985): barycentric points and
/// weights (weights sum to 1; multiply by the triangle's area).
struct TriangleRule {
    std::array<glm::dvec3, 7> point;
    std::array<double, 7> weight;
};

inline const TriangleRule& dunavant5() {
    static const TriangleRule rule = [] {
        constexpr double a1 = 0.059715871789770, b1 = 0.470142064105115;
        constexpr double a2 = 0.797426985353087, b2 = 0.101286507323456;
        constexpr double w0 = 0.225, w1 = 0.132394152788506, w2 = 0.125939180544827;
        return TriangleRule{{glm::dvec3(1.0 / 3.0),
                             {a1, b1, b1},
                             {b1, a1, b1},
                             {b1, b1, a1},
                             {a2, b2, b2},
                             {b2, a2, b2},
                             {b2, b2, a2}},
                            {w0, w1, w1, w1, w2, w2, w2}};
    }();
    return rule;
}

/// The integrand over the outer patch, x -> F_dA(x)->inner polygon.
struct PointToPolygon {
    Vec3 normal;
    std::span<const Vec3> polygon;
    double operator()(const Vec3& x) const { return point_to_polygon(x, normal, polygon); }
};

/// Integral of f over triangle (a, b, c) by the 7-point rule.
template <class F>
double triangle_rule(const F& f, const Vec3& a, const Vec3& b, const Vec3& c, double area) {
    const TriangleRule& r = dunavant5();
    double sum = 0.0;
    for (std::size_t k = 0; k < 7; ++k)
        sum += r.weight[k] * f(r.point[k].x * a + r.point[k].y * b + r.point[k].z * c);
    return sum * area;
}

/// Adaptive quadrature: compares the rule on the triangle with the sum over its four midpoint
/// children and recurses where they disagree by more than the relative tolerance. The integrand
/// is smooth except near an edge shared with the other patch (a logarithmic singularity of its
/// derivative), where refinement concentrates.
template <class F>
double adaptive(const F& f, const Vec3& a, const Vec3& b, const Vec3& c, double area, double coarse,
                const AnalyticOptions& o, int depth) {
    const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    const double q = area / 4.0;
    const std::array<std::array<Vec3, 3>, 4> child{
        {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}}};
    std::array<double, 4> part;
    for (std::size_t k = 0; k < 4; ++k)
        part[k] = triangle_rule(f, child[k][0], child[k][1], child[k][2], q);
    const double fine = part[0] + part[1] + part[2] + part[3];
    // Relative test, with an absolute floor far below anything that matters (1e-9 of the
    // triangle's area): pairs whose exchange is nearly zero, such as neighbours on a slightly
    // non-planar wall, would otherwise refine to the depth limit chasing rounding noise.
    if (depth >= o.max_depth ||
        std::abs(fine - coarse) <= o.tolerance * std::max(std::abs(fine), 1e-3 * area))
        return fine;
    double sum = 0.0;
    for (std::size_t k = 0; k < 4; ++k)
        sum += adaptive(f, child[k][0], child[k][1], child[k][2], q, part[k], o, depth + 1);
    return sum;
}

/// True if no point of polygon p lies strictly in front of the plane (origin, normal).
inline bool behind_plane(std::span<const Vec3> p, const Vec3& origin, const Vec3& normal) {
    const double scale = glm::length(p[0] - origin) + 1.0;
    return std::all_of(p.begin(), p.end(), [&](const Vec3& v) {
        return glm::dot(v - origin, normal) <= 1e-12 * scale;
    });
}

/// True unless one patch lies entirely behind the other's plane: one-sided patches that do not
/// face each other exchange nothing.
inline bool facing(const PatchTable& t, std::size_t a, std::size_t b) {
    return !behind_plane(t.polygon(b), t.centroid(a), t.normal(a)) &&
           !behind_plane(t.polygon(a), t.centroid(b), t.normal(b));
}

/// The two patches of a pair in the order the exchange integral takes them: over the outer one,
/// of the form factor to the inner one.
struct IntegrationOrder {
    std::size_t outer, inner;
};

/// Pair (i, j) ordered so that the integral runs over the smaller patch (fewer points for the
/// same accuracy), ties broken by index: (i, j) and (j, i) give the same order, so the exchange
/// A_i F_ij = A_j F_ji is one number both ways (reciprocity by construction).
inline IntegrationOrder integration_order(const PatchTable& t, std::size_t i, std::size_t j) {
    const bool outer_is_i = t.area(i) < t.area(j) || (t.area(i) == t.area(j) && i < j);
    return outer_is_i ? IntegrationOrder{i, j} : IntegrationOrder{j, i};
}

}  // namespace detail

/// The exchange integral A_a F_a->b = integral over polygon a (unit normal n_a) of F_dA->b, by
/// adaptive quadrature of Lambert's contour integral (Dunavant's 7-point rule on a fan of a,
/// refined where four children disagree with their parent by more than the tolerance). Cost:
/// 35 contour integrals per fan triangle for well-separated polygons, more near shared edges.
inline double exchange_integral(std::span<const Vec3> a, const Vec3& n_a, std::span<const Vec3> b,
                                const AnalyticOptions& options = {}) {
    // Only the part of a in front of b's plane sees b's front: there the integrand is smooth;
    // across b's plane it jumps to 0 (e.g. a floor patch under a block's side), and a jump
    // inside a triangle would send the adaptive quadrature to its depth limit.
    const ClippedPolygon<> clipped(a, b[0], polygon_normal(b));
    const std::span<const Vec3> front = clipped.corners();
    if (front.size() < 3) return 0.0;
    const detail::PointToPolygon f{n_a, b};
    double sum = 0.0;
    for (std::size_t k = 1; k + 1 < front.size(); ++k) {  // fan of the convex clipped polygon
        const Vec3 &p = front[0], &q = front[k], &r = front[k + 1];
        const double area = 0.5 * glm::length(glm::cross(q - p, r - p));
        if (area == 0.0) continue;
        sum +=
            detail::adaptive(f, p, q, r, area, detail::triangle_rule(f, p, q, r, area), options, 1);
    }
    return sum;
}

/// The exchange integral A_a F_a->b by one application of Dunavant's degree-5, 7-point rule on
/// each fan triangle of the part of a in front of b's plane (the coarse level of
/// exchange_integral, without refinement). For well-separated polygons, where F_dA->b is smooth
/// over a, it is exact to 3.2e-6 relative for unit squares 3 apart (the ray-cast near-field
/// boundary is 2.83) and better farther. Cost: 7 contour integrals per fan triangle.
inline double exchange_by_rule(std::span<const Vec3> a, const Vec3& n_a, std::span<const Vec3> b) {
    const ClippedPolygon<> clipped(a, b[0], polygon_normal(b));
    const std::span<const Vec3> front = clipped.corners();
    if (front.size() < 3) return 0.0;
    const detail::PointToPolygon f{n_a, b};
    double sum = 0.0;
    for (std::size_t k = 1; k + 1 < front.size(); ++k) {
        const Vec3 &p = front[0], &q = front[k], &r = front[k + 1];
        const double area = 0.5 * glm::length(glm::cross(q - p, r - p));
        if (area > 0.0) sum += detail::triangle_rule(f, p, q, r, area);
    }
    return sum;
}

/// Area-to-area form factors by the analytic method: F_ij = (1/A_i) integral over A_i of
/// F_dA->A_j (the contour integral above), by adaptive quadrature. Reciprocity is exact by
/// construction: the integral is taken over the smaller patch of the pair and divided by A_i
/// or A_j. No visibility (see the file comment) unless visibility_samples > 0: then times a
/// visible fraction from rays through V, the BVH by default (`Analytic method(options)` is
/// Analytic<Bvh>), or any Visibility built over the patch table. Cost per pair: 35 contour
/// integrals for well-separated patches, more near shared edges; a row costs O(n) pairs.
template <class V = Bvh>
requires Visibility<V> && std::constructible_from<V, const PatchTable&>
class Analytic {
  public:
    /// A method with the given settings; throws Error for a non-positive tolerance or depth.
    explicit Analytic(AnalyticOptions options = {}) : options_(options) {
        if (!(options_.tolerance > 0.0) || options_.max_depth < 0 || options_.max_depth > 20)
            throw Error("analytic form factors: tolerance must be > 0 and max_depth in [0, 20]");
        if (options_.visibility_samples < 0 || options_.visibility_samples > 65536 ||
            options_.penumbra_samples < 0 || options_.penumbra_samples > 65536)
            throw Error(
                "analytic form factors: visibility and penumbra samples must be in [0, "
                "65536]");
    }

    /// Keeps a reference to the patch table (which must outlive the method's use), and builds
    /// the visibility model over it when visibility is asked for.
    void prepare(const PatchTable& patches) {
        patches_ = &patches;
        if (options_.visibility_samples > 0) visibility_ = std::make_shared<const V>(patches);
    }

    /// F_ij for one pair (0 for i == j, planar patches do not see themselves).
    double pair(std::size_t i, std::size_t j) const { return exchange(i, j) / table().area(i); }

    /// The exchange A_i F_ij = A_j F_ji: the same number both ways (ReciprocalFormFactor): the
    /// integral over the smaller patch, times its visible fraction when visibility is on.
    double exchange(std::size_t i, std::size_t j) const {
        if (i == j) return 0.0;
        RADIOSITY_ASSERT(i < table().size() && j < table().size());
        const auto [outer, inner] = detail::integration_order(table(), i, j);
        const double x = area_integral(outer, inner);
        if (x == 0.0 || !visibility_) return x;
        return x * visible_fraction(outer, inner);
    }

    double area(std::size_t i) const { return table().area(i); }  ///< A_i

    /// Row i: F_ij for every patch j (RowSource).
    void row(std::size_t i, std::span<float> out) const {
        RADIOSITY_ASSERT(out.size() == table().size());
        for (std::size_t j = 0; j < out.size(); ++j) out[j] = static_cast<float>(pair(i, j));
    }

    const AnalyticOptions& options() const { return options_; }  ///< the settings

  private:
    const PatchTable& table() const {
        if (patches_ == nullptr) throw Error("analytic form factors: prepare() was not called");
        return *patches_;
    }

    /// Kernel-weighted visible fraction of the pair from k x k jittered sample pairs, with the
    /// pair's own random stream (the same whichever row asks).
    double visible_fraction(std::size_t outer, std::size_t inner) const {
        const PatchTable& t = table();
        Rng rng(pair_seed(options_.seed, outer, inner));
        const int k = static_cast<int>(std::ceil(std::sqrt(double(options_.visibility_samples))));
        std::vector<Vec3> xs, ys;
        jittered_pairs(t.polygon(outer), t.polygon(inner), k, rng, xs, ys);
        return pair_visible_fraction(*visibility_, t, outer, inner, xs, ys,
                                     options_.penumbra_samples, rng);
    }

    /// A_outer F_outer,inner, or 0 when the two do not face each other.
    double area_integral(std::size_t outer, std::size_t inner) const {
        const PatchTable& t = table();
        if (!detail::facing(t, outer, inner)) return 0.0;
        return exchange_integral(t.polygon(outer), t.normal(outer), t.polygon(inner), options_);
    }

    AnalyticOptions options_;
    const PatchTable* patches_ = nullptr;
    std::shared_ptr<const V> visibility_;  // only with visibility_samples > 0
};

static_assert(ReciprocalFormFactor<Analytic<>>);

}  // namespace radiosity
