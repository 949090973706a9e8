// The analytic method against the closed forms of the heat-transfer literature
// (../shared/refdata/cases.json): point-to-polygon values, area-to-area values (including the
// singular shared-edge cases), and the identities of closed enclosures.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/matrix.hpp>

#include "support/approx.hpp"
#include "support/refdata.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace radiosity;

namespace {
double relative_error(double value, double exact) {
    return std::abs(value - exact) / exact;
}
}  // namespace

TEST_CASE("point-to-polygon form factor matches the closed forms to 1e-9") {
    for (const std::string name :
         {"point_to_parallel_rect_corner_a1_b1_c1", "point_to_parallel_rect_centred_a1_b1_c1"}) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const auto poly = refdata::polygons(c);
        const double F = point_to_polygon(refdata::vec3(c["point_position"]),
                                          refdata::vec3(c["point_normal"]), poly[c["to"]]);
        CHECK(relative_error(F, c["expected"]) < 1e-9);
    }
}

TEST_CASE("the subtended angle equals atan2 to an ulp, in every octant and at the edges") {
    // The contour sum's arc tangent (detail::subtended_angle) against the C library's, on
    // seeded pairs spanning 30 decades and both signs of x, and on the folds' boundaries.
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    const auto ulps = [](double a, double b) {
        return std::abs(a - b) / (std::nextafter(std::abs(b), 4.0) - std::abs(b));
    };
    double worst = 0.0;
    for (int i = 0; i < 200000; ++i) {
        const double y = std::abs(g(rng)) * std::exp(8.0 * g(rng)),
                     x = g(rng) * std::exp(8.0 * g(rng));
        worst = std::max(worst, ulps(detail::subtended_angle(y, x), std::atan2(y, x)));
    }
    CHECK(worst <= 1.0);
    for (const double t : {0.0, 1e-300, 0.3, 0.66, std::nextafter(0.66, 1.0), 1.0, 1.5, 1e300})
        for (const double x : {1.0, -1.0}) {
            CAPTURE(t);
            CHECK(ulps(detail::subtended_angle(t, x), std::atan2(t, x)) <= 1.0);
            CHECK(ulps(detail::subtended_angle(1.0, x / (t > 0.0 ? t : 1.0)),
                       std::atan2(1.0, x / (t > 0.0 ? t : 1.0))) <= 1.0);
        }
    CHECK(detail::subtended_angle(0.0, 0.0) == 0.0);
    CHECK(detail::subtended_angle(0.0, -2.0) == std::numbers::pi);
    CHECK(detail::subtended_angle(3.0, 0.0) == std::atan2(3.0, 0.0));
}

TEST_CASE("point-to-polygon: one-sided, clipped to the horizon, zero behind") {
    const std::vector<Vec3> square{{-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}};  // faces -z
    const Vec3 origin(0.0), up(0, 0, 1);
    const double front = point_to_polygon(origin, up, square);
    CHECK(front > 0.0);
    // The same square turned round shows its back to the point: nothing arrives.
    const std::vector<Vec3> back(square.rbegin(), square.rend());
    CHECK(point_to_polygon(origin, up, back) == 0.0);
    // A receiver facing away sees nothing; one facing sideways sees exactly the half in front of
    // it, which by symmetry of the square is half of what a tilted... check the horizon clip by
    // splitting the square in two along x = 0: the two halves must add up to the whole.
    CHECK(point_to_polygon(origin, -up, square) == 0.0);
    const Vec3 side = glm::normalize(Vec3(1, 0, 1));
    const std::vector<Vec3> left{{-1, -1, 1}, {-1, 1, 1}, {0, 1, 1}, {0, -1, 1}};
    const std::vector<Vec3> right{{0, -1, 1}, {0, 1, 1}, {1, 1, 1}, {1, -1, 1}};
    const double whole = point_to_polygon(origin, side, square);
    CHECK(whole ==
          test::approx(point_to_polygon(origin, side, left) + point_to_polygon(origin, side, right))
              .epsilon(1e-12));
    // Unit hemisphere identity: a huge square right above covers almost the whole hemisphere.
    const double L = 1e4;
    const std::vector<Vec3> sky{{-L, -L, 1}, {-L, L, 1}, {L, L, 1}, {L, -L, 1}};
    CHECK(point_to_polygon(origin, up, sky) == test::approx(1.0).epsilon(1e-6));
}

TEST_CASE("area-to-area analytic form factors match every scalar closed form to 1e-6") {
    for (const auto& name : refdata::case_names("form_factor", "scalar")) {
        const auto& c = refdata::find_case(name);
        if (c.contains("point_position")) continue;  // point cases: see above
        CAPTURE(name);
        const PatchTable t = refdata::table(c);
        Analytic method;
        method.prepare(t);
        const std::size_t from = c["from"], to = c["to"];
        CHECK(relative_error(method.pair(from, to), c["expected"]) < 1e-6);
        CHECK(relative_error(method.pair(to, from), c["expected_reverse"]) < 1e-6);
    }
}

TEST_CASE("the small-patch point cases: area-to-area over a tiny square") {
    for (const std::string name :
         {"point_to_parallel_rect_corner_a1_b1_c1", "point_to_parallel_rect_centred_a1_b1_c1"}) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const PatchTable t = refdata::table(c);
        Analytic method;
        method.prepare(t);
        CHECK(relative_error(method.pair(c["from"], c["to"]), c["expected_small_patch"]) < 1e-6);
    }
}

TEST_CASE("closed enclosures: the exact matrices, row sums 1, exact reciprocity") {
    for (const std::string name : {"closed_box_1x1x1", "regular_tetrahedron"}) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const PatchTable t = refdata::table(c);
        Analytic method;
        method.prepare(t);
        const DenseMatrix F = assemble_dense(method, t.size());
        const auto expected = refdata::matrix(c["expected"]);
        for (std::size_t i = 0; i < t.size(); ++i)
            for (std::size_t j = 0; j < t.size(); ++j) {
                CAPTURE(i);
                CAPTURE(j);
                CHECK(F(i, j) == test::approx(expected[i][j]).epsilon(1e-6));
            }
        const MatrixCheck check = check_matrix(F, t.areas());
        CHECK(check.min_row_sum > 1.0 - 2e-6);
        CHECK(check.max_row_sum < 1.0 + 2e-6);
        CHECK(check.reciprocity_error < 1e-7);  // float storage; the doubles agree exactly
    }
}

TEST_CASE("reciprocity of the doubles is exact, also for unequal patches") {
    const auto& c = refdata::find_case("perpendicular_common_edge_w1_h2_l1");
    const PatchTable t = refdata::table(c);
    Analytic method;
    method.prepare(t);
    CHECK(t.area(0) * method.pair(0, 1) ==
          test::approx(t.area(1) * method.pair(1, 0)).epsilon(1e-15));
}

TEST_CASE("analytic options are checked") {
    CHECK_THROWS_AS(Analytic(AnalyticOptions{.tolerance = 0.0}), Error);
    CHECK_THROWS_AS(Analytic(AnalyticOptions{.max_depth = -1}), Error);
    CHECK_THROWS_AS(Analytic(AnalyticOptions{.visibility_samples = -1}), Error);
    CHECK_THROWS_AS(Analytic(AnalyticOptions{.penumbra_samples = 65537}), Error);
    Analytic unprepared;
    CHECK_THROWS_AS(unprepared.pair(0, 1), Error);
}
