#pragma once
/// @file view_args.hpp  The viewer's command line: the `radiosity` program's scene, meshing,
/// form-factor, solver and camera options (program_options.hpp: the same names, checks and
/// defaults, but for the solver, which is progressive shooting here, the one to watch), the
/// picture's size and exposure as the program has them, and the viewer's own: the starting mode,
/// headless pictures and picks, and the live solve's settings.

#include "program_options.hpp"
#include "view_settings.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace radiosity::view {

/// Everything the viewer's command line sets.
struct ViewArgs {
    radiosity::cli::SceneArgs scene;        ///< scene, meshing, form factors, solver
    radiosity::cli::CameraArgs camera;      ///< --camera, --fov
    int width = 512, height = 512;          ///< picture size (--screenshot, --pick)
    bool size_given = false;                ///< --width or --height given: the window's size too
    double exposure = 0.0;                  ///< exposure compensation in stops
    std::string mode = "smooth";            ///< wireframe, flat, smooth, reflectance, emission
    std::string screenshot;                 ///< write one frame to this PNG and exit
    std::vector<std::array<int, 2>> picks;  ///< pixels whose patch and row to print, then exit
    bool ambient = false;                   ///< show shooting's ambient term
    bool ui = false;                        ///< headless pictures with the panels
    std::size_t stop_after = 0;             ///< pause the solve after this many shots or sweeps
    std::size_t batch = 0;                  ///< shots per picture update; 0: n / 100
    bool paused = false;                    ///< start with the solve paused
    bool quiet = false;                     ///< nothing on stderr but errors

    /// Whether the viewer draws pictures and exits instead of opening a window.
    bool headless() const { return !screenshot.empty() || !picks.empty(); }
};

/// Parses the command line into a. Returns the exit status if the viewer is to stop now (0
/// after --help, 2 after a one-line error), nothing if it is to go on.
std::optional<int> parse_view_args(int argc, char** argv, ViewArgs& a);

/// The solver that --solver names.
radiosity::SolverKind chosen_solver(const ViewArgs& a);

/// The view settings that the command line starts with.
ViewSettings initial_settings(const ViewArgs& a);

}  // namespace radiosity::view
