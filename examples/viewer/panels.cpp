// The viewer's panels (panels.hpp).
#include "panels.hpp"

#include "palette.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace radiosity::view {

namespace {

const char* state_name(SolveState s) {
    switch (s) {
        case SolveState::idle:
            return "idle";
        case SolveState::form_factors:
            return "computing form factors";
        case SolveState::running:
            return "running";
        case SolveState::paused:
            return "paused";
        case SolveState::done:
            return "done";
        case SolveState::cancelled:
            return "stopped";
        case SolveState::failed:
            return "failed";
    }
    return "?";
}

constexpr std::array<radiosity::SolverKind, 4> solvers{
    radiosity::SolverKind::jacobi, radiosity::SolverKind::gauss_seidel,
    radiosity::SolverKind::progressive, radiosity::SolverKind::direct};
constexpr std::array<const char*, 4> solver_names{"jacobi", "gauss-seidel", "progressive",
                                                  "direct"};

int solver_index(radiosity::SolverKind s) {
    return static_cast<int>(std::find(solvers.begin(), solvers.end(), s) - solvers.begin());
}

/// A horizontal bar of the false-colour scale between two labels.
void colour_bar(double lo, double hi) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float w = 256.0f, h = 12.0f;
    constexpr int steps = 32;
    for (int k = 0; k < steps; ++k) {
        const glm::vec3 a = false_colour(double(k) / steps),
                        b = false_colour(double(k + 1) / steps);
        const auto col = [](const glm::vec3& c) {
            return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, 1.0f));
        };
        draw->AddRectFilledMultiColor(ImVec2(at.x + w * k / steps, at.y),
                                      ImVec2(at.x + w * (k + 1) / steps, at.y + h), col(a), col(b),
                                      col(b), col(a));
    }
    ImGui::Dummy(ImVec2(w, h));
    ImGui::Text("%.2e", lo);
    ImGui::SameLine(std::max(0.0f, w - 60.0f));
    ImGui::Text("%.2e", hi);
}

}  // namespace

namespace {

/// The mode's radio buttons (two rows), the edges and the ambient term, the exposure.
bool picture_controls(ViewSettings& s, double scale) {
    bool changed = false;
    for (std::size_t k = 0; k < all_modes.size(); ++k) {
        const std::string label = std::to_string(k + 1) + " " + mode_name(all_modes[k]);
        if (ImGui::RadioButton(label.c_str(), s.mode == all_modes[k])) {
            s.mode = all_modes[k];
            changed = true;
        }
        if (k != 2 && k + 1 < all_modes.size()) ImGui::SameLine();
    }
    changed |= ImGui::Checkbox("patch edges (G)", &s.edges);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("ambient term (T)", &s.ambient);
    changed |= ImGui::Checkbox("auto exposure", &s.auto_exposure);
    ImGui::SameLine();
    float stops = static_cast<float>(s.stops);
    ImGui::SetNextItemWidth(100);
    if (ImGui::SliderFloat("stops ([ ])", &stops, -8.0f, 8.0f, "%.1f")) {
        s.stops = stops;
        changed = true;
    }
    ImGui::Text("display = sRGB(%.3g x B)%s", scale, s.auto_exposure ? " (auto)" : "");
    return changed;
}

/// Orbit or fly, home, the field of view.
bool camera_controls(CameraControl& camera) {
    bool changed = false;
    int mode = camera.mode() == CameraMode::orbit ? 0 : 1;
    ImGui::Text("camera (C):");
    ImGui::SameLine();
    if (ImGui::RadioButton("orbit", &mode, 0)) camera.set_mode(CameraMode::orbit);
    ImGui::SameLine();
    if (ImGui::RadioButton("fly", &mode, 1)) camera.set_mode(CameraMode::fly);
    ImGui::SameLine();
    if (ImGui::Button("home (H)")) {
        camera.reset();
        changed = true;
    }
    float fov = static_cast<float>(camera.camera().fov_y_degrees);
    ImGui::SetNextItemWidth(180);
    if (ImGui::SliderFloat("field of view", &fov, 10.0f, 120.0f, "%.1f deg")) {
        camera.set_fov(fov);
        changed = true;
    }
    return changed;
}

}  // namespace

bool view_panel(ViewSettings& s, CameraControl& camera, double scale) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("View", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    bool changed = picture_controls(s, scale);
    changed |= camera_controls(camera);
    if (ImGui::CollapsingHeader("keys and mouse")) {
        ImGui::TextUnformatted(
            "1-5 modes, G edges, T ambient term, [ ] exposure\n"
            "C orbit/fly, H home camera\n"
            "space pause/resume, N one step\n"
            "click a patch: its row and hemicube; Esc: unpick\n"
            "orbit: drag to turn, right-drag to pan, wheel: zoom\n"
            "fly: drag to look, W A S D to move, Q E down/up,\n"
            "     shift faster, wheel: speed");
    }
    ImGui::End();
    return changed;
}

SolvePanel::SolvePanel(SolveWorker& worker) : worker_(worker) {}

void SolvePanel::start(radiosity::SolverKind solver, bool paused) {
    chosen_ = solver_index(solver);
    history_.clear();
    log_residual_.clear();
    worker_.start(solver, paused);
}

bool SolvePanel::draw(ViewSettings& settings) {
    bool changed = false;
    const SolveStatus st = worker_.status();
    for (const ResidualPoint& p : worker_.history(history_.size())) {
        history_.push_back(p);
        log_residual_.push_back(p.residual > 0.0 ? static_cast<float>(std::log10(p.residual))
                                                 : -16.0f);
    }
    ImGui::SetNextWindowPos(ImVec2(10, 230), ImGuiCond_FirstUseEver);
    ImGui::Begin("Solve", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::SetNextItemWidth(140);
    ImGui::Combo("##solver", &chosen_, solver_names.data(), int(solver_names.size()));
    ImGui::SameLine();
    if (ImGui::Button("restart")) start(solvers[std::size_t(chosen_)], false);
    const bool shooting = st.solver == radiosity::SolverKind::progressive;
    ImGui::Text("%s: %s", solver_names[std::size_t(solver_index(st.solver))], state_name(st.state));
    controls(st);
    if (shooting) changed |= ImGui::Checkbox("ambient term (T)", &settings.ambient);
    ImGui::Text("%zu %s, %s %.3e", st.iteration, shooting ? "shots" : "sweeps",
                shooting ? "unshot / emitted" : "relative change", st.residual);
    plot(shooting);
    if (st.state == SolveState::done || st.state == SolveState::cancelled) {
        ImGui::Text("%s in %.2f s", st.report.converged ? "converged" : "NOT converged",
                    st.report.seconds);
        if (!shooting) {
            ImGui::SameLine();
            ImGui::Text("(form factors %.2f s)", st.form_factor_seconds);
        }
    }
    if (st.state == SolveState::failed) ImGui::TextWrapped("error: %s", st.error.c_str());
    ImGui::End();
    return changed;
}

void SolvePanel::controls(const SolveStatus& st) {
    if (st.state == SolveState::form_factors) {
        ImGui::ProgressBar(static_cast<float>(st.fraction), ImVec2(260, 0), "form factors");
        return;
    }
    if (st.state == SolveState::paused) {
        if (ImGui::Button("resume (space)")) worker_.resume();
        ImGui::SameLine();
        if (ImGui::Button("step (N)")) worker_.step();
    } else if (st.state == SolveState::running) {
        if (ImGui::Button("pause (space)")) worker_.pause();
    }
    if (st.solver == radiosity::SolverKind::progressive) {
        int batch = static_cast<int>(worker_.batch());
        ImGui::SetNextItemWidth(120);
        if (ImGui::InputInt("shots per step", &batch, 1, 10))
            worker_.set_batch(std::size_t(std::max(batch, 1)));
    }
}

void SolvePanel::plot(bool shooting) const {
    if (log_residual_.empty()) return;
    char overlay[64];
    std::snprintf(overlay, sizeof overlay, "log10 %s, %zu %s", shooting ? "unshot" : "change",
                  history_.back().iteration, shooting ? "shots" : "sweeps");
    const float lo = *std::min_element(log_residual_.begin(), log_residual_.end());
    ImGui::PlotLines("##history", log_residual_.data(), int(log_residual_.size()), 0, overlay,
                     std::min(lo, -1.0f), std::max(0.0f, log_residual_.front()), ImVec2(300, 90));
}

PatchPanel::PatchPanel(const Patches& patches)
    : patches_(patches), hemicube_(patches.options().hemicube) {
    hemicube_.prepare(patches.table());
    for (auto& t : pictures_) t = gl::make_texture();
}

void PatchPanel::pick(FormFactorRow row, const std::vector<glm::vec3>& colours) {
    unfolded_ = unfold_hemicube(hemicube_, row.patch);
    row_ = std::move(row);
    const int size = unfolded_.size;
    gl::upload_rgba(pictures_[1].get(), size, size, hemicube_id_picture(unfolded_).data());
    gl::upload_rgba(pictures_[2].get(), size, size, hemicube_delta_picture(unfolded_).data());
    recolour(colours);
}

void PatchPanel::set_reciprocity(double error) {
    if (row_) row_->reciprocity = error;
}

void PatchPanel::recolour(const std::vector<glm::vec3>& colours) {
    if (!row_) return;
    gl::upload_rgba(pictures_[0].get(), unfolded_.size, unfolded_.size,
                    hemicube_seen_picture(unfolded_, colours).data());
}

bool PatchPanel::draw(ViewSettings& settings, bool computing_column) {
    if (!row_) return true;
    bool open = true;
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x - 10, 10), ImGuiCond_FirstUseEver,
                            ImVec2(1.0f, 0.0f));  // against the right edge
    ImGui::Begin("Patch", &open, ImGuiWindowFlags_AlwaysAutoResize);
    numbers(settings, computing_column);
    ImGui::Separator();
    hemicube();
    ImGui::End();
    return open;
}

void PatchPanel::numbers(ViewSettings& settings, bool computing_column) {
    const FormFactorRow& r = *row_;
    const auto& t = patches_.table();
    const std::size_t i = r.patch;
    ImGui::Text("patch %zu of %zu, area %.4g", i, patches_.size(), t.area(i));
    ImGui::Text("centre (%.4g, %.4g, %.4g)", t.centroid(i).x, t.centroid(i).y, t.centroid(i).z);
    ImGui::Text("normal (%.3f, %.3f, %.3f)", t.normal(i).x, t.normal(i).y, t.normal(i).z);
    const Colour& E = patches_.emission()[i];
    const Colour& R = patches_.reflectance()[i];
    ImGui::Text("E (%.3g, %.3g, %.3g)", band(E, 0), band(E, 1), band(E, 2));
    ImGui::SameLine();
    ImGui::Text("R (%.3f, %.3f, %.3f)", band(R, 0), band(R, 1), band(R, 2));
    ImGui::Separator();
    ImGui::Text("F_ii = %.3g", r.self);
    ImGui::Text("row sum  sum_j F_ij = %.6f", r.sum);
    if (r.reciprocity)
        ImGui::Text("reciprocity error = %.3e", *r.reciprocity);
    else
        ImGui::Text("reciprocity error: %s", computing_column ? "computing column i..." : "-");
    ImGui::Checkbox("the row F_ij on the scene", &settings.show_row);
    ImGui::TextUnformatted("log scale; dark grey: 0, white: patch i");
    colour_bar(std::max(r.smallest, 1e-4 * r.largest), r.largest);
}

void PatchPanel::hemicube() {
    ImGui::Text("hemicube %d x %d: sum of delta F %.5f", hemicube_.options().resolution,
                hemicube_.options().resolution, unfolded_.total);
    ImGui::Text("on pixels that see a patch: %.5f", unfolded_.covered);
    ImGui::RadioButton("what it sees", &shown_, 0);
    ImGui::SameLine();
    ImGui::RadioButton("which patch", &shown_, 1);
    ImGui::SameLine();
    ImGui::RadioButton("delta F", &shown_, 2);
    const float side = 256.0f;
    const ImVec2 at = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(
                     static_cast<std::intptr_t>(pictures_[static_cast<std::size_t>(shown_)].get())),
                 ImVec2(side, side));
    if (!ImGui::IsItemHovered()) return;
    // The pixel under the cursor: which face, which patch it sees, its delta form factor.
    const ImVec2 m = ImGui::GetIO().MousePos;
    const int n = unfolded_.size;
    const int x = std::clamp(int((m.x - at.x) / side * float(n)), 0, n - 1);
    const int y = std::clamp(int((m.y - at.y) / side * float(n)), 0, n - 1);
    const auto k = static_cast<std::size_t>(y * n + x);
    if (unfolded_.face[k] < 0) return;
    const std::int32_t j = unfolded_.seen[k];
    ImGui::BeginTooltip();
    ImGui::Text("%s, pixel %d: delta F %.3e", hemicube_face_name(unfolded_.face[k]).c_str(),
                unfolded_.face_pixel[k], unfolded_.delta[k]);
    if (j >= 0)
        ImGui::Text("sees patch %d: F_ij = %.4e (its pixels: %.4e)", j,
                    row_->F[static_cast<std::size_t>(j)], unfolded_.seen_sum(j));
    else
        ImGui::TextUnformatted("sees nothing");
    ImGui::EndTooltip();
}

}  // namespace radiosity::view
