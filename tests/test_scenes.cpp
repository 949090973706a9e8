// The built-in Cornell box against the published data (../shared/refdata/cases.json,
// "cornell_box"): surfaces face into the box, the light is cut out of the ceiling with the
// published size and exitance, the box is conforming, and the empty box's light-to-wall form
// factors match the published values.
#include <radiosity/form_factor/analytic.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include "support/approx.hpp"
#include "support/refdata.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <numbers>

using namespace radiosity;

namespace {

const nlohmann::json& published() {
    return refdata::document()["cornell_box"];
}

double published_area(const std::string& polygon) {
    std::vector<Vec3> p;
    for (const auto& v : published()["polygons"][polygon]) p.push_back(refdata::vec3(v));
    return polygon_area(p);
}

std::string material_name(const Scene<Rgb>& s, std::size_t face) {
    return s.materials[s.face_material[face]].name;
}

}  // namespace

TEST_CASE("Cornell box: the light is cut out of the ceiling, with the published exitance") {
    const Scene<Rgb> s = cornell_box<Rgb>();
    const auto mesh = build_mesh(s);
    double light = 0.0, ceiling = 0.0;
    const auto radiance = published()["rgb"]["light_radiance"];
    for (auto f : mesh.faces()) {
        const auto poly = face_polygon(mesh, f);
        const bool top = std::abs(polygon_centroid(poly).y - 548.8) < 1e-9;
        const std::string name = material_name(s, static_cast<std::size_t>(f.idx()));
        if (name == "light") {
            light += polygon_area(poly);
            for (std::size_t k = 0; k < 3; ++k)
                CHECK(band(mesh.data(f).emission, k) ==
                      test::approx(std::numbers::pi * radiance[k].get<double>()));
        } else if (top) {
            ceiling += polygon_area(poly);
            CHECK(max_abs(mesh.data(f).emission) == 0.0f);
        }
    }
    CHECK(light == test::approx(published_area("light")).epsilon(1e-12));
    CHECK(light + ceiling == test::approx(published_area("ceiling")).epsilon(1e-12));
}

TEST_CASE("Cornell box: walls face into the box, block faces out of their block") {
    const Scene<Rgb> s = cornell_box<Rgb>();
    const auto mesh = build_mesh(s);
    const Vec3 centre(278.0, 274.4, 279.6);
    const Vec3 short_block(186.0, 82.5, 168.5), tall_block(368.5, 165.0, 351.25);
    std::size_t blocks = 0;
    for (auto f : mesh.faces()) {
        const auto poly = face_polygon(mesh, f);
        const Vec3 c = polygon_centroid(poly), n = polygon_normal(poly);
        const bool in_block =
            c.y > 1e-6 && c.y < 548.8 - 1e-6 && c.x > 50 && c.x < 500 && c.z > 50 && c.z < 500;
        if (in_block) {
            ++blocks;
            const Vec3& block = c.x < 300 && c.z < 280 && c.y <= 165 ? short_block : tall_block;
            CHECK(glm::dot(n, c - block) > 0.0);
        } else {
            CHECK(glm::dot(n, centre - c) > 0.0);
        }
    }
    CHECK(blocks == 10);
    // Published reflectances, as given.
    const auto rgb = published()["rgb"];
    for (const auto& m : s.materials) {
        if (m.name == "light") continue;
        for (std::size_t k = 0; k < 3; ++k)
            CHECK(band(m.reflectance, k) == test::approx(rgb[m.name][k].get<double>()));
    }
}

TEST_CASE("Cornell box: conforming, open only at the front and under the blocks") {
    const auto mesh = build_mesh(cornell_box<Rgb>());
    std::size_t open = 0, front = 0;
    for (auto e : mesh.edges()) {
        if (!mesh.is_boundary(e)) continue;
        ++open;
        const auto h = mesh.halfedge_handle(e, 0);
        const auto a = mesh.point(mesh.from_vertex_handle(h)),
                   b = mesh.point(mesh.to_vertex_handle(h));
        front += a[2] == 0.0 && b[2] == 0.0;
    }
    CHECK(front == 8);     // the front opening: 3 + 3 floor and ceiling edges, 2 wall edges
    CHECK(open == 8 + 8);  // and the open bottoms of the two blocks
    // Subdivision keeps it so: the same outline, cut finer.
    const auto sub = subdivide(mesh, {.max_edge = 60.0});
    std::size_t open_after = 0;
    for (auto e : sub.edges()) open_after += sub.is_boundary(e);
    CHECK(open_after > open);
    double rim = 0.0, rim_after = 0.0;
    for (auto e : mesh.edges())
        if (mesh.is_boundary(e)) rim += mesh.calc_edge_length(e);
    for (auto e : sub.edges())
        if (sub.is_boundary(e)) rim_after += sub.calc_edge_length(e);
    CHECK(rim_after == test::approx(rim).epsilon(1e-12));  // no new gaps inside
}

TEST_CASE("empty Cornell box: light-to-wall form factors match the published values") {
    const Scene<float> s = cornell_box<float>(false);
    const auto mesh = build_mesh(s);
    const PatchTable t = make_patch_table(mesh);
    Analytic analytic;
    analytic.prepare(t);
    std::size_t light = 0;
    for (std::size_t f = 0; f < s.faces.size(); ++f)
        if (s.materials[s.face_material[f]].name == "light") light = f;
    // Which wall each face belongs to, by its centroid.
    auto wall = [&](std::size_t f) -> std::string {
        const Vec3 c = t.centroid(f);
        if (c.y < 1e-6) return "floor";
        if (c.z > 559.2 - 1e-6) return "back_wall";
        if (c.x < 1e-6) return "right_wall_green";
        if (c.x > 549.0) return "left_wall_red";
        return "ceiling";
    };
    std::map<std::string, double> F;
    for (std::size_t f = 0; f < t.size(); ++f) F[wall(f)] += analytic.pair(light, f);
    const auto& values = published()["empty_box_light_form_factors"];
    for (const std::string name : {"floor", "back_wall", "right_wall_green", "left_wall_red"}) {
        CAPTURE(name);
        CHECK(F.at(name) == test::approx(values.at(name).get<double>()).epsilon(1e-5));
    }
    // The open front: what leaves the light and hits no wall (nor the ceiling it lies in).
    double walls = 0.0;
    for (const auto& [w, v] : F) walls += v;
    CHECK(1.0 - walls == test::approx(values.at("front_opening").get<double>()).epsilon(1e-5));
}

TEST_CASE("built-in scenes by name") {
    for (const auto& name : builtin_scene_names())
        CHECK_NOTHROW(build_mesh(builtin_scene<float>(name)));
    CHECK_THROWS_AS(builtin_scene<float>("kitchen"), Error);
}
