#pragma once
/// @file conservation.hpp  The meshing's invariant, checked on every run: the patches cut from
/// an input face cover exactly that face. Their Newell vectors, projected on the face's normal,
/// add up to the face's area (Newell's vector is additive over any partition whose shared edges
/// cancel, whatever the vertices' positions, so this holds to rounding for exact coverage and
/// fails for overlaps, gaps or patches outside); each patch faces the face's way; each patch's
/// centroid lies in the face (a patch in a concave polygon's notch has its centroid outside);
/// and, for a face flat to within the planarity tolerance, the patches' own areas add up to
/// the face's too. Cost: O(patches + corners), the point-in-face tests bucketed by rows.

#include <radiosity/error.hpp>
#include <radiosity/geometry/predicates.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/mesh/conforming.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace radiosity::detail {

/// Newell's vector of a polygon taken about its first vertex (Newell 1972): the same vector as
/// about the origin, with rounding relative to the polygon's size rather than its position.
inline Vec3 local_newell(std::span<const Vec3> p) {
    Vec3 n(0.0);
    for (std::size_t k = 1; k + 1 < p.size(); ++k) n += glm::cross(p[k] - p[0], p[k + 1] - p[0]);
    return n;
}

/// Area centroid of a polygon as a fan about its first vertex, each triangle weighted by its
/// signed area along the normal n (the vertex mean for a degenerate polygon).
inline Vec3 local_centroid(std::span<const Vec3> p, const Vec3& n) {
    Vec3 c(0.0);
    double w = 0.0;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
        const double a = glm::dot(glm::cross(p[k] - p[0], p[k + 1] - p[0]), n);
        c += a * (p[k] - p[0] + p[k + 1] - p[0]) / 3.0;
        w += a;
    }
    if (w != 0.0) return p[0] + c / w;
    for (const Vec3& v : p) c += v - p[0];
    return p[0] + c / static_cast<double>(p.size());
}

/// How far a face's corners lie from its best-fit plane (Newell's normal through their mean),
/// per unit of the face's size (its bounding box's diagonal).
inline double non_planarity(std::span<const Vec3> p) {
    if (p.size() < 4) return 0.0;
    const Vec3 n = glm::normalize(local_newell(p));
    Vec3 mean(0.0), lo(p[0]), hi(p[0]);
    for (const Vec3& x : p) {
        mean += x;
        lo = glm::min(lo, x);
        hi = glm::max(hi, x);
    }
    mean /= static_cast<double>(p.size());
    double off = 0.0;
    for (const Vec3& x : p) off = std::max(off, std::abs(glm::dot(x - mean, n)));
    return off / glm::length(hi - lo);
}

/// Point-in-polygon by winding number (Sunday 2001's form of Hormann & Agathos 2001), the
/// crossings decided by exact orientation; a point on the boundary counts as inside. The edges
/// are bucketed by rows of y so that a query looks at the few edges of its row.
class PolygonContains {
  public:
    explicit PolygonContains(std::vector<Vec2> p) : p_(std::move(p)) {
        lo_ = hi_ = p_[0].y;
        for (const Vec2& q : p_) {
            lo_ = std::min(lo_, q.y);
            hi_ = std::max(hi_, q.y);
        }
        rows_.resize(std::max<std::size_t>(1, p_.size() / 8));
        for (std::uint32_t k = 0; k < p_.size(); ++k) {
            const Vec2 &a = p_[k], &b = p_[(k + 1) % p_.size()];
            const std::size_t r0 = row(std::min(a.y, b.y)), r1 = row(std::max(a.y, b.y));
            for (std::size_t r = r0; r <= r1; ++r) rows_[r].push_back(k);
        }
    }

    bool operator()(const Vec2& q) const {
        if (q.y < lo_ || q.y > hi_) return false;
        int winding = 0;
        for (std::uint32_t k : rows_[row(q.y)]) {
            const Vec2 &a = p_[k], &b = p_[(k + 1) % p_.size()];
            const int o = orient2d(a, b, q);
            if (o == 0 && q.x >= std::min(a.x, b.x) && q.x <= std::max(a.x, b.x) &&
                q.y >= std::min(a.y, b.y) && q.y <= std::max(a.y, b.y))
                return true;  // on the boundary
            if (a.y <= q.y) {
                if (b.y > q.y && o > 0) ++winding;
            } else if (b.y <= q.y && o < 0) {
                --winding;
            }
        }
        return winding != 0;
    }

  private:
    std::size_t row(double y) const {
        const double t = hi_ > lo_ ? (y - lo_) / (hi_ - lo_) : 0.0;
        return std::min(
            rows_.size() - 1,
            static_cast<std::size_t>(std::max(0.0, t) * static_cast<double>(rows_.size())));
    }
    std::vector<Vec2> p_;
    std::vector<std::vector<std::uint32_t>> rows_;
    double lo_, hi_;
};

/// Checks the invariant (see the file comment) for the patches of a soup against the input
/// faces: face[f] is input face f's polygon (empty for a face left out on purpose), flat[f]
/// whether it is planar enough for its patches' own areas to be compared. Throws Error naming
/// the face when any part fails: it cannot fail unless the meshing has a bug, and a patch mesh
/// that does not cover its scene must not be solved.
inline void check_conservation(const PatchSoup& s, const std::vector<std::vector<Vec3>>& face,
                               const std::vector<char>& flat, double relative = 1e-9) {
    struct Sum {
        double projected = 0.0, own = 0.0;
        std::size_t patches = 0;
    };
    std::vector<Sum> sum(face.size());
    std::vector<Vec3> normal(face.size());
    std::vector<std::vector<std::size_t>> of(face.size());
    for (std::size_t f = 0; f < face.size(); ++f)
        if (!face[f].empty()) normal[f] = glm::normalize(local_newell(face[f]));
    for (std::size_t i = 0; i < s.faces.size(); ++i) {
        const std::size_t f = s.parent[i];
        std::vector<Vec3> p;
        for (std::uint32_t v : s.faces[i]) p.push_back(s.points[v]);
        const Vec3 N = local_newell(p);
        const double along = glm::dot(N, normal[f]);
        const std::string at =
            "mesh check: face " + std::to_string(f) + ": patch " + std::to_string(i);
        if (!(along > 0.0)) throw Error(at + " faces the other way or has no area");
        sum[f].projected += 0.5 * along;
        sum[f].own += 0.5 * glm::length(N);
        ++sum[f].patches;
        of[f].push_back(i);
    }
    for (std::size_t f = 0; f < face.size(); ++f) {
        if (face[f].empty()) continue;
        const std::string at = "mesh check: face " + std::to_string(f);
        const double area = 0.5 * glm::length(local_newell(face[f]));
        auto differs = [&](double x) { return !(std::abs(x - area) <= relative * area); };
        if (differs(sum[f].projected) || (flat[f] && differs(sum[f].own)))
            throw Error(at + ": its " + std::to_string(sum[f].patches) +
                        " patches cover an area of " + std::to_string(sum[f].own) + " (projected " +
                        std::to_string(sum[f].projected) + "), the face has " +
                        std::to_string(area));
        Vec3 u, v;
        orthonormal_basis(normal[f], u, v);
        const Vec3 o = face[f][0];
        auto flat2 = [&](const Vec3& x) { return Vec2(glm::dot(x - o, u), glm::dot(x - o, v)); };
        std::vector<Vec2> outline;
        for (const Vec3& x : face[f]) outline.push_back(flat2(x));
        const PolygonContains inside(std::move(outline));
        for (std::size_t i : of[f]) {
            std::vector<Vec3> p;
            for (std::uint32_t k : s.faces[i]) p.push_back(s.points[k]);
            if (!inside(flat2(local_centroid(p, normal[f]))))
                throw Error(at + ": the centroid of patch " + std::to_string(i) +
                            " lies outside the face");
        }
    }
}

}  // namespace radiosity::detail
