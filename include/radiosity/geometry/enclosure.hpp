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
#include <cmath>
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

/// Probe rays cast from each point: enough that an opening as large as the Cornell box's open
/// front is met by several of them from any point inside, even behind a block (26 axis and
/// diagonal directions missed it from behind the blocks).
inline constexpr std::size_t probe_count = 128;

/// probe_count directions spread evenly over the sphere: a Fibonacci lattice (z stepped evenly,
/// the azimuth turned by the golden angle; Gonzalez 2010), so that no direction lies along an
/// axis or in an axis-aligned wall's plane (no z is 0, and the azimuths are irrational turns).
inline const std::array<Vec3, probe_count>& probe_directions() {
    static const std::array<Vec3, probe_count> directions = [] {
        std::array<Vec3, probe_count> d{};
        const double golden_angle = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
        for (std::size_t k = 0; k < probe_count; ++k) {
            const double z = 1.0 - (2.0 * double(k) + 1.0) / double(probe_count);
            const double r = std::sqrt(1.0 - z * z), phi = golden_angle * (double(k) + 0.5);
            d[k] = Vec3(r * std::cos(phi), r * std::sin(phi), z);
        }
        return d;
    }();
    return directions;
}

}  // namespace detail

/// Whether every one of the probe rays from o hits a surface, and how many hit fronts.
struct Probe {
    bool enclosed = true;     ///< no ray escaped
    std::size_t front = 0;    ///< rays whose first hit is a face's front
    std::size_t back = 0;     ///< rays whose first hit is a face's back
    std::size_t escaped = 0;  ///< rays that hit nothing
};

/// Casts the probe directions from o to the first surface within `far`. Cost: probe_count rays.
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

/// Whether point o, enclosed and seeing mostly backs, lies in the scene's outermost shell (an
/// inside-out room: beyond the backs it sees there is nothing) rather than inside a solid
/// object standing in a room or an open box (beyond its backs lie the walls): the rays go on
/// past their first hit, and the shell is outermost if none of them hits anything more.
/// Cost: up to 2 probe_count rays.
inline bool outermost_shell(const Bvh& bvh, const Vec3& o, double far) {
    for (const Vec3& d : detail::probe_directions()) {
        const auto hit = bvh.intersect(o, d, 0.0, far);
        if (!hit) continue;
        if (bvh.intersect(o, d, hit->t + 1e-7 * far, far)) return false;  // past the face hit
    }
    return true;
}

/// Classifies a scene by rays (in the spirit of point-in-polyhedron tests by rays; Haines
/// 1994): from the 27 points at 1/4, 1/2 and 3/4 of its bounding box along each axis,
/// probe_count rays each to the first surface hit. Points from which some ray escapes lie outside
/// any room (or in an open one: the Cornell box) and are not counted. An enclosed point that meets
/// fronts at least as often as backs is in a room facing in; one that meets mostly backs is inside
/// a solid object (a block, a teapot: something lies beyond its backs), not counted, or in the
/// outermost shell of a scene facing out (outermost_shell). A room if any point is in one, else
/// inside out if any point is in an outermost shell, else open; the counts are those of the
/// points behind the verdict. Cost: a BVH over the patches (O(n log n)) and 27 to 81 probe_count
/// rays.
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
    EnclosureReport room, out;
    for (double fx : {0.25, 0.5, 0.75})
        for (double fy : {0.25, 0.5, 0.75})
            for (double fz : {0.25, 0.5, 0.75}) {
                const Vec3 o = lo + Vec3(fx, fy, fz) * (hi - lo);
                const Probe p = probe(bvh, patches, o, far);
                r.escaped += p.escaped;
                if (!p.enclosed) continue;
                EnclosureReport* into = nullptr;
                if (p.front >= p.back)
                    into = &room;
                else if (outermost_shell(bvh, o, far))
                    into = &out;
                if (into == nullptr) continue;  // inside furniture
                into->front += p.front;
                into->back += p.back;
            }
    const bool is_room = room.front + room.back > 0, is_out = out.front + out.back > 0;
    r.front = is_room ? room.front : out.front;
    r.back = is_room ? room.back : out.back;
    r.kind = is_room ? Enclosure::room : is_out ? Enclosure::inside_out : Enclosure::open;
    return r;
}

}  // namespace radiosity
