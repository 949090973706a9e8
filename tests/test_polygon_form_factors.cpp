// Form factors to and through convex patches of many corners, as the meshing of polygons makes
// them (boundary pieces of a disk, with straight corners where a neighbour's point was
// inserted): every method against the closed form of a small patch above a coaxial disk,
// F = R^2 / (R^2 + h^2) (Howell's catalogue, B-13: differential area to a parallel coaxial
// disk), unscreened and screened by a smaller disk in between. Screened, the ray-cast estimate
// of a large, partly hidden patch is noisy at its default sample counts (about 7 % here, for
// squares as for disks); with 16,384 sample pairs its spread is about 0.5 %, well inside the
// tolerance.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/form_factor/ray_cast.hpp>
#include <radiosity/geometry/patch_table.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

using namespace radiosity;

namespace {

/// A disk of radius r in the plane z as an n-gon, each edge cut into `run` collinear pieces
/// (straight corners), facing +z (up) or -z.
std::vector<Vec3> disk(double r, double z, int n, int run, bool up) {
    std::vector<Vec3> p;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * k / n, b = 2 * std::numbers::pi * (k + 1) / n;
        const Vec3 from(r * std::cos(a), r * std::sin(a), z),
            to(r * std::cos(b), r * std::sin(b), z);
        for (int j = 0; j < run; ++j) p.push_back(from + (double(j) / run) * (to - from));
    }
    if (!up) std::reverse(p.begin(), p.end());
    return p;
}

/// A small square of side s centred on the axis at height z, facing down.
std::vector<Vec3> small_square(double s, double z) {
    const double h = s / 2;
    return {{-h, -h, z}, {-h, h, z}, {h, h, z}, {h, -h, z}};
}

double disk_factor(double r, double h) {
    return r * r / (r * r + h * h);
}

double relative_error(double x, double expected) {
    return std::abs(x - expected) / expected;
}

template <class Method>
std::vector<float> row_of(Method method, const PatchTable& t, std::size_t i) {
    method.prepare(t);
    std::vector<float> row(t.size());
    method.row(i, row);
    return row;
}

}  // namespace

TEST_CASE("a small patch above a 512-corner disk: every method matches the closed form") {
    PatchTable t;
    t.add(small_square(0.01, 1.0), "receiver");
    t.add(disk(1.0, 0.0, 64, 8, true), "disk");  // 512 corners, 448 of them straight
    REQUIRE(t.polygon(1).size() == 512);
    const double polygon = disk_factor(1.0, 1.0);  // the 64-gon's is 0.16 % below the disk's
    const double inscribed = 1.0 * std::cos(std::numbers::pi / 64);
    for (const auto& [name, row, tolerance] :
         {std::tuple{"analytic", row_of(Analytic{}, t, 0), 2e-3},
          std::tuple{"hemicube", row_of(Hemicube{}, t, 0), 2e-2},
          std::tuple{"ray-cast", row_of(RayCast{}, t, 0), 1e-2}}) {
        CAPTURE(std::string(name));
        REQUIRE(std::isfinite(row[1]));
        // Between the inscribed and the circumscribed disk's values.
        CHECK(row[1] <= disk_factor(1.0, 1.0) * (1 + tolerance));
        CHECK(row[1] >= disk_factor(inscribed, 1.0) * (1 - tolerance));
        MESSAGE(std::string(name) << ": F = " << row[1] << " (disk " << polygon << ")");
    }
}

TEST_CASE("screened by a 512-corner disk in between: hemicube and rays see the annulus") {
    // From the receiver at height 1, a disk of radius 0.25 at height 0.5 hides the floor disk out
    // to radius 0.5: the floor's visible part is the annulus 0.5 .. 1, F = 0.5 - 0.2 = 0.3, and the
    // screen itself takes 0.25^2 / (0.25^2 + 0.5^2) = 0.2.
    PatchTable t;
    t.add(small_square(0.01, 1.0), "receiver");
    t.add(disk(1.0, 0.0, 64, 8, true), "floor");
    t.add(disk(0.25, 0.5, 64, 8, true), "screen");
    const double floor = disk_factor(1.0, 1.0) - disk_factor(0.5, 1.0);
    const double screen = disk_factor(0.25, 0.5);
    const auto cube = row_of(Hemicube{}, t, 0);
    CHECK(relative_error(cube[1], floor) < 0.01);
    CHECK(relative_error(cube[2], screen) < 0.01);
    const auto rays = row_of(RayCast({.samples = 16384}), t, 0);
    CHECK(relative_error(rays[1], floor) < 0.02);
    CHECK(relative_error(rays[2], screen) < 0.01);
    MESSAGE("hemicube: F to the floor " << cube[1] << " (" << floor << "), to the screen "
                                        << cube[2] << " (" << screen << "); ray-cast " << rays[1]
                                        << " and " << rays[2]);
}
