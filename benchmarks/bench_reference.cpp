// An independent reference for the per-material means that the accuracy tables of the README
// quote: the radiosity equation solved by a random walk (the collision estimator of the Neumann
// series, Spanier & Gelbard 1969), with no form factor, no patch and no solver of the library,
// only its meshing (the same faces, cut as the program cuts them) and its BVH for the rays.
//
//   bench_reference SCENE [WALKS]   SCENE: an RRV .xml, an OBJ or a built-in scene name
//
// For each material that emits nothing, WALKS points uniform in area over its faces; from each,
// a walk in band k: B(x) = E(x) + rho(x) * (the radiosity seen along a cosine-weighted ray), the
// walk going on with probability rho and scoring E at every face it reaches (analog absorption:
// unbiased, the score per walk 0 or E-sized). A ray that meets the back of a face or leaves the
// scene ends the walk (one-sided faces: what is seen from behind sends nothing). Prints per
// material and band the mean B and its standard error. Seeded: the same numbers on every run.
#include <radiosity/radiosity.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <string>
#include <vector>

namespace {

using radiosity::Rgb;
using radiosity::Vec3;

radiosity::Mesh<Rgb> load(const std::string& name) {
    const auto ends = [&](const char* x) {
        const std::string s(x);
        return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
    };
    if (ends(".xml")) return radiosity::build_mesh(radiosity::read_rrv<Rgb>(name));
    if (ends(".obj")) return radiosity::build_mesh(radiosity::read_obj<Rgb>(name));
    return radiosity::build_mesh(radiosity::builtin_scene<Rgb>(name));
}

/// A cosine-weighted direction about unit normal n (Malley's method).
Vec3 cosine_direction(const Vec3& n, radiosity::Rng& rng) {
    const Vec3 t1 = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, Vec3(1, 0, 0))
                                                       : glm::cross(n, Vec3(0, 1, 0)));
    const Vec3 t2 = glm::cross(n, t1);
    const double a = rng.uniform(), phi = 2.0 * std::numbers::pi * rng.uniform();
    return std::sqrt(a) * (std::cos(phi) * t1 + std::sin(phi) * t2) + std::sqrt(1.0 - a) * n;
}

/// A uniform point of a convex polygon (fan triangle by area, then Shirley's map).
Vec3 polygon_point(std::span<const Vec3> p, radiosity::Rng& rng) {
    double total = 0.0;
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
        total += glm::length(glm::cross(p[k] - p[0], p[k + 1] - p[0]));
    double pick = rng.uniform() * total;
    std::size_t k = 1;
    for (; k + 2 < p.size(); ++k) {
        const double a = glm::length(glm::cross(p[k] - p[0], p[k + 1] - p[0]));
        if (pick < a) break;
        pick -= a;
    }
    const double s = std::sqrt(rng.uniform()), v = rng.uniform();
    return (1.0 - s) * p[0] + s * (1.0 - v) * p[k] + s * v * p[k + 1];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_reference SCENE [WALKS]\n");
        return 2;
    }
    const long walks = argc > 2 ? std::atol(argv[2]) : 4000000;
    // The faces the program solves: cut where others cross them, pieces in solids left out.
    radiosity::SubdivisionOptions roots;  // the faces as they are, but cut (as the program does)
    const auto meshed = radiosity::subdivide_with_report(load(argv[1]), roots);
    const radiosity::PatchTable faces = radiosity::make_patch_table(meshed.mesh);
    const radiosity::Bvh bvh(faces);
    struct Face {
        Rgb E, rho;
        std::uint32_t material;
    };
    std::vector<Face> data;
    for (auto f : meshed.mesh.faces()) {
        const auto& d = meshed.mesh.data(f);
        data.push_back({d.emission, d.reflectance, d.material});
    }
    std::map<std::uint32_t, std::vector<std::uint32_t>> by_material;
    for (std::uint32_t f = 0; f < faces.size(); ++f) by_material[data[f].material].push_back(f);
    double scale = 0.0;
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (const Vec3& v : faces.polygon(f)) scale = std::max(scale, glm::length(v));
    const double t_min = 1e-9 * (scale + 1.0);
    std::printf("%zu faces; %ld walks per material and band\n", faces.size(), walks);
    std::printf("| material | area | band | mean B | standard error |\n|---|---|---|---|---|\n");
    for (const auto& [material, list] : by_material) {
        if (radiosity::mean_band(data[list[0]].E) > 0.0f) continue;  // emitters: B >= E
        std::vector<double> cdf;                                     // of the material's face areas
        double area = 0.0;
        for (const std::uint32_t f : list) cdf.push_back(area += faces.area(f));
        for (std::size_t k = 0; k < 3; ++k) {
            double sum = 0.0, sum2 = 0.0;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for reduction(+ : sum, sum2) schedule(dynamic, 4096)
#endif
            for (long i = 0; i < walks; ++i) {
                radiosity::Rng rng(radiosity::splitmix64(std::uint64_t(i) * 0x9e3779b97f4a7c15ull ^
                                                         (std::uint64_t(material) << 40) ^ k));
                const double a = rng.uniform() * area;
                const auto at = std::upper_bound(cdf.begin(), cdf.end(), a) - cdf.begin();
                std::uint32_t f = list[std::min<std::size_t>(std::size_t(at), list.size() - 1)];
                Vec3 x = polygon_point(faces.polygon(f), rng);
                double score = radiosity::band(data[f].E, k);
                while (rng.uniform() < radiosity::band(data[f].rho, k)) {
                    const Vec3 d = cosine_direction(faces.normal(f), rng);
                    const auto hit = bvh.intersect(x, d, t_min);
                    if (!hit || glm::dot(faces.normal(hit->patch), d) >= 0.0) break;
                    x += hit->t * d;
                    f = hit->patch;
                    score += radiosity::band(data[f].E, k);
                }
                sum += score;
                sum2 += score * score;
            }
            const double mean = sum / double(walks);
            const double error =
                std::sqrt(std::max(0.0, sum2 / double(walks) - mean * mean) / double(walks));
            std::printf("| %u | %.2f | %zu | %.5f | %.5f |\n", material, area, k, mean, error);
        }
    }
    return 0;
}
