#pragma once
/// @file shaded_mesh.hpp  A triangle mesh with a linear RGB colour per vertex: what shading
/// produces (flat: each patch's corners get its B; smooth: per-vertex averages) and what the
/// camera renderer and the exporters consume.

#include <radiosity/geometry/vec.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace radiosity {

/// Triangles with per-vertex positions and linear RGB colours (radiant exitance B per band;
/// a grey B is copied to all three).
struct ShadedMesh {
    std::vector<Vec3> positions;                          ///< vertex positions
    std::vector<glm::vec3> colours;                       ///< linear RGB per vertex
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise from the front
};

}  // namespace radiosity
