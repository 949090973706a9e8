// The `radiosity` program's scene, meshing, form-factor, solver and camera options, scene loading
// and default camera (program_options.hpp), as examples/radiosity_cli.cpp has them.
#include "program_options.hpp"

#include <radiosity/error.hpp>
#include <radiosity/io/gltf_read.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace radiosity::cli {

namespace {

/// The built-in scenes' names, comma-separated, for the help text.
std::string builtin_names() {
    std::string s;
    for (const auto& n : radiosity::builtin_scene_names()) s += (s.empty() ? "" : ", ") + n;
    return s;
}

void add_meshing_options(CLI::Option_group& g, SceneArgs& a) {
    g.add_option("--max-edge", a.max_edge,
                 "subdivide patches to this edge length in scene units (0 keeps the input "
                 "faces; default: 1/30 of the scene's bounding-box diagonal)")
        ->check(CLI::NonNegativeNumber);
    auto* max_area =
        g.add_option("--max-area", a.max_area,
                     "subdivide patches until none is larger than this area, each split 1->4 "
                     "at its edge midpoints as RRV's `divide` does, and neighbours split alike "
                     "(no T-junctions); --max-edge then defaults to no limit")
            ->check(CLI::PositiveNumber);
    g.add_option("--divide", a.divide,
                 "subdivide exactly as RRV's `divide`: each face split 1->4 by itself until "
                 "none is larger than this area, leaving T-junctions where neighbours differ "
                 "(RRV's patches, to compare with its results)")
        ->check(CLI::PositiveNumber)
        ->excludes(max_area);
}

void add_form_factor_options(CLI::Option_group& g, SceneArgs& a) {
    g.add_option("--form-factor", a.form_factor, "form-factor method")
        ->check(CLI::IsMember({"analytic", "hemicube", "raycast"}))
        ->capture_default_str();
    g.add_option("--resolution", a.resolution, "hemicube resolution in pixels (default 128)")
        ->check(CLI::Range(8, 4096));
    g.add_option("--samples", a.samples, "ray-cast sample pairs per patch pair (default 16)")
        ->check(CLI::Range(1, 65536));
}

void add_solver_options(CLI::Option_group& g, SceneArgs& a) {
    g.add_option("--solver", a.solver, "solver")
        ->check(CLI::IsMember({"jacobi", "gauss-seidel", "progressive", "direct"}))
        ->capture_default_str();
    g.add_option("--tolerance", a.tolerance, "relative residual at which the solver stops")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
}

}  // namespace

SceneGroups add_scene_options(CLI::App& app, SceneArgs& a) {
    app.add_option("scene", a.scene,
                   "an OBJ file (Kd: reflectance, Ke: emission), an RRV scene (.xml), a glTF file "
                   "(.gltf, .glb) or a built-in scene: " +
                       builtin_names())
        ->capture_default_str();
    SceneGroups g;
    g.scene = app.add_option_group("Scene and meshing",
                                   "how the scene's faces are cut into patches (the unknowns)");
    add_meshing_options(*g.scene, a);
    g.form_factors = app.add_option_group(
        "Form factors", "how F_ij, the share of patch i's light that reaches patch j, is computed");
    add_form_factor_options(*g.form_factors, a);
    g.solver = app.add_option_group("Solver", "how B = E + R F B is solved, and when it stops");
    add_solver_options(*g.solver, a);
    return g;
}

void add_camera_options(CLI::App& app, CameraArgs& a) {
    app.add_option("--camera", a.camera, "camera eye, target and up: ex,ey,ez,tx,ty,tz,ux,uy,uz")
        ->expected(9)
        ->delimiter(',');
    app.add_option("--fov", a.fov, "vertical field of view in degrees")
        ->check(CLI::Range(1.0, 179.0));
}

std::optional<int> parse(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help
        std::fprintf(stderr, "%s: error: %s (see --help)\n", app.get_name().c_str(), e.what());
        return 2;
    }
    return std::nullopt;
}

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

radiosity::SolveOptions solve_options(const SceneArgs& a, const radiosity::Mesh<Colour>& scene) {
    radiosity::SolveOptions o;
    o.form_factor = radiosity::parse_form_factor_kind(a.form_factor);
    o.solver = radiosity::parse_solver_kind(a.solver);
    const bool by_area = a.max_area > 0.0 || a.divide > 0.0;
    o.subdivision.max_edge = a.max_edge >= 0.0 ? a.max_edge
                             : by_area         ? 0.0
                                               : diagonal(bounding_box(scene)) / 30.0;
    o.subdivision.max_area = a.divide > 0.0 ? a.divide : a.max_area;
    o.subdivision.conforming = !(a.divide > 0.0);
    o.tolerance = a.tolerance;
    if (a.resolution > 0) o.hemicube.resolution = a.resolution;
    if (a.samples > 0) o.ray_cast.samples = a.samples;
    return o;
}

}  // namespace radiosity::cli
