#pragma once
/// @file solve.hpp  Solving as the radiosity programs do: the command line's options turned into
/// SolveOptions (with the default meshing rule), and a solve or lightmap bake that shows a
/// progress bar on stderr and stops cleanly on Ctrl-C.

#include "cli/options.hpp"
#include "cli/scene.hpp"

#include <radiosity/lightmap/lightmap.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solve.hpp>

#include <chrono>
#include <optional>
#include <string>

namespace radiosity::cli {

/// The library's options for a's scene, meshing, form factors and solver. With no meshing
/// option an RRV scene (.xml) is meshed as RRV meshes it (--divide 1: each triangle split 1 -> 4
/// until none is larger than 1, room3's 9,680 patches), and any other scene's patch edges are
/// cut to 1/30 of its bounding-box diagonal, unless a lightmap's texels (sized_by_texels) size
/// them instead. --max-memory sets the dense matrix's limit (SolveOptions::max_matrix_bytes).
radiosity::SolveOptions solve_options(const SceneArgs& a, const radiosity::Mesh<Colour>& scene,
                                      bool sized_by_texels = false);

/// RRV's own meshing rule, the default for its scenes: split until no patch is larger than
/// this area (RRV's `divide` default).
inline constexpr double rrv_default_divide = 1.0;

/// The library's lightmap options for --lightmap-size, --texel-density, --lightmap-gutter and
/// --texels-per-patch (dilation fills each chart's own gutter, no further).
radiosity::LightmapOptions lightmap_options(const LightmapArgs& a);

/// A progress bar on stderr: phase, percentage and an estimate of the time left, redrawn in
/// place on a terminal, one line per phase otherwise. It also relays Ctrl-C (see solve_scene):
/// returning false asks the library to stop.
class ProgressBar {
  public:
    /// quiet: draw nothing, only relay Ctrl-C.
    explicit ProgressBar(bool quiet);
    /// The progress callback (radiosity::ProgressCallback).
    bool operator()(const radiosity::Progress& p);
    /// Ends the bar's line.
    void finish() const;

  private:
    bool quiet_, tty_;
    std::string phase_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// A solution: the solved scene and, when a lightmap was baked, the bake (whose own solution
/// has been moved into `result`).
struct Solution {
    radiosity::SolveResult<Colour> result;
    std::optional<radiosity::BakeResult<Colour>> baked;
};

/// Solves the scene (or, given lightmap options, bakes it) with a ProgressBar as o.progress,
/// Ctrl-C asking it to stop (and SIGTERM, and SIGUSR1, which mpirun passes on to its ranks): a
/// solver stopped that way returns its report with `cancelled` set (the hierarchical one
/// writes its checkpoint first, if asked for one). Returns nothing if the stop came while the
/// form factors were computed or the links refined (nothing to show).
std::optional<Solution> solve_scene(const radiosity::Mesh<Colour>& scene, radiosity::SolveOptions o,
                                    const std::optional<radiosity::LightmapOptions>& lightmap,
                                    bool quiet);

}  // namespace radiosity::cli
