#pragma once
/// @file program_options.hpp  The `radiosity` program's scene, meshing, form-factor, solver and
/// camera options, its scene loading and its default camera, as the viewer takes them: the same
/// names, checks and defaults as examples/radiosity_cli.cpp. This file and program_options.cpp
/// stand in for the program's own reusable pieces until the program is split into them; the
/// declarations follow that split (namespace radiosity::cli), so that swapping is a change of
/// includes.

#include <radiosity/mesh/mesh.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/solve.hpp>
#include <radiosity/spectrum.hpp>

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace radiosity::cli {

/// The programs solve in RGB.
using Colour = radiosity::Rgb;

/// What decides the solution: the scene, its meshing, the form-factor method and the solver.
struct SceneArgs {
    std::string scene = "cornell";  ///< a built-in scene's name or an OBJ, RRV or glTF file
    double max_edge = -1.0;  ///< negative: from the scene size (unless max_area or divide is set)
    double max_area = 0.0;   ///< > 0: RRV's `divide` rule, neighbours split alike
    double divide = 0.0;     ///< > 0: RRV's `divide` rule, each face by itself (T-junctions)
    std::string form_factor = "hemicube";  ///< analytic, hemicube or raycast
    int resolution = 0;                    ///< hemicube pixels; 0: the hemicube's default
    int samples = 0;                       ///< ray-cast sample pairs; 0: the method's default
    std::string solver = "gauss-seidel";   ///< jacobi, gauss-seidel, progressive or direct
    double tolerance = 1e-4;               ///< relative residual at which the solver stops
};

/// The option groups that add_scene_options made, for a program to add its own options to.
struct SceneGroups {
    CLI::Option_group* scene = nullptr;         ///< "Scene and meshing"
    CLI::Option_group* form_factors = nullptr;  ///< "Form factors"
    CLI::Option_group* solver = nullptr;        ///< "Solver"
};

/// Declares the positional scene and the groups "Scene and meshing" (--max-edge, --max-area,
/// --divide), "Form factors" (--form-factor, --resolution, --samples) and "Solver" (--solver,
/// --tolerance) on app, all filling a (whose values at the call are the defaults shown).
SceneGroups add_scene_options(CLI::App& app, SceneArgs& a);

/// Where the camera stands: empty camera and fov 0 keep the default camera.
struct CameraArgs {
    std::vector<double> camera;  ///< eye, target, up: 9 numbers; empty: the default camera
    double fov = 0.0;            ///< vertical field of view in degrees; 0: the default
};

/// Declares --camera and --fov on app (or on one of its option groups), filling a.
void add_camera_options(CLI::App& app, CameraArgs& a);

/// Parses the command line. Returns the exit status if the program is to stop now: 0 after
/// printing --help, 2 after a one-line error on stderr ("NAME: error: ... (see --help)");
/// nothing if it is to go on.
std::optional<int> parse(CLI::App& app, int argc, char** argv);

/// Loads a scene: a built-in name, else a file by its extension: RRV's XML (.xml), glTF (.gltf,
/// .glb) or OBJ (anything else). Throws radiosity::Error naming the scene if it is neither a
/// built-in name nor an existing file, or if the file is bad.
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

/// The default camera: for the Cornell box the published one (35 mm lens, 25 mm film), else
/// one with the same field of view that frames the sphere around the bounding box from its -z
/// side (the Cornell box's convention).
radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh);

/// The default camera with --camera's eye, target and up and --fov's angle where given.
radiosity::Camera chosen_camera(const CameraArgs& a, const std::string& scene,
                                const radiosity::Mesh<Colour>& mesh);

/// The library's options for a's scene, meshing, form factors and solver. Without --max-edge
/// the patches' edges are cut to 1/30 of the scene's bounding-box diagonal, unless the area
/// rule (--max-area, --divide) sizes them instead.
radiosity::SolveOptions solve_options(const SceneArgs& a, const radiosity::Mesh<Colour>& scene);

}  // namespace radiosity::cli
