// The options turned into SolveOptions, and the solve with its progress bar and Ctrl-C
// (solve.hpp).
#include "cli/solve.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <cstdio>
#include <unistd.h>

namespace radiosity::cli {

namespace {

/// Set by Ctrl-C (SIGINT); the progress callback then asks the library to stop.
std::atomic<bool> interrupted{false};
extern "C" void on_interrupt(int) {
    interrupted = true;
}

}  // namespace

radiosity::SolveOptions solve_options(const SceneArgs& a, const radiosity::Mesh<Colour>& scene,
                                      bool sized_by_texels) {
    radiosity::SolveOptions o;
    o.form_factor = radiosity::parse_form_factor_kind(a.form_factor);
    o.solver = radiosity::parse_solver_kind(a.solver.empty() ? "gauss-seidel" : a.solver);
    o.hierarchical_when_too_big = a.solver.empty();
    if (a.link_error > 0.0) o.hierarchical.link_error = a.link_error;
    if (a.min_area > 0.0) o.hierarchical.min_area = a.min_area;
    if ((!a.checkpoint.empty() || !a.resume.empty()) && a.solver != "hierarchical")
        throw radiosity::Error(
            "--checkpoint and --resume are for --solver hierarchical (the "
            "dense solves keep no state worth saving)");
    o.hierarchical.checkpoint = {
        .file = a.checkpoint, .every_seconds = a.checkpoint_every, .resume = a.resume};
    const bool rrv_default = a.max_edge < 0.0 && a.max_area <= 0.0 && a.divide <= 0.0 &&
                             !sized_by_texels &&
                             std::filesystem::path(a.scene).extension() == ".xml";
    const double divide = rrv_default ? rrv_default_divide : a.divide;
    const bool by_area = a.max_area > 0.0 || divide > 0.0 || sized_by_texels;
    o.subdivision.max_edge = a.max_edge >= 0.0 ? a.max_edge
                             : by_area         ? 0.0
                                               : diagonal(bounding_box(scene)) / 30.0;
    o.subdivision.max_area = divide > 0.0 ? divide : a.max_area;
    o.subdivision.conforming = !(divide > 0.0);
    o.subdivision.cut_intersections = !a.no_cut;
    if (a.max_memory_gb > 0.0) o.max_matrix_bytes = static_cast<std::size_t>(a.max_memory_gb * 1e9);
    o.tolerance = a.tolerance;
    o.max_iterations = a.max_iterations;
    if (a.resolution > 0) o.hemicube.resolution = a.resolution;
    if (a.samples > 0) o.ray_cast.samples = a.samples;
    return o;
}

radiosity::LightmapOptions lightmap_options(const LightmapArgs& a) {
    radiosity::LightmapOptions o;
    o.unwrap.size = a.size;
    o.unwrap.texel_density = a.texel_density;
    o.unwrap.gutter = a.gutter;
    o.bake.dilation = a.gutter;  // fill each chart's own gutter, no further
    o.texels_per_patch = a.texels_per_patch;
    return o;
}

ProgressBar::ProgressBar(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}

bool ProgressBar::operator()(const radiosity::Progress& p) {
    if (interrupted) return false;
    if (quiet_) return true;
    const auto now = std::chrono::steady_clock::now();
    if (p.phase != phase_) start_ = now;
    if (tty_) {
        const double f = std::clamp(p.fraction, 0.0, 1.0);
        const int filled = static_cast<int>(std::lround(30.0 * f));
        std::fprintf(stderr, "\r%-13s [%s%s] %3.0f%%", std::string(p.phase).c_str(),
                     std::string(static_cast<std::size_t>(filled), '#').c_str(),
                     std::string(static_cast<std::size_t>(30 - filled), ' ').c_str(), 100.0 * f);
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

void ProgressBar::finish() const {
    if (!quiet_ && tty_ && !phase_.empty()) std::fputc('\n', stderr);
}

std::optional<Solution> solve_scene(const radiosity::Mesh<Colour>& scene, radiosity::SolveOptions o,
                                    const std::optional<radiosity::LightmapOptions>& lightmap,
                                    bool quiet) {
    ProgressBar bar(quiet);
    o.progress = [&bar](const radiosity::Progress& p) { return bar(p); };
    std::signal(SIGINT, on_interrupt);
    std::signal(SIGTERM, on_interrupt);  // a batch system's stop
    // mpirun kills its ranks at Ctrl-C, but passes SIGUSR1 on to every one of them: the way to
    // stop a distributed solve with a checkpoint.
    std::signal(SIGUSR1, on_interrupt);
    Solution s;
    try {
        if (lightmap) {  // patches follow the texels unless --max-edge says finer
            s.baked = radiosity::bake(scene, o, *lightmap);
            s.result = std::move(s.baked->solution);
        } else {
            s.result = radiosity::solve(scene, o);
        }
    } catch (const radiosity::Cancelled&) {
        bar.finish();
        return std::nullopt;
    }
    bar.finish();
    return s;
}

}  // namespace radiosity::cli
