#pragma once
/// @file vertex_shading.hpp  From patch radiosities to a coloured triangle mesh: flat shading
/// (each patch in its own colour) and smooth shading (Gouraud 1971: colours at the vertices,
/// interpolated across the triangles), where a vertex's radiosity is the area-weighted mean of
/// the patches around it (Cohen & Wallace 1993, sec. 6.1) - but never across a crease sharper
/// than a set angle nor across a change of material, where the light really does jump.

#include <radiosity/geometry/polygon.hpp>
#include <radiosity/mesh/mesh.hpp>
#include <radiosity/shading/shaded_mesh.hpp>

#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <tuple>
#include <vector>

namespace radiosity {

/// Settings of smooth shading.
struct SmoothShadingOptions {
    double crease_angle_degrees = 30.0;  ///< faces meeting at a sharper angle are not averaged
};

namespace detail {
template <SpectrumType S>
glm::vec3 rgb_of(const S& b) {
    const auto c = to_rgb(b);
    return {c[0], c[1], c[2]};
}

/// Whether output vertices a, b, c make a triangle of no area (collinear, to rounding).
inline bool flat_triangle(const ShadedMesh& out, std::uint32_t a, std::uint32_t b,
                          std::uint32_t c) {
    const Vec3 &p = out.positions[a], &q = out.positions[b], &r = out.positions[c];
    const double scale = glm::dot(q - p, q - p) + glm::dot(r - p, r - p);
    return glm::length(glm::cross(q - p, r - p)) <= 1e-9 * scale;
}

/// Appends triangles over the given output vertices of one (convex) face: a fan from the first
/// corner, unless that would make a triangle of no area, as it does where a face has corners
/// in a row along an edge (the T-vertices a hierarchical solve inserts, leaves.hpp); then ears
/// are cut at corners that turn, so every vertex is used and no triangle is flat.
inline void fan(ShadedMesh& out, const std::vector<std::uint32_t>& corners) {
    bool flat = false;
    for (std::size_t k = 1; k + 1 < corners.size() && !flat; ++k)
        flat = flat_triangle(out, corners[0], corners[k], corners[k + 1]);
    if (!flat) {
        for (std::size_t k = 1; k + 1 < corners.size(); ++k)
            out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
        return;
    }
    std::vector<std::uint32_t> left = corners;
    while (left.size() >= 3) {
        const std::size_t n = left.size();
        std::size_t ear = n;
        for (std::size_t i = 0; i < n && ear == n; ++i)
            if (!flat_triangle(out, left[(i + n - 1) % n], left[i], left[(i + 1) % n])) ear = i;
        if (ear == n) return;  // all in a row: nothing with area is left
        out.triangles.push_back({left[(ear + n - 1) % n], left[ear], left[(ear + 1) % n]});
        left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
    }
}
}  // namespace detail

/// Whether smooth shading carries the light across the edge between two faces: the same
/// material, and unit normals at most the crease angle apart (cos_crease its cosine). Lightmap
/// charts end where this is false, so that no jump of the light lies inside a chart.
inline bool light_continuous(const Vec3& normal_a, const Vec3& normal_b, std::uint32_t material_a,
                             std::uint32_t material_b, double cos_crease) {
    return material_a == material_b && glm::dot(normal_a, normal_b) >= cos_crease;
}

/// Flat shading: every patch gets its own vertices, coloured with its radiosity B (as RGB), with
/// the patch's lightmap UVs if it has them. Cost: O(faces).
template <SpectrumType S>
ShadedMesh flat_shading(const Mesh<S>& mesh) {
    ShadedMesh out;
    for (auto f : mesh.faces()) {
        const glm::vec3 c = detail::rgb_of(mesh.data(f).radiosity);
        std::vector<std::uint32_t> corners;
        for (const Vec3& p : face_polygon(mesh, f)) {
            corners.push_back(static_cast<std::uint32_t>(out.positions.size()));
            out.positions.push_back(p);
            out.colours.push_back(c);
        }
        for (const glm::vec2& uv : corner_uvs(mesh, f)) out.uvs.push_back(uv);
        detail::fan(out, corners);
    }
    return out;
}

/// Smooth shading (see the file comment). Around each mesh vertex the faces are grouped: two
/// faces sharing an edge at that vertex are in one group if they have the same material and
/// their normals differ by at most the crease angle. Each group gets its own output vertex,
/// coloured with the area-weighted mean B of the group's faces. Where the mesh has lightmap UVs,
/// a group's corners with different UVs (a seam of the UV charts) get separate output vertices of
/// the same colour, so the light stays continuous across the seam. Cost: O(faces + vertices).
template <SpectrumType S>
ShadedMesh smooth_shading(const Mesh<S>& mesh, const SmoothShadingOptions& options = {}) {
    const double cos_crease = std::cos(options.crease_angle_degrees * std::numbers::pi / 180.0);
    std::vector<Vec3> normal(mesh.n_faces());
    std::vector<double> area(mesh.n_faces());
    for (auto f : mesh.faces()) {
        const auto poly = face_polygon(mesh, f);
        normal[static_cast<std::size_t>(f.idx())] = polygon_normal(poly);
        area[static_cast<std::size_t>(f.idx())] = polygon_area(poly);
    }
    auto smooth = [&](typename Mesh<S>::FaceHandle a, typename Mesh<S>::FaceHandle b) {
        return light_continuous(normal[static_cast<std::size_t>(a.idx())],
                                normal[static_cast<std::size_t>(b.idx())], mesh.data(a).material,
                                mesh.data(b).material, cos_crease);
    };
    ShadedMesh out;
    // Output vertex of (mesh vertex, face), filled vertex by vertex.
    std::map<std::pair<int, int>, std::uint32_t> corner;
    for (auto v : mesh.vertices()) {
        std::vector<typename Mesh<S>::FaceHandle> faces;
        for (auto f : mesh.vf_range(v)) faces.push_back(f);
        std::vector<std::size_t> group(faces.size());
        std::iota(group.begin(), group.end(), std::size_t{0});
        auto find = [&](std::size_t x) {
            while (group[x] != x) x = group[x] = group[group[x]];
            return x;
        };
        auto index = [&](typename Mesh<S>::FaceHandle f) {
            return static_cast<std::size_t>(std::find(faces.begin(), faces.end(), f) -
                                            faces.begin());
        };
        for (auto h : mesh.voh_range(v)) {  // faces on both sides of each edge at v
            const auto f1 = mesh.face_handle(h),
                       f2 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
            if (f1.is_valid() && f2.is_valid() && smooth(f1, f2))
                group[find(index(f1))] = find(index(f2));
        }
        // Area-weighted sum of B and area of each group, then one output vertex per (group,
        // UV) pair.
        std::vector<std::pair<glm::dvec3, double>> sums(faces.size(), {glm::dvec3(0.0), 0.0});
        for (std::size_t m = 0; m < faces.size(); ++m) {
            const double a = area[static_cast<std::size_t>(faces[m].idx())];
            auto& [sum, weight] = sums[find(m)];
            sum += a * glm::dvec3(detail::rgb_of(mesh.data(faces[m]).radiosity));
            weight += a;
        }
        std::map<std::tuple<std::size_t, float, float>, std::uint32_t> made;
        for (std::size_t k = 0; k < faces.size(); ++k) {
            const std::size_t root = find(k);
            const glm::vec2 uv = corner_uv(mesh, faces[k], v);
            auto [it, fresh] = made.try_emplace({root, uv.x, uv.y},
                                                static_cast<std::uint32_t>(out.positions.size()));
            if (fresh) {
                const auto& p = mesh.point(v);
                const auto& [sum, weight] = sums[root];
                out.positions.emplace_back(p[0], p[1], p[2]);
                out.colours.push_back(glm::vec3(sum / weight));
                if (has_corner_uvs(mesh)) out.uvs.push_back(uv);
            }
            corner[{v.idx(), faces[k].idx()}] = it->second;
        }
    }
    for (auto f : mesh.faces()) {
        std::vector<std::uint32_t> corners;
        for (auto v : mesh.fv_range(f)) corners.push_back(corner.at({v.idx(), f.idx()}));
        detail::fan(out, corners);
    }
    return out;
}

}  // namespace radiosity
