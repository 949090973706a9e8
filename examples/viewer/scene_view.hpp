#pragma once
/// @file scene_view.hpp  The scene as the viewer shows it: RRV's modes and more (patches as a
/// wireframe over flat shading, flat and smooth radiosity, reflectance, emission), a picked
/// patch's form-factor row in false colour, and the exposure chosen as the library chooses it
/// for its pictures (shading/tonemap.hpp: the 95th percentile of the picture's luminance
/// mapped to 0.8, then 2^stops). It turns the solver's values into what the GPU draws.

#include "form_factor_row.hpp"
#include "patches.hpp"
#include "renderer.hpp"
#include "scene_upload.hpp"
#include "solve_worker.hpp"
#include "view_settings.hpp"

#include <radiosity/shading/camera.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace radiosity::view {

/// The scene's patches with their current values, drawn by the Renderer (see the file
/// comment). Needs a current OpenGL context.
class SceneView {
  public:
    /// Uploads the patches' geometry (smooth shading's triangles and the patch edges).
    explicit SceneView(const Patches& patches);

    /// The solver's values to show from now on.
    void set_solution(const SolveSnapshot& snapshot);
    /// The picked patch's form-factor row to show (in false colour), or none.
    void set_row(std::optional<FormFactorRow> row);
    const std::optional<FormFactorRow>& row() const { return row_; }  ///< the picked row

    /// Draws a width x height picture. With automatic exposure and `measure`, the picture's
    /// linear values set the exposure, and it is drawn again if that changed the scale.
    void draw(const radiosity::Camera& camera, const ViewSettings& settings, int width, int height,
              bool measure);
    /// Whether the settings show light (B or E) under the exposure, rather than a reflectance
    /// or a false-colour row shown as it is.
    bool exposed(const ViewSettings& settings) const;
    /// The exposure scale of the next picture: display = scale x B before the sRGB curve.
    double scale(const ViewSettings& settings) const;
    /// B as shown: the solver's values, plus the ambient term when asked for and shooting's
    /// unshot radiosity is known (radiosity::with_ambient).
    std::vector<Colour> shown_radiosity(bool ambient) const;
    /// Each patch's value as the current settings show it flat: light, reflectance or the
    /// row's false colour (linear; display colours are srgb of scale x value if exposed).
    std::vector<glm::vec3> patch_values(const ViewSettings& settings) const;

    /// The patches' light (B as shown) in display colours, sRGB of scale x B: what a hemicube
    /// at a patch sees.
    std::vector<glm::vec3> light_colours(const ViewSettings& settings) const;

    const Renderer& renderer() const { return renderer_; }       ///< the pictures drawn
    Renderer& renderer() { return renderer_; }                   ///< for the headless panels
    const SolveSnapshot& solution() const { return solution_; }  ///< the values shown

  private:
    void upload(const ViewSettings& settings);
    bool row_shown(const ViewSettings& settings) const;

    const Patches& patches_;
    radiosity::Mesh<Colour> shading_mesh_;  // the patches with the shown B, for smooth shading
    radiosity::ShadedMesh topology_;
    GpuScene gpu_;
    Renderer renderer_;
    SolveSnapshot solution_;
    std::optional<FormFactorRow> row_;
    std::uint64_t revision_ = 1, uploaded_ = 0;  // bumped when values change
    std::string uploaded_for_;                   // the settings the GPU values were made for
    double base_scale_ = 1.0;                    // auto_exposure_scale of the last measured picture
};

}  // namespace radiosity::view
