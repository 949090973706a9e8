// Lightmap UVs against what a lightmap needs, checked from the UVs alone: every corner in
// [0, 1], faces counter-clockwise, no two faces on one texel (rasterised at 4 samples per texel
// side), charts at least 2 x gutter texels apart and gutter texels from the border, planar
// charts flattened without distortion (every edge and diagonal scaled by density / size), walls
// of separate quads as one chart, a cube as six, identical results on identical input.
#include <radiosity/io/scenes.hpp>
#include <radiosity/lightmap/atlas.hpp>
#include <radiosity/lightmap/charts.hpp>
#include <radiosity/mesh/mesh.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>
#include <support/scenes.hpp>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>

using namespace radiosity;

namespace {

/// A scene of polygons that share no vertex indices (a polygon soup, like many OBJ files).
Scene<float> soup(const std::vector<std::vector<Vec3>>& polygons) {
    Scene<float> s;
    for (const auto& poly : polygons) {
        std::vector<std::uint32_t> idx;
        for (const Vec3& p : poly) {
            idx.push_back(static_cast<std::uint32_t>(s.positions.size()));
            s.positions.push_back(p);
        }
        s.faces.push_back(idx);
        s.face_material.push_back(0);
    }
    s.materials = {{0.0f, 0.5f, "grey"}};
    return s;
}

/// A scene over shared vertices.
Scene<float> indexed(std::vector<Vec3> positions, std::vector<std::vector<std::uint32_t>> faces) {
    Scene<float> s;
    s.positions = std::move(positions);
    s.faces = std::move(faces);
    s.face_material.assign(s.faces.size(), 0);
    s.materials = {{0.0f, 0.5f, "grey"}};
    return s;
}

/// The unit cube over 8 shared vertices, faces pointing out.
Scene<float> cube() {
    return indexed(
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
        {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}});
}

/// The unit cube as 6 quads with their own vertices (24 in all).
Scene<float> separate_cube() {
    return soup({{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},
                 {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
                 {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
                 {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
                 {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
                 {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}});
}

/// A flat wall of nx x ny separate quads (no shared vertices) in a tilted plane, facing n.
Scene<float> quad_wall(int nx, int ny) {
    const Vec3 o(1, 2, 3), s = glm::normalize(Vec3(2, 1, 0)), t = glm::normalize(Vec3(-1, 2, 3));
    const Vec3 ts = glm::normalize(t - glm::dot(t, s) * s);  // in the plane, across s
    std::vector<std::vector<Vec3>> q;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            auto at = [&](double a, double b) { return o + 0.7 * a * s + 0.4 * b * ts; };
            q.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return soup(q);
}

/// An icosahedron, each triangle cut into 4 `levels` times, on the unit sphere, faces out.
Scene<float> icosphere(int levels) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> p{{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                        {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& v : p) v = glm::normalize(v);
    std::vector<std::vector<std::uint32_t>> f{
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            auto [it, fresh] = mid.try_emplace(std::minmax(a, b), 0u);
            if (fresh) {
                it->second = static_cast<std::uint32_t>(p.size());
                p.push_back(glm::normalize(p[a] + p[b]));
            }
            return it->second;
        };
        std::vector<std::vector<std::uint32_t>> g;
        for (const auto& tri : f) {
            const std::uint32_t a = middle(tri[0], tri[1]), b = middle(tri[1], tri[2]),
                                c = middle(tri[2], tri[0]);
            g.push_back({tri[0], a, c});
            g.push_back({tri[1], b, a});
            g.push_back({tri[2], c, b});
            g.push_back({a, b, c});
        }
        f = std::move(g);
    }
    return indexed(p, f);
}

/// A spiral ramp (inner radius 1, outer 2) of `turns` turns rising 0.5 per turn, in triangles
/// facing up: every normal is within 5 degrees of +z, yet its projection overlaps itself.
Scene<float> spiral_ramp(double turns) {
    std::vector<std::vector<Vec3>> tris;
    const int steps = static_cast<int>(32 * turns);
    auto at = [](double r, int i) {
        const double a = 2.0 * std::numbers::pi * i / 32.0;
        return Vec3(r * std::cos(a), r * std::sin(a), 0.5 * i / 32.0);
    };
    for (int i = 0; i < steps; ++i) {
        tris.push_back({at(1, i), at(2, i), at(2, i + 1)});
        tris.push_back({at(1, i), at(2, i + 1), at(1, i + 1)});
    }
    return soup(tris);
}

/// A rough terrain: an n x n grid of unit squares over shared vertices, each cut into two
/// triangles, with heights from a fixed linear congruential sequence (the same on every
/// platform) up to `relief`: slopes of every direction, steep enough to split charts.
Scene<float> terrain(int n, double relief, std::uint64_t seed) {
    std::vector<Vec3> p;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            const double r = static_cast<double>(seed >> 11) * std::ldexp(1.0, -53);
            p.emplace_back(i, j, relief * r);
        }
    std::vector<std::vector<std::uint32_t>> f;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto v = static_cast<std::uint32_t>(j * (n + 1) + i);
            const auto w = static_cast<std::uint32_t>(n + 1);
            f.push_back({v, v + 1, v + w + 1});
            f.push_back({v, v + w + 1, v + w});
        }
    return indexed(p, f);
}

/// One face as the atlas left it: its corners' points and UVs, in halfedge order.
struct UvFace {
    std::vector<Vec3> point;
    std::vector<Vec2> uv;
};

template <class M>
std::vector<UvFace> uv_faces(const M& mesh) {
    std::vector<UvFace> out;
    for (auto f : mesh.faces()) {
        UvFace u;
        u.point = face_polygon(mesh, f);
        for (const glm::vec2& t : corner_uvs(mesh, f)) u.uv.emplace_back(t);
        out.push_back(u);
    }
    return out;
}

/// Whether a face is planar: every corner within 1e-9 of its size from its Newell plane.
bool planar(const std::vector<Vec3>& p) {
    const Vec3 n = polygon_normal(p);
    const Vec3 c = polygon_centroid(p);
    double size = 0.0;
    for (const Vec3& q : p) size = std::max(size, glm::distance(q, c));
    for (const Vec3& q : p)
        if (std::abs(glm::dot(q - c, n)) > 1e-9 * size) return false;
    return true;
}

struct AtlasStats {
    double coverage = 0.0;  ///< face area x density^2 / atlas texels
    std::size_t similar_faces = 0;
};

/// All the checks of the file comment; returns the coverage of the atlas by faces.
template <class M>
AtlasStats check_atlas(const M& mesh, const Atlas& atlas, const UnwrapOptions& opt) {
    AtlasStats stats;
    const auto faces = uv_faces(mesh);
    const int W = atlas.width, H = atlas.height;
    REQUIRE(W > 0);
    REQUIRE(W == H);
    REQUIRE(atlas.face_chart.size() == faces.size());
    REQUIRE(atlas.texel_density > 0.0);
    const double d = atlas.texel_density;
    for (std::uint32_t c : atlas.face_chart) REQUIRE(c < atlas.charts);

    // Corners in [0, 1], faces counter-clockwise in (u, v).
    std::size_t outside = 0, clockwise = 0;
    for (const auto& f : faces) {
        for (const Vec2& t : f.uv)
            if (!(t.x >= 0.0 && t.x <= 1.0 && t.y >= 0.0 && t.y <= 1.0)) ++outside;
        for (std::size_t k = 1; k + 1 < f.uv.size(); ++k)
            if (!(detail::signed_area2(f.uv[0], f.uv[k], f.uv[k + 1]) > 0.0)) ++clockwise;
        stats.coverage += polygon_area(f.point) * d * d / (double(W) * H);
    }
    CHECK(outside == 0);
    CHECK(clockwise == 0);

    // No sample point (4 x 4 per texel) strictly inside two faces.
    const int R = 4 * W;
    std::vector<int> owner(std::size_t(R) * R, -1);
    std::size_t shared = 0;
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const auto& uv = faces[f].uv;
        for (std::size_t k = 1; k + 1 < uv.size(); ++k) {
            const Vec2 a = uv[0] * double(R), b = uv[k] * double(R), c = uv[k + 1] * double(R);
            const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
            const int x1 = std::min(R - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
            const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
            const int y1 = std::min(R - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const Vec2 s(x + 0.5, y + 0.5);
                    const double e = 1e-9;  // on an edge is inside neither face
                    if (detail::signed_area2(a, b, s) > e && detail::signed_area2(b, c, s) > e &&
                        detail::signed_area2(c, a, s) > e) {
                        int& o = owner[std::size_t(y) * R + x];
                        if (o >= 0 && o != int(f)) ++shared;
                        o = int(f);
                    }
                }
        }
    }
    CHECK(shared == 0);

    // Charts' texel rectangles: gutter from the border, 2 x gutter from each other.
    const double slack = 1e-4;  // float texcoords: a few ulps of an atlas coordinate
    struct Rect {
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    };
    std::vector<Rect> rect(atlas.charts);
    for (std::size_t f = 0; f < faces.size(); ++f)
        for (const Vec2& t : faces[f].uv) {
            Rect& r = rect[atlas.face_chart[f]];
            r.x0 = std::min(r.x0, t.x * W);
            r.x1 = std::max(r.x1, t.x * W);
            r.y0 = std::min(r.y0, t.y * H);
            r.y1 = std::max(r.y1, t.y * H);
        }
    std::size_t near_border = 0, near_chart = 0;
    for (Rect& r : rect) {  // to whole texels: those the chart touches
        r.x0 = std::floor(r.x0 + slack);
        r.y0 = std::floor(r.y0 + slack);
        r.x1 = std::ceil(r.x1 - slack);
        r.y1 = std::ceil(r.y1 - slack);
        if (r.x0 < opt.gutter || r.y0 < opt.gutter || r.x1 > W - opt.gutter ||
            r.y1 > H - opt.gutter)
            ++near_border;
    }
    for (std::size_t a = 0; a < rect.size(); ++a)
        for (std::size_t b = a + 1; b < rect.size(); ++b) {
            const double gap = std::max({rect[b].x0 - rect[a].x1, rect[a].x0 - rect[b].x1,
                                         rect[b].y0 - rect[a].y1, rect[a].y0 - rect[b].y1});
            if (gap < 2 * opt.gutter) ++near_chart;
        }
    CHECK(near_border == 0);
    CHECK(near_chart == 0);

    // Planar charts (planar faces, one normal) are flattened isometrically: every distance
    // between corners, in texels, is the scene distance times the density.
    std::vector<bool> flat(atlas.charts, true);
    std::vector<Vec3> normal(atlas.charts, Vec3(0.0));
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const std::uint32_t c = atlas.face_chart[f];
        const Vec3 n = polygon_normal(faces[f].point);
        if (!planar(faces[f].point)) flat[c] = false;
        if (normal[c] == Vec3(0.0)) normal[c] = n;
        if (glm::dot(normal[c], n) < 1.0 - 1e-12) flat[c] = false;
    }
    // float texcoords hold about 2^-24 of the atlas side per coordinate
    const double float_tol = 4.0 * W * std::ldexp(1.0, -24);
    std::size_t distorted = 0;
    for (std::size_t f = 0; f < faces.size(); ++f) {
        if (!flat[atlas.face_chart[f]]) continue;
        ++stats.similar_faces;
        const auto& p = faces[f].point;
        const auto& uv = faces[f].uv;
        for (std::size_t i = 0; i < p.size(); ++i)
            for (std::size_t j = i + 1; j < p.size(); ++j) {
                const double scene = glm::distance(p[i], p[j]) * d;
                const Vec2 e = uv[i] - uv[j];
                const double texels = std::hypot(e.x * W, e.y * H);
                if (std::abs(texels - scene) > 1e-6 * scene + float_tol) ++distorted;
            }
    }
    CHECK(distorted == 0);
    return stats;
}

std::vector<Vec2> all_uvs(const Mesh<float>& m) {
    std::vector<Vec2> out;
    for (const auto& f : uv_faces(m)) out.insert(out.end(), f.uv.begin(), f.uv.end());
    return out;
}

}  // namespace

TEST_CASE("charts: a tilted rectangle is turned to its bounding rectangle, long side along u") {
    // A 2 x 1 rectangle, turned 30 degrees in a plane tilted out of every axis plane.
    const Vec3 n = glm::normalize(Vec3(1, 2, 3));
    const Vec3 s = glm::normalize(glm::cross(n, Vec3(0, 0, 1)));
    const Vec3 t = glm::cross(n, s);
    const double a = std::numbers::pi / 6.0;
    const Vec3 e1 = std::cos(a) * s + std::sin(a) * t, e2 = glm::cross(n, e1);
    const Vec3 o(5, -1, 2);
    const auto mesh = build_mesh(soup({{o, o + 2.0 * e1, o + 2.0 * e1 + e2, o + e2}}));
    const auto charts = make_charts(mesh);
    REQUIRE(charts.size() == 1);
    CHECK(charts[0].extent.x == test::approx(2.0).epsilon(1e-12));
    CHECK(charts[0].extent.y == test::approx(1.0).epsilon(1e-12));
    CHECK(glm::dot(charts[0].normal, n) == test::approx(1.0).epsilon(1e-12));
    for (const Vec2& p : charts[0].corner) {
        CHECK(p.x >= -1e-12);
        CHECK(p.y >= -1e-12);
    }
}

TEST_CASE("charts: a hexagon's minimum rectangle lies along one of its edges") {
    // A long irregular convex hexagon: the minimum-area rectangle is flush with its long edge.
    std::vector<Vec3> hex{{0, 0, 0}, {4, 1, 0}, {5, 2, 0}, {4.5, 3, 0}, {0.5, 2, 0}, {-0.5, 1, 0}};
    const auto charts = make_charts(build_mesh(soup({hex})));
    REQUIRE(charts.size() == 1);
    // Brute force over 100000 directions: the calipers' area is never beaten.
    std::vector<Vec2> q;
    for (const Vec3& p : hex) q.emplace_back(p.x, p.y);
    double best = std::numeric_limits<double>::max();
    for (int k = 0; k < 100000; ++k) {
        const double a = std::numbers::pi * k / 100000.0;
        const Vec2 u(std::cos(a), std::sin(a)), v(-u.y, u.x);
        double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
        for (const Vec2& p : q) {
            u0 = std::min(u0, glm::dot(p, u));
            u1 = std::max(u1, glm::dot(p, u));
            v0 = std::min(v0, glm::dot(p, v));
            v1 = std::max(v1, glm::dot(p, v));
        }
        best = std::min(best, (u1 - u0) * (v1 - v0));
    }
    CHECK(charts[0].extent.x * charts[0].extent.y <= best * (1.0 + 1e-12));
    CHECK(charts[0].extent.x >= charts[0].extent.y);
}

TEST_CASE("unwrap: a flat wall of separate quads is one chart, flattened without distortion") {
    auto mesh = build_mesh(quad_wall(5, 3));
    const UnwrapOptions opt;
    const Atlas atlas = make_lightmap_uvs(mesh, opt);
    CHECK(atlas.charts == 1);
    CHECK(atlas.width == 512);
    const auto stats = check_atlas(mesh, atlas, opt);
    CHECK(stats.similar_faces == 15);
    // One 3.5 x 1.2 chart: the density puts its long side across the atlas, less the gutters.
    CHECK(atlas.texel_density == test::approx((512 - 4) / 3.5).epsilon(1e-6));
}

TEST_CASE("unwrap: a cube gives six charts, with or without shared vertices") {
    for (const auto& scene : {cube(), separate_cube()}) {
        auto mesh = build_mesh(scene);
        const UnwrapOptions opt{.size = 64, .gutter = 3};
        const Atlas atlas = make_lightmap_uvs(mesh, opt);
        CHECK(atlas.charts == 6);
        CHECK(std::set<std::uint32_t>(atlas.face_chart.begin(), atlas.face_chart.end()).size() ==
              6);
        CHECK(check_atlas(mesh, atlas, opt).similar_faces == 6);
    }
}

TEST_CASE("unwrap: any OpenMesh mesh will do, such as a triangle mesh of float points") {
    OpenMesh::TriMesh_ArrayKernelT<> mesh;  // a cube of 12 triangles
    std::vector<OpenMesh::VertexHandle> v;
    for (int k = 0; k < 8; ++k)
        v.push_back(mesh.add_vertex({float(k & 1), float(k >> 1 & 1), float(k >> 2)}));
    for (auto [a, b, c, d] : {std::array{0, 2, 3, 1},
                              {4, 5, 7, 6},
                              {0, 1, 5, 4},
                              {2, 6, 7, 3},
                              {0, 4, 6, 2},
                              {1, 3, 7, 5}}) {
        mesh.add_face(v[a], v[b], v[c]);
        mesh.add_face(v[a], v[c], v[d]);
    }
    const UnwrapOptions opt{.size = 32, .gutter = 1};
    const Atlas atlas = make_lightmap_uvs(mesh, opt);
    CHECK(atlas.charts == 6);
    CHECK(check_atlas(mesh, atlas, opt).similar_faces == 12);
}

TEST_CASE("unwrap: a sphere is cut into charts that neither overlap nor fold") {
    auto mesh = build_mesh(icosphere(3));  // 1280 triangles
    const UnwrapOptions opt{.size = 1024};
    const Atlas atlas = make_lightmap_uvs(mesh, opt);
    MESSAGE("icosphere: ", mesh.n_faces(), " faces in ", atlas.charts, " charts, coverage ",
            check_atlas(mesh, atlas, opt).coverage);
    CHECK(atlas.charts >= 7);  // a cap of 45 degrees is 15% of the sphere
    CHECK(atlas.charts < mesh.n_faces() / 10);
    // Orthogonal projection never stretches: each face's UV area is at most its scene area.
    const auto faces = uv_faces(mesh);
    const double scale = atlas.texel_density / atlas.width;
    std::size_t stretched = 0;
    for (const auto& f : faces) {
        const double uv = 0.5 * detail::signed_area2(f.uv[0], f.uv[1], f.uv[2]);
        if (uv > polygon_area(f.point) * scale * scale * (1.0 + 1e-5)) ++stretched;
    }
    CHECK(stretched == 0);
    // A narrower cone gives more charts.
    auto narrow = build_mesh(icosphere(3));
    const UnwrapOptions tight{.size = 1024, .charts = {.max_chart_angle_degrees = 20.0}};
    const Atlas more = make_lightmap_uvs(narrow, tight);
    CHECK(more.charts > atlas.charts);
    check_atlas(narrow, more, tight);
}

TEST_CASE("unwrap: a chart stops growing where its projection would overlap itself") {
    auto mesh = build_mesh(spiral_ramp(2.5));
    const UnwrapOptions opt;
    const Atlas atlas = make_lightmap_uvs(mesh, opt);
    MESSAGE("spiral ramp of 2.5 turns: ", atlas.charts, " charts");
    CHECK(atlas.charts >= 3);  // no chart can go once around
    check_atlas(mesh, atlas, opt);
}

TEST_CASE("unwrap: rough terrains are cut into charts that neither overlap nor fold") {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        auto mesh = build_mesh(terrain(24, 1.5, seed));
        const UnwrapOptions opt{.size = 1024, .gutter = 1};
        const Atlas atlas = make_lightmap_uvs(mesh, opt);
        CAPTURE(seed);
        CHECK(atlas.charts > 1);
        check_atlas(mesh, atlas, opt);
    }
}

TEST_CASE("unwrap: the Cornell box packs at least 40% of its atlas") {
    auto mesh = build_mesh(cornell_box<Rgb>());
    const UnwrapOptions opt;
    const Atlas atlas = make_lightmap_uvs(mesh, opt);
    const AtlasStats stats = check_atlas(mesh, atlas, opt);
    MESSAGE("cornell box: ", mesh.n_faces(), " faces in ", atlas.charts, " charts, ",
            atlas.texel_density, " texels/mm in ", atlas.width, " x ", atlas.height,
            ", faces cover ", stats.coverage, " of the atlas");
    // Five walls (the red wall is not planar but within the angles), the light (a material of
    // its own: its light jumps at its edge, so it is not in the ceiling's chart) and the
    // blocks' ten faces.
    CHECK(atlas.charts == 16);
    CHECK(stats.similar_faces == mesh.n_faces() - 3);  // all but the 3 cells of the red wall
    CHECK(stats.coverage >= 0.4);
}

TEST_CASE("unwrap: the same input gives the same UVs") {
    for (const auto& scene : {cornell_box<float>(), icosphere(2), separate_cube()}) {
        auto a = build_mesh(scene), b = build_mesh(scene);
        const Atlas x = make_lightmap_uvs(a), y = make_lightmap_uvs(b);
        CHECK(x.texel_density == y.texel_density);
        CHECK(x.face_chart == y.face_chart);
        std::size_t corners = 0;
        for (const auto& f : scene.faces) corners += f.size();
        REQUIRE(all_uvs(a).size() == corners);  // every corner has its UV
        CHECK(all_uvs(a) == all_uvs(b));
    }
}

TEST_CASE("unwrap: a given texel density sets the smallest atlas that holds the charts") {
    auto mesh = build_mesh(cornell_box<Rgb>());
    const UnwrapOptions opt{.texel_density = 0.25, .gutter = 1};
    const Atlas atlas = make_lightmap_uvs(mesh, opt);
    CHECK(atlas.texel_density == 0.25);
    CHECK(atlas.width % 4 == 0);
    CHECK(atlas.width == atlas.height);
    check_atlas(mesh, atlas, opt);
    // One size smaller does not hold them at this density (same charts, same packing).
    const auto charts = make_charts(mesh);
    std::vector<std::uint32_t> order(charts.size());
    std::iota(order.begin(), order.end(), std::uint32_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return charts[a].extent.y > charts[b].extent.y;
    });
    std::vector<std::array<int, 2>> at;
    const auto rect = detail::chart_rectangles(charts, 0.25, 1);
    CHECK(detail::pack_shelves(rect, order, atlas.width, atlas.width, at));
    CHECK_FALSE(detail::pack_shelves(rect, order, atlas.width - 4, atlas.width - 4, at));
}

TEST_CASE("unwrap: without a gutter, charts may touch but never overlap") {
    auto mesh = build_mesh(cornell_box<float>());
    const UnwrapOptions opt{.size = 128, .gutter = 0};
    check_atlas(mesh, make_lightmap_uvs(mesh, opt), opt);
}

TEST_CASE("unwrap: bad options, an empty mesh and too many charts throw") {
    auto mesh = build_mesh(cube());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (const UnwrapOptions& bad :
         {UnwrapOptions{.size = 4}, UnwrapOptions{.size = 16385}, UnwrapOptions{.size = -1},
          UnwrapOptions{.texel_density = -1.0}, UnwrapOptions{.texel_density = nan},
          UnwrapOptions{.texel_density = inf}, UnwrapOptions{.gutter = -1},
          UnwrapOptions{.gutter = 65}, UnwrapOptions{.charts = {.max_chart_angle_degrees = 0.0}},
          UnwrapOptions{.charts = {.max_chart_angle_degrees = 90.0}},
          UnwrapOptions{.charts = {.max_chart_angle_degrees = -5.0}},
          UnwrapOptions{.charts = {.max_chart_angle_degrees = nan}},
          UnwrapOptions{.charts = {.crease_angle_degrees = 0.0}},
          UnwrapOptions{.charts = {.crease_angle_degrees = 181.0}},
          UnwrapOptions{.charts = {.crease_angle_degrees = nan}}})
        CHECK_THROWS_AS(make_lightmap_uvs(mesh, bad), Error);
    Mesh<float> empty;
    CHECK_THROWS_AS(make_lightmap_uvs(empty), Error);
    // Six charts of at least 5 x 5 texels (gutter 2) cannot share 8 x 8 texels.
    CHECK_THROWS_WITH_AS(make_lightmap_uvs(mesh, {.size = 8}), doctest::Contains("6 charts"),
                         Error);
    // Nor can a density of a million texels per unit fit in 16384 texels.
    CHECK_THROWS_AS(make_lightmap_uvs(mesh, {.texel_density = 1e6}), Error);
    CHECK_NOTHROW(make_lightmap_uvs(mesh, {.size = 16, .gutter = 0}));
}

TEST_CASE("unwrap: charts end at creases and at changes of material") {
    // A flat 2 x 1 strip of two quads (one chart), then the same strip with a second material,
    // then folded by 40 degrees (within the chart angle, beyond the crease angle).
    auto strip = [](double fold_degrees, std::uint32_t second_material) {
        return build_mesh(test::two_squares(second_material == 0, fold_degrees));
    };
    auto charts = [](Mesh<float> m, UnwrapOptions o = {}) {
        return make_lightmap_uvs(m, o).charts;
    };
    CHECK(charts(strip(0.0, 0)) == 1);
    CHECK(charts(strip(0.0, 1)) == 2);
    CHECK(charts(strip(40.0, 0)) == 2);
    UnwrapOptions wide;
    wide.charts.crease_angle_degrees = 60.0;
    wide.charts.split_materials = false;
    CHECK(charts(strip(40.0, 0), wide) == 1);
    CHECK(charts(strip(0.0, 1), wide) == 1);
}
