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
#include <radiosity/hierarchy/hierarchical.hpp>
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
/// Which solver solve() uses: the dense ones over the n x n form factors, or hierarchical
/// radiosity with clustering (hierarchy/hierarchical.hpp), which needs no matrix.
enum class SolverKind { jacobi, gauss_seidel, progressive, direct, hierarchical };

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
    /// Hierarchical radiosity's settings (solver = hierarchical). Its roots are the scene's
    /// faces (cut where they cross, as `subdivision` says); where min_area is 0 it follows the
    /// meshing options: a quarter of max_area, or of max_edge squared (patches no finer than a
    /// dense solve at those options would make).
    HierarchicalOptions hierarchical{};
    /// A dense solve whose matrix would pass max_matrix_bytes is solved hierarchically instead
    /// of refused (SolveResult::chose_hierarchical says so). Programs set it when the user named
    /// no solver.
    bool hierarchical_when_too_big = false;
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
    /// The hierarchy's counts and times, when solved hierarchically.
    std::optional<HierarchyReport> hierarchy;
    /// True if the solve went hierarchical because the dense matrix was too big
    /// (SolveOptions::hierarchical_when_too_big).
    bool chose_hierarchical = false;
};

/// Parses a form-factor method name: "analytic", "hemicube" or "raycast". Throws Error
/// otherwise.
inline FormFactorKind parse_form_factor_kind(const std::string& name) {
    if (name == "analytic") return FormFactorKind::analytic;
    if (name == "hemicube") return FormFactorKind::hemicube;
    if (name == "raycast" || name == "ray-cast") return FormFactorKind::ray_cast;
    throw Error("unknown form-factor method '" + name + "' (known: analytic, hemicube, raycast)");
}

/// Parses a solver name: "jacobi", "gauss-seidel", "progressive", "direct" or "hierarchical".
/// Throws Error otherwise.
inline SolverKind parse_solver_kind(const std::string& name) {
    if (name == "jacobi") return SolverKind::jacobi;
    if (name == "gauss-seidel") return SolverKind::gauss_seidel;
    if (name == "progressive") return SolverKind::progressive;
    if (name == "direct") return SolverKind::direct;
    if (name == "hierarchical") return SolverKind::hierarchical;
    throw Error("unknown solver '" + name +
                "' (known: jacobi, gauss-seidel, progressive, direct, hierarchical)");
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
        case SolverKind::hierarchical:
            break;  // no matrix: solve() takes it apart (solve_hierarchically)
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

/// Hierarchical options with min_area from the meshing options where it is not set (see
/// SolveOptions::hierarchical).
inline HierarchicalOptions hierarchical_options(const SolveOptions& o) {
    HierarchicalOptions h = o.hierarchical;
    if (h.min_area > 0.0) return h;
    if (o.subdivision.max_area > 0.0)
        h.min_area = 0.25 * o.subdivision.max_area;
    else if (o.subdivision.max_edge > 0.0)
        h.min_area = 0.25 * o.subdivision.max_edge * o.subdivision.max_edge;
    return h;
}

/// The hierarchical path of solve(): the scene's faces as roots (cut where they cross, convex
/// pieces of concave faces), the leaves as the result's patches.
template <SpectrumType S>
SolveResult<S> solve_hierarchically(const Mesh<S>& scene, const SolveOptions& o) {
    if (o.keep_form_factors)
        throw Error("solve: the hierarchical solver makes no form-factor matrix to keep");
    SubdivisionOptions roots = o.subdivision;
    roots.max_edge = 0.0;
    roots.max_area = 0.0;
    roots.conforming = true;
    Subdivided<S> meshed = subdivide_with_report(scene, roots);
    SolveResult<S> result;
    result.meshing = std::move(meshed.report);
    HierarchicalResult<S> h = solve_hierarchical<S>(meshed.mesh, hierarchical_options(o),
                                                    o.tolerance, o.max_iterations, o.progress);
    result.mesh = std::move(h.mesh);
    result.patches = make_patch_table(result.mesh);
    result.report = h.report;
    result.hierarchy = h.hierarchy;
    return result;
}

}  // namespace detail

/// Solves the radiosity equation B = E + R F B on a scene (Goral et al. 1984; Cohen & Wallace
/// 1993): conforming subdivision (its report in the result), form factors by the chosen method,
/// the chosen solver; or hierarchical radiosity (solve_hierarchical), the path for large
/// scenes. Throws Error on bad input, MemoryLimitError (before allocating) if the dense matrix
/// would exceed options.max_matrix_bytes (unless hierarchical_when_too_big sends the solve
/// down the hierarchical path), and Cancelled if the progress callback stops the form factors
/// or the hierarchy's refinement.
template <SpectrumType S>
SolveResult<S> solve(const Mesh<S>& scene, const SolveOptions& options = {}) {
    if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
        throw Error("solve: tolerance must be a positive number, not " +
                    std::to_string(options.tolerance));
    if (options.solver == SolverKind::hierarchical)
        return detail::solve_hierarchically(scene, options);
    Subdivided<S> meshed = subdivide_with_report(scene, options.subdivision);
    SolveResult<S> result;
    result.mesh = std::move(meshed.mesh);
    result.meshing = std::move(meshed.report);
    result.patches = make_patch_table(result.mesh);
    const bool dense = options.solver != SolverKind::progressive || options.keep_form_factors;
    const std::size_t limit =
        options.max_matrix_bytes ? options.max_matrix_bytes : default_matrix_limit();
    if (options.hierarchical_when_too_big && dense &&
        dense_matrix_bytes(result.patches.size()) > double(limit)) {
        SolveOptions h = options;
        h.solver = SolverKind::hierarchical;
        h.keep_form_factors = false;
        SolveResult<S> out = detail::solve_hierarchically(scene, h);
        out.chose_hierarchical = true;
        return out;
    }
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
