// Loading the scene and placing the camera (scene.hpp).
#include "cli/scene.hpp"

#include <radiosity/error.hpp>
#include <radiosity/io/gltf_read.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace radiosity::cli {

radiosity::Mesh<Colour> load_scene(const std::string& scene) {
    const auto names = radiosity::builtin_scene_names();
    if (std::find(names.begin(), names.end(), scene) != names.end())
        return radiosity::build_mesh(radiosity::builtin_scene<Colour>(scene));
    if (!std::filesystem::exists(scene))
        throw radiosity::Error(scene + ": no such file, and not a built-in scene");
    const auto extension = std::filesystem::path(scene).extension();
    if (extension == ".xml")  // RRV's scene format
        return radiosity::build_mesh(radiosity::read_rrv<Colour>(scene));
    if (extension == ".gltf" || extension == ".glb")
        return radiosity::build_mesh(radiosity::read_gltf<Colour>(scene));
    return radiosity::build_mesh(radiosity::read_obj<Colour>(scene));
}

Box bounding_box(const radiosity::Mesh<Colour>& mesh) {
    Box b{glm::dvec3(std::numeric_limits<double>::max()),
          glm::dvec3(-std::numeric_limits<double>::max())};
    for (auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        b.lo = glm::min(b.lo, glm::dvec3(p[0], p[1], p[2]));
        b.hi = glm::max(b.hi, glm::dvec3(p[0], p[1], p[2]));
    }
    return b;
}

radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh) {
    const double fov = 2.0 * std::atan(12.5 / 35.0) * 180.0 / M_PI;  // 25 mm film, 35 mm lens
    if (scene == "cornell")
        return {{278.0, 273.0, -800.0}, {278.0, 273.0, 0.0}, {0.0, 1.0, 0.0}, fov};
    const Box b = bounding_box(mesh);
    const glm::dvec3 c = 0.5 * (b.lo + b.hi);
    const double radius = 0.5 * diagonal(b);
    const double distance = radius / std::sin(0.5 * fov * M_PI / 180.0);
    return {c - glm::dvec3(0.0, 0.0, distance), c, {0.0, 1.0, 0.0}, fov};
}

radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh) {
    radiosity::Camera c = default_camera(scene, mesh);
    if (!a.camera.empty()) {
        c.eye = {a.camera[0], a.camera[1], a.camera[2]};
        c.target = {a.camera[3], a.camera[4], a.camera[5]};
        c.up = {a.camera[6], a.camera[7], a.camera[8]};
    }
    if (a.fov > 0.0) c.fov_y_degrees = a.fov;
    return c;
}

}  // namespace radiosity::cli
