// The meshing's invariant (mesh/conservation.hpp) refuses, naming the face, every way patches
// can fail to cover their face: the fan that concave polygons used to get (area 4 for an
// L-shaped hexagon of area 3, patches in its notch), a patch missing, a patch turned over, a
// patch moved into the notch (the area right, a centroid outside), an area off by more than
// 1e-9 of the face's; and accepts exact covers, in any plane, and faces left out (empty).
#include <radiosity/mesh/conservation.hpp>

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace radiosity;
using namespace radiosity::detail;

namespace {

/// The L-shaped hexagon of area 3: the unit square [1, 2] x [1, 2] cut out of [0, 2]^2.
const std::vector<Vec3> hexagon{{2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}};

/// A soup whose patches are the given polygons, all of input face `parent`.
PatchSoup soup_of(const std::vector<std::vector<Vec3>>& patches, std::size_t parent = 0) {
    PatchSoup s;
    for (const auto& p : patches) {
        std::vector<std::uint32_t> f;
        for (const Vec3& x : p) {
            f.push_back(static_cast<std::uint32_t>(s.points.size()));
            s.points.push_back(x);
        }
        s.faces.push_back(f);
        s.parent.push_back(parent);
        s.uvs.emplace_back();
        s.on.emplace_back(p.size());
    }
    return s;
}

std::vector<Vec3> square(double x, double y, double side = 1.0) {
    return {{x, y, 0}, {x + side, y, 0}, {x + side, y + side, 0}, {x, y + side, 0}};
}

/// The message check_conservation gives, or "" when it accepts.
std::string refusal(const PatchSoup& s, const std::vector<std::vector<Vec3>>& faces) {
    try {
        check_conservation(s, faces, std::vector<char>(faces.size(), 1));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("conservation: an exact cover of a concave face is accepted") {
    CHECK(refusal(soup_of({square(0, 0), square(1, 0), square(0, 1)}), {hexagon}).empty());
    // The same cover turned into another plane and moved far off the origin.
    auto place = [](const Vec3& p) { return Vec3(1e3 + p.y, -2e3 + 0.6 * p.x, 5e2 + 0.8 * p.x); };
    std::vector<std::vector<Vec3>> cover{square(0, 0), square(1, 0), square(0, 1)};
    std::vector<Vec3> face = hexagon;
    for (auto& p : cover)
        for (Vec3& x : p) x = place(x);
    for (Vec3& x : face) x = place(x);
    CHECK(refusal(soup_of(cover), {face}).empty());
    // A face left out on purpose (empty) is not checked; the other face still is.
    CHECK(refusal(soup_of({square(0, 0), square(1, 0), square(0, 1)}, 1), {{}, hexagon}).empty());
}

TEST_CASE("conservation: the fan of a concave face (area 4, patches in the notch) is refused") {
    // Fanned from its first corner, (2, 1), as concave polygons were: four triangles, the
    // second and third of them in the notch.
    std::vector<std::vector<Vec3>> fan;
    for (std::size_t k = 1; k + 1 < hexagon.size(); ++k)
        fan.push_back({hexagon[0], hexagon[k], hexagon[k + 1]});
    const std::string message = refusal(soup_of(fan), {hexagon});
    CHECK(message.find("mesh check: face 0") != std::string::npos);
}

TEST_CASE("conservation: a missing, turned or misplaced patch is refused, naming the face") {
    const std::vector<std::vector<Vec3>> faces{{}, hexagon};  // face 0 left out
    SUBCASE("missing") {
        const std::string m = refusal(soup_of({square(0, 0), square(1, 0)}, 1), faces);
        CHECK(m.find("mesh check: face 1: its 2 patches cover an area of 2") != std::string::npos);
    }
    SUBCASE("turned over") {
        std::vector<Vec3> turned = square(0, 1);
        std::swap(turned[1], turned[3]);
        const std::string m = refusal(soup_of({square(0, 0), square(1, 0), turned}, 1), faces);
        CHECK(m.find("mesh check: face 1: patch 2 faces the other way") != std::string::npos);
    }
    SUBCASE("in the notch, the area right") {
        const std::string m =
            refusal(soup_of({square(0, 0), square(1, 0), square(1, 1)}, 1), faces);
        CHECK(m.find("mesh check: face 1: the centroid of patch 2 lies outside the face") !=
              std::string::npos);
    }
    SUBCASE("an area off by 1e-8 of the face's") {
        std::vector<Vec3> wide = square(1, 0);
        wide[1].x += 1e-8;
        wide[2].x += 1e-8;
        const std::string m = refusal(soup_of({square(0, 0), wide, square(0, 1)}, 1), faces);
        CHECK(m.find("mesh check: face 1") != std::string::npos);
        // Off by 1e-11, within the 1e-9 the check allows: accepted.
        wide = square(1, 0);
        wide[1].x += 1e-11;
        wide[2].x += 1e-11;
        CHECK(refusal(soup_of({square(0, 0), wide, square(0, 1)}, 1), faces).empty());
    }
}
