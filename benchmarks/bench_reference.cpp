// An independent reference for the per-material means that the accuracy tables of the README
// quote: the radiosity equation solved by a random walk (the collision estimator of the Neumann
// series, Spanier & Gelbard 1969), with no form factor, no patch and no solver of the library,
// only its meshing (the same faces, cut as the program cuts them) and its BVH for the rays.
//
//   bench_reference SCENE [WALKS]              per material
//   bench_reference SCENE [WALKS] --surfaces   per surface (bench::surfaces_of: the input faces
//                                              grouped by material and plane, as in
//                                              bench_hierarchy surfaces)
//   bench_reference SCENE [WALKS] --region X0 Y0 Z0 X1 Y1 Z1   per surface, the walks started
//                                              only inside that box (the area column: the
//                                              area inside it, from 4096 points; surfaces with
//                                              none left out), e.g. the floor under a table
//
//   SCENE: an RRV .xml, an OBJ or a built-in scene name; WALKS: per group and band (4000000).
//
// For each material (or surface) that emits nothing, WALKS points uniform in area over its faces
// (the meshed pieces, each mapped to a surface through the input face it was cut from); from each,
// a walk in band k: B(x) = E(x) + rho(x) * (the radiosity seen along a cosine-weighted ray), the
// walk going on with probability rho and scoring E at every face it reaches (analog absorption:
// unbiased, the score per walk 0 or E-sized). A ray that meets the back of a face or leaves the
// scene ends the walk (one-sided faces: what is seen from behind sends nothing). Prints per
// material and band the mean B and its standard error; per surface, its area, the mean of the
// bands and its standard error, the three bands, the walk count and the seconds taken. Seeded per
// group and band: the same numbers on every run.
#include <radiosity/radiosity.hpp>

#include "support/tessellated_box.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace {

using radiosity::Rgb;
using radiosity::Vec3;

/// The scene named on the command line (kept as a Scene: bench::surfaces_of groups its faces).
radiosity::Scene<Rgb> load(const std::string& name) {
    const auto ends = [&](const char* x) {
        const std::string s(x);
        return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
    };
    if (ends(".xml")) return radiosity::read_rrv<Rgb>(name);
    if (ends(".obj")) return radiosity::read_obj<Rgb>(name);
    return radiosity::builtin_scene<Rgb>(name);
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

/// E and rho of a meshed face, its material and the input face it was cut from.
struct Face {
    Rgb E, rho;
    std::uint32_t material, surface;
};

/// What every walk reads: the meshed faces (as patches), their BVH, their data, and the ray
/// offset. One bundle so that both modes run the one walk below.
struct Walker {
    const radiosity::PatchTable& faces;
    const radiosity::Bvh& bvh;
    const std::vector<Face>& data;
    double t_min;
};

/// A group of faces to start walks from (a material or a surface): the faces, the running sum of
/// their areas (to pick one in proportion to area) and the total.
struct Group {
    std::vector<std::uint32_t> list;
    std::vector<double> cdf;
    double area = 0.0;
};

/// A box that the walks' starting points are kept to (--region): a point drawn outside it is
/// drawn again, so that the mean is over the part of a surface inside it (the floor under a
/// table, where a surface's mean would hide it). The whole space by default.
struct Region {
    Vec3 lo{-std::numeric_limits<double>::infinity()}, hi{std::numeric_limits<double>::infinity()};
    bool contains(const Vec3& x) const {
        return glm::all(glm::greaterThanEqual(x, lo)) && glm::all(glm::lessThanEqual(x, hi));
    }
    /// Whether polygon p's bounding box meets the box.
    bool meets(std::span<const Vec3> p) const {
        Vec3 a = p[0], b = p[0];
        for (const Vec3& v : p) a = glm::min(a, v), b = glm::max(b, v);
        return glm::all(glm::lessThanEqual(a, hi)) && glm::all(glm::greaterThanEqual(b, lo));
    }
};

/// The group of `list` with its area table (see Group).
Group group_of(const radiosity::PatchTable& faces, std::vector<std::uint32_t> list) {
    Group g{std::move(list), {}, 0.0};
    for (const std::uint32_t f : g.list) g.cdf.push_back(g.area += faces.area(f));
    return g;
}

/// A mean and its standard error.
struct Estimate {
    double mean = 0.0, error = 0.0;
};

/// A point uniform in area over group g's faces, and the face it lies on.
std::pair<std::uint32_t, Vec3> area_point(const radiosity::PatchTable& faces, const Group& g,
                                          radiosity::Rng& rng) {
    const double a = rng.uniform() * g.area;
    const auto at = std::upper_bound(g.cdf.begin(), g.cdf.end(), a) - g.cdf.begin();
    const std::uint32_t f = g.list[std::min<std::size_t>(std::size_t(at), g.list.size() - 1)];
    return {f, polygon_point(faces.polygon(f), rng)};
}

/// The share of group g's area inside `region`, from 4096 points (per_surface drops the groups
/// with none, whose walks could not start, and shows the area inside).
double region_share(const radiosity::PatchTable& faces, const Group& g, const Region& region) {
    radiosity::Rng rng(0x5e91);
    int inside = 0;
    for (int i = 0; i < 4096; ++i) inside += region.contains(area_point(faces, g, rng).second);
    return inside / 4096.0;
}

/// The mean B in band k over group g: `walks` walks from points uniform in area over its faces
/// (see the file comment), walk i seeded with splitmix64(i * golden ratio ^ key ^ k), so that each
/// group (key) and band has its own deterministic stream. The one estimator of both modes.
Estimate walk_mean(const Walker& w, const Group& g, std::uint64_t key, std::size_t k, long walks,
                   const Region& region = {}) {
    const auto& faces = w.faces;
    const auto& data = w.data;
    double sum = 0.0, sum2 = 0.0;
#if defined(RADIOSITY_WITH_OPENMP)
#pragma omp parallel for reduction(+ : sum, sum2) schedule(dynamic, 4096)
#endif
    for (long i = 0; i < walks; ++i) {
        radiosity::Rng rng(
            radiosity::splitmix64(std::uint64_t(i) * 0x9e3779b97f4a7c15ull ^ key ^ k));
        auto [f, x] = area_point(faces, g, rng);
        while (!region.contains(x)) std::tie(f, x) = area_point(faces, g, rng);  // region_share > 0
        double score = radiosity::band(data[f].E, k);
        while (rng.uniform() < radiosity::band(data[f].rho, k)) {
            const Vec3 d = cosine_direction(faces.normal(f), rng);
            const auto hit = w.bvh.intersect(x, d, w.t_min);
            if (!hit || glm::dot(faces.normal(hit->patch), d) >= 0.0) break;
            x += hit->t * d;
            f = hit->patch;
            score += radiosity::band(data[f].E, k);
        }
        sum += score;
        sum2 += score * score;
    }
    const double mean = sum / double(walks);
    return {mean, std::sqrt(std::max(0.0, sum2 / double(walks) - mean * mean) / double(walks))};
}

/// Per material and band, the mean B and its standard error (the program's first mode; its
/// output as it has always been).
void per_material(const Walker& w, long walks) {
    std::map<std::uint32_t, std::vector<std::uint32_t>> by_material;
    for (std::uint32_t f = 0; f < w.faces.size(); ++f) by_material[w.data[f].material].push_back(f);
    std::printf("%zu faces; %ld walks per material and band\n", w.faces.size(), walks);
    std::printf("| material | area | band | mean B | standard error |\n|---|---|---|---|---|\n");
    for (auto& [material, list] : by_material) {
        if (radiosity::mean_band(w.data[list[0]].E) > 0.0f) continue;  // emitters: B >= E
        const Group g = group_of(w.faces, std::move(list));
        for (std::size_t k = 0; k < 3; ++k) {
            const Estimate e = walk_mean(w, g, std::uint64_t(material) << 40, k, walks);
            std::printf("| %u | %.2f | %zu | %.5f | %.5f |\n", material, g.area, k, e.mean,
                        e.error);
        }
    }
}

/// Per surface of the scene (bench::surfaces_of, so that the rows match bench_hierarchy
/// surfaces'): its area, the mean of the bands of B with its standard error, and each band. A
/// meshed face belongs to the surface of the input face it was cut from. Surfaces that emit, and
/// those whose faces the meshing left out, are skipped. Largest first, as bench_hierarchy sorts.
void per_surface(const Walker& w, const radiosity::Scene<Rgb>& scene, long walks,
                 const Region& region) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> names;
    const std::vector<std::uint32_t> surface = bench::surfaces_of(scene, names);
    std::vector<std::vector<std::uint32_t>> lists(names.size());
    std::vector<char> emits(names.size(), 0);
    for (std::uint32_t f = 0; f < w.faces.size(); ++f) {
        if (!region.meets(w.faces.polygon(f))) continue;  // (left out as if meshed away)
        const std::uint32_t s = surface.at(w.data[f].surface);
        lists[s].push_back(f);
        emits[s] |= radiosity::mean_band(w.data[f].E) > 0.0f;
    }
    std::vector<std::size_t> order;
    std::size_t emitting = 0, empty = 0;
    for (std::size_t s = 0; s < names.size(); ++s) {
        if (lists[s].empty())
            ++empty;
        else if (emits[s])
            ++emitting;
        else
            order.push_back(s);
    }
    std::vector<Group> groups(names.size());
    for (const std::size_t s : order) groups[s] = group_of(w.faces, std::move(lists[s]));
    std::vector<double> inside(names.size(), 0.0);  // the area inside the region
    std::erase_if(order, [&](std::size_t s) {       // none: no walk could start there
        inside[s] = groups[s].area * region_share(w.faces, groups[s], region);
        return !(inside[s] > 0.0);
    });
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return groups[a].area > groups[b].area; });
    std::printf(
        "%zu faces, %zu surfaces (%zu emitting, %zu left out by the meshing, not listed); %ld "
        "walks per surface and band\n",
        w.faces.size(), names.size(), emitting, empty, walks);
    std::printf(
        "| surface | area | mean B (mean of the bands) | standard error | B per band | standard "
        "errors per band |\n|---|---|---|---|---|---|\n");
    for (const std::size_t s : order) {
        Estimate e[3];
        for (std::size_t k = 0; k < 3; ++k)  // a stream of its own, apart from the materials'
            e[k] =
                walk_mean(w, groups[s], (std::uint64_t(s) << 40) ^ (1ull << 63), k, walks, region);
        // The bands' walks are independent: the variance of their mean is the sum over 9.
        const double mean = (e[0].mean + e[1].mean + e[2].mean) / 3.0;
        const double error =
            std::sqrt(e[0].error * e[0].error + e[1].error * e[1].error + e[2].error * e[2].error) /
            3.0;
        std::printf("| %s | %.2f | %.5f | %.5f | %.5f %.5f %.5f | %.5f %.5f %.5f |\n",
                    names[s].c_str(), inside[s], mean, error, e[0].mean, e[1].mean, e[2].mean,
                    e[0].error, e[1].error, e[2].error);
        std::fflush(stdout);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%zu surfaces, %ld walks per surface and band, %.1f s\n", order.size(), walks,
                seconds);
}

}  // namespace

int main(int argc, char** argv) {
    bool surfaces = false;
    Region region;
    std::vector<const char*> args;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--surfaces") == 0) {
            surfaces = true;
        } else if (std::strcmp(argv[i], "--region") == 0 && i + 6 < argc) {
            for (int c = 0; c < 3; ++c) region.lo[c] = std::atof(argv[i + 1 + c]);
            for (int c = 0; c < 3; ++c) region.hi[c] = std::atof(argv[i + 4 + c]);
            surfaces = true;
            i += 6;
        } else {
            args.push_back(argv[i]);
        }
    }
    if (args.empty() || args.size() > 2) {
        std::fprintf(stderr,
                     "usage: bench_reference SCENE [WALKS] [--surfaces] [--region X0 Y0 Z0 X1 Y1 "
                     "Z1]\n");
        return 2;
    }
    const long walks = args.size() > 1 ? std::atol(args[1]) : 4000000;
    if (walks < 1) {
        std::fprintf(stderr, "bench_reference: WALKS must be a positive count\n");
        return 2;
    }
    const radiosity::Scene<Rgb> scene = load(args[0]);
    // The faces the program solves: cut where others cross them, pieces in solids left out.
    radiosity::SubdivisionOptions roots;  // the faces as they are, but cut (as the program does)
    const auto meshed = radiosity::subdivide_with_report(radiosity::build_mesh(scene), roots);
    const radiosity::PatchTable faces = radiosity::make_patch_table(meshed.mesh);
    const radiosity::Bvh bvh(faces);
    std::vector<Face> data;
    for (auto f : meshed.mesh.faces()) {
        const auto& d = meshed.mesh.data(f);
        data.push_back({d.emission, d.reflectance, d.material, d.surface});
    }
    double scale = 0.0;
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (const Vec3& v : faces.polygon(f)) scale = std::max(scale, glm::length(v));
    const Walker w{faces, bvh, data, 1e-9 * (scale + 1.0)};
    if (surfaces)
        per_surface(w, scene, walks, region);
    else
        per_material(w, walks);
    return 0;
}
