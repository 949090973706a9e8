// The viewer's patches and form-factor method (patches.hpp).
#include "patches.hpp"

#include <radiosity/mesh/subdivide.hpp>

namespace radiosity::view {

namespace {
std::variant<radiosity::Analytic<>, radiosity::Hemicube, radiosity::RayCast<>> make_method(
    const radiosity::SolveOptions& o) {
    switch (o.form_factor) {
        case radiosity::FormFactorKind::analytic:
            return radiosity::Analytic<>(o.analytic);
        case radiosity::FormFactorKind::hemicube:
            return radiosity::Hemicube(o.hemicube);
        case radiosity::FormFactorKind::ray_cast:
            return radiosity::RayCast<>(o.ray_cast);
    }
    throw radiosity::Error("unknown form-factor method");
}
}  // namespace

Patches::Patches(const radiosity::Mesh<Colour>& scene, const radiosity::SolveOptions& o)
    : options_(o),
      mesh_(radiosity::subdivide(scene, o.subdivision)),
      table_(radiosity::make_patch_table(mesh_)),
      E_(radiosity::face_emission(mesh_)),
      R_(radiosity::face_reflectance(mesh_)),
      method_(make_method(o)) {
    system().validate();
    std::visit([this](auto& m) { m.prepare(table_); }, method_);
}

void Patches::row(std::size_t i, std::span<float> out) const {
    std::visit([&](const auto& m) { m.row(i, out); }, method_);
}

std::optional<double> Patches::pair(std::size_t i, std::size_t j) const {
    return std::visit(
        [&](const auto& m) -> std::optional<double> {
            if constexpr (radiosity::PairFormFactor<std::decay_t<decltype(m)>>)
                return m.pair(i, j);
            else
                return std::nullopt;
        },
        method_);
}

bool Patches::has_pairs() const {
    return std::visit(
        [](const auto& m) { return radiosity::PairFormFactor<std::decay_t<decltype(m)>>; },
        method_);
}

}  // namespace radiosity::view
