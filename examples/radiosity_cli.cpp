// radiosity: the command-line program. Solves a scene (an OBJ file or a built-in scene) by the
// radiosity method and writes a picture, a PLY mesh, glTF, a lightmap and CSV dumps. With no
// arguments it renders the built-in Cornell box into cornell_box.png. Errors: one line on stderr,
// exit status 1 (2 for a bad command line).

#include <radiosity/radiosity.hpp>

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using Colour = radiosity::Rgb;

/// Everything the command line can set.
struct Args {
    std::string scene = "cornell";
    std::string form_factor = "hemicube";
    std::string solver = "gauss-seidel";
    double max_edge = -1.0;  // negative: choose from the scene size (unless max_area is set)
    double max_area = 0.0;   // > 0: RRV's `divide` rule, neighbours split alike
    double divide = 0.0;     // > 0: RRV's `divide` rule, each face by itself (T-junctions)
    double tolerance = 1e-4;
    std::string image;
    int width = 512, height = 512;
    bool flat = false;
    double exposure = 0.0;
    int resolution = 0;  // 0: the hemicube's default
    int samples = 0;     // 0: the ray-cast method's default
    std::string ply, gltf, hdr, dump_form_factors, dump_patches, form_factors_text, rrv_out;
    std::vector<double> camera;  // eye, target, up: 9 numbers; empty: the default camera
    double fov = 0.0;            // vertical field of view in degrees; 0: the default
    bool quiet = false;
    bool ply_float = false;      // linear float colours in the PLY instead of 8-bit sRGB
    bool partial = false;        // on Ctrl-C during the solve, still write what was computed
    std::string lightmap;        // bake a lightmap into this picture (.hdr, .exr, .png)
    int lightmap_size = 256;     // 2.8k patches on the Cornell box: a bake of seconds
    double texel_density = 0.0;  // > 0: texels per scene unit instead of a fixed size
    int gutter = 2;
    double texels_per_patch = 4.0;
};

/// Set by Ctrl-C (SIGINT); the progress callback then asks the library to stop.
std::atomic<bool> interrupted{false};
extern "C" void on_interrupt(int) {
    interrupted = true;
}

/// A progress bar on stderr: phase, percentage and an estimate of the time left, redrawn in
/// place on a terminal, one line per phase otherwise. It also relays Ctrl-C: returning false
/// asks the library to stop.
class ProgressBar {
  public:
    explicit ProgressBar(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}

    bool operator()(const radiosity::Progress& p) {
        if (interrupted) return false;
        if (quiet_) return true;
        const auto now = std::chrono::steady_clock::now();
        if (p.phase != phase_) start_ = now;
        if (tty_) {
            const double f = std::clamp(p.fraction, 0.0, 1.0);
            const int filled = static_cast<int>(std::lround(30.0 * f));
            std::fprintf(stderr, "\r%-13s [%s%s] %3.0f%%", std::string(p.phase).c_str(),
                         std::string(static_cast<std::size_t>(filled), '#').c_str(),
                         std::string(static_cast<std::size_t>(30 - filled), ' ').c_str(),
                         100.0 * f);
            const double elapsed = std::chrono::duration<double>(now - start_).count();
            if (f > 0.02 && f < 1.0 && elapsed > 0.5)  // left = elapsed (1 - f) / f
                std::fprintf(stderr, " %5.0f s left", elapsed * (1.0 - f) / f);
            else
                std::fprintf(stderr, "             ");
            if (p.residual > 0.0) std::fprintf(stderr, " residual %.2e", p.residual);
            std::fflush(stderr);
        } else if (p.phase != phase_) {
            std::fprintf(stderr, "%s...\n", std::string(p.phase).c_str());
        }
        phase_ = p.phase;
        return true;
    }
    /// Ends the bar's line.
    void finish() const {
        if (!quiet_ && tty_ && !phase_.empty()) std::fputc('\n', stderr);
    }

  private:
    bool quiet_, tty_;
    std::string phase_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Loads the scene: a built-in name, an OBJ, RRV (.xml) or glTF (.gltf, .glb) file.
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

/// Diagonal of the scene's bounding box.
double scene_diagonal(const radiosity::Mesh<Colour>& mesh) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        lo = glm::min(lo, glm::dvec3(p[0], p[1], p[2]));
        hi = glm::max(hi, glm::dvec3(p[0], p[1], p[2]));
    }
    return glm::length(hi - lo);
}

/// The camera: the published one for the Cornell box, else one that frames the bounding box
/// from its -z side (the Cornell box's convention).
radiosity::Camera default_camera(const std::string& scene, const radiosity::Mesh<Colour>& mesh) {
    const double fov = 2.0 * std::atan(12.5 / 35.0) * 180.0 / M_PI;  // 25 mm film, 35 mm lens
    if (scene == "cornell")
        return {{278.0, 273.0, -800.0}, {278.0, 273.0, 0.0}, {0.0, 1.0, 0.0}, fov};
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        lo = glm::min(lo, glm::dvec3(p[0], p[1], p[2]));
        hi = glm::max(hi, glm::dvec3(p[0], p[1], p[2]));
    }
    const glm::dvec3 c = 0.5 * (lo + hi);
    const double radius = 0.5 * glm::length(hi - lo);
    const double distance = radius / std::sin(0.5 * fov * M_PI / 180.0);
    return {c - glm::dvec3(0.0, 0.0, distance), c, {0.0, 1.0, 0.0}, fov};
}

/// The camera from --camera and --fov where given, the default one otherwise.
radiosity::Camera chosen_camera(const Args& a, const radiosity::Mesh<Colour>& mesh) {
    radiosity::Camera c = default_camera(a.scene, mesh);
    if (!a.camera.empty()) {
        c.eye = {a.camera[0], a.camera[1], a.camera[2]};
        c.target = {a.camera[3], a.camera[4], a.camera[5]};
        c.up = {a.camera[6], a.camera[7], a.camera[8]};
    }
    if (a.fov > 0.0) c.fov_y_degrees = a.fov;
    return c;
}

/// The matrix as plain text for thermal-analysis tools: n, then the n areas, then n rows of n
/// view factors, whitespace-separated.
void write_form_factor_text(const std::string& path, const radiosity::DenseMatrix& F,
                            const radiosity::PatchTable& patches) {
    std::ofstream out(path);
    if (!out) throw radiosity::Error(path + ": cannot open for writing");
    char buf[32];
    out << "# radiosity view factors: n, then areas A_i, then rows F_ij (A_i F_ij = A_j F_ji)\n";
    out << F.size() << '\n';
    for (std::size_t i = 0; i < F.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.12g", patches.area(i));
        out << (i ? " " : "") << buf;
    }
    out << '\n';
    for (std::size_t i = 0; i < F.size(); ++i) {
        for (std::size_t j = 0; j < F.size(); ++j) {
            std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(F(i, j)));
            out << (j ? " " : "") << buf;
        }
        out << '\n';
    }
    if (!out) throw radiosity::Error(path + ": write failed");
}

void write_form_factors(const std::string& path, const radiosity::DenseMatrix& F) {
    std::ofstream out(path);
    if (!out) throw radiosity::Error(path + ": cannot open for writing");
    char buf[32];
    for (std::size_t i = 0; i < F.size(); ++i) {
        for (std::size_t j = 0; j < F.size(); ++j) {
            std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(F(i, j)));
            out << (j ? "," : "") << buf;
        }
        out << '\n';
    }
    if (!out) throw radiosity::Error(path + ": write failed");
}

void write_patches(const std::string& path, const radiosity::SolveResult<Colour>& r) {
    std::ofstream out(path);
    if (!out) throw radiosity::Error(path + ": cannot open for writing");
    out << "patch,area,cx,cy,cz,nx,ny,nz,E_r,E_g,E_b,R_r,R_g,R_b,B_r,B_g,B_b\n";
    char buf[64];
    auto num = [&](double x) {
        std::snprintf(buf, sizeof buf, ",%.9g", x);
        out << buf;
    };
    for (auto f : r.mesh.faces()) {
        const auto i = static_cast<std::size_t>(f.idx());
        const auto& d = r.mesh.data(f);
        out << i;
        num(r.patches.area(i));
        for (int k = 0; k < 3; ++k) num(r.patches.centroid(i)[k]);
        for (int k = 0; k < 3; ++k) num(r.patches.normal(i)[k]);
        for (const Colour* c : {&d.emission, &d.reflectance, &d.radiosity})
            for (std::size_t k = 0; k < 3; ++k) num(band(*c, k));
        out << '\n';
    }
    if (!out) throw radiosity::Error(path + ": write failed");
}

radiosity::LightmapOptions lightmap_options(const Args& a) {
    radiosity::LightmapOptions o;
    o.unwrap.size = a.lightmap_size;
    o.unwrap.texel_density = a.texel_density;
    o.unwrap.gutter = a.gutter;
    o.bake.dilation = a.gutter;  // fill each chart's own gutter, no further
    o.texels_per_patch = a.texels_per_patch;
    return o;
}

/// Writes the lightmap, and the glTF textured with it; the PNG and the glTF's texture use the
/// same exposure, chosen from the lightmap's texels.
void write_lightmap(const Args& a, const radiosity::BakeResult<Colour>& b,
                    const radiosity::ToneMapOptions& tone) {
    radiosity::write_image(b.lightmap.image, a.lightmap, tone);
    if (!a.gltf.empty())
        radiosity::write_gltf_lightmapped(b.shaded, b.lightmap.image, a.gltf,
                                          radiosity::exposure_scale(b.lightmap.image.pixels, tone));
    using radiosity::TexelState;
    if (!a.quiet)
        std::fprintf(stderr,
                     "lightmap %dx%d, %s UVs (%zu charts, %.4g texels per unit, patches cut to "
                     "%.4g units): %zu surface, %zu inside geometry, %zu gutter texels; unwrap "
                     "%.2f s, solve %.2f s, bake %.2f s; wrote %s\n",
                     b.atlas.width, b.atlas.height, b.generated_uvs ? "generated" : "the scene's",
                     b.atlas.charts, b.atlas.texel_density, b.patch_edge,
                     b.lightmap.count(TexelState::surface), b.lightmap.count(TexelState::inside),
                     b.lightmap.count(TexelState::dilated), b.unwrap_seconds, b.solve_seconds,
                     b.bake_seconds, a.lightmap.c_str());
}

int run(const Args& a) {
    const auto t0 = std::chrono::steady_clock::now();
    ProgressBar bar(a.quiet);
    const auto scene = load_scene(a.scene);
    if (!a.lightmap.empty()) radiosity::picture_format(a.lightmap);  // refuse a bad name now

    radiosity::SolveOptions o;
    o.form_factor = radiosity::parse_form_factor_kind(a.form_factor);
    o.solver = radiosity::parse_solver_kind(a.solver);
    // Without --max-edge: none where the area rule or a lightmap's texels size the patches.
    const bool by_area = a.max_area > 0.0 || a.divide > 0.0 || !a.lightmap.empty();
    o.subdivision.max_edge = a.max_edge >= 0.0 ? a.max_edge
                             : by_area         ? 0.0
                                               : scene_diagonal(scene) / 30.0;
    o.subdivision.max_area = a.divide > 0.0 ? a.divide : a.max_area;
    o.subdivision.conforming = !(a.divide > 0.0);
    o.tolerance = a.tolerance;
    if (a.resolution > 0) o.hemicube.resolution = a.resolution;
    if (a.samples > 0) o.ray_cast.samples = a.samples;
    o.keep_form_factors = !a.dump_form_factors.empty() || !a.form_factors_text.empty();
    o.ambient = a.partial;  // progressive shooting stopped early: show the unshot light too
    o.progress = [&bar](const radiosity::Progress& p) { return bar(p); };
    std::signal(SIGINT, on_interrupt);
    radiosity::SolveResult<Colour> result;
    std::optional<radiosity::BakeResult<Colour>> baked;
    try {
        if (!a.lightmap.empty()) {  // patches follow the texels unless --max-edge says finer
            baked = radiosity::bake(scene, o, lightmap_options(a));
            result = std::move(baked->solution);
        } else {
            result = radiosity::solve(scene, o);
        }
    } catch (const radiosity::Cancelled&) {
        bar.finish();
        std::fprintf(stderr,
                     "radiosity: interrupted while computing form factors; nothing written\n");
        return 130;
    }
    bar.finish();
    if (result.report.cancelled && !a.partial) {
        std::fprintf(stderr,
                     "radiosity: interrupted after %zu iterations (residual %.2e); nothing "
                     "written (--partial writes what was computed)\n",
                     result.report.iterations, result.report.residual);
        return 130;
    }

    if (!a.dump_form_factors.empty()) write_form_factors(a.dump_form_factors, *result.form_factors);
    if (!a.form_factors_text.empty())
        write_form_factor_text(a.form_factors_text, *result.form_factors, result.patches);
    if (!a.dump_patches.empty()) write_patches(a.dump_patches, result);

    // Without any output named, a picture: cornell_box.png for the Cornell box, else the
    // scene's name with .png (in the current folder).
    bool no_output = true;
    for (const std::string* o : {&a.image, &a.ply, &a.gltf, &a.hdr, &a.rrv_out, &a.lightmap,
                                 &a.dump_patches, &a.dump_form_factors, &a.form_factors_text})
        no_output = no_output && o->empty();
    const std::string image = !no_output ? a.image
                              : a.scene == "cornell"
                                  ? "cornell_box.png"
                                  : std::filesystem::path(a.scene).stem().string() + ".png";
    const radiosity::ShadedMesh shaded = baked    ? baked->shaded
                                         : a.flat ? radiosity::flat_shading(result.mesh)
                                                  : radiosity::smooth_shading(result.mesh);
    radiosity::ToneMapOptions tone;
    tone.stops = a.exposure;
    if (baked) write_lightmap(a, *baked, tone);
    if (!image.empty() || !a.hdr.empty()) {
        // Back faces culled: a closed room seen from outside shows its inside (a cut-away).
        const auto picture =
            radiosity::render(shaded, chosen_camera(a, result.mesh),
                              {.width = a.width, .height = a.height, .cull_back_faces = true});
        if (!image.empty()) radiosity::write_png(picture, image, tone);
        if (!a.hdr.empty()) radiosity::write_hdr(picture, a.hdr);
    }
    if (!a.rrv_out.empty()) radiosity::write_rrv(result.mesh, a.rrv_out);
    if (!a.gltf.empty() && !baked)
        radiosity::write_gltf(shaded, a.gltf, radiosity::exposure_scale(shaded.colours, tone));
    if (!a.ply.empty())
        radiosity::write_ply(
            shaded, a.ply, radiosity::exposure_scale(shaded.colours, tone),
            a.ply_float ? radiosity::PlyColours::linear_float : radiosity::PlyColours::srgb8);

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& r = result.report;
    std::fprintf(stderr,
                 "%zu patches; form factors (%s) %.2f s; %s: %zu iterations, residual %.2e, %s "
                 "in %.2f s; total %.2f s%s%s\n",
                 result.patches.size(), a.form_factor.c_str(), result.form_factor_seconds,
                 r.solver.c_str(), r.iterations, r.residual,
                 r.cancelled   ? "INTERRUPTED"
                 : r.converged ? "converged"
                               : "NOT converged",
                 r.seconds, seconds, image.empty() ? "" : "; wrote ", image.c_str());
    return r.cancelled ? 130 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    CLI::App app{
        "radiosity: diffuse global illumination by the radiosity method.\n"
        "With no arguments, renders the built-in Cornell box into cornell_box.png.",
        "radiosity"};
    app.failure_message(CLI::FailureMessage::simple);
    app.add_option(
           "scene", a.scene,
           "an OBJ file (Kd: reflectance, Ke: emission), an RRV scene (.xml), a glTF file "
           "(.gltf, .glb) or a built-in scene: " +
               [] {
                   std::string s;
                   for (const auto& n : radiosity::builtin_scene_names())
                       s += (s.empty() ? "" : ", ") + n;
                   return s;
               }())
        ->capture_default_str();
    app.add_option("--form-factor", a.form_factor, "form-factor method")
        ->check(CLI::IsMember({"analytic", "hemicube", "raycast"}))
        ->capture_default_str();
    app.add_option("--solver", a.solver, "solver")
        ->check(CLI::IsMember({"jacobi", "gauss-seidel", "progressive", "direct"}))
        ->capture_default_str();
    app.add_option("--max-edge", a.max_edge,
                   "subdivide patches to this edge length in scene units (0 keeps the input "
                   "faces; default: 1/30 of the scene's bounding-box diagonal)")
        ->check(CLI::NonNegativeNumber);
    auto* max_area =
        app.add_option("--max-area", a.max_area,
                       "subdivide patches until none is larger than this area, each split 1->4 "
                       "at its edge midpoints as RRV's `divide` does, and neighbours split alike "
                       "(no T-junctions); --max-edge then defaults to no limit")
            ->check(CLI::PositiveNumber);
    app.add_option("--divide", a.divide,
                   "subdivide exactly as RRV's `divide`: each face split 1->4 by itself until "
                   "none is larger than this area, leaving T-junctions where neighbours differ "
                   "(RRV's patches, to compare with its results)")
        ->check(CLI::PositiveNumber)
        ->excludes(max_area);
    app.add_option("--tolerance", a.tolerance,
                   "bound on the relative error of B, |B - B*| / |B*|, at which the solver stops")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--resolution", a.resolution, "hemicube resolution in pixels (default 128)")
        ->check(CLI::Range(8, 4096));
    app.add_option("--samples", a.samples, "ray-cast sample pairs per patch pair (default 16)")
        ->check(CLI::Range(1, 65536));
    app.add_option("--image", a.image,
                   "write a PNG picture (Cornell box camera, or one that frames the scene)");
    app.add_option("--width", a.width, "image width")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--height", a.height, "image height")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--exposure", a.exposure, "exposure compensation in stops")
        ->check(CLI::Range(-64.0, 64.0))
        ->capture_default_str();
    app.add_flag("--flat", a.flat, "flat shading (one colour per patch) instead of smooth");
    app.add_option("--ply", a.ply, "write the shaded mesh as PLY with 8-bit sRGB vertex colours");
    app.add_flag("--ply-float", a.ply_float,
                 "PLY colours as linear floats (after exposure, unclamped) instead of 8-bit sRGB");
    app.add_option("--dump-form-factors", a.dump_form_factors, "write F as CSV: line i holds F_ij");
    app.add_option("--form-factors-text", a.form_factors_text,
                   "write F as plain text for thermal tools: n, the areas, then the rows");
    app.add_option("--gltf", a.gltf,
                   "write the shaded mesh as glTF 2.0 with vertex colours, or with --lightmap "
                   "textured with the lightmap (.glb: one binary file)");
    app.add_option("--lightmap", a.lightmap,
                   "bake a lightmap into this picture: .hdr or .exr (linear radiance) or .png "
                   "(8-bit sRGB); uses the scene's UVs (OBJ vt) or makes them");
    app.add_option("--lightmap-size", a.lightmap_size, "lightmap width and height in texels")
        ->check(CLI::Range(8, 16384))
        ->capture_default_str();
    app.add_option("--texel-density", a.texel_density,
                   "texels per scene unit (the lightmap size then follows from it)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--lightmap-gutter", a.gutter, "empty texels around each chart, dilated")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    app.add_option("--texels-per-patch", a.texels_per_patch,
                   "longest patch edge in lightmap texels (0: use --max-edge)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--rrv-out", a.rrv_out,
                   "write the solved scene in RRV's XML format, a radiosity per triangle");
    app.add_option("--hdr", a.hdr, "write a linear Radiance HDR picture (radiance B / pi)");
    app.add_option("--camera", a.camera, "camera eye, target and up: ex,ey,ez,tx,ty,tz,ux,uy,uz")
        ->expected(9)
        ->delimiter(',');
    app.add_option("--fov", a.fov, "vertical field of view in degrees")
        ->check(CLI::Range(1.0, 179.0));
    app.add_option("--dump-patches", a.dump_patches,
                   "write patches as CSV: patch,area,cx,cy,cz,nx,ny,nz,E_*,R_*,B_*");
    app.add_flag("--quiet", a.quiet, "no progress bar");
    app.add_flag("--partial", a.partial,
                 "on Ctrl-C during the solve, still write the outputs from what was computed");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help
        std::fprintf(stderr, "radiosity: error: %s (see --help)\n", e.what());
        return 2;
    }
    try {
        return run(a);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "radiosity: error: %s\n", e.what());
        return 1;
    }
}
