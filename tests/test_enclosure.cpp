// Closed rooms and which way they face (geometry/enclosure.hpp, mesh/orientation.hpp): a box
// facing in is a room, the same box facing out (as modelling tools make solids) inside out,
// an open box open; turning faces round and two-sided faces; scenes without an emitter.
#include <radiosity/geometry/enclosure.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/orientation.hpp>

#include <doctest/doctest.h>

using namespace radiosity;

namespace {

/// The unit cube's six faces, counter-clockwise about the inward normal; `skip` leaves one out.
Scene<Rgb> cube(int skip = -1) {
    Scene<Rgb> s;
    s.materials = {{Rgb(1.0f), Rgb(0.5f), "lamp"}};
    for (int k = 0; k < 8; ++k) s.positions.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const std::vector<std::vector<std::uint32_t>> faces{{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                                        {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (int f = 0; f < 6; ++f)
        if (f != skip) {
            s.faces.push_back(faces[std::size_t(f)]);
            s.face_material.push_back(0);
        }
    return s;
}

EnclosureReport classify(const Scene<Rgb>& s) {
    return classify_enclosure(make_patch_table(build_mesh(s)));
}

}  // namespace

TEST_CASE("the cube's faces as listed point into it") {
    const Mesh<Rgb> m = build_mesh(cube());
    for (auto f : m.faces()) {
        const auto p = face_polygon(m, f);
        CHECK(glm::dot(polygon_normal(p), Vec3(0.5) - polygon_centroid(p)) > 0.0);
    }
}

TEST_CASE("a closed box facing in is a room, facing out inside out, and open open") {
    const EnclosureReport room = classify(cube());
    CHECK(room.kind == Enclosure::room);
    CHECK(room.escaped == 0);
    CHECK(room.back == 0);
    CHECK(room.front == 27 * detail::probe_count);
    Scene<Rgb> out = cube();
    flip_faces(out);
    const EnclosureReport inside_out = classify(out);
    CHECK(inside_out.kind == Enclosure::inside_out);
    CHECK(inside_out.front == 0);
    CHECK(inside_out.back == 27 * detail::probe_count);
    flip_faces(out);  // turned round twice: as it was
    CHECK(classify(out).kind == Enclosure::room);
    const EnclosureReport open = classify(cube(3));
    CHECK(open.kind == Enclosure::open);
    CHECK(open.escaped > 0);
    // Open at the front: the points inside its blocks see the blocks' backs all round, but the
    // walls lie beyond them (furniture, not a room facing out).
    CHECK(classify(cornell_box<Rgb>()).kind == Enclosure::open);
}

TEST_CASE("RRV's rooms are closed rooms facing in") {
    for (const std::string room : {"room2.xml", "room3.xml"}) {
        CAPTURE(room);
        const auto e =
            classify(read_rrv<Rgb>(std::string(RADIOSITY_REFDATA_DIR) + "/../rrv/" + room));
        CHECK(e.kind == Enclosure::room);
        CHECK(e.back < e.front);  // room2 is turned in its box: points outside it are not counted
    }
}

TEST_CASE("two-sided faces: a reversed twin of every face, same material, UVs reversed too") {
    Scene<Rgb> s = cube(3);
    s.face_uvs.assign(s.faces.size(), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    make_two_sided(s);
    REQUIRE(s.faces.size() == 10);
    REQUIRE(s.face_uvs.size() == 10);
    for (std::size_t f = 0; f < 5; ++f) {
        CHECK(s.faces[f + 5] == std::vector<std::uint32_t>(s.faces[f].rbegin(), s.faces[f].rend()));
        CHECK(s.face_material[f + 5] == s.face_material[f]);
        CHECK(s.face_uvs[f + 5][0] == s.face_uvs[f][3]);
    }
    const Mesh<Rgb> m = build_mesh(s);  // twins share vertices in the opposite direction
    CHECK(m.n_faces() == 10);
}

TEST_CASE("has_emitter: a scene with no positive emission has none") {
    Scene<Rgb> s = cube();
    CHECK(has_emitter(s));
    s.materials[0].emission = Rgb(0.0f);
    CHECK_FALSE(has_emitter(s));
    s.materials[0].emission = Rgb(0.0f, 0.0f, 1e-3f);
    CHECK(has_emitter(s));
}
