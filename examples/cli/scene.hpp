#pragma once
/// @file scene.hpp  The scene the radiosity programs solve: loaded by name or file type, and
/// the camera that looks at it unless the command line places one.

#include "cli/options.hpp"

#include <radiosity/mesh/mesh.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/spectrum.hpp>

#include <string>

namespace radiosity::cli {

/// The programs solve in RGB.
using Colour = radiosity::Rgb;

/// Loads a scene: a built-in name (builtin_scene_names), else a file by its extension: RRV's
/// XML (.xml), glTF (.gltf, .glb) or OBJ (anything else). Throws radiosity::Error naming the
/// scene if it is neither a built-in name nor an existing file, or if the file is bad.
radiosity::Mesh<Colour> load_scene(const std::string& scene);

/// The corners of the axis-aligned box around a mesh's vertices. Cost: O(vertices).
struct Box {
    glm::dvec3 lo, hi;
};
Box bounding_box(const radiosity::Mesh<Colour>& mesh);

/// The length of a box's diagonal.
inline double diagonal(const Box& b) {
    return glm::length(b.hi - b.lo);
}

/// The default camera: for the Cornell box the published one (the Cornell Program of Computer
/// Graphics' box data: 35 mm lens, 25 mm film), else one with the same field of view that
/// frames the sphere around the bounding box from its -z side (the Cornell box's convention).
radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh);

/// The default camera with --camera's eye, target and up and --fov's angle where given.
radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh);

}  // namespace radiosity::cli
