// Core types: spectra, polygons, the patch table, mesh building and the matrix checks.
#include <radiosity/detail/bulk_memory.hpp>
#include <radiosity/form_factor/matrix.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/solver/system.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

using namespace radiosity;

TEST_CASE("spectrum arithmetic is per band") {
    const Rgb a{0.5f, 0.25f, 1.0f}, b{2.0f, 4.0f, 0.5f};
    CHECK(a * b == Rgb{1.0f, 1.0f, 0.5f});
    CHECK(a + b == Rgb{2.5f, 4.25f, 1.5f});
    CHECK(max_abs(a - b) == test::approx(3.75f));
    CHECK(band(a * 2.0f, 2) == test::approx(2.0f));
    CHECK_FALSE(all_finite(Rgb{1.0f, NAN, 0.0f}));
}

TEST_CASE("polygon area, normal and centroid of a unit square") {
    const std::vector<Vec3> sq{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    CHECK(polygon_area(sq) == test::approx(2.0));
    CHECK(polygon_normal(sq).z == test::approx(1.0));
    const Vec3 c = polygon_centroid(sq);
    CHECK(c.x == test::approx(1.0));
    CHECK(c.y == test::approx(0.5));
}

TEST_CASE("clipping a square to a plane keeps the front half") {
    const std::vector<Vec3> sq{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
    const auto half = clip_to_plane(sq, Vec3(1, 0, 0), Vec3(1, 0, 0));
    CHECK(polygon_area(half) == test::approx(2.0));
    CHECK(clip_to_plane(sq, Vec3(5, 0, 0), Vec3(1, 0, 0)).empty());
}

TEST_CASE("patch table rejects degenerate patches") {
    PatchTable t;
    const std::vector<Vec3> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    CHECK_THROWS_AS(t.add(line), Error);
    const std::vector<Vec3> nan{{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}};
    CHECK_THROWS_AS(t.add(nan), Error);
}

TEST_CASE("build_mesh carries materials to faces and rejects bad input") {
    Scene<Rgb> s;
    s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.faces = {{0, 1, 2}, {0, 2, 3}};
    s.face_material = {0, 1};
    s.materials = {{Rgb(0.0f), Rgb(0.5f), "grey"}, {Rgb(1.0f), Rgb(0.0f), "light"}};
    const auto mesh = build_mesh(s);
    CHECK(mesh.n_faces() == 2);
    CHECK(face_emission(mesh)[1] == Rgb(1.0f));
    CHECK(make_patch_table(mesh).area(0) == test::approx(0.5));

    auto bad = s;
    bad.materials[0].reflectance = Rgb(1.0f);
    CHECK_THROWS_WITH_AS(build_mesh(bad), doctest::Contains("material 0"), Error);
    bad = s;
    bad.faces[1] = {0, 2, 7};
    CHECK_THROWS_WITH_AS(build_mesh(bad), doctest::Contains("face 1"), Error);
    bad = s;
    bad.positions.push_back({2, 0, 0});
    bad.faces[1] = {0, 1, 4};
    CHECK_THROWS_WITH_AS(build_mesh(bad), doctest::Contains("zero area"), Error);
}

TEST_CASE("check_matrix measures reciprocity and row sums") {
    DenseMatrix F(2);
    F.row(0)[1] = 1.0f;
    F.row(1)[0] = 0.5f;
    const std::vector<double> area{1.0, 2.0};
    const auto c = check_matrix(F, area);
    CHECK(c.reciprocity_error == test::approx(0.0));
    CHECK(c.min_row_sum == test::approx(0.5));
    CHECK(c.max_row_sum == test::approx(1.0));
    F.row(1)[0] = 0.25f;
    CHECK(check_matrix(F, area).reciprocity_error == test::approx(0.5));
}

TEST_CASE("the bulk allocator keeps a list's values as it grows past a huge page") {
    // Small lists come from operator new, those of a huge page (2 MiB) and more from a mapping
    // aligned to it; growing across that size moves the values from one to the other and back.
    std::vector<std::uint64_t, detail::BulkAllocator<std::uint64_t>> v;
    const std::size_t n = 3 * detail::huge_page / sizeof(std::uint64_t) + 5;
    for (std::size_t i = 0; i < n; ++i) v.push_back(i * i);
    CHECK(v.capacity() * sizeof(std::uint64_t) >= detail::huge_page);
#if defined(__linux__)
    CHECK(reinterpret_cast<std::uintptr_t>(v.data()) % detail::huge_page == 0);
#endif
    bool kept = true;
    for (std::size_t i = 0; i < n; ++i) kept = kept && v[i] == i * i;
    CHECK(kept);
    v.resize(100);
    v.shrink_to_fit();  // back below a huge page: operator new again
    CHECK(v.capacity() * sizeof(std::uint64_t) < detail::huge_page);
    CHECK(v[99] == 99u * 99u);
    CHECK(detail::in_huge_pages(1) == detail::huge_page);
    CHECK(detail::in_huge_pages(detail::huge_page + 1) == 2 * detail::huge_page);
}
