#pragma once
/// @file concepts.hpp  The customisation points of the library, each stated as a contract.
/// A policy header ends with a static_assert that its type models its concept.

#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/vec.hpp>
#include <radiosity/progress.hpp>
#include <radiosity/solver/system.hpp>
#include <radiosity/spectrum.hpp>

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>

namespace radiosity {

/// Something that fills row i of the form-factor matrix: `rows.row(i, out)` writes F_ij for every
/// patch j into out (out.size() == n, F_ii = 0). Must be callable concurrently for different i
/// (it is const and keeps its scratch per call), and deterministic: row i never depends on which
/// rows were asked for before, nor on the thread that asks.
template <class R>
concept RowSource = requires(const R& rows, std::size_t i, std::span<float> out) {
    rows.row(i, out);
};

/// A form-factor method (analytic, hemicube, ray-cast): `method.prepare(table)` sees the patch
/// geometry once (building acceleration structures, keeping a reference to the table, which must
/// outlive the method's use); afterwards it is a RowSource over those patches.
template <class M>
concept FormFactorMethod = RowSource<M> && requires(M& method, const PatchTable& table) {
    method.prepare(table);
};

/// Optional capability of a form-factor method: one pair `method.pair(i, j)` = F_ij without
/// computing the whole row (analytic and ray-cast have it; the hemicube, which sees all patches
/// at once, does not).
template <class M>
concept PairFormFactor = FormFactorMethod<M> &&
    requires(const M& method, std::size_t i, std::size_t j) {
    { method.pair(i, j) } -> std::convertible_to<double>;
};

/// Optional capability of a pair method that is reciprocal by construction: `method.exchange(i,
/// j)` = A_i F_ij = A_j F_ji (the same number both ways) and `method.area(i)` = A_i. Assembly
/// then computes each pair once and fills both F_ij and F_ji, halving the work.
template <class M>
concept ReciprocalFormFactor = PairFormFactor<M> &&
    requires(const M& method, std::size_t i, std::size_t j) {
    { method.exchange(i, j) } -> std::convertible_to<double>;
    { method.area(i) } -> std::convertible_to<double>;
};

/// An assembled form-factor matrix (dense or sparse): its size, and a visit of the non-zero
/// entries of row i as f(j, F_ij).
template <class Mx>
concept AssembledMatrix = requires(const Mx& m, std::size_t i, void (*f)(std::size_t, float)) {
    { m.size() } -> std::convertible_to<std::size_t>;
    m.for_each_in_row(i, f);
};

/// An assembled matrix whose rows are stored as contiguous floats: `m.row(i)` views the n
/// entries F_i0 .. F_i(n-1). The sweeping solvers then gather with the vectorised dense kernel
/// (detail/dense_dot.hpp) instead of visiting entries one at a time.
template <class Mx>
concept DenseRowMatrix = AssembledMatrix<Mx> && requires(const Mx& m, std::size_t i) {
    { m.row(i) } -> std::convertible_to<std::span<const float>>;
};

/// A solver of the radiosity system (solver/system.hpp): `solver.solve(system, F, progress)`
/// returns B and a Report. F is an assembled matrix (Jacobi, Gauss-Seidel, direct) or, for
/// progressive shooting, any RowSource, so that rows can be computed on demand.
template <class X, class S, class Mx>
concept Solver = SpectrumType<S> &&
    requires(const X& solver, const System<S>& system, const Mx& F, const ProgressCallback& p) {
    { solver.solve(system, F, p) } -> std::same_as<Solution<S>>;
};

/// Something that answers "is the segment p -> q blocked?", the visibility term V of the form
/// factor: `v.occluded(p, q, a, b)` is true if the open segment between p and q meets any
/// surface other than patches a and b (the patches the segment starts and ends on, which must
/// not block it). Must be const and thread-safe. Form-factor methods build theirs over their
/// patch table, V(table) (RayCast<V>, Analytic<V>). Models: Bvh (geometry/bvh.hpp, the default),
/// BruteForceVisibility (geometry/brute_force_visibility.hpp, the definition), EmbreeVisibility
/// (geometry/embree.hpp, optional).
template <class V>
concept Visibility = requires(const V& v, const Vec3& p, const Vec3& q, std::uint32_t a,
                              std::uint32_t b) {
    { v.occluded(p, q, a, b) } -> std::convertible_to<bool>;
};

/// Optional capability of a Visibility: pair culling, proving without a ray that nothing can
/// stand between two patches (may_block, form_factor/pair_culling.hpp), so that a method casts
/// no ray for such a pair (a method without it casts rays for every pair, with the same answers).
/// It needs a walk of the model's triangles box by box: `v.any_triangle(enter, test)` opens only
/// the boxes (lo, hi) that enter accepts, passes each triangle in them to test until one returns
/// true, and returns whether one did; `v.box_slack()` bounds how far a box may reach beyond what
/// it holds, in any direction. Model: Bvh.
template <class V>
concept PairCulling = Visibility<V> && requires(const V& v, bool (*enter)(const Vec3&, const Vec3&),
                                                bool (*test)(const PatchTriangle&)) {
    { v.any_triangle(enter, test) } -> std::convertible_to<bool>;
    { v.box_slack() } -> std::convertible_to<double>;
};

}  // namespace radiosity
