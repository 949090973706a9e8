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
//
// Built with MPI (-DRADIOSITY_WITH_MPI=ON) it runs under `mpirun -np N`: every rank loads the
// scene and takes part in the hierarchical solve (distributed/mpi.hpp); rank 0 alone prints
// progress and writes the outputs. An error on any rank ends the whole job (MPI_Abort).

#include "cli/options.hpp"
#include "cli/outputs.hpp"
#include "cli/scene.hpp"
#include "cli/solve.hpp"

#if defined(RADIOSITY_WITH_MPI)
#include <radiosity/distributed/mpi.hpp>
#endif
#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif

#include <chrono>
#include <cmath>
#include <string>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
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

/// The processes of this run: one, or the ranks of an mpirun.
struct Ranks {
    radiosity::Communicator* comm = nullptr;  // null: one process
    int rank = 0, size = 1;
};

/// The exit status a solve's report gives (as rank 0's outputs end with it).
int status_of(const radiosity::Report& r) {
    if (r.cancelled) return 130;
    return r.converged ? 0 : cli::not_converged_status;
}

/// The message after Ctrl-C: where the checkpoint is, if one was asked for.
std::string checkpoint_note(const cli::SceneArgs& s) {
    return s.checkpoint.empty() ? ""
                                : "; the checkpoint " + s.checkpoint +
                                      " holds the state (--resume " + s.checkpoint + " continues)";
}

int run(const Args& a, const Ranks& ranks) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool first = ranks.rank == 0;
    const cli::LoadedScene loaded = cli::load_scene(a.scene);
    const auto& scene = loaded.mesh;
    cli::check_outputs(a.out);
    const auto& lightmap = a.out.lightmap.path;
    radiosity::SolveOptions o = cli::solve_options(a.scene, scene, !lightmap.empty());
    if (ranks.size > 1 && o.solver != radiosity::SolverKind::hierarchical)
        throw radiosity::Error("with " + std::to_string(ranks.size) +
                               " ranks, name --solver hierarchical: it is the solve that is "
                               "spread over them (run the dense solvers as one process)");
    o.hierarchical.communicator = ranks.comm;
    const auto& e = a.out.exports;
    o.keep_form_factors = !e.dump_form_factors.empty() || !e.form_factors_text.empty();
    o.ambient = a.partial;  // progressive shooting stopped early: show the unshot light too
    const auto solved = cli::solve_scene(
        scene, o,
        lightmap.empty() ? std::nullopt : std::optional(cli::lightmap_options(a.out.lightmap)),
        a.quiet || !first);
    if (!solved) {
        if (first)
            std::fprintf(stderr, "radiosity: interrupted while %s; nothing written%s\n",
                         o.solver == radiosity::SolverKind::hierarchical ? "refining links"
                                                                         : "computing form factors",
                         checkpoint_note(a.scene).c_str());
        return 130;
    }
    if (!first) return status_of(solved->result.report);  // rank 0 writes and tells
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
                     "written (--partial writes what was computed)%s\n",
                     r.iterations, r.residual, checkpoint_note(a.scene).c_str());
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
    cli::add_checkpoint_options(*cli::add_scene_options(app, a.scene).solver, a.scene);
    cli::add_output_options(app, a.out);
    app.add_flag("--quiet", a.quiet, "no progress bar");
    app.add_flag("--partial", a.partial,
                 "on Ctrl-C during the solve, still write the outputs from what was computed");
    if (const auto status = cli::parse(app, argc, argv)) return *status;
    Ranks ranks;
#if defined(RADIOSITY_WITH_MPI)
    // Under mpirun, one rank of the job; run on its own, one process without MPI (the same
    // result, bit for bit, without the runtime's start-up).
    std::optional<radiosity::MpiSession> session;
    std::optional<radiosity::MpiCommunicator> world;
    if (radiosity::MpiSession::launched()) {
        session.emplace(argc, argv);
        world.emplace();
        ranks = {&*world, world->rank(), world->size()};
#if defined(RADIOSITY_WITH_OPENMP)
        // The ranks on one machine share its cores, unless OMP_NUM_THREADS says otherwise.
        if (std::getenv("OMP_NUM_THREADS") == nullptr)
            omp_set_num_threads(std::max(1, omp_get_num_procs() / session->ranks_on_this_node()));
#endif
    }
#endif
    try {
        return run(a, ranks);
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
        if (ranks.size > 1)
            std::fprintf(stderr, "radiosity: error (rank %d of %d): %s\n", ranks.rank, ranks.size,
                         e.what());
        else
            std::fprintf(stderr, "radiosity: error: %s\n", e.what());
#if defined(RADIOSITY_WITH_MPI)
        if (ranks.size > 1) radiosity::MpiSession::abort(1);  // the others may be waiting on us
#endif
        return 1;
    }
}
