#pragma once
/// @file palette.hpp  Colours that are not light: the false-colour scale of a form-factor row,
/// a colour per patch id (hemicube item buffers), and the sRGB curve's inverse, so that colours
/// chosen on screen can travel through the same sRGB encoding as the light.

#include <glm/vec3.hpp>

#include <cstdint>

namespace radiosity::view {

/// The linear value whose sRGB encoding (IEC 61966-2-1) is `display`.
glm::vec3 srgb_to_linear(const glm::vec3& display);

/// The false-colour scale at t in [0, 1], as a display (sRGB) colour: dark blue through purple,
/// red and orange to pale yellow, growing lighter all the way, so that it also reads in grey.
glm::vec3 false_colour(double t);

/// Where F lies on the row's logarithmic scale from lo (0) to hi (1), clamped; F <= 0 gives -1.
double log_position(double F, double lo, double hi);

/// A colour for patch id j (display), scattered so that neighbours differ; black for -1.
glm::vec3 id_colour(std::int32_t id);

}  // namespace radiosity::view
