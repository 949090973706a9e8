// The contracts of concepts.hpp (and of the concepts that live beside their policies) reject
// what breaks them: for each concept, a small model with every requirement is accepted, and
// models that each miss exactly one requirement (a member absent, const missing, a result of
// the wrong type) are rejected at compile time; the library's own types are accepted, and
// rejected where they lack an optional capability. Everything here is a static_assert: the
// file compiles only if each holds. Two test cases then run minimal models through the library.
#include <radiosity/concepts.hpp>
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/geometry/brute_force_visibility.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/solver/direct.hpp>
#include <radiosity/solver/gauss_seidel.hpp>
#include <radiosity/solver/jacobi.hpp>
#include <radiosity/solver/progressive.hpp>
#if defined(RADIOSITY_WITH_EMBREE)
#include <radiosity/geometry/embree.hpp>
#endif

#include "support/approx.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

using namespace radiosity;

namespace {

// ---- RowSource: a const row(i, out) -------------------------------------------------------

struct Rows {
    void row(std::size_t, std::span<float>) const {}
};
struct RowsNotConst {  // row() must be callable on a const source (rows are computed in parallel)
    void row(std::size_t, std::span<float>) {}
};
struct RowsWrongSpan {  // out must be a span of floats
    void row(std::size_t, std::span<double>) const {}
};
struct NoRows {};

static_assert(RowSource<Rows>);
static_assert(!RowSource<RowsNotConst>);
static_assert(!RowSource<RowsWrongSpan>);
static_assert(!RowSource<NoRows>);

// ---- FormFactorMethod: a RowSource with prepare(table) ------------------------------------

struct Method {
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
};
struct MethodWithoutPrepare {
    void row(std::size_t, std::span<float>) const {}
};
struct MethodWithoutRow {
    void prepare(const PatchTable&) {}
};
struct MethodPreparingOnWhat {  // prepare takes something else than the patch table
    void prepare(const std::string&) {}
    void row(std::size_t, std::span<float>) const {}
};

static_assert(FormFactorMethod<Method>);
static_assert(!FormFactorMethod<MethodWithoutPrepare>);
static_assert(!FormFactorMethod<MethodWithoutRow>);
static_assert(!FormFactorMethod<MethodPreparingOnWhat>);

// ---- PairFormFactor: a FormFactorMethod with a const pair(i, j) -> double -----------------

struct Pairs {
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    double pair(std::size_t, std::size_t) const { return 0.0; }
};
struct PairsNotConst {
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    double pair(std::size_t, std::size_t) { return 0.0; }
};
struct PairsOfNothing {  // pair() gives no number
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    void pair(std::size_t, std::size_t) const {}
};
struct PairsWithoutPrepare {  // a pair method must still be a FormFactorMethod
    void row(std::size_t, std::span<float>) const {}
    double pair(std::size_t, std::size_t) const { return 0.0; }
};

static_assert(PairFormFactor<Pairs>);
static_assert(!PairFormFactor<PairsNotConst>);
static_assert(!PairFormFactor<PairsOfNothing>);
static_assert(!PairFormFactor<PairsWithoutPrepare>);

// ---- ReciprocalFormFactor: a PairFormFactor with exchange(i, j) and area(i) ---------------

struct Reciprocal {
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    double pair(std::size_t, std::size_t) const { return 0.0; }
    double exchange(std::size_t, std::size_t) const { return 0.0; }
    double area(std::size_t) const { return 1.0; }
};
struct ReciprocalWithoutArea {
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    double pair(std::size_t, std::size_t) const { return 0.0; }
    double exchange(std::size_t, std::size_t) const { return 0.0; }
};
struct ReciprocalWithoutExchange {
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    double pair(std::size_t, std::size_t) const { return 0.0; }
    double area(std::size_t) const { return 1.0; }
};
struct ReciprocalWithoutPair {  // exchange without pair is not enough
    void prepare(const PatchTable&) {}
    void row(std::size_t, std::span<float>) const {}
    double exchange(std::size_t, std::size_t) const { return 0.0; }
    double area(std::size_t) const { return 1.0; }
};

static_assert(ReciprocalFormFactor<Reciprocal>);
static_assert(!ReciprocalFormFactor<ReciprocalWithoutArea>);
static_assert(!ReciprocalFormFactor<ReciprocalWithoutExchange>);
static_assert(!ReciprocalFormFactor<ReciprocalWithoutPair>);

// ---- AssembledMatrix: size() and for_each_in_row(i, f) ------------------------------------

struct Matrix {
    std::size_t size() const { return 0; }
    template <class F>
    void for_each_in_row(std::size_t, F&&) const {}
};
struct MatrixWithoutSize {
    template <class F>
    void for_each_in_row(std::size_t, F&&) const {}
};
struct MatrixWithoutVisit {
    std::size_t size() const { return 0; }
};
struct MatrixSizedByName {  // size() must give a count
    std::string size() const { return "n"; }
    template <class F>
    void for_each_in_row(std::size_t, F&&) const {}
};

static_assert(AssembledMatrix<Matrix>);
static_assert(!AssembledMatrix<MatrixWithoutSize>);
static_assert(!AssembledMatrix<MatrixWithoutVisit>);
static_assert(!AssembledMatrix<MatrixSizedByName>);

// ---- DenseRowMatrix: an AssembledMatrix whose row(i) views contiguous floats --------------

struct DenseRows {
    std::size_t size() const { return 0; }
    template <class F>
    void for_each_in_row(std::size_t, F&&) const {}
    std::span<const float> row(std::size_t) const { return {}; }
};
struct DenseRowsOfDoubles {  // the dense kernel reads floats
    std::size_t size() const { return 0; }
    template <class F>
    void for_each_in_row(std::size_t, F&&) const {}
    std::span<const double> row(std::size_t) const { return {}; }
};
struct DenseRowsWithoutVisit {  // still an AssembledMatrix first
    std::size_t size() const { return 0; }
    std::span<const float> row(std::size_t) const { return {}; }
};

static_assert(DenseRowMatrix<DenseRows>);
static_assert(!DenseRowMatrix<DenseRowsOfDoubles>);
static_assert(!DenseRowMatrix<DenseRowsWithoutVisit>);
static_assert(!DenseRowMatrix<Matrix>);

// ---- Solver: solve(system, F, progress) -> Solution<S> -------------------------------------

struct Solves {
    template <class S, class Mx>
    Solution<S> solve(const System<S>&, const Mx&, const ProgressCallback&) const {
        return {};
    }
};
struct SolvesNotConst {
    template <class S, class Mx>
    Solution<S> solve(const System<S>&, const Mx&, const ProgressCallback&) {
        return {};
    }
};
struct SolvesToPlainValues {  // the result must be a Solution (B and its Report)
    template <class S, class Mx>
    std::vector<S> solve(const System<S>&, const Mx&, const ProgressCallback&) const {
        return {};
    }
};
struct SolvesWithoutProgress {  // long work takes a progress callback
    template <class S, class Mx>
    Solution<S> solve(const System<S>&, const Mx&) const {
        return {};
    }
};

static_assert(Solver<Solves, Rgb, DenseMatrix>);
static_assert(!Solver<SolvesNotConst, Rgb, DenseMatrix>);
static_assert(!Solver<SolvesToPlainValues, Rgb, DenseMatrix>);
static_assert(!Solver<SolvesWithoutProgress, Rgb, DenseMatrix>);
static_assert(!Solver<Solves, std::string, DenseMatrix>);  // not a colour type

// ---- Visibility: a const occluded(p, q, a, b) -> bool -------------------------------------

struct Sees {
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const { return false; }
};
struct SeesNotConst {  // queries run on many threads at once
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) { return false; }
};
struct SeesWithoutEndPatches {  // the end patches must be named, or they block their own rays
    bool occluded(const Vec3&, const Vec3&) const { return false; }
};
struct SeesNothingUseful {  // no yes-or-no answer
    void occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const {}
};

static_assert(Visibility<Sees>);
static_assert(!Visibility<SeesNotConst>);
static_assert(!Visibility<SeesWithoutEndPatches>);
static_assert(!Visibility<SeesNothingUseful>);

// ---- PairCulling: a Visibility with any_triangle(enter, test) and box_slack() -------------

struct Culls {
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const { return false; }
    template <class Enter, class Test>
    bool any_triangle(Enter&&, Test&&) const {
        return false;
    }
    double box_slack() const { return 0.0; }
};
struct CullsWithoutSlack {  // pruning by planes needs to know how loose the boxes are
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const { return false; }
    template <class Enter, class Test>
    bool any_triangle(Enter&&, Test&&) const {
        return false;
    }
};
struct CullsWithoutWalk {
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const { return false; }
    double box_slack() const { return 0.0; }
};
struct CullsButCannotSee {  // pair culling is a capability of a Visibility
    template <class Enter, class Test>
    bool any_triangle(Enter&&, Test&&) const {
        return false;
    }
    double box_slack() const { return 0.0; }
};

static_assert(PairCulling<Culls>);
static_assert(!PairCulling<CullsWithoutSlack>);
static_assert(!PairCulling<CullsWithoutWalk>);
static_assert(!PairCulling<CullsButCannotSee>);

// ---- SpectrumType: the colour types -------------------------------------------------------

static_assert(SpectrumType<float> && SpectrumType<Rgb> && SpectrumType<Spectrum<3>>);
static_assert(!SpectrumType<int*> && !SpectrumType<std::string>);

// ---- Minimal models at work: what a concept accepts is all the library's code needs -------

/// The smallest form-factor method: each patch gives every other an equal share of its row.
struct EqualShares {
    std::size_t n = 0;
    void prepare(const PatchTable& t) { n = t.size(); }
    void row(std::size_t i, std::span<float> out) const {
        for (std::size_t j = 0; j < out.size(); ++j)
            out[j] = j == i ? 0.0f : 1.0f / static_cast<float>(n - 1);
    }
};
static_assert(FormFactorMethod<EqualShares> && !PairFormFactor<EqualShares>);

/// Visibility models built from a table that see through everything, or nothing.
struct NothingInTheWay {
    explicit NothingInTheWay(const PatchTable&) {}
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const { return false; }
};
struct AlwaysBlocked {
    explicit AlwaysBlocked(const PatchTable&) {}
    bool occluded(const Vec3&, const Vec3&, std::uint32_t, std::uint32_t) const { return true; }
};

/// A square of side 1 at height z, facing up or down.
std::vector<Vec3> square(double z, double side, bool up) {
    const double h = side / 2;
    std::vector<Vec3> p{{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}};
    if (!up) std::reverse(p.begin(), p.end());
    return p;
}

// ---- The library's own types --------------------------------------------------------------

static_assert(ReciprocalFormFactor<Analytic<>> && ReciprocalFormFactor<RayCast<>>);
static_assert(ReciprocalFormFactor<RayCast<BruteForceVisibility>> &&
              ReciprocalFormFactor<Analytic<BruteForceVisibility>>);
static_assert(FormFactorMethod<Hemicube> && !PairFormFactor<Hemicube>);  // rows only
static_assert(RowSource<DenseMatrix> && AssembledMatrix<DenseMatrix> &&
              AssembledMatrix<SparseMatrix>);
static_assert(DenseRowMatrix<DenseMatrix> && !DenseRowMatrix<SparseMatrix>);
static_assert(Solver<Jacobi, Rgb, DenseMatrix> && Solver<GaussSeidel, float, SparseMatrix>);
static_assert(Solver<Direct, Spectrum<4>, DenseMatrix> && Solver<Progressive, Rgb, DenseMatrix>);
static_assert(Solver<Progressive, Rgb, Hemicube>);  // shooting computes rows on demand
static_assert(Visibility<Bvh> && PairCulling<Bvh>);
static_assert(Visibility<BruteForceVisibility> && !PairCulling<BruteForceVisibility>);
static_assert(!Visibility<Hemicube> && !FormFactorMethod<Bvh>);
#if defined(RADIOSITY_WITH_EMBREE)
static_assert(Visibility<EmbreeVisibility> && !PairCulling<EmbreeVisibility>);
#endif

// The methods take any Visibility built over a patch table, and nothing else.
template <class V>
concept RayCastable = requires {
    typename RayCast<V>;
};
static_assert(RayCastable<Bvh> && RayCastable<BruteForceVisibility>);
static_assert(!RayCastable<Sees>);  // a Visibility, but not built from a patch table
static_assert(!RayCastable<Hemicube>);

}  // namespace

// The static_asserts above are this file's main test: it compiles only if each holds. The test
// cases below run minimal models through the library's generic code.

TEST_CASE("a method with only the members FormFactorMethod requires is assembled and solved") {
    // A closed box whose six faces give each other equal shares: rows sum to 1, so a uniform
    // emission E and reflectance R give the furnace solution B = E / (1 - R) = 2 here.
    PatchTable t;
    for (int axis = 0; axis < 6; ++axis) t.add(square(double(axis), 1.0, axis % 2 == 0));
    EqualShares method;
    method.prepare(t);
    const DenseMatrix F = assemble_dense(method, t.size());
    const MatrixCheck check = check_matrix(F, t.areas());
    CHECK(check.min_row_sum == test::approx(1.0).epsilon(1e-6));
    CHECK(check.max_row_sum == test::approx(1.0).epsilon(1e-6));
    const std::vector<float> E(t.size(), 1.0f), R(t.size(), 0.5f);
    const System<float> system{E, R, t.areas()};
    const Solution<float> B = Jacobi({.tolerance = 1e-7}).solve(system, F);
    REQUIRE(B.report.converged);
    for (float b : B.radiosity) CHECK(b == test::approx(2.0).epsilon(1e-5));
}

TEST_CASE("a Visibility with only occluded() and a constructor from the table plugs into RayCast") {
    // Floor and ceiling 2 apart, a larger screen halfway between them: the BVH sees the screen
    // (F = 0); a model that sees through everything gives the unoccluded value, the brute force
    // without the screen's patch the same (identical rays, none blocked); one that blocks
    // everything gives 0. The method's answer is its model's.
    PatchTable t;
    t.add(square(0.0, 1.0, true));   // 0: floor
    t.add(square(2.0, 1.0, false));  // 1: ceiling
    t.add(square(1.0, 3.0, true));   // 2: screen
    PatchTable open;
    open.add(square(0.0, 1.0, true));
    open.add(square(2.0, 1.0, false));
    RayCast<NothingInTheWay> through;
    RayCast<AlwaysBlocked> blocked;
    RayCast<BruteForceVisibility> brute;
    RayCast<> bvh;
    through.prepare(t);
    blocked.prepare(t);
    brute.prepare(open);
    bvh.prepare(t);
    const double unoccluded = through.pair(0, 1);
    // Parallel unit squares 2 apart (Howell C-11, X = Y = 1/2): F = 0.0685896.
    CHECK(unoccluded == test::approx(0.0685896).epsilon(1e-3));
    CHECK(unoccluded == brute.pair(0, 1));
    CHECK(blocked.pair(0, 1) == 0.0);
    CHECK(bvh.pair(0, 1) == 0.0);
    Analytic<NothingInTheWay> analytic({.visibility_samples = 16});
    analytic.prepare(t);
    CHECK(analytic.pair(0, 1) == test::approx(unoccluded).epsilon(0.01));
}
