// Loading the scene and placing the camera (scene.hpp).
#include "cli/scene.hpp"

#include <radiosity/error.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/io/gltf_read.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/orientation.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <utility>

namespace radiosity::cli {

radiosity::Scene<Colour> read_scene(const std::string& scene) {
    const auto names = radiosity::builtin_scene_names();
    if (std::find(names.begin(), names.end(), scene) != names.end())
        return radiosity::builtin_scene<Colour>(scene);
    if (!std::filesystem::exists(scene))
        throw radiosity::Error(scene + ": no such file, and not a built-in scene");
    const auto extension = std::filesystem::path(scene).extension();
    if (extension == ".xml") return radiosity::read_rrv<Colour>(scene);  // RRV's scene format
    if (extension == ".gltf" || extension == ".glb") return radiosity::read_gltf<Colour>(scene);
    return radiosity::read_obj<Colour>(scene);
}

radiosity::Mesh<Colour> load_scene(const std::string& scene) {
    return radiosity::build_mesh(read_scene(scene));
}

double parse_unit(const std::string& unit) {
    static const std::map<std::string, double> named{
        {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}, {"ft", 0.3048}};
    if (const auto it = named.find(unit); it != named.end()) return it->second;
    std::size_t used = 0;
    double metres = 0.0;
    try {
        metres = std::stod(unit, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != unit.size() || !(metres > 0.0) || !std::isfinite(metres))
        throw radiosity::Error("--unit '" + unit +
                               "': not m, cm, mm, in, ft or a positive number of metres");
    return metres;
}

namespace {

/// Refuses a closed room whose faces point out: its patches see only each other's backs.
void check_orientation(const radiosity::EnclosureReport& e, const std::string& scene) {
    if (e.kind != radiosity::Enclosure::inside_out) return;
    throw radiosity::Error(
        scene + ": a closed room whose faces point out (" + std::to_string(e.back) + " of " +
        std::to_string(e.back + e.front) +
        " rays from inside it meet the back of a face; modelling tools make solids that way): "
        "patches shine from their front only, so the room would stay dark; turn the faces "
        "round with --flip-faces, or make them two-sided with --two-sided (twice the patches)");
}

}  // namespace

LoadedScene load_scene(const SceneArgs& a) {
    radiosity::Scene<Colour> s = read_scene(a.scene);
    if (!a.unit.empty()) s.metres_per_unit = parse_unit(a.unit);
    if (a.flip_faces) radiosity::flip_faces(s);
    if (a.two_sided) radiosity::make_two_sided(s);
    // The faces first (a face of zero area or one that crosses itself is named), then the scene.
    LoadedScene loaded{radiosity::build_mesh(s), {s.metres_per_unit, radiosity::Enclosure::open}};
    if (!radiosity::has_emitter(s))
        throw radiosity::Error(
            a.scene +
            ": no face emits light (OBJ: Ke in the MTL; glTF: emissiveFactor; RRV: emission), so "
            "every radiosity would be 0 and the picture black; give a light source an emission");
    const auto e = radiosity::classify_enclosure(radiosity::make_patch_table(loaded.mesh));
    if (!a.two_sided) check_orientation(e, a.scene);  // twins face both ways by construction
    loaded.info.enclosure = e.kind == radiosity::Enclosure::open ? radiosity::Enclosure::open
                                                                 : radiosity::Enclosure::room;
    return loaded;
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

namespace {

/// Inside a closed room, looking horizontally (y is up) along `axis` (0: x, 2: z) in direction
/// `sign`: the eye at mid-height in the middle of the near wall, 1% of the depth inside it; the
/// far wall (width w, height h at distance d) fills the vertical field of view
/// 2 atan(max(w, h) / 2d), 5% wider so that its edges show, within 20..120°.
radiosity::Camera room_camera(const Box& b, int axis, double sign) {
    const glm::dvec3 size = b.hi - b.lo, c = 0.5 * (b.lo + b.hi);
    const auto k = static_cast<glm::length_t>(axis);
    glm::dvec3 eye = c, target = c;
    eye[k] = sign > 0.0 ? b.lo[k] + 0.01 * size[k] : b.hi[k] - 0.01 * size[k];
    target[k] = sign > 0.0 ? b.hi[k] : b.lo[k];
    const double d = std::abs(target[k] - eye[k]);
    const double half = 1.05 * 0.5 * std::max(size[2 - k], size.y);
    const double fov = std::clamp(2.0 * std::atan(half / d) * 180.0 / M_PI, 20.0, 120.0);
    return {eye, target, {0.0, 1.0, 0.0}, fov};
}

/// How much of the far wall a room camera sees: of 15 x 15 rays from the eye to points
/// spread over the far wall's plane within the room, those that get within 2% of it unblocked.
int far_wall_seen(const radiosity::Bvh& bvh, const Box& b, const radiosity::Camera& cam, int axis) {
    const auto across = static_cast<glm::length_t>(2 - axis);
    int seen = 0;
    for (int i = 0; i < 15; ++i)
        for (int j = 0; j < 15; ++j) {
            glm::dvec3 p = cam.target;
            p[across] = b.lo[across] + (i + 0.5) / 15.0 * (b.hi[across] - b.lo[across]);
            p.y = b.lo.y + (j + 0.5) / 15.0 * (b.hi.y - b.lo.y);
            seen += !bvh.intersect(cam.eye, p - cam.eye, 0.0, 0.98);  // the wall itself at 1
        }
    return seen;
}

/// The room camera of the four horizontal views (along +z first, the Cornell box's convention,
/// then -z, +x, -x) that sees the most of its far wall past what stands in the room, each eye
/// moved in from the box's side until it is enclosed (classify_enclosure's probe).
radiosity::Camera room_camera(const radiosity::Mesh<Colour>& mesh, const Box& b) {
    const radiosity::PatchTable patches = radiosity::make_patch_table(mesh);
    const radiosity::Bvh bvh(patches);
    radiosity::Camera best = room_camera(b, 2, 1.0);
    int best_seen = -1;
    using View = std::pair<int, double>;  // axis (0: x, 2: z), direction along it
    for (const auto& [axis, sign] : {View{2, 1.0}, View{2, -1.0}, View{0, 1.0}, View{0, -1.0}}) {
        radiosity::Camera cam = room_camera(b, axis, sign);
        // A room turned in its box (RRV's room2) leaves the box's walls outside it: step the
        // eye in towards the middle until surfaces surround it.
        const auto k = static_cast<glm::length_t>(axis);
        glm::dvec3 step(0.0);
        step[k] = 0.05 * sign * (b.hi[k] - b.lo[k]);
        for (int i = 0;
             i < 9 && !radiosity::probe(bvh, patches, cam.eye, 4.0 * diagonal(b)).enclosed; ++i)
            cam.eye += step;
        cam.fov_y_degrees = std::clamp(
            2.0 *
                std::atan(1.05 * 0.5 * std::max(b.hi[2 - k] - b.lo[2 - k], b.hi.y - b.lo.y) /
                          std::abs(cam.target[k] - cam.eye[k])) *
                180.0 / M_PI,
            20.0, 120.0);
        const int seen = far_wall_seen(bvh, b, cam, axis);
        if (seen > best_seen) best = cam, best_seen = seen;
    }
    return best;
}

}  // namespace

radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh) {
    return default_camera(
        scene, mesh,
        scene == "cornell" ? radiosity::Enclosure::open
                           : radiosity::classify_enclosure(radiosity::make_patch_table(mesh)).kind);
}

radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh,
                                 radiosity::Enclosure enclosure) {
    const double fov = 2.0 * std::atan(12.5 / 35.0) * 180.0 / M_PI;  // 25 mm film, 35 mm lens
    if (scene == "cornell")
        return {{278.0, 273.0, -800.0}, {278.0, 273.0, 0.0}, {0.0, 1.0, 0.0}, fov};
    const Box b = bounding_box(mesh);
    if (enclosure == radiosity::Enclosure::room) return room_camera(mesh, b);
    const glm::dvec3 c = 0.5 * (b.lo + b.hi);
    const double radius = 0.5 * diagonal(b);
    const double distance = radius / std::sin(0.5 * fov * M_PI / 180.0);
    return {c - glm::dvec3(0.0, 0.0, distance), c, {0.0, 1.0, 0.0}, fov};
}

radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh) {
    return chosen_camera(a, scene, mesh,
                         scene != "cornell"
                             ? radiosity::classify_enclosure(radiosity::make_patch_table(mesh)).kind
                             : radiosity::Enclosure::open);
}

radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh,
                                radiosity::Enclosure enclosure) {
    radiosity::Camera c = default_camera(scene, mesh, enclosure);
    if (!a.camera.empty()) {
        c.eye = {a.camera[0], a.camera[1], a.camera[2]};
        c.target = {a.camera[3], a.camera[4], a.camera[5]};
        c.up = {a.camera[6], a.camera[7], a.camera[8]};
    }
    if (a.fov > 0.0) c.fov_y_degrees = a.fov;
    return c;
}

}  // namespace radiosity::cli
