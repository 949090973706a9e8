#pragma once
/// @file scene.hpp  The scene the radiosity programs solve: loaded by name or file type, and
/// the camera that looks at it unless the command line places one.

#include "cli/options.hpp"

#include <radiosity/geometry/enclosure.hpp>
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

/// The scene as plain arrays, as load_scene reads it (same names, same errors).
radiosity::Scene<Colour> read_scene(const std::string& scene);

/// What the programs know of a scene beyond its mesh: its unit and whether it is a room.
struct SceneInfo {
    double metres_per_unit = 1.0;  ///< length of one scene unit in metres (glTF is in metres)
    radiosity::Enclosure enclosure = radiosity::Enclosure::open;  ///< open, or a closed room
};

/// A scene loaded as the command line asks, with what is known of it.
struct LoadedScene {
    radiosity::Mesh<Colour> mesh;  ///< the input faces, before subdivision
    SceneInfo info;                ///< unit and enclosure
};

/// The length of one unit in metres: "m", "cm", "mm", "in", "ft" or a positive number of
/// metres. Throws radiosity::Error naming --unit otherwise.
double parse_unit(const std::string& unit);

/// Loads a.scene as load_scene does, its unit from --unit (else the scene's own), turned round
/// (--flip-faces) or made two-sided (--two-sided), and checks before any solve what would only
/// give a black picture: a scene with no emitter, and a closed room whose faces point out
/// (classify_enclosure), each a radiosity::Error saying what is wrong and what to do.
/// Cost: reading the scene, and a BVH and 702 rays over its faces.
LoadedScene load_scene(const SceneArgs& a);

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
/// Graphics' box data: 35 mm lens, 25 mm film); for a closed room (classify_enclosure) one
/// inside it, as RRV's visualiser shows a room: the eye at the middle of the room's -z side
/// just inside its near wall, looking along +z, the field of view just wide enough for the
/// whole far wall; else one with the Cornell box's field of view that frames the sphere around
/// the bounding box from its -z side (the Cornell box's convention).
radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh,
                                 radiosity::Enclosure enclosure);

/// The default camera, the enclosure found by classify_enclosure over the mesh's faces.
radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh);

/// The default camera (given the enclosure) with --camera's and --fov's settings where given.
radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh,
                                radiosity::Enclosure enclosure);

/// The default camera with --camera's eye, target and up and --fov's angle where given.
radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh);

}  // namespace radiosity::cli
