// radiosity: the command-line program. Solves a scene (an OBJ, RRV or glTF file or a built-in
// scene) by the radiosity method and writes a picture, a PLY mesh, glTF, a lightmap and CSV
// dumps. With no arguments it renders the built-in Cornell box into cornell_box.png. Errors: one
// line on stderr, exit status 1 (2 for a bad command line, 130 after Ctrl-C). A solver that
// stopped short of its tolerance (its iteration guard) gives a warning and exit status 3, the
// outputs still written (cli::not_converged_status).
//
// Its jobs live beside it: options.hpp (the command line), scene.hpp (loading, the camera),
// solve.hpp (options to SolveOptions, the progress bar, Ctrl-C) and outputs.hpp (what it
// writes); this file only runs them in order.

#include "cli/options.hpp"
#include "cli/outputs.hpp"
#include "cli/scene.hpp"
#include "cli/solve.hpp"

#include <chrono>
#include <cmath>
#include <string>
#include <cstdio>
#include <exception>
#include <optional>

namespace {

namespace cli = radiosity::cli;

/// Everything the command line can set.
struct Args {
    cli::SceneArgs scene;
    cli::OutputArgs out;
    bool quiet = false;    // no progress bar
    bool partial = false;  // on Ctrl-C during the solve, still write what was computed
};

int run(const Args& a) {
    const auto t0 = std::chrono::steady_clock::now();
    const cli::LoadedScene loaded = cli::load_scene(a.scene);
    const auto& scene = loaded.mesh;
    cli::check_outputs(a.out);
    const auto& lightmap = a.out.lightmap.path;
    radiosity::SolveOptions o = cli::solve_options(a.scene, scene, !lightmap.empty());
    const auto& e = a.out.exports;
    o.keep_form_factors = !e.dump_form_factors.empty() || !e.form_factors_text.empty();
    o.ambient = a.partial;  // progressive shooting stopped early: show the unshot light too
    const auto solved = cli::solve_scene(
        scene, o,
        lightmap.empty() ? std::nullopt : std::optional(cli::lightmap_options(a.out.lightmap)),
        a.quiet);
    if (!solved) {
        std::fprintf(stderr,
                     "radiosity: interrupted while computing form factors; nothing written\n");
        return 130;
    }
    for (const std::string& line : solved->result.meshing.lines())
        std::fprintf(stderr, "radiosity: %s\n", line.c_str());
    if (solved->result.chose_hierarchical)
        std::fprintf(stderr,
                     "radiosity: the dense form-factor matrix would pass the memory limit "
                     "(--max-memory), so the scene was solved by hierarchical radiosity (no "
                     "matrix); name a --solver to choose yourself\n");
    const auto& r = solved->result.report;
    if (r.cancelled && !a.partial) {
        std::fprintf(stderr,
                     "radiosity: interrupted after %zu iterations (residual %.2e); nothing "
                     "written (--partial writes what was computed)\n",
                     r.iterations, r.residual);
        return 130;
    }
    const auto files = cli::write_all_outputs(*solved, a.scene.scene, a.out, loaded.info, a.quiet);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cli::print_summary(solved->result, a.scene.form_factor, seconds, files);
    if (r.cancelled) return 130;
    if (!r.converged) {
        cli::warn_not_converged(r, a.scene.tolerance);
        return cli::not_converged_status;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    CLI::App app{
        "radiosity: diffuse global illumination by the radiosity method.\n"
        "With no arguments, renders the built-in Cornell box into cornell_box.png.",
        "radiosity"};
    app.failure_message(CLI::FailureMessage::simple);
    cli::add_scene_options(app, a.scene);
    cli::add_output_options(app, a.out);
    app.add_flag("--quiet", a.quiet, "no progress bar");
    app.add_flag("--partial", a.partial,
                 "on Ctrl-C during the solve, still write the outputs from what was computed");
    if (const auto status = cli::parse(app, argc, argv)) return *status;
    try {
        return run(a);
    } catch (const radiosity::MemoryLimitError& e) {
        std::fprintf(stderr,
                     "radiosity: error: %zu patches need a dense form-factor matrix of %.3g GB, "
                     "more than the limit of %.3g GB%s; use fewer patches (a longer --max-edge, "
                     "a larger --max-area or --divide: the matrix shrinks with the square of the "
                     "patch count), --solver hierarchical or progressive (no matrix), or raise "
                     "the limit with --max-memory GB\n",
                     e.patches, e.bytes_needed / 1e9, double(e.limit_bytes) / 1e9,
                     e.estimated_seconds >= 0.0
                         ? (" (and about " + std::to_string(std::lround(e.estimated_seconds)) +
                            " s of form factors on one core)")
                               .c_str()
                         : "");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "radiosity: error: %s\n", e.what());
        return 1;
    }
}
