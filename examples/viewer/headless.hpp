#pragma once
/// @file headless.hpp  The viewer without a window, for tests and documentation: the solve runs
/// to its end (or to --stop-after), then --pick prints the patch under each pixel with its
/// row's numbers, and --screenshot draws one frame (the chosen mode and camera, the last pick's
/// row if any, the panels with --ui) into a PNG. It still needs an OpenGL 3.3 context, so a
/// display: under CI, Xvfb with Mesa's software renderer.

#include "patches.hpp"
#include "view_args.hpp"

#include <radiosity/shading/camera.hpp>

namespace radiosity::view {

/// Runs the headless viewer; returns the exit status. Throws WindowError without a display,
/// radiosity::Error for a failed solve or an unwritable picture.
int run_headless(const ViewArgs& a, const Patches& patches, const radiosity::Camera& camera);

}  // namespace radiosity::view
