#pragma once
/// @file enclosure.hpp  Whether a scene is a closed room, seen from inside: rays from points
/// spread through its bounding box must all hit a surface, and a room whose surfaces face in
/// shows them their fronts. A box modelled with its faces pointing out (as modelling tools
/// make a solid) shows their backs: an inside-out room, in which no patch sees another, so that
/// the solve finds nothing to bounce and the picture is black.

#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

namespace radiosity {

/// What rays from inside a scene's bounding box find.
enum class Enclosure {
    open,        ///< from no point do all rays hit a surface (the Cornell box, an object)
    room,        ///< some points see surfaces all round, mostly their fronts: facing in
    inside_out,  ///< some points see surfaces all round, mostly their backs: facing out
};

/// The counts behind an Enclosure: rays that hit a front face, a back face, or nothing.
struct EnclosureReport {
    Enclosure kind = Enclosure::open;  ///< the verdict
    std::size_t front = 0;    ///< rays from enclosed points whose first hit is a face's front
    std::size_t back = 0;     ///< rays from enclosed points whose first hit is a face's back
    std::size_t escaped = 0;  ///< rays, from any point, that hit nothing
};

namespace detail {

/// The 26 directions from a cube's centre to its face centres, edges and corners, turned a
/// little off the axes so that no ray runs inside an axis-aligned wall's plane.
inline std::array<Vec3, 26> probe_directions() {
    std::array<Vec3, 26> d{};
    std::size_t k = 0;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                if (x != 0 || y != 0 || z != 0)
                    d[k++] = glm::normalize(Vec3(x + 0.0123, y + 0.0371, z - 0.0257));
    return d;
}

}  // namespace detail

/// Whether every one of the 26 probe rays from o hits a surface, and how many hit fronts.
struct Probe {
    bool enclosed = true;     ///< no ray escaped
    std::size_t front = 0;    ///< rays whose first hit is a face's front
    std::size_t back = 0;     ///< rays whose first hit is a face's back
    std::size_t escaped = 0;  ///< rays that hit nothing
};

/// Casts the 26 probe directions from o to the first surface within `far`. Cost: 26 rays.
inline Probe probe(const Bvh& bvh, const PatchTable& patches, const Vec3& o, double far) {
    Probe p;
    for (const Vec3& d : detail::probe_directions()) {
        const auto hit = bvh.intersect(o, d, 0.0, far);
        if (!hit)
            ++p.escaped;
        else if (glm::dot(patches.normal(hit->patch), d) < 0.0)
            ++p.front;
        else
            ++p.back;
    }
    p.enclosed = p.escaped == 0;
    return p;
}

/// Classifies a scene by rays (in the spirit of point-in-polyhedron tests by rays; Haines
/// 1994): from the 27 points at 1/4, 1/2 and 3/4 of its bounding box along each axis, 26 rays
/// each to the first surface hit. Points from which some ray escapes lie outside any room (or
/// in an open one: the Cornell box) and are not counted. If no point is enclosed the scene is
/// open; otherwise it is a room if the enclosed points' rays hit fronts at least as often as
/// backs (furniture seen from a point inside it gives back hits, the walls outnumber it), else
/// inside out. Cost: a BVH over the patches (O(n log n)) and 702 ray queries.
inline EnclosureReport classify_enclosure(const PatchTable& patches) {
    EnclosureReport r;
    if (patches.size() == 0) return r;
    Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3& p : patches.vertices()) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const Bvh bvh(patches);
    const double far = 4.0 * glm::length(hi - lo) + 1.0;
    bool any_enclosed = false;
    for (double fx : {0.25, 0.5, 0.75})
        for (double fy : {0.25, 0.5, 0.75})
            for (double fz : {0.25, 0.5, 0.75}) {
                const Probe p = probe(bvh, patches, lo + Vec3(fx, fy, fz) * (hi - lo), far);
                r.escaped += p.escaped;
                if (!p.enclosed) continue;
                any_enclosed = true;
                r.front += p.front;
                r.back += p.back;
            }
    r.kind = !any_enclosed       ? Enclosure::open
             : r.front >= r.back ? Enclosure::room
                                 : Enclosure::inside_out;
    return r;
}

}  // namespace radiosity
