#pragma once
/// @file rrv_transform.hpp  The transforms of RRV scenes (Dudka 2007): translate, scale, rotate
/// (RRV's own order and turn directions, ../shared/rrv/README.md) and shear (ignored, as RRV does),
/// and the stack of them that the body's nesting builds, applied innermost first. The stack is an
/// explicit array, not a chain of closures or a recursion, so that no depth of nesting in a file
/// can overflow the call stack; its cost is one step per level and point.

#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace radiosity::detail {

/// RRV's rotate with the sines and cosines computed once: the axis (normalised) times the angle
/// gives (ax, ay, az); a point turns about z by az, then about y by ay (RRV's turn direction, the
/// opposite of the right-hand rule), then about x by ax.
struct RrvRotation {
    double cx = 1, sx = 0, cy = 1, sy = 0, cz = 1, sz = 0;

    explicit RrvRotation(const Vec3& angles = Vec3(0.0))
        : cx(std::cos(angles.x)),
          sx(std::sin(angles.x)),
          cy(std::cos(angles.y)),
          sy(std::sin(angles.y)),
          cz(std::cos(angles.z)),
          sz(std::sin(angles.z)) {}

    Vec3 operator()(Vec3 p) const {
        p = {p.x * cz - p.y * sz, p.x * sz + p.y * cz, p.z};
        p = {p.x * cy - p.z * sy, p.y, p.x * sy + p.z * cy};
        p = {p.x, p.y * cx - p.z * sx, p.y * sx + p.z * cx};
        return p;
    }
};

/// The rotation angles of RRV's rotate: the axis d normalised, times the angle in radians. An
/// angle beyond a full turn is reduced first (exactly: fmod is exact), so that a huge angle cannot
/// become an infinite one; an axis whose length squared would underflow or overflow is rescaled
/// first. A zero axis gives no rotation.
inline Vec3 rrv_rotation_angles(Vec3 d, double degrees) {
    if (std::abs(degrees) > 360.0) degrees = std::fmod(degrees, 360.0);
    const double angle = degrees * std::numbers::pi / 180.0;
    double len = glm::length(d);
    if (!(len > 1e-150 && len < 1e150)) {  // x^2 + y^2 + z^2 leaves double's range
        const double big = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
        if (!(big > 0.0)) return Vec3(0.0);
        d /= big;
        len = glm::length(d);
    }
    return d / len * angle;
}

/// One transform of an RRV body: translate by d, scale by d, rotate, or shear (no change).
struct RrvTransform {
    enum class Kind { translate, scale, rotate, shear } kind = Kind::shear;
    Vec3 d{0.0};           ///< the offset or the scale factors
    RrvRotation rotation;  ///< for rotate

    Vec3 operator()(const Vec3& p) const {
        switch (kind) {
            case Kind::translate:
                return p + d;
            case Kind::scale:
                return p * d;
            case Kind::rotate:
                return rotation(p);
            default:
                return p;
        }
    }
};

/// The transforms around the current element of an RRV body, outermost first; a point is placed
/// by the innermost first (RRV's order). Cost: one step per level.
class RrvTransformStack {
  public:
    void push(const RrvTransform& t) { stack_.push_back(t); }
    void pop() { stack_.pop_back(); }
    std::size_t depth() const { return stack_.size(); }

    Vec3 place(Vec3 p) const {
        for (auto t = stack_.rbegin(); t != stack_.rend(); ++t) p = (*t)(p);
        return p;
    }

  private:
    std::vector<RrvTransform> stack_;
};

}  // namespace radiosity::detail
