// Ray-cast form factors and the BVH: the closed forms of ../shared/refdata/cases.json, rows of
// closed scenes with occluders summing to 1, a fully screened pair giving exactly 0,
// reciprocity, and results independent of the thread count.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/form_factor/pair_culling.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/geometry/bvh.hpp>
#include <radiosity/geometry/sampling.hpp>

#include "../benchmarks/support/rooms.hpp"
#include "support/approx.hpp"
#include "support/refdata.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(RADIOSITY_WITH_OPENMP)
#include <omp.h>
#endif

using namespace radiosity;

namespace {

double relative_error(double value, double exact) {
    return std::abs(value - exact) / exact;
}

using bench::add_box;

/// A closed room of side 4 (2 x 2 patches per wall) with a floating block in it.
PatchTable room_with_block() {
    PatchTable t;
    add_box(t, Vec3(0.0), Vec3(4.0), 2, true);
    add_box(t, Vec3(1.2, 1.4, 1.0), Vec3(2.6, 2.5, 2.2), 1, false);
    return t;
}

std::vector<Vec3> square(double z, double s, bool up) {
    const double h = s / 2;
    std::vector<Vec3> p{{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}};
    if (!up) std::reverse(p.begin(), p.end());
    return p;
}

}  // namespace

TEST_CASE("bvh: closest hits and occlusion against a hand-made scene") {
    PatchTable t;
    t.add(square(0.0, 2.0, true));   // 0
    t.add(square(1.0, 1.0, false));  // 1
    t.add(square(2.0, 2.0, false));  // 2
    const Bvh bvh(t);
    CHECK(bvh.triangle_count() == 6);
    const auto hit = bvh.intersect(Vec3(0.1, 0.2, 3.0), Vec3(0, 0, -1));
    REQUIRE(hit);
    CHECK(hit->patch == 2);
    CHECK(hit->t == test::approx(1.0));
    const auto below = bvh.intersect(Vec3(0.1, 0.2, 1.5), Vec3(0, 0, -1));
    REQUIRE(below);
    CHECK(below->patch == 1);
    CHECK(bvh.occluded({0.1, 0.2, 0.0}, {0.1, 0.2, 2.0}, 0, 2));   // square 1 in between
    CHECK(!bvh.occluded({0.9, 0.9, 0.0}, {0.9, 0.9, 2.0}, 0, 2));  // beside square 1
    CHECK(!bvh.intersect(Vec3(5, 5, 5), Vec3(0, 0, 1)));
}

namespace {
/// A patch index drawn uniformly.
std::uint32_t random_patch(const PatchTable& t, Rng& rng) {
    return static_cast<std::uint32_t>(rng.uniform() * double(t.size()));
}

/// A closed 4 x 4 x 4 room with nine blocks standing on its floor, sharing the floor's plane.
PatchTable cluttered_room() {
    PatchTable t;
    add_box(t, Vec3(0.0), Vec3(4.0), 3, true);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            add_box(t, Vec3(0.3 + a * 1.3, 0.0, 0.3 + b * 1.3),
                    Vec3(1.1 + a * 1.3, 0.5 + 0.4 * a, 1.1 + b * 1.3), 2, false);
    return t;
}
}  // namespace

TEST_CASE("bvh answers exactly as testing every triangle, on random rays in a cluttered room") {
    // The reference: one leaf holding all triangles (every triangle tested, through the same
    // single-precision filter and double test): this checks the tree's traversal; the exact test
    // itself is checked against plain double arithmetic below.
    const PatchTable t = cluttered_room();
    const Bvh bvh(t), brute(t, {.bins = 16, .max_leaf_size = 1 << 30});
    REQUIRE(brute.node_count() == 1);
    Rng rng(7);
    std::vector<Vec3> xs, ys;
    int disagree = 0, blocked = 0;
    for (int k = 0; k < 4000; ++k) {
        const std::uint32_t a = random_patch(t, rng), b = random_patch(t, rng);
        if (a == b) continue;
        jittered_pairs(t.polygon(a), t.polygon(b), 1, rng, xs, ys);
        const bool hidden = bvh.occluded(xs[0], ys[0], a, b);
        blocked += hidden;
        disagree += hidden != brute.occluded(xs[0], ys[0], a, b);
        const auto h1 = bvh.intersect(xs[0], ys[0] - xs[0], 1e-9);
        const auto h2 = brute.intersect(xs[0], ys[0] - xs[0], 1e-9);
        disagree +=
            bool(h1) != bool(h2) ||
            (h1 && h1->t != h2->t);  // same t, maybe another patch: block bottoms lie on the floor
    }
    CHECK(disagree == 0);
    CHECK(blocked > 100);  // the scene really is cluttered
}

namespace {

/// The reference for the BVH's single-precision filter: Woop et al.'s watertight test in double
/// precision, written out again, on every fan triangle of every patch but a and b.
bool blocked_by_any_triangle(const PatchTable& t, const Vec3& p, const Vec3& q, std::uint32_t a,
                             std::uint32_t b) {
    const Vec3 dir = q - p, m = glm::abs(dir);
    const double* d = glm::value_ptr(dir);
    const int kz = m.x > m.y ? (m.x > m.z ? 0 : 2) : (m.y > m.z ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    if (d[kz] < 0.0) std::swap(kx, ky);
    const double sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
    for (std::uint32_t i = 0; i < t.size(); ++i) {
        if (i == a || i == b) continue;
        const auto poly = t.polygon(i);
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            const Vec3 dA = poly[0] - p, dB = poly[k] - p, dC = poly[k + 1] - p;
            const double *A = glm::value_ptr(dA), *B = glm::value_ptr(dB), *C = glm::value_ptr(dC);
            const double ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
            const double bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
            const double cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
            const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
            if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) continue;
            const double det = U + V + W;
            if (det == 0.0) continue;
            const double hit = sz * (U * A[kz] + V * B[kz] + W * C[kz]) / det;
            if (hit > 1e-9 && hit < 1.0 - 1e-9) return true;
        }
    }
    return false;
}

}  // namespace

TEST_CASE("bvh occlusion is exactly the double-precision watertight test of every triangle") {
    // Random segments, and segments between centroids and vertices of patches that share planes
    // and edges (where single-precision shortcuts would go wrong first).
    const PatchTable t = cluttered_room();
    const Bvh bvh(t);
    Rng rng(11);
    std::vector<Vec3> xs, ys;
    int disagree = 0, blocked = 0;
    for (int k = 0; k < 3000; ++k) {
        const std::uint32_t a = random_patch(t, rng), b = random_patch(t, rng);
        if (a == b) continue;
        jittered_pairs(t.polygon(a), t.polygon(b), 1, rng, xs, ys);
        const std::array<std::array<Vec3, 2>, 3> segments{
            {{xs[0], ys[0]}, {t.centroid(a), t.centroid(b)}, {t.polygon(a)[0], t.polygon(b)[1]}}};
        for (const auto& [p, q] : segments) {
            const bool hidden = bvh.occluded(p, q, a, b);
            blocked += hidden;
            disagree += hidden != blocked_by_any_triangle(t, p, q, a, b);
        }
    }
    CHECK(disagree == 0);
    CHECK(blocked > 1000);
}

TEST_CASE("bvh is watertight: rays through shared edges and vertices never slip through") {
    // A fan of triangles around the origin; rays aimed exactly at the shared edges and centre.
    PatchTable t;
    const int n = 12;
    for (int k = 0; k < n; ++k) {
        const double a0 = 2 * std::numbers::pi * k / n, a1 = 2 * std::numbers::pi * (k + 1) / n;
        t.add(std::vector<Vec3>{
            {0, 0, 0}, {std::cos(a0), std::sin(a0), 0}, {std::cos(a1), std::sin(a1), 0}});
    }
    const Bvh bvh(t);
    int misses = 0;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * k / n;
        for (double r : {0.0, 0.25, 0.5, 0.75}) {
            const Vec3 target(r * std::cos(a), r * std::sin(a), 0.0);
            for (const Vec3& from : {Vec3(0.3, -0.2, 1.0), Vec3(-0.7, 0.1, -2.0)})
                if (!bvh.intersect(from, target - from)) ++misses;
        }
    }
    CHECK(misses == 0);
}

TEST_CASE("ray-cast at default settings is within 1% of every form-factor closed form") {
    for (const auto& name : refdata::case_names("form_factor", "scalar")) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const PatchTable t = refdata::table(c);
        RayCast method;
        method.prepare(t);
        const std::size_t from = c["from"], to = c["to"];
        const bool point = c.contains("point_position");
        const double forward = point ? double(c["expected_small_patch"]) : double(c["expected"]);
        CHECK(relative_error(method.pair(from, to), forward) < 0.01);
        if (!point) CHECK(relative_error(method.pair(to, from), c["expected_reverse"]) < 0.01);
    }
    for (const std::string name : {"closed_box_1x1x1", "regular_tetrahedron"}) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const PatchTable t = refdata::table(c);
        RayCast method;
        method.prepare(t);
        const auto expected = refdata::matrix(c["expected"]);
        const DenseMatrix F = assemble_dense(method, t.size());
        for (std::size_t i = 0; i < t.size(); ++i)
            for (std::size_t j = 0; j < t.size(); ++j)
                if (i != j) CHECK(relative_error(F(i, j), expected[i][j]) < 0.01);
    }
}

TEST_CASE("a larger square between two squares screens them completely: F = 0 exactly") {
    PatchTable t;
    t.add(square(0.0, 1.0, true));   // floor
    t.add(square(2.0, 1.0, false));  // ceiling
    t.add(square(1.0, 3.0, true));   // screen
    RayCast ray_cast;
    ray_cast.prepare(t);
    CHECK(ray_cast.pair(0, 1) == 0.0);
    CHECK(ray_cast.pair(1, 0) == 0.0);
    Analytic analytic({.visibility_samples = 16, .penumbra_samples = 256});
    analytic.prepare(t);
    CHECK(analytic.pair(0, 1) == 0.0);
}

TEST_CASE("closed room with a block: every row of every method with visibility sums to 1") {
    // The analytic method's visibility at 256 penumbra rays per partly hidden pair; the
    // ray-cast method at its default (tests/test_row_sums.cpp holds it to 1e-3).
    const PatchTable t = room_with_block();
    RayCast ray_cast;
    Analytic analytic({.visibility_samples = 16, .penumbra_samples = 256});
    Hemicube hemicube;
    ray_cast.prepare(t);
    analytic.prepare(t);
    hemicube.prepare(t);
    const DenseMatrix by_rays = assemble_dense(ray_cast, t.size());
    const DenseMatrix by_analytic = assemble_dense(analytic, t.size());
    const DenseMatrix by_hemicube = assemble_dense(hemicube, t.size());
    for (const DenseMatrix* F : {&by_rays, &by_analytic, &by_hemicube}) {
        const MatrixCheck check = check_matrix(*F, t.areas());
        CHECK(check.min_row_sum > 0.99);
        CHECK(check.max_row_sum < 1.01);
    }
    // Reciprocity within 2%. (The hemicube, which sees each patch from its centre only, is not
    // reciprocal by construction; with these coarse 2 x 2 walls it is off by about 8%.)
    CHECK(check_matrix(by_rays, t.areas()).reciprocity_error < 0.02);
    CHECK(check_matrix(by_analytic, t.areas()).reciprocity_error < 0.02);
}

TEST_CASE("ray-cast rows are bit-identical for 1 and N threads") {
    const PatchTable t = room_with_block();
    RayCast method;
    method.prepare(t);
#if defined(RADIOSITY_WITH_OPENMP)
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    const DenseMatrix one = assemble_dense(method, t.size());
    omp_set_num_threads(std::max(2, before));
    const DenseMatrix many = assemble_dense(method, t.size());
    omp_set_num_threads(before);
#else
    const DenseMatrix one = assemble_dense(method, t.size());
    // Serially, rows asked for in reverse order must still come out the same.
    DenseMatrix many(t.size());
    for (std::size_t i = t.size(); i-- > 0;) method.row(i, many.row(i));
#endif
    bool identical = true;
    for (std::size_t i = 0; i < t.size(); ++i)
        identical = identical && std::memcmp(one.row(i).data(), many.row(i).data(),
                                             t.size() * sizeof(float)) == 0;
    CHECK(identical);
}

TEST_CASE("ray-cast options are checked") {
    CHECK_THROWS_AS(RayCast({.samples = 0}), Error);
    CHECK_THROWS_AS(RayCast({.samples = 64, .max_samples = 32}), Error);
    CHECK_THROWS_AS(RayCast({.max_samples = 65537}), Error);
    CHECK_THROWS_AS(RayCast({.samples_per_form_factor = -1.0}), Error);
    RayCast unprepared;
    CHECK_THROWS_AS(unprepared.pair(0, 1), Error);
}

TEST_CASE("pair culling: a pair with nothing between it and its walls needs no ray") {
    // Floor and ceiling of an empty box: the walls lie on the pair's bounding box, so nothing
    // can block; with a block between them, something may.
    PatchTable empty;
    add_box(empty, Vec3(0.0), Vec3(1.0), 1, true);
    const Bvh bvh(empty);
    const std::array<Vec3, 2> floor{empty.centroid(0), empty.normal(0)};
    const std::array<Vec3, 2> ceiling{empty.centroid(1), empty.normal(1)};
    CHECK(!may_block(bvh, Vec3(0.0), Vec3(1.0), 0, 1, floor, ceiling, 1e-12));
    PatchTable cluttered = empty;
    add_box(cluttered, Vec3(0.4), Vec3(0.6), 1, false);
    const Bvh with_block(cluttered);
    CHECK(may_block(with_block, Vec3(0.0), Vec3(1.0), 0, 1, floor, ceiling, 1e-12));
}
