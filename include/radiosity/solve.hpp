#pragma once
/// @file solve.hpp  The one-call facade: radiosity::solve(mesh, options) subdivides the scene,
/// computes form factors with the chosen method, solves B = E + R F B with the chosen solver and
/// returns the patch mesh with B on every face. For finer control use the policies directly
/// (form_factor/*.hpp, solver/*.hpp): this file only wires them together.

#include <radiosity/error.hpp>
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/budget.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/mesh/subdivide.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <variant>

namespace radiosity {

/// Which form-factor method solve() uses.
enum class FormFactorKind { analytic, hemicube, ray_cast };
/// Which solver solve() uses.
enum class SolverKind { jacobi, gauss_seidel, progressive, direct };

/// Options of solve(): the meshing, the form-factor method, the solver and their settings.
struct SolveOptions {
    SubdivisionOptions subdivision{};                       ///< max edge length (0: keep faces)
    FormFactorKind form_factor = FormFactorKind::hemicube;  ///< how F is computed
    SolverKind solver = SolverKind::gauss_seidel;           ///< how B = E + R F B is solved
    /// Stop once the relative error of B against the converged B* is bounded by this:
    /// ||B - B*||_inf / ||B*||_inf (progressive shooting with rows on demand: the same in the
    /// power norm sum_i A_i |B_i - B*_i|); see detail::StoppingRule.
    double tolerance = 1e-4;
    std::size_t max_iterations = 0;  ///< iteration guard; 0: from what the tolerance needs
    AnalyticOptions analytic{};      ///< settings of the analytic method
    HemicubeOptions hemicube{};      ///< settings of the hemicube method
    RayCastOptions ray_cast{};       ///< settings of the ray-cast method
    bool keep_form_factors = false;  ///< return the assembled matrix (n^2 floats)
    /// Largest dense matrix to allocate, in bytes; 0: half the physical memory
    /// (default_matrix_limit). Above it, solve() throws MemoryLimitError before allocating.
    std::size_t max_matrix_bytes = 0;
    bool ambient = false;  ///< progressive: add the ambient term to B (useful if stopped early)
    ProgressCallback progress{};  ///< phases "form factors" and "solve"; return false to cancel
};

/// What solve() returns: the patch mesh with B on every face, the patch geometry, the solver's
/// report, the time spent on form factors, if asked for the matrix, and the meshing's report.
template <SpectrumType S>
struct SolveResult {
    Mesh<S> mesh;                             ///< subdivided mesh, B stored in each face
    PatchTable patches;                       ///< patch i = face i of mesh
    Report report;                            ///< the solver's report
    double form_factor_seconds = 0.0;         ///< time spent assembling F (0 for progressive)
    std::optional<DenseMatrix> form_factors;  ///< F, when keep_form_factors was set
    MeshingReport meshing;  ///< faces left out and warnings of the meshing (subdivide.hpp)
};

/// Parses a form-factor method name: "analytic", "hemicube" or "raycast". Throws Error
/// otherwise.
inline FormFactorKind parse_form_factor_kind(const std::string& name) {
    if (name == "analytic") return FormFactorKind::analytic;
    if (name == "hemicube") return FormFactorKind::hemicube;
    if (name == "raycast" || name == "ray-cast") return FormFactorKind::ray_cast;
    throw Error("unknown form-factor method '" + name + "' (known: analytic, hemicube, raycast)");
}

/// Parses a solver name: "jacobi", "gauss-seidel", "progressive" or "direct". Throws Error
/// otherwise.
inline SolverKind parse_solver_kind(const std::string& name) {
    if (name == "jacobi") return SolverKind::jacobi;
    if (name == "gauss-seidel") return SolverKind::gauss_seidel;
    if (name == "progressive") return SolverKind::progressive;
    if (name == "direct") return SolverKind::direct;
    throw Error("unknown solver '" + name + "' (known: jacobi, gauss-seidel, progressive, direct)");
}

namespace detail {

template <class T>
T with_cap(T options, double tolerance, std::size_t cap) {
    options.tolerance = tolerance;
    if (cap > 0) options.max_iterations = cap;
    return options;
}

inline ProgressiveOptions progressive_options(const SolveOptions& o) {
    ProgressiveOptions p = with_cap(ProgressiveOptions{}, o.tolerance, o.max_iterations);
    p.ambient = o.ambient;
    return p;
}

/// Runs the chosen solver on an assembled matrix.
template <SpectrumType S, AssembledMatrix Mx>
Solution<S> solve_assembled(const System<S>& system, const Mx& F, const SolveOptions& o) {
    switch (o.solver) {
        case SolverKind::jacobi:
            return Jacobi(with_cap(JacobiOptions{}, o.tolerance, o.max_iterations))
                .solve(system, F, o.progress);
        case SolverKind::gauss_seidel:
            return GaussSeidel(with_cap(GaussSeidelOptions{}, o.tolerance, o.max_iterations))
                .solve(system, F, o.progress);
        case SolverKind::progressive:
            return Progressive(progressive_options(o)).solve(system, F, o.progress);
        case SolverKind::direct:
            return Direct().solve(system, F, o.progress);
    }
    throw Error("solve: unknown solver");
}

/// Computes form factors with `method` and solves: progressive shooting takes rows on demand
/// (no n x n matrix unless asked for); the other solvers gather over the assembled matrix.
template <SpectrumType S, FormFactorMethod M>
void solve_with(SolveResult<S>& result, const System<S>& system, M& method, const SolveOptions& o) {
    method.prepare(result.patches);
    const std::size_t n = result.patches.size();
    Solution<S> solution;
    if (o.solver == SolverKind::progressive && !o.keep_form_factors) {
        solution = Progressive(progressive_options(o)).solve(system, method, o.progress);
    } else {
        check_dense_budget(method, n, o.max_matrix_bytes);
        const auto t0 = std::chrono::steady_clock::now();
        DenseMatrix F = assemble_dense(method, n, o.progress);
        result.form_factor_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        solution = solve_assembled(system, F, o);
        if (o.keep_form_factors) result.form_factors = std::move(F);
    }
    result.report = solution.report;
    set_face_radiosity<S>(result.mesh, solution.radiosity);
}

}  // namespace detail

/// Solves the radiosity equation B = E + R F B on a scene (Goral et al. 1984; Cohen & Wallace
/// 1993): conforming subdivision (its report in the result), form factors by the chosen method,
/// the chosen solver. Throws Error on bad input, MemoryLimitError (before allocating) if the
/// dense matrix would exceed options.max_matrix_bytes, and Cancelled if the progress callback
/// stops the form factors.
template <SpectrumType S>
SolveResult<S> solve(const Mesh<S>& scene, const SolveOptions& options = {}) {
    if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
        throw Error("solve: tolerance must be a positive number, not " +
                    std::to_string(options.tolerance));
    Subdivided<S> meshed = subdivide_with_report(scene, options.subdivision);
    SolveResult<S> result;
    result.mesh = std::move(meshed.mesh);
    result.meshing = std::move(meshed.report);
    result.patches = make_patch_table(result.mesh);
    const std::vector<S> E = face_emission(result.mesh), R = face_reflectance(result.mesh);
    const System<S> system{E, R, result.patches.areas()};
    system.validate();
    switch (options.form_factor) {
        case FormFactorKind::analytic: {
            Analytic method(options.analytic);
            detail::solve_with(result, system, method, options);
            break;
        }
        case FormFactorKind::hemicube: {
            Hemicube method(options.hemicube);
            detail::solve_with(result, system, method, options);
            break;
        }
        case FormFactorKind::ray_cast: {
            RayCast method(options.ray_cast);
            detail::solve_with(result, system, method, options);
            break;
        }
    }
    return result;
}

}  // namespace radiosity
