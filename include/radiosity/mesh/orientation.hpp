#pragma once
/// @file orientation.hpp  Which side of a face shines. A patch radiates from its front (the
/// side its vertices turn counter-clockwise about) only, as in the radiosity method since Goral
/// et al. (1984); a room modelled as a solid (faces pointing out) is therefore dark inside. The
/// two fixes that lightmap bakers offer for such single-sided geometry: turning every face
/// round, and two-sided surfaces (a reversed twin behind every face).

#include <radiosity/mesh/mesh.hpp>

#include <algorithm>
#include <cstddef>

namespace radiosity {

/// Turns every face of the scene round (reverses its vertex order, and its UVs with it), so
/// that a closed room modelled with its faces pointing out faces in. Cost: O(corners); the
/// solve costs the same as before.
template <SpectrumType S>
void flip_faces(Scene<S>& scene) {
    for (auto& f : scene.faces) std::reverse(f.begin(), f.end());
    for (auto& uv : scene.face_uvs) std::reverse(uv.begin(), uv.end());
}

/// Makes every surface two-sided: each face gets a twin with the reversed vertex order and the
/// same material, so light leaves and arrives on both sides (as a renderer's "two-sided"
/// flag shows it). The twins are separate patches: twice the patches, so four times the dense
/// matrix's memory and form-factor time, and the twins of a closed room's outside see only the
/// dark exterior. Cost: O(corners).
template <SpectrumType S>
void make_two_sided(Scene<S>& scene) {
    const std::size_t n = scene.faces.size();
    scene.faces.reserve(2 * n);
    scene.face_material.reserve(2 * n);
    for (std::size_t f = 0; f < n; ++f) {
        scene.faces.emplace_back(scene.faces[f].rbegin(), scene.faces[f].rend());
        scene.face_material.push_back(scene.face_material[f]);
    }
    if (scene.face_uvs.empty()) return;
    scene.face_uvs.reserve(2 * n);
    for (std::size_t f = 0; f < n; ++f)
        scene.face_uvs.emplace_back(scene.face_uvs[f].rbegin(), scene.face_uvs[f].rend());
}

/// Whether any face of the scene emits (a band of its material's emission above 0): a scene
/// without one solves to B = 0 everywhere, a black picture. Cost: O(faces).
template <SpectrumType S>
bool has_emitter(const Scene<S>& scene) {
    for (std::uint32_t m : scene.face_material)
        if (m < scene.materials.size() && max_abs(scene.materials[m].emission) > 0.0f) return true;
    return false;
}

}  // namespace radiosity
