// The command line's option groups (options.hpp): each option's name, check and help text.
#include "cli/options.hpp"

#include <radiosity/io/scenes.hpp>

#include <cstdio>

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
                 "faces; default: 1/30 of the scene's bounding-box diagonal, or for an RRV scene "
                 "RRV's own rule, --divide 1)")
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
    g.add_option("--unit", a.unit,
                 "the scene file's length unit: m, cm, mm, in, ft or metres per unit (default: "
                 "the scene's own; metres for files, which do not say; glTF is written in metres)");
    g.add_flag("--flip-faces", a.flip_faces,
               "turn every face round: for a closed room modelled with its faces pointing out "
               "(patches shine from their front only); costs nothing");
    g.add_flag("--no-cut", a.no_cut,
               "do not cut faces where other faces cross them (by default they are cut, so that "
               "no patch straddles another surface, and the pieces inside closed solids are left "
               "out)");
    g.add_flag("--two-sided", a.two_sided,
               "every face also shines and receives on its back: twice the patches, four times "
               "the matrix's memory and form-factor time");
}

void add_form_factor_options(CLI::Option_group& g, SceneArgs& a) {
    g.add_option("--form-factor", a.form_factor, "form-factor method")
        ->check(CLI::IsMember({"analytic", "hemicube", "raycast"}))
        ->capture_default_str();
    g.add_option("--resolution", a.resolution, "hemicube resolution in pixels (default 128)")
        ->check(CLI::Range(8, 4096));
    g.add_option("--samples", a.samples,
                 "fewest ray-cast rays per patch pair that may be blocked (default 16)")
        ->check(CLI::Range(1, 65536));
    g.add_option("--max-memory", a.max_memory_gb,
                 "largest dense form-factor matrix (4 n^2 bytes) to allocate, in GB; larger "
                 "runs are refused before they start (default: half the physical memory)")
        ->check(CLI::PositiveNumber);
}

void add_solver_options(CLI::Option_group& g, SceneArgs& a) {
    g.add_option("--solver", a.solver,
                 "solver (default gauss-seidel; hierarchical, by itself, where the dense matrix "
                 "would pass --max-memory): the dense ones over the n x n form factors, or "
                 "hierarchical radiosity with clustering, no matrix, for large scenes")
        ->check(CLI::IsMember({"jacobi", "gauss-seidel", "progressive", "direct", "hierarchical"}));
    g.add_option("--tolerance", a.tolerance,
                 "bound on the relative error of B, |B - B*| / |B*|, at which the solver stops")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    g.add_option("--max-iterations", a.max_iterations,
                 "stop after this many sweeps (shots for progressive) even if not converged; "
                 "the program then warns and exits with status 3 (default: the solver's guard)")
        ->check(CLI::PositiveNumber);
    g.add_option("--link-error", a.link_error,
                 "hierarchical: refine a link while it would move more than this share of the "
                 "emitted power (default 1e-4; smaller is finer and slower)")
        ->check(CLI::PositiveNumber);
    g.add_option("--min-area", a.min_area,
                 "hierarchical: split no element into pieces smaller than this area (default: a "
                 "quarter of the meshing's patch size, --divide or --max-area, or of --max-edge "
                 "squared)")
        ->check(CLI::PositiveNumber);
}

void add_picture_options(CLI::Option_group& g, PictureArgs& a) {
    g.add_option("--image", a.image,
                 "write a PNG picture (the Cornell box's camera; inside a closed room, one looking "
                 "across it; else one that frames the scene)");
    g.add_option("--hdr", a.hdr, "write a linear Radiance HDR picture (radiance B / pi)");
    add_view_options(g, a);
}

void add_export_options(CLI::Option_group& g, ExportArgs& a) {
    g.add_option("--ply", a.ply, "write the shaded mesh as PLY with 8-bit sRGB vertex colours");
    g.add_flag("--ply-float", a.ply_float,
               "PLY colours as linear floats (after exposure, unclamped) instead of 8-bit sRGB");
    g.add_option("--gltf", a.gltf,
                 "write the shaded mesh as glTF 2.0 with vertex colours, or with --lightmap "
                 "textured with the lightmap (.glb: one binary file)");
    g.add_option("--rrv-out", a.rrv_out,
                 "write the solved scene in RRV's XML format, a radiosity per triangle");
    g.add_option("--dump-form-factors", a.dump_form_factors, "write F as CSV: line i holds F_ij");
    g.add_option("--form-factors-text", a.form_factors_text,
                 "write F as plain text for thermal tools: n, the areas, then the rows");
    g.add_option("--dump-patches", a.dump_patches,
                 "write patches as CSV: patch,area,cx,cy,cz,nx,ny,nz,E_*,R_*,B_*");
}

void add_lightmap_options(CLI::Option_group& g, LightmapArgs& a) {
    g.add_option("--lightmap", a.path,
                 "bake a lightmap into this picture: .hdr or .exr (linear radiance) or .png "
                 "(8-bit sRGB); uses the scene's UVs (OBJ vt) or makes them");
    g.add_option("--lightmap-size", a.size, "lightmap width and height in texels")
        ->check(CLI::Range(8, 16384))
        ->capture_default_str();
    g.add_option("--texel-density", a.texel_density,
                 "texels per scene unit (the lightmap size then follows from it)")
        ->check(CLI::NonNegativeNumber);
    g.add_option("--lightmap-gutter", a.gutter, "empty texels around each chart, dilated")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    g.add_option("--texels-per-patch", a.texels_per_patch,
                 "longest patch edge in lightmap texels (0: use --max-edge)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
}

/// CLI11's help layout with a blank line before each option group.
class GroupsApart : public CLI::Formatter {
  public:
    std::string make_expanded(const CLI::App* sub) const override {
        return "\n" + CLI::Formatter::make_expanded(sub);
    }
};

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

void add_checkpoint_options(CLI::Option_group& g, SceneArgs& a) {
    g.add_option("--checkpoint", a.checkpoint,
                 "hierarchical: write the solve's state to this file now and then and at Ctrl-C "
                 "(atomically: a crash leaves the last good one), for --resume");
    g.add_option("--checkpoint-every", a.checkpoint_every,
                 "seconds between two checkpoints (0: after every refinement round and sweep)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    g.add_option("--resume", a.resume,
                 "hierarchical: continue from this checkpoint (same scene and options) to the "
                 "result an uninterrupted run gives")
        ->check(CLI::ExistingFile);
}

void add_camera_options(CLI::App& app, CameraArgs& a) {
    app.add_option("--camera", a.camera, "camera eye, target and up: ex,ey,ez,tx,ty,tz,ux,uy,uz")
        ->expected(9)
        ->delimiter(',');
    app.add_option("--fov", a.fov, "vertical field of view in degrees")
        ->check(CLI::Range(1.0, 179.0));
}

void add_view_options(CLI::App& app, PictureArgs& a) {
    app.add_option("--width", a.width, "image width")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--height", a.height, "image height")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    add_camera_options(app, a.camera);
    app.add_flag("--flat", a.flat, "flat shading (one colour per patch) instead of smooth");
    app.add_option("--exposure", a.exposure, "exposure compensation in stops")
        ->check(CLI::Range(-64.0, 64.0))
        ->capture_default_str();
}

void add_output_options(CLI::App& app, OutputArgs& a) {
    add_picture_options(
        *app.add_option_group("Pictures",
                              "the rendered view of the solution; --flat and --exposure colour "
                              "the exports too"),
        a.picture);
    add_export_options(*app.add_option_group("Exports",
                                             "the solution for other tools: shaded meshes, "
                                             "RRV's scene format, the matrix and the patches"),
                       a.exports);
    add_lightmap_options(*app.add_option_group("Lightmaps",
                                               "the solution baked into a texture for game "
                                               "engines, with UVs made or taken from the scene"),
                         a.lightmap);
}

std::optional<int> parse(CLI::App& app, int argc, char** argv) {
    app.formatter(std::make_shared<GroupsApart>());
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help
        std::fprintf(stderr, "%s: error: %s (see --help)\n", app.get_name().c_str(), e.what());
        return 2;
    }
    return std::nullopt;
}

}  // namespace radiosity::cli
