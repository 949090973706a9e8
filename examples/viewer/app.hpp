#pragma once
/// @file app.hpp  The interactive viewer: a window on the scene, the solve running on its worker
/// thread and drawn as it goes, the panels, the keys and the mouse (camera and picking).

#include "patches.hpp"
#include "view_args.hpp"

#include <radiosity/shading/camera.hpp>

namespace radiosity::view {

/// Opens the window and runs until it is closed; returns the exit status. Throws WindowError
/// when no window can be opened.
int run_interactive(const ViewArgs& a, const Patches& patches, const radiosity::Camera& home);

}  // namespace radiosity::view
