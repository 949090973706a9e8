// The scene as the viewer shows it (scene_view.hpp).
#include "scene_view.hpp"

#include "palette.hpp"

#include <radiosity/shading/tonemap.hpp>
#include <radiosity/shading/vertex_shading.hpp>
#include <radiosity/solver/progressive.hpp>

#include <cmath>

namespace radiosity::view {

namespace {
glm::vec3 rgb(const Colour& c) {
    return {band(c, 0), band(c, 1), band(c, 2)};
}

/// The patches' values as flat colours.
std::vector<glm::vec3> rgbs(const std::vector<Colour>& v) {
    std::vector<glm::vec3> out;
    out.reserve(v.size());
    for (const auto& c : v) out.push_back(rgb(c));
    return out;
}

/// The smooth-shading topology of the patches (its colours are set later, frame by frame).
radiosity::ShadedMesh topology_of(const radiosity::Mesh<Colour>& mesh) {
    return radiosity::smooth_shading(mesh);
}
}  // namespace

SceneView::SceneView(const Patches& patches)
    : patches_(patches),
      shading_mesh_(patches.mesh()),
      topology_(topology_of(shading_mesh_)),
      gpu_(patches, topology_) {
    solution_.radiosity = patches.emission();
}

void SceneView::set_solution(const SolveSnapshot& snapshot) {
    solution_ = snapshot;
    ++revision_;
}

void SceneView::set_row(std::optional<FormFactorRow> row) {
    row_ = std::move(row);
    ++revision_;
}

bool SceneView::row_shown(const ViewSettings& s) const {
    return row_.has_value() && s.show_row;
}

bool SceneView::exposed(const ViewSettings& s) const {
    return !row_shown(s) && s.mode != Mode::reflectance;
}

double SceneView::scale(const ViewSettings& s) const {
    return base_scale_ * std::exp2(s.stops);
}

std::vector<Colour> SceneView::shown_radiosity(bool ambient) const {
    if (!ambient || solution_.unshot.size() != solution_.radiosity.size())
        return solution_.radiosity;
    return radiosity::with_ambient<Colour>(patches_.system(), solution_.radiosity,
                                           solution_.unshot);
}

std::vector<glm::vec3> SceneView::patch_values(const ViewSettings& s) const {
    if (row_shown(s)) {
        const FormFactorRow& r = *row_;
        const double lo = std::max(r.smallest, 1e-4 * r.largest);
        std::vector<glm::vec3> out(r.F.size());
        for (std::size_t j = 0; j < out.size(); ++j) {
            const double t = log_position(r.F[j], lo, r.largest);
            out[j] = srgb_to_linear(t < 0.0 ? glm::vec3(0.12f) : false_colour(t));
        }
        return out;
    }
    switch (s.mode) {
        case Mode::reflectance:
            return rgbs(patches_.reflectance());
        case Mode::emission:
            return rgbs(patches_.emission());
        default:
            return rgbs(shown_radiosity(s.ambient));
    }
}

std::vector<glm::vec3> SceneView::light_colours(const ViewSettings& s) const {
    std::vector<glm::vec3> out;
    const double k = scale(s);
    for (const Colour& b : shown_radiosity(s.ambient))
        out.emplace_back(radiosity::srgb_encode(float(k * band(b, 0))),
                         radiosity::srgb_encode(float(k * band(b, 1))),
                         radiosity::srgb_encode(float(k * band(b, 2))));
    return out;
}

void SceneView::upload(const ViewSettings& s) {
    const bool smooth = s.mode == Mode::smooth && !row_shown(s);
    const std::string what = std::string(mode_name(s.mode)) + (s.ambient ? "+ambient" : "") +
                             (row_shown(s) ? "+row" : "");
    if (uploaded_ == revision_ && uploaded_for_ == what) return;
    if (smooth) {
        radiosity::set_face_radiosity<Colour>(shading_mesh_, shown_radiosity(s.ambient));
        gpu_.set_vertex_colours(radiosity::smooth_shading(shading_mesh_).colours);
    } else {
        gpu_.set_patch_values(patch_values(s));
    }
    uploaded_ = revision_;
    uploaded_for_ = what;
}

void SceneView::draw(const radiosity::Camera& camera, const ViewSettings& s, int width, int height,
                     bool measure) {
    upload(s);
    renderer_.resize(width, height);
    const bool lit = exposed(s);
    const bool row = row_shown(s);
    DrawSettings d{.camera = camera,
                   .smooth = s.mode == Mode::smooth && !row,
                   .exposed = lit,
                   .scale = lit ? scale(s) : 1.0,
                   .edges = s.edges || s.mode == Mode::wireframe,
                   .edge_colour = glm::vec3(0.0f),
                   .highlight = row ? static_cast<int>(row_->patch) : -1,
                   .highlight_colour = glm::vec3(1.0f)};
    renderer_.draw(gpu_, d);
    if (!(lit && s.auto_exposure && measure)) return;
    const double before = base_scale_;
    base_scale_ = radiosity::auto_exposure_scale(renderer_.linear_pixels());
    if (std::abs(base_scale_ - before) <= 1e-6 * before) return;
    d.scale = scale(s);
    renderer_.draw(gpu_, d);
}

}  // namespace radiosity::view
