#pragma once
/// @file vec.hpp  Vector types of the library: glm's double-precision vectors for geometry
/// (form factors are computed in double), float vectors for images.

#include <glm/glm.hpp>

namespace radiosity {
using Vec3 = glm::dvec3;  ///< a point or direction in scene units
using Vec2 = glm::dvec2;  ///< a point in a 2-D parameter domain
}  // namespace radiosity
