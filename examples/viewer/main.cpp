// radiosity-view: the interactive viewer. Solves a scene (the `radiosity` program's scene,
// meshing, form-factor and solver options) on a worker thread and shows the light as it spreads,
// in RRV's modes and more; a click on a patch shows its form-factor row and its hemicube. With
// --screenshot or --pick it draws off screen and exits. Errors: one line on stderr, exit status
// 1 (2 for a bad command line), also when no window can be opened.

#include "app.hpp"
#include "headless.hpp"
#include "patches.hpp"
#include "cli/scene.hpp"
#include "cli/solve.hpp"
#include "view_args.hpp"
#include "window.hpp"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    using namespace radiosity::view;
    ViewArgs a;
    if (auto status = parse_view_args(argc, argv, a)) return *status;
    try {
        const auto scene = radiosity::cli::load_scene(a.scene.scene);
        const Patches patches(scene, radiosity::cli::solve_options(a.scene, scene));
        const radiosity::Camera home =
            radiosity::cli::chosen_camera(a.picture.camera, a.scene.scene, scene);
        return a.headless() ? run_headless(a, patches, home) : run_interactive(a, patches, home);
    } catch (const WindowError& e) {
        std::fprintf(stderr, "radiosity-view: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "radiosity-view: error: %s\n", e.what());
        return 1;
    }
}
