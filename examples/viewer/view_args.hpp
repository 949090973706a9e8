#pragma once
/// @file view_args.hpp  The viewer's command line: the `radiosity` program's scene, meshing,
/// form-factor and solver options and its picture's size, camera, shading and exposure, declared
/// by the program's own functions (examples/cli/options.hpp: one definition of each option;
/// the solver defaults to progressive shooting here, the one to watch), and the viewer's own: the
/// starting mode, headless pictures and picks, and the live solve's settings.

#include "cli/options.hpp"
#include "view_settings.hpp"

#include <radiosity/solve.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace radiosity::view {

/// Everything the viewer's command line sets.
struct ViewArgs {
    radiosity::cli::SceneArgs scene;      ///< scene, meshing, form factors, solver
    radiosity::cli::PictureArgs picture;  ///< size (--screenshot, --pick), camera, --flat, exposure
                                          ///< (image and hdr are not declared here)
    bool size_given = false;              ///< --width or --height given: the window's size too
    std::string mode = "smooth";          ///< wireframe, flat, smooth, reflectance, emission
    std::string screenshot;               ///< write one frame to this PNG and exit
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
