#pragma once
// The scenes and measures that the hierarchy's benchmarks share: the Cornell box tessellated
// into a million triangles, and per-material means of B.
#include <radiosity/radiosity.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace bench {

using radiosity::Rgb;

/// The Cornell box with every face cut into triangles of about `edge` (mm): each input face
/// (triangles and quads in the built-in box) split into an n x n grid of its own shape, quads'
/// cells into two triangles. `origin`, if given, receives for each triangle the index of the
/// box's face it was cut from.
inline radiosity::Scene<Rgb> tessellated_box(double edge,
                                             std::vector<std::uint32_t>* origin = nullptr) {
    radiosity::Scene<Rgb> in = radiosity::cornell_box<Rgb>(true), out;
    out.materials = in.materials;
    out.source = "Cornell box, tessellated";
    out.metres_per_unit = in.metres_per_unit;
    struct Piece {
        std::vector<radiosity::Vec3> p;
        std::uint32_t face;
    };
    std::vector<Piece> pieces;
    for (std::uint32_t f = 0; f < in.faces.size(); ++f) {  // triangles and quads; others fanned
        std::vector<radiosity::Vec3> p;
        for (auto v : in.faces[f]) p.push_back(in.positions[v]);
        if (p.size() <= 4)
            pieces.push_back({p, f});
        else
            for (std::size_t k = 1; k + 1 < p.size(); ++k)
                pieces.push_back({{p[0], p[k], p[k + 1]}, f});
    }
    if (origin) origin->clear();
    for (const auto& [p, face] : pieces) {
        const std::uint32_t material = in.face_material[face];
        double longest = 0.0;
        for (std::size_t k = 0; k < p.size(); ++k)
            longest = std::max(longest, glm::length(p[(k + 1) % p.size()] - p[k]));
        const int n = std::max(1, static_cast<int>(std::ceil(longest / edge)));
        auto at = [&](int i,
                      int j) {  // point (i/n, j/n) of the face's bilinear (or barycentric) map
            const double u = double(i) / n, v = double(j) / n;
            if (p.size() == 3) return p[0] + u * (p[1] - p[0]) + v * (p[2] - p[0]);
            return (1 - u) * (1 - v) * p[0] + u * (1 - v) * p[1] + u * v * p[2] +
                   (1 - u) * v * p[3];
        };
        const auto base = static_cast<std::uint32_t>(out.positions.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) out.positions.push_back(at(i, j));
        auto id = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (n + 1) + i); };
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                if (p.size() == 3 && i + j >= n) continue;
                out.faces.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
                out.face_material.push_back(material);
                if (origin) origin->push_back(face);
                if (p.size() == 3 && i + j + 1 >= n) continue;
                out.faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
                out.face_material.push_back(material);
                if (origin) origin->push_back(face);
            }
    }
    return out;
}

/// Area-weighted mean of the mean band of B over the faces of material m.
inline double material_mean(const radiosity::Mesh<Rgb>& mesh, std::uint32_t m) {
    double sum = 0.0, area = 0.0;
    for (auto f : mesh.faces()) {
        if (mesh.data(f).material != m) continue;
        const double a = radiosity::polygon_area(radiosity::face_polygon(mesh, f));
        sum += a * radiosity::mean_band(mesh.data(f).radiosity);
        area += a;
    }
    return area > 0.0 ? sum / area : 0.0;
}

/// The surfaces of a scene: its faces grouped by material and plane (Newell normal to 0.01,
/// offset to 1 unit), so that the cells of one wall are one surface. Returns the surface of
/// each face and, in `names`, one name per surface (material and normal).
inline std::vector<std::uint32_t> surfaces_of(const radiosity::Scene<Rgb>& s,
                                              std::vector<std::string>& names) {
    std::map<std::array<long, 5>, std::uint32_t> index;
    std::vector<std::uint32_t> surface;
    names.clear();
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
        std::vector<radiosity::Vec3> p;
        for (auto v : s.faces[f]) p.push_back(s.positions[v]);
        radiosity::Vec3 n(0.0);  // Newell's normal
        for (std::size_t k = 0; k < p.size(); ++k) n += glm::cross(p[k], p[(k + 1) % p.size()]);
        n = glm::normalize(n);
        const double offset = glm::dot(n, p[0]);
        const std::array<long, 5> key{long(s.face_material[f]), std::lround(n.x * 100),
                                      std::lround(n.y * 100), std::lround(n.z * 100),
                                      std::lround(offset)};
        const auto [it, fresh] = index.emplace(key, std::uint32_t(names.size()));
        if (fresh) {
            char name[96];
            std::snprintf(name, sizeof name, "%s (%+.2f %+.2f %+.2f) at %.0f",
                          s.materials[s.face_material[f]].name.c_str(), n.x, n.y, n.z, offset);
            names.push_back(name);
        }
        surface.push_back(it->second);
    }
    return surface;
}

/// Area-weighted means of the mean band of B per surface: `surface_of_input` maps the input
/// face that each patch was cut from (its `surface` index) to its surface.
inline std::vector<double> surface_means(const radiosity::Mesh<Rgb>& mesh,
                                         const std::vector<std::uint32_t>& surface_of_input,
                                         std::size_t surfaces) {
    std::vector<double> sum(surfaces, 0.0), area(surfaces, 0.0);
    for (auto f : mesh.faces()) {
        const std::uint32_t g = surface_of_input.at(mesh.data(f).surface);
        const double a = radiosity::polygon_area(radiosity::face_polygon(mesh, f));
        sum[g] += a * radiosity::mean_band(mesh.data(f).radiosity);
        area[g] += a;
    }
    for (std::size_t g = 0; g < surfaces; ++g) sum[g] = area[g] > 0.0 ? sum[g] / area[g] : 0.0;
    return sum;
}

}  // namespace bench
