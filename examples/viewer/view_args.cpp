// The viewer's command line (view_args.hpp).
#include "view_args.hpp"

#include <cstdio>
#include <filesystem>
#include <regex>

namespace radiosity::view {

namespace {
/// "X,Y" as two non-negative integers.
std::optional<std::array<int, 2>> parse_pixel(const std::string& s) {
    static const std::regex pixel(R"(\s*(\d{1,5})\s*,\s*(\d{1,5})\s*)");
    std::smatch m;
    if (!std::regex_match(s, m, pixel)) return std::nullopt;
    return std::array<int, 2>{std::stoi(m[1]), std::stoi(m[2])};
}
}  // namespace

namespace {

/// What the command line gives before it is checked: the --pick strings.
struct Raw {
    std::vector<std::string> picks;
};

/// The viewer's own option groups: the picture (the program's --width, --height, --camera,
/// --fov, --flat and --exposure, and --mode), headless runs, the live solve.
void add_view_options(CLI::App& app, ViewArgs& a, Raw& raw) {
    auto* picture = app.add_option_group(
        "Picture",
        "what the view shows, and from where; --width and --height size the pictures "
        "of --screenshot and --pick, and the window when given");
    radiosity::cli::add_view_options(*picture, a.picture);
    picture
        ->add_option("--mode", a.mode,
                     "what the surfaces show: wireframe (the patches' edges over flat shading), "
                     "flat, smooth, reflectance or emission (keys 1 to 5); --flat: flat")
        ->check(CLI::IsMember({"wireframe", "flat", "smooth", "reflectance", "emission"}))
        ->capture_default_str();
    auto* headless = app.add_option_group("Headless", "pictures and numbers without a window");
    headless->add_option("--screenshot", a.screenshot,
                         "after the solve, draw one frame into this PNG and exit");
    headless
        ->add_option("--pick", raw.picks,
                     "print the patch seen at pixel X,Y (row 0 at the top) and its form-factor "
                     "row's numbers, then exit (repeatable; with --screenshot, the last pick's "
                     "row is shown)")
        ->type_name("X,Y");
    headless->add_flag("--ui", a.ui, "draw the panels into the screenshot too");
    auto* live = app.add_option_group("Live solve", "how the solve is shown as it goes");
    live->add_flag("--ambient", a.ambient,
                   "add shooting's ambient term to B, for the light not yet shot (key T)");
    live->add_option("--stop-after", a.stop_after,
                     "pause the solve after this many shots (or sweeps); with --screenshot, the "
                     "picture shows that moment");
    live->add_option("--batch", a.batch, "shots between picture updates (default: n / 100)")
        ->check(CLI::PositiveNumber);
    live->add_flag("--paused", a.paused, "start with the solve paused (space resumes, N steps)");
    app.add_flag("--quiet", a.quiet, "no progress on stderr");
}

/// One line on stderr and the status of a bad command line.
int bad(const std::string& message) {
    std::fprintf(stderr, "radiosity-view: error: %s (see --help)\n", message.c_str());
    return 2;
}

/// Checks what CLI11 cannot check alone and fills in the rest of a.
std::optional<int> finish(const CLI::App& app, ViewArgs& a, const Raw& raw) {
    a.size_given = app.count("--width") > 0 || app.count("--height") > 0;
    if (a.scene.solver == "hierarchical")
        return bad(
            "--solver hierarchical: the viewer watches the dense solvers sweep their "
            "patches; solve hierarchically with the radiosity program (its --ply or "
            "--gltf can be viewed)");
    if (a.picture.flat) a.mode = "flat";
    for (const std::string& p : raw.picks) {
        const auto xy = parse_pixel(p);
        if (!xy) return bad("--pick: '" + p + "' is not X,Y");
        if ((*xy)[0] >= a.picture.width || (*xy)[1] >= a.picture.height)
            return bad("--pick: pixel " + p + " lies outside the " +
                       std::to_string(a.picture.width) + " x " + std::to_string(a.picture.height) +
                       " picture");
        a.picks.push_back(*xy);
    }
    if (!a.screenshot.empty() && std::filesystem::path(a.screenshot).extension() != ".png")
        return bad("--screenshot writes a PNG: '" + a.screenshot + "'");
    if (a.ui && a.screenshot.empty()) return bad("--ui needs --screenshot");
    return std::nullopt;
}

}  // namespace

std::optional<int> parse_view_args(int argc, char** argv, ViewArgs& a) {
    CLI::App app{
        "radiosity-view: watch the radiosity method at work. Opens a window on the scene, "
        "solves it on a worker thread and shows the light as it spreads; a click on a patch "
        "shows its form-factor row and its hemicube. With --screenshot or --pick it draws "
        "off screen and exits.",
        "radiosity-view"};
    app.failure_message(CLI::FailureMessage::simple);
    a.scene.solver = "progressive";  // the solver to watch (the program's default: gauss-seidel)
    radiosity::cli::add_scene_options(app, a.scene);
    Raw raw;
    add_view_options(app, a, raw);
    if (auto status = radiosity::cli::parse(app, argc, argv)) return status;
    return finish(app, a, raw);
}

radiosity::SolverKind chosen_solver(const ViewArgs& a) {
    return radiosity::parse_solver_kind(a.scene.solver);
}

ViewSettings initial_settings(const ViewArgs& a) {
    ViewSettings s;
    s.mode = parse_mode(a.mode).value_or(Mode::smooth);
    s.ambient = a.ambient;
    s.stops = a.picture.exposure;
    return s;
}

}  // namespace radiosity::view
