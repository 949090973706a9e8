#pragma once
// Small scenes shared by several test files.
#include <radiosity/mesh/mesh.hpp>

#include <cmath>
#include <numbers>

namespace radiosity::test {

/// Two unit squares side by side in the plane z = 0, sharing the edge x = 1; the second one
/// folded up about that edge by fold_degrees and, unless same_material, of a second material.
inline Scene<float> two_squares(bool same_material = true, double fold_degrees = 0.0) {
    Scene<float> s;
    const double a = fold_degrees * std::numbers::pi / 180.0;
    s.positions = {{0, 0, 0},
                   {1, 0, 0},
                   {1, 1, 0},
                   {0, 1, 0},
                   {1 + std::cos(a), 0, std::sin(a)},
                   {1 + std::cos(a), 1, std::sin(a)}};
    s.faces = {{0, 1, 2, 3}, {1, 4, 5, 2}};
    s.face_material = {0, same_material ? 0u : 1u};
    s.materials = {{0.0f, 0.5f, "a"}, {0.0f, 0.5f, "b"}};
    return s;
}

/// The furnace: the unit cube as a closed scene, faces pointing inwards, one material of
/// uniform emission and reflectance rho, whose exact radiosity is B = E / (1 - rho) on every
/// patch (cases.json, furnace note).
inline Scene<Rgb> furnace_cube(float emission, float rho) {
    Scene<Rgb> s;
    s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    // counter-clockwise seen from inside the cube
    s.faces = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 3, 7, 4}, {1, 5, 6, 2}, {0, 4, 5, 1}, {3, 2, 6, 7}};
    s.face_material.assign(6, 0);
    s.materials = {{Rgb(emission), Rgb(rho), "furnace"}};
    s.source = "furnace cube";
    return s;
}

}  // namespace radiosity::test
