// The interactive viewer (app.hpp).
#include "app.hpp"

#include "camera_control.hpp"
#include "panels.hpp"
#include "scene_view.hpp"
#include "solve_worker.hpp"
#include "ui.hpp"
#include "window.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <radiosity/shading/tonemap.hpp>

#include <chrono>
#include <cstdio>
#include <future>
#include <limits>
#include <memory>

namespace radiosity::view {

namespace {

using Clock = std::chrono::steady_clock;

/// The centre of the patches' bounding box.
glm::dvec3 centre(const Patches& patches) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::size_t i = 0; i < patches.size(); ++i)
        for (const auto& p : patches.table().polygon(i)) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    return 0.5 * (lo + hi);
}

/// The viewer's state and its frame loop.
class App {
  public:
    App(const ViewArgs& a, const Patches& patches, const radiosity::Camera& home)
        : patches_(patches),
          window_(a.size_given ? a.picture.width : 1280, a.size_given ? a.picture.height : 800,
                  "radiosity-view: " + a.scene.scene, true),
          ui_(window_.handle()),
          worker_(patches),
          view_(patches),
          camera_(home, centre(patches)),
          settings_(initial_settings(a)),
          solve_panel_(worker_),
          patch_panel_(patches) {
        if (a.batch > 0) worker_.set_batch(a.batch);
        if (a.stop_after > 0) worker_.pause_at(a.stop_after);
        solve_panel_.start(chosen_solver(a), a.paused);
        if (!a.quiet)
            std::fprintf(stderr, "%zu patches; %s\n", patches.size(), window_.renderer().c_str());
    }

    int run() {
        auto last = Clock::now();
        while (!window_.should_close()) {
            const SolveState state = worker_.status().state;
            const bool busy = state == SolveState::running || state == SolveState::form_factors ||
                              column_.valid() || dirty_;
            window_.poll(busy ? 0.0 : 0.1);
            const auto now = Clock::now();
            const double seconds = std::chrono::duration<double>(now - last).count();
            last = now;
            take_solution();
            take_column();
            ui_.begin_frame();
            handle_keys();
            handle_mouse(seconds);
            dirty_ |= view_panel(settings_, camera_, view_.scale(settings_));
            dirty_ |= solve_panel_.draw(settings_);
            if (!patch_panel_.draw(settings_, column_.valid())) unpick();
            draw_scene(now);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            const auto [w, h] = window_.framebuffer_size();
            glViewport(0, 0, w, h);
            ui_.end_frame();
            window_.swap();
        }
        worker_.cancel();
        return 0;
    }

  private:
    /// The worker's latest values, if new.
    void take_solution() {
        auto s = worker_.snapshot_after(version_);
        if (!s) return;
        version_ = s->version;
        view_.set_solution(*s);
        changed();
        if (patch_panel_.active()) patch_panel_.recolour(view_.light_colours(settings_));
    }

    /// Column i of the matrix assembled for the picked patch's reciprocity error, once ready.
    void take_column() {
        if (!column_.valid() ||
            column_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
            return;
        columns_ = column_.get();
        if (!patch_panel_.active() || !view_.row()) return;
        const std::size_t i = patch_panel_.patch();
        std::vector<float> column(patches_.size());
        for (std::size_t j = 0; j < column.size(); ++j) column[j] = (*columns_)(j, i);
        const double error = row_reciprocity(patches_.table(), i, view_.row()->F, column);
        patch_panel_.set_reciprocity(error);
        std::printf("  patch %zu: reciprocity error = %.6e\n", i, error);
        std::fflush(stdout);
    }

    void changed() {
        dirty_ = true;
        measure_ = true;
    }

    void draw_scene(Clock::time_point now) {
        const auto [w, h] = window_.framebuffer_size();
        if (w <= 0 || h <= 0) return;
        if (w != view_.renderer().width() || h != view_.renderer().height()) changed();
        if (dirty_) {
            // The exposure follows the picture at most five times a second while it changes.
            const bool measure = measure_ && now - measured_ > std::chrono::milliseconds(200);
            view_.draw(camera_.camera(), settings_, w, h, measure);
            if (measure) {
                measured_ = now;
                measure_ = false;
            }
            dirty_ = measure_;
        }
        view_.renderer().show(w, h);
    }

    void handle_keys() {
        const std::vector<int> presses = window_.take_key_presses();
        if (ImGui::GetIO().WantCaptureKeyboard) return;  // typing into a panel
        for (const int key : presses) handle_key(key);
    }

    void handle_key(int key) {
        if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + int(all_modes.size()))
            return set(settings_.mode, all_modes[std::size_t(key - GLFW_KEY_1)]);
        switch (key) {
            case GLFW_KEY_G:
                return set(settings_.edges, !settings_.edges);
            case GLFW_KEY_T:
                return set(settings_.ambient, !settings_.ambient);
            case GLFW_KEY_LEFT_BRACKET:
                return set(settings_.stops, settings_.stops - 0.5);
            case GLFW_KEY_RIGHT_BRACKET:
                return set(settings_.stops, settings_.stops + 0.5);
            case GLFW_KEY_C:
                return camera_.set_mode(camera_.mode() == CameraMode::orbit ? CameraMode::fly
                                                                            : CameraMode::orbit);
            case GLFW_KEY_H:
                camera_.reset();
                return changed();
            case GLFW_KEY_SPACE:
                if (worker_.status().state == SolveState::paused) return worker_.resume();
                return worker_.pause();
            case GLFW_KEY_N:
                return worker_.step();
            case GLFW_KEY_ESCAPE:
                return unpick();
            default:
                return;
        }
    }

    template <class T>
    void set(T& setting, T value) {
        setting = value;
        changed();
    }

    void handle_mouse(double seconds) {
        const ImGuiIO& io = ImGui::GetIO();
        for (int b = 0; b < 3; ++b)  // a drag belongs to the scene if it started there
            if (ImGui::IsMouseClicked(b)) owned_[b] = !io.WantCaptureMouse;
        CameraInput in;
        in.seconds = seconds;
        in.view_height = io.DisplaySize.y;
        const glm::dvec2 delta(io.MouseDelta.x, io.MouseDelta.y);
        if (ImGui::IsMouseDown(0) && owned_[0] && !io.KeyShift) in.drag = delta;
        if ((ImGui::IsMouseDown(1) && owned_[1]) || (ImGui::IsMouseDown(2) && owned_[2]) ||
            (ImGui::IsMouseDown(0) && owned_[0] && io.KeyShift))
            in.pan = delta;
        if (!io.WantCaptureMouse) in.wheel = io.MouseWheel;
        if (camera_.mode() == CameraMode::fly && !io.WantCaptureKeyboard) {
            auto axis = [this](int minus, int plus) {
                return (window_.key_down(plus) ? 1.0 : 0.0) - (window_.key_down(minus) ? 1.0 : 0.0);
            };
            in.move = {axis(GLFW_KEY_A, GLFW_KEY_D), axis(GLFW_KEY_Q, GLFW_KEY_E),
                       axis(GLFW_KEY_S, GLFW_KEY_W)};
            in.fast = io.KeyShift;
        }
        if (camera_.update(in)) changed();
        // A click (no drag) on the scene picks the patch under the cursor.
        if (ImGui::IsMouseReleased(0) && owned_[0] && io.MouseDragMaxDistanceSqr[0] < 9.0f)
            pick(int(io.MousePos.x * io.DisplayFramebufferScale.x),
                 int(io.MousePos.y * io.DisplayFramebufferScale.y));
    }

    void pick(int x, int y) {
        const std::uint32_t id = view_.renderer().patch_at(x, y);
        if (id == 0) return unpick();
        const std::size_t i = id - 1;
        const auto assembled = worker_.matrix();
        const radiosity::DenseMatrix* F = assembled ? assembled.get() : columns_.get();
        FormFactorRow row = form_factor_row(patches_, F, i);
        const auto& c = patches_.table().centroid(i);
        std::printf("patch %zu (area %.6g, centre %.6g %.6g %.6g)\n%s", i, patches_.table().area(i),
                    c.x, c.y, c.z, describe_row(row).c_str());
        std::fflush(stdout);
        if (!row.reciprocity && !column_.valid()) {
            // The hemicube's column i needs every row: assemble them off the viewer's thread.
            const Patches& p = patches_;
            column_ = std::async(std::launch::async, [&p] {
                return std::make_shared<const radiosity::DenseMatrix>(
                    p.visit([&](const auto& method) {
                        return radiosity::assemble_dense(method, p.size());
                    }));
            });
        }
        patch_panel_.pick(row, view_.light_colours(settings_));
        view_.set_row(std::move(row));
        changed();
    }

    void unpick() {
        if (!patch_panel_.active()) return;
        patch_panel_.clear();
        view_.set_row(std::nullopt);
        changed();
    }

    const Patches& patches_;
    Window window_;
    Ui ui_;
    SolveWorker worker_;
    SceneView view_;
    CameraControl camera_;
    ViewSettings settings_;
    SolvePanel solve_panel_;
    PatchPanel patch_panel_;
    std::uint64_t version_ = 0;
    bool dirty_ = true, measure_ = true;
    bool owned_[3] = {false, false, false};
    Clock::time_point measured_{};
    std::future<std::shared_ptr<const radiosity::DenseMatrix>> column_;
    std::shared_ptr<const radiosity::DenseMatrix> columns_;
};

}  // namespace

int run_interactive(const ViewArgs& a, const Patches& patches, const radiosity::Camera& home) {
    App app(a, patches, home);
    return app.run();
}

}  // namespace radiosity::view
