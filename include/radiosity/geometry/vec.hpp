#pragma once
/// @file vec.hpp  Vector types of the library: glm's double-precision vectors for geometry
/// (form factors are computed in double), float vectors for images.

#include <glm/glm.hpp>

#include <cmath>

namespace radiosity {
using Vec3 = glm::dvec3;  ///< a point or direction in scene units
using Vec2 = glm::dvec2;  ///< a point in a 2-D parameter domain

/// The 2-D cross product u x v: twice the signed area of the triangle (0, u, v), positive when
/// v lies counter-clockwise of u.
inline double cross2(const Vec2& u, const Vec2& v) {
    return u.x * v.y - u.y * v.x;
}

/// Two unit vectors u, v completing the unit vector n to a right-handed orthonormal frame
/// (u x v = n), without branches or normalisation (Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited", JCGT 6(1)).
inline void orthonormal_basis(const Vec3& n, Vec3& u, Vec3& v) {
    const double s = std::copysign(1.0, n.z);
    const double a = -1.0 / (s + n.z), b = n.x * n.y * a;
    u = Vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    v = Vec3(b, s + n.y * n.y * a, -n.y);
}
}  // namespace radiosity
