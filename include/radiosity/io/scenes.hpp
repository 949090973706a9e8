#pragma once
/// @file scenes.hpp  Built-in scenes: the Cornell box as published by the Cornell Program of
/// Computer Graphics (geometry in mm; the RGB reflectances in common use; light exitance
/// E = pi x the published radiance, since a Lambertian emitter of radiance L has exitance pi L).

#include <radiosity/error.hpp>
#include <radiosity/mesh/mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <vector>

namespace radiosity {

namespace detail {

/// Builds a Scene from polygons, sharing a vertex index between equal points (to 1e-6), so
/// that faces that meet along an edge are connected in the mesh. Cost: O(log n) per corner.
template <SpectrumType S>
class SceneBuilder {
  public:
    explicit SceneBuilder(std::string source) { scene_.source = std::move(source); }

    std::uint32_t material(const Material<S>& m) {
        scene_.materials.push_back(m);
        return static_cast<std::uint32_t>(scene_.materials.size() - 1);
    }

    /// Adds a polygon of finite points; returns false, adding nothing, if sharing its corners
    /// leaves fewer than three distinct vertices or repeats one (a face smaller than the 1e-6
    /// tolerance, which has no area to exchange light).
    bool face(const std::vector<Vec3>& polygon, std::uint32_t material) {
        std::vector<Key> keys;
        for (const Vec3& p : polygon) keys.push_back(key(p));
        for (std::size_t k = 0; k < keys.size(); ++k)
            if (std::find(keys.begin(), keys.begin() + std::ptrdiff_t(k), keys[k]) !=
                keys.begin() + std::ptrdiff_t(k))
                return false;
        if (keys.size() < 3) return false;
        std::vector<std::uint32_t> f;
        for (std::size_t k = 0; k < keys.size(); ++k) f.push_back(vertex(keys[k], polygon[k]));
        scene_.faces.push_back(f);
        scene_.face_material.push_back(material);
        return true;
    }

    /// A quadrilateral a b c d (a to b is the s direction, a to d the t direction) cut into a
    /// grid along the given fractions of s and t, each cell bilinear in the corners. Sides cut
    /// at the same fractions meet vertex to vertex.
    void grid(const std::array<Vec3, 4>& q, const std::vector<double>& fs,
              const std::vector<double>& ft, std::uint32_t material,
              std::uint32_t centre_material = UINT32_MAX) {
        auto at = [&](double s, double t) {
            return (1 - s) * (1 - t) * q[0] + s * (1 - t) * q[1] + s * t * q[2] +
                   (1 - s) * t * q[3];
        };
        for (std::size_t b = 0; b + 1 < ft.size(); ++b)
            for (std::size_t a = 0; a + 1 < fs.size(); ++a) {
                const bool centre = a == 1 && b == 1 && centre_material != UINT32_MAX;
                face({at(fs[a], ft[b]), at(fs[a + 1], ft[b]), at(fs[a + 1], ft[b + 1]),
                      at(fs[a], ft[b + 1])},
                     centre ? centre_material : material);
            }
    }

    Scene<S> take() { return std::move(scene_); }

  private:
    /// A point rounded to 1e-6, held as doubles so that no coordinate is out of a key's range
    /// (beyond 2^53 a double is its own rounding). The points are finite: NaN has no order.
    using Key = std::array<double, 3>;
    static Key key(const Vec3& p) {
        return {std::round(p.x * 1e6), std::round(p.y * 1e6), std::round(p.z * 1e6)};
    }

    std::uint32_t vertex(const Key& key, const Vec3& p) {
        auto [it, fresh] =
            index_.try_emplace(key, static_cast<std::uint32_t>(scene_.positions.size()));
        if (fresh) scene_.positions.push_back(p);
        return it->second;
    }

    Scene<S> scene_;
    std::map<Key, std::uint32_t> index_;
};

}  // namespace detail

/// The Cornell box (Cornell Program of Computer Graphics, "Cornell Box Data"), in mm, open at
/// the front (z = 0), seen from the published camera at (278, 273, -800). Surfaces face into
/// the box; the blocks' faces face out. The light (130 x 105 mm) lies in the ceiling plane, so
/// it is cut out of the ceiling: the ceiling is a 3 x 3 grid whose middle cell is the light.
/// To keep the box conforming, the walls and floor are cut where the ceiling grid meets them
/// (x at 213 and 343, z at 227 and 332, along each wall). Reflectances (RGB): white (0.725,
/// 0.71, 0.68), red (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091); light radiance (17, 12, 4),
/// so E = pi (17, 12, 4), light reflectance 0.78 (McGuire's CornellBox-Original). The red wall
/// is not planar in the published data (3.2 mm off); it is kept as published. With
/// `blocks = false`, the empty box.
template <SpectrumType S>
Scene<S> cornell_box(bool blocks = true) {
    detail::SceneBuilder<S> b(blocks ? "cornell box" : "empty cornell box");
    const float pi = std::numbers::pi_v<float>;
    const auto white = b.material({S{}, from_rgb<S>(0.725f, 0.71f, 0.68f), "white"});
    const auto red = b.material({S{}, from_rgb<S>(0.63f, 0.065f, 0.05f), "red"});
    const auto green = b.material({S{}, from_rgb<S>(0.14f, 0.45f, 0.091f), "green"});
    const auto light = b.material({from_rgb<S>(17.0f * pi, 12.0f * pi, 4.0f * pi),
                                   from_rgb<S>(0.78f, 0.78f, 0.78f), "light"});
    // Cuts along x and z where the light's edges are (x 213..343, z 227..332).
    const std::vector<double> fx{0.0, 213.0 / 556.0, 343.0 / 556.0, 1.0};
    const std::vector<double> fz{0.0, 227.0 / 559.2, 332.0 / 559.2, 1.0};
    const std::vector<double> whole{0.0, 1.0};
    // Corners: floor (y = 0) and ceiling (y = 548.8), at x = 0 (green side) and x = max (red).
    const Vec3 f00(0, 0, 0), f10(552.8, 0, 0), f11(549.6, 0, 559.2), f01(0, 0, 559.2);
    const Vec3 c00(0, 548.8, 0), c10(556, 548.8, 0), c11(556, 548.8, 559.2), c01(0, 548.8, 559.2);
    // Each quad is listed so that its normal points into the box.
    b.grid({f00, f01, f11, f10}, fz, fx, white);         // floor: s along z, t along x
    b.grid({c00, c10, c11, c01}, fx, fz, white, light);  // ceiling, light in the middle
    b.grid({f01, c01, c11, f11}, whole, fx, white);      // back wall (z = 559.2)
    b.grid({f00, c00, c01, f01}, whole, fz, green);      // right wall, green (x = 0)
    b.grid({f10, f11, c11, c10}, fz, whole, red);        // left wall, red (x = 556)
    if (blocks) {
        using Quad = std::vector<Vec3>;
        for (const Quad& q :
             std::vector<Quad>{{{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}},
                               {{290, 0, 114}, {290, 165, 114}, {240, 165, 272}, {240, 0, 272}},
                               {{130, 0, 65}, {130, 165, 65}, {290, 165, 114}, {290, 0, 114}},
                               {{82, 0, 225}, {82, 165, 225}, {130, 165, 65}, {130, 0, 65}},
                               {{240, 0, 272}, {240, 165, 272}, {82, 165, 225}, {82, 0, 225}},
                               {{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}},
                               {{423, 0, 247}, {423, 330, 247}, {472, 330, 406}, {472, 0, 406}},
                               {{472, 0, 406}, {472, 330, 406}, {314, 330, 456}, {314, 0, 456}},
                               {{314, 0, 456}, {314, 330, 456}, {265, 330, 296}, {265, 0, 296}},
                               {{265, 0, 296}, {265, 330, 296}, {423, 330, 247}, {423, 0, 247}}})
            b.face(q, white);  // the published short and tall blocks, faces pointing out
    }
    Scene<S> scene = b.take();
    scene.metres_per_unit = 0.001;  // published in millimetres
    return scene;
}

/// Names of the built-in scenes: "cornell" (the Cornell box) and "cornell-empty" (without its
/// blocks, whose light-to-wall form factors are published).
inline std::vector<std::string> builtin_scene_names() {
    return {"cornell", "cornell-empty"};
}

/// The built-in scene of that name; throws Error for an unknown name.
template <SpectrumType S>
Scene<S> builtin_scene(const std::string& name) {
    if (name == "cornell") return cornell_box<S>(true);
    if (name == "cornell-empty") return cornell_box<S>(false);
    std::string known;
    for (const auto& n : builtin_scene_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown scene '" + name + "' (known: " + known + ")");
}

}  // namespace radiosity
