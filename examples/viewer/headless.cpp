// The viewer without a window (headless.hpp).
#include "headless.hpp"

#include "camera_control.hpp"
#include "form_factor_row.hpp"
#include "panels.hpp"
#include "scene_view.hpp"
#include "solve_worker.hpp"
#include "ui.hpp"
#include "window.hpp"

#include <radiosity/error.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/shading/tonemap.hpp>

#include <cstdio>
#include <memory>

namespace radiosity::view {

namespace {

/// Runs the solve to its end, or to --stop-after, and says how it went (unless quiet).
void solve(SolveWorker& worker, const ViewArgs& a, std::size_t patches) {
    if (a.batch > 0) worker.set_batch(a.batch);
    if (a.stop_after > 0) worker.pause_at(a.stop_after);
    worker.start(chosen_solver(a));
    worker.wait_settled();
    const SolveStatus st = worker.status();
    if (st.state == SolveState::failed) throw radiosity::Error(st.error);
    if (!a.quiet)
        std::fprintf(stderr, "%zu patches; %s: %zu iterations, residual %.2e, %s\n", patches,
                     a.scene.solver.c_str(), st.iteration, st.residual,
                     st.state == SolveState::paused ? "paused (--stop-after)"
                     : st.report.converged          ? "converged"
                                                    : "NOT converged");
}

/// The matrix for column i: the solver's if it assembled one, else assembled now.
std::shared_ptr<const radiosity::DenseMatrix> matrix_for_columns(
    const Patches& patches, std::shared_ptr<const radiosity::DenseMatrix> F) {
    if (F) return F;
    return std::make_shared<const radiosity::DenseMatrix>(patches.visit(
        [&](const auto& method) { return radiosity::assemble_dense(method, patches.size()); }));
}

/// Prints the patch under every --pick pixel and its row's numbers; returns the last row.
std::optional<FormFactorRow> print_picks(const ViewArgs& a, const Patches& patches, SceneView& view,
                                         SolveWorker& worker) {
    std::optional<FormFactorRow> last;
    std::shared_ptr<const radiosity::DenseMatrix> F = worker.matrix();
    for (const auto& [x, y] : a.picks) {
        const std::uint32_t id = view.renderer().patch_at(x, y);
        if (id == 0) {
            std::printf("pick %d,%d: no patch\n", x, y);
            continue;
        }
        FormFactorRow row = form_factor_row(patches, F.get(), id - 1);
        if (!row.reciprocity) {  // the hemicube's column i needs every row
            F = matrix_for_columns(patches, F);
            row = form_factor_row(patches, F.get(), id - 1);
        }
        const auto& c = patches.table().centroid(id - 1);
        std::printf("pick %d,%d: patch %u (area %.6g, centre %.6g %.6g %.6g)\n%s", x, y, id - 1,
                    patches.table().area(id - 1), c.x, c.y, c.z, describe_row(row).c_str());
        last = std::move(row);
    }
    std::fflush(stdout);
    return last;
}

/// Draws the panels over the picture, as the window would show them after a few frames (ImGui
/// sizes its windows in the frames after their first).
void draw_panels(const ViewArgs& a, const Patches& patches, SceneView& view, SolveWorker& worker,
                 const Window& window, ViewSettings& s, const radiosity::Camera& camera) {
    Ui ui(window.handle());
    CameraControl control(camera, camera.target);  // the panel only shows it
    SolvePanel solve_panel(worker);
    PatchPanel patch_panel(patches);
    if (view.row()) patch_panel.pick(*view.row(), view.light_colours(s));
    for (int frame = 0; frame < 3; ++frame) {
        view.draw(camera, s, a.picture.width, a.picture.height, frame == 0);
        ui.begin_frame(glm::ivec2(a.picture.width, a.picture.height));
        view_panel(s, control, view.scale(s));
        solve_panel.draw(s);
        patch_panel.draw(s, false);
        glBindFramebuffer(GL_FRAMEBUFFER, view.renderer().framebuffer());
        const GLenum display = GL_COLOR_ATTACHMENT0;
        glDrawBuffers(1, &display);
        glViewport(0, 0, a.picture.width, a.picture.height);
        ui.end_frame();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
}

void write_png(const std::string& path, int width, int height,
               const std::vector<std::uint8_t>& rgb) {
    if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3))
        throw radiosity::Error("cannot write '" + path + "'");
}

}  // namespace

int run_headless(const ViewArgs& a, const Patches& patches, const radiosity::Camera& camera) {
    // The window only provides the context: the pictures have their own framebuffer.
    const Window window(a.ui ? a.picture.width : 64, a.ui ? a.picture.height : 64, "radiosity-view",
                        false);
    SolveWorker worker(patches);
    solve(worker, a, patches.size());
    SceneView view(patches);
    view.set_solution(*worker.snapshot_after(0));
    ViewSettings s = initial_settings(a);
    if (!a.picks.empty()) {
        // Which patch each pixel sees; the light's exposure is measured before the row hides it.
        view.draw(camera, s, a.picture.width, a.picture.height, true);
        if (auto row = print_picks(a, patches, view, worker)) view.set_row(std::move(row));
    }
    if (!a.screenshot.empty()) {
        if (a.ui)
            draw_panels(a, patches, view, worker, window, s, camera);
        else
            view.draw(camera, s, a.picture.width, a.picture.height, true);
        write_png(a.screenshot, a.picture.width, a.picture.height,
                  view.renderer().display_pixels());
        if (!a.quiet) std::fprintf(stderr, "wrote %s\n", a.screenshot.c_str());
    }
    worker.cancel();
    return 0;
}

}  // namespace radiosity::view
