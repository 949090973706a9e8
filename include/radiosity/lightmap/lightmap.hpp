#pragma once
/// @file lightmap.hpp  Lightmap baking end to end, as a game engine's light baker does it: lightmap
/// UVs (the scene's own, or made by unwrapping and packing charts: atlas.hpp), patches cut to the
/// lightmap's resolution so the solve is as fine as the texture that shows it, the radiosity
/// solve, smooth shading and the bake into texels (bake.hpp).

#include <radiosity/error.hpp>
#include <radiosity/lightmap/atlas.hpp>
#include <radiosity/lightmap/bake.hpp>
#include <radiosity/mesh/corner_uv.hpp>
#include <radiosity/shading/vertex_shading.hpp>
#include <radiosity/solve.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace radiosity {

/// Settings of a lightmap bake.
struct LightmapOptions {
    UnwrapOptions unwrap{};         ///< atlas size or density, gutter, chart angle (its crease
                                    ///< angle is taken from shading)
    double texels_per_patch = 4.0;  ///< longest patch edge in texels (0: the solve's own meshing)
    /// Patches made by the texel rule, at most (then coarser), for the dense solvers; the
    /// hierarchical solver has no cap.
    std::size_t max_patches = 20000;
    BakeOptions bake{};              ///< inside-geometry test and dilation
    SmoothShadingOptions shading{};  ///< crease angle of the interpolated radiosity
};

/// What bake() returns: the solved scene, its shaded mesh with lightmap UVs, the lightmap, the
/// atlas it lives in, and where the time went.
template <SpectrumType S>
struct BakeResult {
    SolveResult<S> solution;      ///< patches, B, the solver's report
    ShadedMesh shaded;            ///< smooth-shaded triangles with lightmap UVs
    Lightmap lightmap;            ///< the baked texels
    Atlas atlas;                  ///< size and texel density of the lightmap
    bool generated_uvs = false;   ///< true if the UVs were made here (the scene had none)
    double patch_edge = 0.0;      ///< the max edge the patches were cut to (0: not cut)
    double unwrap_seconds = 0.0;  ///< making the UVs
    double solve_seconds = 0.0;   ///< subdivision, form factors and the solver
    double bake_seconds = 0.0;    ///< shading and baking
};

/// The texel density (texels per scene unit) of a mesh's existing UVs in a W x H lightmap: the
/// square root of the UV area in texels over the surface area, summed over all faces.
template <class M>
double uv_texel_density(const M& mesh, int width, int height) {
    double uv_area = 0.0, area = 0.0;
    for (auto f : mesh.faces()) {
        const auto uv = corner_uvs(mesh, f);
        const auto poly = face_polygon(mesh, f);
        for (std::size_t k = 1; k + 1 < uv.size(); ++k) {
            const glm::dvec2 a = glm::dvec2(uv[k] - uv[0]) * glm::dvec2(width, height),
                             b = glm::dvec2(uv[k + 1] - uv[0]) * glm::dvec2(width, height);
            uv_area += 0.5 * std::abs(cross2(a, b));
        }
        area += polygon_area(poly);
    }
    return area > 0.0 ? std::sqrt(uv_area / area) : 0.0;
}

namespace detail {
/// The lightmap UVs of the scene: its own, in a size x size atlas, or made by make_lightmap_uvs.
template <SpectrumType S>
Atlas lightmap_atlas(Mesh<S>& mesh, const LightmapOptions& o, bool& generated) {
    generated = !has_corner_uvs(mesh);
    if (generated) {  // charts end where the shading breaks, so no jump is blurred in a chart
        UnwrapOptions unwrap = o.unwrap;
        unwrap.charts.crease_angle_degrees = o.shading.crease_angle_degrees;
        return make_lightmap_uvs(mesh, unwrap);
    }
    Atlas atlas;
    atlas.width = atlas.height = o.unwrap.size;
    atlas.texel_density = uv_texel_density(mesh, atlas.width, atlas.height);
    return atlas;
}

/// The patch edge for the texel rule: `edge`, or longer where that would make more than
/// max_patches patches (the dense solve needs n^2 form factors; smooth shading still gives every
/// texel its own interpolated value). Each try scales the edge by the square root of the excess.
template <SpectrumType S>
double texel_patch_edge(const Mesh<S>& mesh, double edge, std::size_t max_patches) {
    for (int attempt = 0; attempt < 16; ++attempt) {
        const std::size_t n = subdivided_face_count(mesh, SubdivisionOptions{edge});
        if (n <= max_patches) return edge;
        edge *= 1.02 * std::sqrt(double(n) / double(max_patches));
    }
    return edge;
}

}  // namespace detail

/// Bakes a scene's radiosity into a lightmap (see the file comment). The patches are cut so
/// that none is longer than texels_per_patch texels, unless that would make more than
/// max_patches patches (then coarser), or solve.subdivision.max_edge, if that is finer. Throws
/// Error for bad options or input, Cancelled if the progress callback stops.
template <SpectrumType S>
BakeResult<S> bake(const Mesh<S>& scene, SolveOptions solve_options,
                   const LightmapOptions& options = {}) {
    if (!(options.texels_per_patch >= 0.0) || !std::isfinite(options.texels_per_patch))
        throw Error("lightmap: texels per patch must be a finite number >= 0, not " +
                    std::to_string(options.texels_per_patch));
    if (options.max_patches < 1) throw Error("lightmap: max patches must be at least 1");
    BakeResult<S> out;
    auto t0 = std::chrono::steady_clock::now();
    Mesh<S> mesh = scene;
    out.atlas = detail::lightmap_atlas(mesh, options, out.generated_uvs);
    out.unwrap_seconds = detail::seconds_since(t0);
    if (options.texels_per_patch > 0.0 && out.atlas.texel_density > 0.0) {
        double& max_edge = solve_options.subdivision.max_edge;
        // The cap keeps a dense matrix in bounds; the hierarchical solver has none (its leaves
        // follow the texel rule down to a quarter of the texel patch's area, as needed).
        const bool capped = solve_options.solver != SolverKind::hierarchical;
        const double edge = detail::texel_patch_edge(
            mesh, options.texels_per_patch / out.atlas.texel_density,
            capped ? options.max_patches : std::numeric_limits<std::size_t>::max());
        max_edge = max_edge > 0.0 ? std::min(max_edge, edge) : edge;
    }
    out.patch_edge = solve_options.subdivision.max_edge;
    t0 = std::chrono::steady_clock::now();
    out.solution = solve(mesh, solve_options);
    out.solve_seconds = detail::seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    out.shaded = smooth_shading(out.solution.mesh, options.shading);
    out.lightmap = bake_lightmap(out.shaded, out.atlas.width, out.atlas.height, options.bake);
    out.bake_seconds = detail::seconds_since(t0);
    return out;
}

}  // namespace radiosity
