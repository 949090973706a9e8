// The hemicube against the exact point-to-polygon form factor (what it approximates: F from the
// patch centre), the closed enclosures' identities, and visibility by depth.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/matrix.hpp>

#include "support/approx.hpp"
#include "support/refdata.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace radiosity;

namespace {

std::vector<float> hemicube_row(const PatchTable& t, std::size_t i, HemicubeOptions o = {}) {
    Hemicube h(o);
    h.prepare(t);
    std::vector<float> row(t.size());
    h.row(i, row);
    return row;
}

/// An axis-aligned square of side s centred at (cx, cy) in the plane z, facing +z or -z.
std::vector<Vec3> square(double cx, double cy, double z, double s, bool up) {
    const double h = s / 2;
    std::vector<Vec3> p{
        {cx - h, cy - h, z}, {cx + h, cy - h, z}, {cx + h, cy + h, z}, {cx - h, cy + h, z}};
    if (!up) std::reverse(p.begin(), p.end());
    return p;
}

}  // namespace

TEST_CASE("the delta form factors of the hemicube add up to 1") {
    // Each delta form factor is the kernel at its pixel's centre: the midpoint rule, whose sum
    // is off 1 by O(1 / r^2) (0.542 / r^2 at every resolution from 32 to 512).
    for (int r : {64, 128, 256}) {
        CAPTURE(r);
        const double sum = Hemicube({.resolution = r}).delta_form_factor_sum();
        CHECK(std::abs(sum - 1.0) < 0.6 / (double(r) * r));
    }
}

TEST_CASE("hemicube at the default resolution is within 2% of the exact point cases") {
    for (const std::string name :
         {"point_to_parallel_rect_corner_a1_b1_c1", "point_to_parallel_rect_centred_a1_b1_c1"}) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const PatchTable t = refdata::table(c);
        const std::size_t from = c["from"], to = c["to"];
        for (bool rotate : {false, true}) {
            const auto row = hemicube_row(t, from, {.resolution = 128, .rotate = rotate});
            CHECK(std::abs(row[to] - double(c["expected"])) / double(c["expected"]) < 0.02);
        }
    }
}

TEST_CASE("hemicube within 2% of the exact point-to-polygon value from the patch centre") {
    // On every scalar geometry of the reference cases, what the hemicube estimates is exactly
    // the point-to-polygon form factor at the centroid: compare against the contour integral.
    for (const auto& name : refdata::case_names("form_factor", "scalar")) {
        CAPTURE(name);
        const auto& c = refdata::find_case(name);
        const PatchTable t = refdata::table(c);
        for (auto [i, j] : {std::pair<std::size_t, std::size_t>{c["from"], c["to"]},
                            std::pair<std::size_t, std::size_t>{c["to"], c["from"]}}) {
            // The point cases' 1 mm source covers less than a pixel seen from the far square:
            // point sampling cannot resolve it (the method's aliasing), so skip that direction.
            if (c.contains("point_position") && i == std::size_t(c["to"])) continue;
            const double exact = point_to_polygon(t.centroid(i), t.normal(i), t.polygon(j));
            const auto row = hemicube_row(t, i);
            CHECK(std::abs(row[j] - exact) / exact < 0.02);
        }
    }
}

TEST_CASE("hemicube rows of a closed box sum to 1 and match the exact matrix to 2%") {
    const auto& c = refdata::find_case("closed_box_1x1x1");
    const PatchTable t = refdata::table(c);
    Hemicube h;
    h.prepare(t);
    const DenseMatrix F = assemble_dense(h, t.size());
    const MatrixCheck check = check_matrix(F, t.areas());
    CHECK(check.min_row_sum == test::approx(1.0).epsilon(1e-4));
    CHECK(check.max_row_sum == test::approx(1.0).epsilon(1e-4));
    // From the centre of a face the other faces are seen as: opposite 0.2 -> point value
    // differs from the area value, so compare with the point-to-polygon value at the centre.
    for (std::size_t i = 0; i < t.size(); ++i)
        for (std::size_t j = 0; j < t.size(); ++j) {
            if (i == j) {
                CHECK(F(i, j) == 0.0f);
                continue;
            }
            const double exact = point_to_polygon(t.centroid(i), t.normal(i), t.polygon(j));
            CHECK(std::abs(F(i, j) - exact) / exact < 0.02);
        }
}

TEST_CASE("a screen between two squares hides them from each other, its back absorbs") {
    PatchTable t;
    t.add(square(0, 0, 0, 1, true));   // 0: floor, faces up
    t.add(square(0, 0, 2, 1, false));  // 1: ceiling, faces down
    t.add(square(0, 0, 1, 3, true));   // 2: screen, its front towards the ceiling
    const auto row = hemicube_row(t, 0);
    CHECK(row[1] == 0.0f);  // fully hidden
    CHECK(row[2] == 0.0f);  // the screen shows the floor its back: occludes, takes nothing
    const auto from_ceiling = hemicube_row(t, 1);
    CHECK(from_ceiling[0] == 0.0f);
    const double exact = point_to_polygon(t.centroid(1), t.normal(1), t.polygon(2));
    CHECK(std::abs(from_ceiling[2] - exact) / exact < 0.02);
}

TEST_CASE("hemicube rows are deterministic and options are checked") {
    const auto& c = refdata::find_case("closed_box_1x1x1");
    const PatchTable t = refdata::table(c);
    // The same row before and after a row of another, larger scene on the same thread: the
    // per-thread buffers carry nothing over from one row to the next.
    const std::vector<float> first = hemicube_row(t, 3);
    PatchTable big;
    for (double dz : {0.0, 5.0})
        for (std::size_t i = 0; i < t.size(); ++i) {
            std::vector<Vec3> p(t.polygon(i).begin(), t.polygon(i).end());
            for (Vec3& v : p) v.z += dz;
            big.add(p);
        }
    REQUIRE(hemicube_row(big, 7).size() == big.size());
    CHECK(hemicube_row(t, 3) == first);
    CHECK_THROWS_AS(Hemicube({.resolution = 127}), Error);
    CHECK_THROWS_AS(Hemicube({.resolution = 0}), Error);
    Hemicube unprepared;
    std::vector<float> row(2);
    CHECK_THROWS_AS(unprepared.row(0, row), Error);
}

TEST_CASE("frustum outcodes: the SIMD path sets exactly the bits of the one-at-a-time definition") {
    using detail::Outcode;
    const double near = 1e-7;
    // Ties decide the bits: values equal to 0, +-near, and u = +-n, v = +-u, plus random ones.
    const std::vector<double> special = {0.0, -0.0, near, -near, 1.0, -1.0, 0.5, -0.5, 1e-300};
    std::uint64_t state = 42;
    auto random = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(static_cast<std::int64_t>(state >> 11) % 2001 - 1000) / 500.0;
    };
    std::uint32_t ever_set = 0, ever_clear = 0;
    for (double u : special)
        for (double v : special)
            for (double n : special) {
                const std::uint32_t code = Outcode::of_scalar(u, v, n, near);
                CHECK(Outcode::of(u, v, n, near) == code);
                ever_set |= code;
                ever_clear |= ~code;
            }
    // The special values reach both outcomes of every one of the 19 bits, so the comparison
    // above tested each bit both ways.
    constexpr std::uint32_t all_bits = (1u << 19) - 1;
    CHECK(ever_set == all_bits);
    CHECK((ever_clear & all_bits) == all_bits);
#if defined(__SSE2__)
    std::size_t differ = 0;
    for (int k = 0; k < 100000; ++k) {
        const double u = random(), v = random(), n = random();
        differ += Outcode::of(u, v, n, near) != Outcode::of_scalar(u, v, n, near);
    }
    CHECK(differ == 0);
#else
    // Without SSE2, Outcode::of is of_scalar: the comparisons above and below test only the
    // definitions (the ties), not a second path.
    MESSAGE("no SSE2 in this build: Outcode::of is of_scalar, no SIMD path to compare");
    (void)random;
#endif
    // Ties, bit by bit from the definitions: u = near is "u <= near"; u - n = 0 and v + n = 0 are
    // neither above nor below; n = -0 is on the horizon (n <= 0) but not under it (n < 0).
    using O = Outcode;
    const std::uint32_t tie = O::u_near | O::v_near | O::mu_near | O::mv_near | O::v_below_n |
                              O::u_above_mn | O::v_below_u | O::n_near;
    CHECK(Outcode::of_scalar(near, -near, near, near) == tie);
    CHECK(Outcode::of(near, -near, near, near) == tie);
    const std::uint32_t flat =
        O::u_near | O::v_near | O::mu_near | O::mv_near | O::n_near | O::horizon;
    CHECK(Outcode::of_scalar(0.0, 0.0, -0.0, near) == flat);
    CHECK(Outcode::of(0.0, 0.0, -0.0, near) == flat);
    // A vertex straight above the centre is inside the top face only.
    const std::uint32_t up = Outcode::of(0.0, 0.0, 1.0, near);
    CHECK((up & Outcode::face[0]) == 0u);
    for (std::size_t f = 1; f < 5; ++f) CHECK((up & Outcode::face[f]) != 0u);
    CHECK((Outcode::of(0.3, 0.1, -0.2, near) & Outcode::horizon) != 0u);
}
