#pragma once
/// @file options.hpp  The command line of the radiosity programs, as CLI11 option groups: what
/// each group sets is a plain struct with defaults, and an add_*_options function declares the
/// group's options on a CLI::App and fills that struct when it parses. The scene, meshing,
/// form-factor, solver and camera groups are shared by every program that solves a scene (the
/// `radiosity` program, a viewer); pictures, exports and lightmaps are the `radiosity` program's.

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace radiosity::cli {

/// What decides the solution: the scene, its meshing, the form-factor method and the solver.
struct SceneArgs {
    std::string scene = "cornell";  ///< a built-in scene's name or an OBJ, RRV or glTF file
    double max_edge = -1.0;   ///< negative: from the scene size (unless max_area or divide is set)
    double max_area = 0.0;    ///< > 0: RRV's `divide` rule, neighbours split alike
    double divide = 0.0;      ///< > 0: RRV's `divide` rule, each face by itself (T-junctions)
    std::string unit;         ///< the file's length unit (m, cm, mm, in, ft or metres); "": its own
    bool flip_faces = false;  ///< turn every face round (a room modelled with faces pointing out)
    bool two_sided = false;   ///< every face also shines from its back (twice the patches)
    bool no_cut = false;      ///< leave faces that cross others uncut (intersect.hpp)
    std::string form_factor = "hemicube";  ///< analytic, hemicube or raycast
    int resolution = 0;                    ///< hemicube pixels; 0: the hemicube's default
    int samples = 0;                       ///< ray-cast sample pairs; 0: the method's default
    double max_memory_gb = 0.0;  ///< largest dense matrix in GB; 0: half the physical memory
    /// jacobi, gauss-seidel, progressive, direct or hierarchical; empty: not named (then
    /// gauss-seidel, or hierarchical where the dense matrix would pass --max-memory)
    std::string solver;
    double link_error = 0.0;  ///< hierarchical: BF threshold per emitted power; 0: its default
    double min_area = 0.0;    ///< hierarchical: smallest element; 0: from the meshing options
    std::string checkpoint;   ///< hierarchical: checkpoint file; empty: none
    double checkpoint_every = 60.0;  ///< seconds between checkpoints
    std::string resume;              ///< hierarchical: checkpoint to continue from
    double tolerance = 1e-4;         ///< relative residual at which the solver stops
    std::size_t max_iterations = 0;  ///< the solver's iteration guard; 0: its default
};

/// The option groups that add_scene_options made, for a program to add its own options to.
struct SceneGroups {
    CLI::Option_group* scene = nullptr;         ///< "Scene and meshing"
    CLI::Option_group* form_factors = nullptr;  ///< "Form factors"
    CLI::Option_group* solver = nullptr;        ///< "Solver"
};

/// Declares the positional scene on app and the groups "Scene and meshing" (--max-edge,
/// --max-area, --divide, --unit, --flip-faces, --two-sided), "Form factors" (--form-factor,
/// --resolution, --samples, --max-memory) and "Solver"
/// (--solver, --tolerance, --max-iterations, --link-error, --min-area), all filling a.
SceneGroups add_scene_options(CLI::App& app, SceneArgs& a);

/// Declares --checkpoint, --checkpoint-every and --resume (the hierarchical solve's
/// checkpoints; the `radiosity` program's, not the viewer's) on a group, filling a.
void add_checkpoint_options(CLI::Option_group& g, SceneArgs& a);

/// Where the camera stands: empty camera and fov 0 keep the default camera (scene.hpp).
struct CameraArgs {
    std::vector<double> camera;  ///< eye, target, up: 9 numbers; empty: the default camera
    double fov = 0.0;            ///< vertical field of view in degrees; 0: the default
};

/// Declares --camera and --fov on app (or on one of its option groups), filling a.
void add_camera_options(CLI::App& app, CameraArgs& a);

/// The picture: file, size, camera, shading and exposure (the last two colour the exports too).
struct PictureArgs {
    std::string image;  ///< PNG; empty: none, unless no output at all is named (outputs.hpp)
    std::string hdr;    ///< Radiance HDR
    int width = 512, height = 512;  ///< picture size in pixels
    CameraArgs camera;              ///< where the picture is taken from
    bool flat = false;              ///< one colour per patch instead of smooth shading
    double exposure = 0.0;          ///< exposure compensation in stops
};

/// The solved scene written for other tools: meshes, RRV's XML and tables of numbers.
struct ExportArgs {
    std::string ply;                ///< the shaded mesh as PLY
    bool ply_float = false;         ///< linear float colours in the PLY instead of 8-bit sRGB
    std::string gltf;               ///< the shaded mesh as glTF (textured with a baked lightmap)
    std::string rrv_out;            ///< the solved scene in RRV's XML
    std::string dump_form_factors;  ///< F as CSV
    std::string form_factors_text;  ///< F as plain text for thermal tools
    std::string dump_patches;       ///< the patches (area, centroid, normal, E, R, B) as CSV
};

/// A lightmap bake: the picture it goes into and the atlas's size, density and gutter.
struct LightmapArgs {
    std::string path;  ///< .hdr, .exr or .png; empty: no bake
    int size = 256;    ///< width and height in texels (the Cornell box: 2.8k patches, seconds)
    double texel_density = 0.0;     ///< > 0: texels per scene unit instead of a fixed size
    int gutter = 2;                 ///< empty texels around each chart, filled by dilation
    double texels_per_patch = 4.0;  ///< longest patch edge in texels (0: the meshing options)
};

/// Declares how a picture of the solution is taken: --width, --height, --camera, --fov, --flat
/// and --exposure, on app or one of its option groups, filling those fields of a (not image or
/// hdr). The `radiosity` program's pictures and the viewer's both take them.
void add_view_options(CLI::App& app, PictureArgs& a);

/// Everything the `radiosity` program writes.
struct OutputArgs {
    PictureArgs picture;
    ExportArgs exports;
    LightmapArgs lightmap;
};

/// Declares the groups "Pictures", "Exports" and "Lightmaps" on app, filling a.
void add_output_options(CLI::App& app, OutputArgs& a);

/// Parses the command line (--help sets each option group apart by a blank line, so the groups
/// read as sections). Returns the exit status if the program is to stop now: 0 after
/// printing --help, 2 after a one-line error on stderr ("NAME: error: ... (see --help)");
/// nothing if it is to go on.
std::optional<int> parse(CLI::App& app, int argc, char** argv);

}  // namespace radiosity::cli
