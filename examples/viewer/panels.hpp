#pragma once
/// @file panels.hpp  The viewer's Dear ImGui panels: the view (mode, edges, exposure, camera),
/// the solve (solver, pause / step / resume, the ambient term, the unshot energy or the sweep's
/// change against iterations) and the picked patch (its numbers, its form-factor row's scale,
/// and its hemicube: what it sees, which patch each pixel sees, the delta form factors).

#include "camera_control.hpp"
#include "form_factor_row.hpp"
#include "gl.hpp"
#include "hemicube_view.hpp"
#include "patches.hpp"
#include "scene_view.hpp"
#include "solve_worker.hpp"

#include <radiosity/form_factor/hemicube.hpp>

#include <array>
#include <optional>
#include <vector>

namespace radiosity::view {

/// Draws the view panel; returns whether a setting changed (the picture must be redrawn).
bool view_panel(ViewSettings& settings, CameraControl& camera, double scale);

/// The solve panel, which keeps the convergence history it has fetched.
class SolvePanel {
  public:
    /// A panel for the worker's solves.
    explicit SolvePanel(SolveWorker& worker);
    /// Draws it; returns whether the ambient term was switched (the picture must be redrawn).
    bool draw(ViewSettings& settings);
    /// Starts a solve with the chosen solver (a restart from B = E).
    void start(radiosity::SolverKind solver, bool paused);

  private:
    void controls(const SolveStatus& st);
    void plot(bool shooting) const;

    SolveWorker& worker_;
    int chosen_ = 2;  // the solver in the combo: jacobi, gauss-seidel, progressive,
                      // direct
    std::vector<ResidualPoint> history_;
    std::vector<float> log_residual_;
};

/// The picked patch's panel: its row's numbers and its hemicube (see the file comment).
class PatchPanel {
  public:
    /// A panel for these patches (the hemicube is made with the run's hemicube options).
    explicit PatchPanel(const Patches& patches);

    /// Shows patch row.patch: its numbers and its hemicube, seen in the given display colours
    /// (one per patch, sRGB).
    void pick(FormFactorRow row, const std::vector<glm::vec3>& colours);
    /// The row's reciprocity error, once column i is known.
    void set_reciprocity(double error);
    /// New display colours of the patches, for the picture of what the patch sees.
    void recolour(const std::vector<glm::vec3>& colours);
    void clear() { row_.reset(); }                                ///< nothing picked
    bool active() const { return row_.has_value(); }              ///< a patch is picked
    std::size_t patch() const { return row_ ? row_->patch : 0; }  ///< which
    /// Draws the panel; returns false when the user closed it (the pick is to be cleared).
    bool draw(ViewSettings& settings, bool computing_column);

  private:
    void numbers(ViewSettings& settings, bool computing_column);
    void hemicube();

    const Patches& patches_;
    radiosity::Hemicube hemicube_;
    std::optional<FormFactorRow> row_;
    UnfoldedHemicube unfolded_;
    std::array<gl::Texture, 3> pictures_;  // seen colours, patch ids, delta form factors
    int shown_ = 0;
};

}  // namespace radiosity::view
