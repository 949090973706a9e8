#pragma once
/// @file pair_culling.hpp  Pair culling for form factors: proving, without any ray, that nothing
/// can stand between two patches, so that their visibility is 1 exactly. A radiosity query (it
/// knows that patches are one-sided and radiate from their planes) over the box walk of any
/// visibility model that offers one (the PairCulling concept: the BVH).

#include <radiosity/concepts.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace radiosity {

/// True if some triangle of a patch other than a and b might block a segment from the front of
/// plane A to the front of plane B inside the box [lo, hi]: its bounding box reaches into the
/// box's interior and it is not entirely behind (or on) either plane. A conservative test: false
/// proves that every such segment is free, so two patches inside the box that face each other
/// see each other without any ray (the walls around them lie on the box's faces or behind the
/// patches' planes). Planes are (point, unit normal); eps is a length. Cost: O(log n + what
/// reaches into the box) for the BVH.
template <PairCulling V>
bool may_block(const V& visibility, const Vec3& lo, const Vec3& hi, std::uint32_t a,
               std::uint32_t b, const std::array<Vec3, 2>& plane_a,
               const std::array<Vec3, 2>& plane_b, double eps) {
    auto overlaps = [&](const Vec3& l, const Vec3& h) {
        return l.x < hi.x && h.x > lo.x && l.y < hi.y && h.y > lo.y && l.z < hi.z && h.z > lo.z;
    };
    auto behind = [&](const PatchTriangle& t, const std::array<Vec3, 2>& plane) {
        for (const Vec3& v : t.v)
            if (glm::dot(v - plane[0], plane[1]) > eps) return false;
        return true;
    };
    // A whole box on or behind either plane holds nothing that could block: without this, a
    // pair on a floor of n patches visits every floor leaf under its box (their boxes, rounded
    // outwards, reach just above the floor), and a row costs O(n^2). The margin covers that
    // rounding; a triangle within it of a plane lies flat on the plane.
    const double margin = eps + visibility.box_slack();
    auto box_behind = [&](const Vec3& l, const Vec3& h, const std::array<Vec3, 2>& plane) {
        const Vec3 centre = 0.5 * (l + h), half = 0.5 * (h - l);
        return glm::dot(centre - plane[0], plane[1]) + glm::dot(half, glm::abs(plane[1])) <= margin;
    };
    auto enter = [&](const Vec3& l, const Vec3& h) {
        return overlaps(l, h) && !box_behind(l, h, plane_a) && !box_behind(l, h, plane_b);
    };
    auto blocks = [&](const PatchTriangle& t) {
        if (t.patch == a || t.patch == b) return false;
        if (!overlaps(glm::min(glm::min(t.v[0], t.v[1]), t.v[2]),
                      glm::max(glm::max(t.v[0], t.v[1]), t.v[2])))
            return false;
        return !behind(t, plane_a) && !behind(t, plane_b);
    };
    return visibility.any_triangle(enter, blocks);
}

/// may_block for patches a and b of a table: the box is their joint bounding box, the planes
/// theirs (through their centroids), eps 1e-9 of the box's diagonal. False proves V_ab = 1.
template <PairCulling V>
bool pair_may_be_blocked(const V& visibility, const PatchTable& t, std::size_t a, std::size_t b) {
    Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::size_t p : {a, b})
        for (const Vec3& v : t.polygon(p)) {
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
    const double eps = 1e-9 * glm::length(hi - lo);
    return may_block(visibility, lo, hi, static_cast<std::uint32_t>(a),
                     static_cast<std::uint32_t>(b), {t.centroid(a), t.normal(a)},
                     {t.centroid(b), t.normal(b)}, eps);
}

}  // namespace radiosity
