#pragma once
/// @file shaded_mesh.hpp  A triangle mesh with a linear RGB colour per vertex: what shading
/// produces (flat: each patch's corners get its B; smooth: per-vertex averages) and what the
/// camera renderer and the exporters consume.

#include <radiosity/geometry/vec.hpp>

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace radiosity {

/// Triangles with per-vertex positions and linear RGB colours (radiant exitance B per band;
/// a grey B is copied to all three) and, when the patch mesh has them, lightmap UVs.
struct ShadedMesh {
    std::vector<Vec3> positions;                          ///< vertex positions
    std::vector<glm::vec3> colours;                       ///< linear RGB per vertex
    std::vector<glm::vec2> uvs;                           ///< lightmap UV per vertex, or empty
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise from the front
};

}  // namespace radiosity
