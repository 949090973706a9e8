#pragma once
/// @file camera.hpp  Pictures of a shaded mesh: a pinhole camera, the library's rasteriser with a
/// z-buffer, and Gouraud interpolation of the vertex colours (Gouraud 1971), perspective-correct.
/// Pixels hold linear radiant exitance B; io/image.hpp tone-maps and writes them.

#include <radiosity/error.hpp>
#include <radiosity/geometry/raster.hpp>
#include <radiosity/shading/image.hpp>
#include <radiosity/shading/shaded_mesh.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace radiosity {

/// A pinhole camera: where it is, what it looks at, which way is up, the vertical field of view.
struct Camera {
    Vec3 eye{0.0, 0.0, 1.0};      ///< centre of projection
    Vec3 target{0.0, 0.0, 0.0};   ///< a point on the line of sight
    Vec3 up{0.0, 1.0, 0.0};       ///< the picture's up direction (need not be orthogonal)
    double fov_y_degrees = 40.0;  ///< vertical field of view, in (0, 180)
};

/// Settings of a rendering.
struct RenderOptions {
    int width = 512;             ///< picture width in pixels, 1..16384
    int height = 512;            ///< picture height in pixels, 1..16384
    glm::vec3 background{0.0f};  ///< value where nothing is seen
    /// Skip triangles seen from behind, as the radiosity method sees them (a patch has one side):
    /// a camera outside a closed room sees into it through the near walls. false draws both
    /// sides (open geometry of unknown winding).
    bool cull_back_faces = true;
};

namespace detail {
/// Refuses options the projection cannot use; each message names the option at fault.
inline void check_view(const Camera& c, const RenderOptions& o) {
    if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
        throw Error("render: RenderOptions width and height must be in [1, 16384], not " +
                    std::to_string(o.width) + " x " + std::to_string(o.height));
    if (!(c.fov_y_degrees > 0.0 && c.fov_y_degrees < 180.0))
        throw Error("render: Camera fov_y_degrees must be in (0, 180), not " +
                    std::to_string(c.fov_y_degrees));
    const Vec3 view = c.target - c.eye;
    if (!(glm::length(view) > 0.0)) throw Error("render: Camera eye and target coincide");
    if (!(glm::length(glm::cross(view, c.up)) > 1e-12 * glm::length(view) * glm::length(c.up)))
        throw Error("render: Camera up is parallel to the view direction (or zero)");
}

/// Near and far planes that hold the whole mesh: far beyond its farthest point along the view,
/// near a small fraction of that (double-precision depth keeps the ratio harmless).
inline std::pair<double, double> depth_range(const ShadedMesh& m, const glm::dmat4& view) {
    double far = 0.0;
    for (const Vec3& p : m.positions) far = std::max(far, -(view * glm::dvec4(p, 1.0)).z);
    far = far > 0.0 ? 1.01 * far : 1.0;
    return {far * 1e-6, far};
}
}  // namespace detail

/// Renders the mesh as the camera sees it: every triangle through the shared rasteriser
/// (near-plane clipping, top-left rule), nearest surface kept per pixel, and the pixel's value
/// shade(triangle index, perspective-correct barycentric weights). Back faces are skipped
/// unless options.cull_back_faces is false. Throws Error for bad options.
/// Cost: O(triangles + covered pixels).
template <class Shade>
Image render_with(const ShadedMesh& mesh, const Camera& camera, const RenderOptions& options,
                  Shade&& shade) {
    detail::check_view(camera, options);
    const glm::dmat4 view = glm::lookAt(camera.eye, camera.target, camera.up);
    const auto [near, far] = detail::depth_range(mesh, view);
    const glm::dmat4 clip = perspective(camera.fov_y_degrees * std::numbers::pi / 180.0,
                                        double(options.width) / options.height, near, far) *
                            view;
    Image image{
        options.width, options.height,
        std::vector<glm::vec3>(std::size_t(options.width) * options.height, options.background)};
    std::vector<double> depth(image.pixels.size(), std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        if (options.cull_back_faces) {  // the eye behind the triangle's plane sees its back
            const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]],
                       &c = mesh.positions[t[2]];
            if (glm::dot(glm::cross(b - a, c - a), camera.eye - a) <= 0.0) continue;
        }
        const std::array<Vec4, 3> p{clip * Vec4(mesh.positions[t[0]], 1.0),
                                    clip * Vec4(mesh.positions[t[1]], 1.0),
                                    clip * Vec4(mesh.positions[t[2]], 1.0)};
        rasterize_triangle(p, options.width, options.height, [&](const Fragment& f) {
            const std::size_t at = std::size_t(f.y) * options.width + f.x;
            if (f.depth >= depth[at]) return;
            depth[at] = f.depth;
            image.pixels[at] = shade(i, f.weight);
        });
    }
    return image;
}

/// Renders the mesh with its vertex colours interpolated (Gouraud 1971), perspective-correctly.
inline Image render(const ShadedMesh& mesh, const Camera& camera,
                    const RenderOptions& options = {}) {
    return render_with(mesh, camera, options, [&](std::size_t i, const glm::dvec3& w) {
        const auto& t = mesh.triangles[i];
        return glm::vec3(w.x * glm::dvec3(mesh.colours[t[0]]) +
                         w.y * glm::dvec3(mesh.colours[t[1]]) +
                         w.z * glm::dvec3(mesh.colours[t[2]]));
    });
}

/// The lightmap UV at barycentric weights w of triangle i (the mesh must have UVs).
inline glm::vec2 interpolate_uv(const ShadedMesh& mesh, std::size_t i, const glm::dvec3& w) {
    const auto& t = mesh.triangles[i];
    return glm::vec2(w.x * glm::dvec2(mesh.uvs[t[0]]) + w.y * glm::dvec2(mesh.uvs[t[1]]) +
                     w.z * glm::dvec2(mesh.uvs[t[2]]));
}

/// Renders the mesh textured with a lightmap, as a game engine shows a baked scene: the lightmap
/// UVs interpolated perspective-correctly, the lightmap sampled bilinearly. Throws Error if the
/// mesh has no UVs or the lightmap is empty.
inline Image render_lightmapped(const ShadedMesh& mesh, const Image& lightmap, const Camera& camera,
                                const RenderOptions& options = {}) {
    if (mesh.uvs.size() != mesh.positions.size())
        throw Error("render_lightmapped: the mesh has no lightmap UVs");
    if (lightmap.width < 1 || lightmap.height < 1)
        throw Error("render_lightmapped: the lightmap is empty");
    return render_with(mesh, camera, options, [&](std::size_t i, const glm::dvec3& w) {
        return sample_bilinear(lightmap, interpolate_uv(mesh, i, w));
    });
}

}  // namespace radiosity
