#pragma once
// The scenes and measures that the hierarchy's benchmarks share: the Cornell box tessellated
// into a million triangles, and per-material means of B.
#include <radiosity/radiosity.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace bench {

using radiosity::Rgb;

/// The Cornell box with every face cut into triangles of about `edge` (mm): each input face
/// (triangles and quads in the built-in box) split into an n x n grid of its own shape, quads'
/// cells into two triangles.
inline radiosity::Scene<Rgb> tessellated_box(double edge) {
    radiosity::Scene<Rgb> in = radiosity::cornell_box<Rgb>(true), out;
    out.materials = in.materials;
    out.source = "Cornell box, tessellated";
    out.metres_per_unit = in.metres_per_unit;
    std::vector<std::pair<std::vector<radiosity::Vec3>, std::uint32_t>> pieces;
    for (std::size_t f = 0; f < in.faces.size(); ++f) {  // triangles and quads; others fanned
        std::vector<radiosity::Vec3> p;
        for (auto v : in.faces[f]) p.push_back(in.positions[v]);
        if (p.size() <= 4)
            pieces.push_back({p, in.face_material[f]});
        else
            for (std::size_t k = 1; k + 1 < p.size(); ++k)
                pieces.push_back({{p[0], p[k], p[k + 1]}, in.face_material[f]});
    }
    for (const auto& [p, material] : pieces) {
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
                if (p.size() == 3 && i + j + 1 >= n) continue;
                out.faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
                out.face_material.push_back(material);
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

}  // namespace bench
