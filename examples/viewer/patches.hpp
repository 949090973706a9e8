#pragma once
/// @file patches.hpp  What the viewer solves and shows: the scene cut into patches exactly as
/// radiosity::solve cuts it (the same subdivision, patch table, E and R), and the chosen
/// form-factor method prepared on those patches, whose rows the solver and the patch picker read.

#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/solve.hpp>
#include <radiosity/solver/system.hpp>

#include <optional>
#include <span>
#include <variant>
#include <vector>

namespace radiosity::view {

/// The viewer solves in RGB, as the `radiosity` program does.
using Colour = radiosity::Rgb;

/// The scene's patches and the form-factor method over them. The method keeps a reference to
/// the patch table, so a Patches object stays where it was made (neither copied nor moved).
class Patches {
  public:
    /// Subdivides the scene by o.subdivision, makes the patch table, checks E and R (as
    /// radiosity::solve does) and prepares o.form_factor's method. Throws radiosity::Error for
    /// bad input.
    Patches(const radiosity::Mesh<Colour>& scene, const radiosity::SolveOptions& o);
    Patches(const Patches&) = delete;
    Patches& operator=(const Patches&) = delete;

    std::size_t size() const { return table_.size(); }             ///< number of patches n
    const radiosity::Mesh<Colour>& mesh() const { return mesh_; }  ///< face i is patch i
    const radiosity::PatchTable& table() const { return table_; }  ///< patch geometry
    const std::vector<Colour>& emission() const { return E_; }     ///< E_i
    const std::vector<Colour>& reflectance() const { return R_; }  ///< R_i
    /// The system B = E + R F B over these patches (views into this object).
    radiosity::System<Colour> system() const { return {E_, R_, table_.areas()}; }
    /// The options the patches were made with.
    const radiosity::SolveOptions& options() const { return options_; }

    /// Row i of F from the form-factor method. Safe to call from several threads at once.
    void row(std::size_t i, std::span<float> out) const;
    /// F_ij alone, where the method computes single pairs (analytic, ray-cast); nothing for the
    /// hemicube, which sees every patch at once.
    std::optional<double> pair(std::size_t i, std::size_t j) const;
    /// Whether pair() gives values (the method is a radiosity::PairFormFactor).
    bool has_pairs() const;
    /// Calls f(method) with the prepared method (a radiosity::FormFactorMethod).
    template <class F>
    decltype(auto) visit(F&& f) const {
        return std::visit(std::forward<F>(f), method_);
    }

  private:
    radiosity::SolveOptions options_;
    radiosity::Mesh<Colour> mesh_;
    radiosity::PatchTable table_;
    std::vector<Colour> E_, R_;
    std::variant<radiosity::Analytic<>, radiosity::Hemicube, radiosity::RayCast<>> method_;
};

}  // namespace radiosity::view
