// Lecture example 6: baking the Cornell box into a lightmap, as a game engine's light baker does.
//
// A game does not solve radiosity while it runs: it draws each surface with a texture, the
// lightmap, that holds the light computed beforehand. Baking takes four steps:
//   1. lightmap UVs: the surfaces are cut into charts (connected faces facing about the same
//      way), each flattened and packed into one square texture with a gutter around it;
//   2. patches from texels: the scene is cut so that no patch is longer than a few texels;
//   3. the radiosity solve B = E + R F B, and smooth shading (B at the vertices);
//   4. the bake: each texel takes B interpolated at its point on the surface.
// Writes cornell_lightmap.png (the texture, and the box drawn with it) and cornell_lightmap.glb
// (the box textured with it, for Blender or three.js), and checks that the texture, drawn through
// its UVs, gives the same picture as drawing B at the vertices directly; exit status 1 if not.
#include <radiosity/radiosity.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>

int main() {
    using namespace radiosity;
    const Mesh<Rgb> scene = build_mesh(cornell_box<Rgb>());
    LightmapOptions options;
    options.unwrap.size = 256;       // 256 x 256 texels for the whole box
    options.texels_per_patch = 4.0;  // patches of at most 4 x 4 texels
    const BakeResult<Rgb> baked = bake(scene, SolveOptions{}, options);
    const Lightmap& lightmap = baked.lightmap;
    std::printf(
        "%zu charts at %.3f texels/mm; %zu patches; %zu texels on surfaces, %zu inside "
        "geometry (refilled), %zu in gutters\n",
        baked.atlas.charts, baked.atlas.texel_density, baked.solution.patches.size(),
        lightmap.count(TexelState::surface), lightmap.count(TexelState::inside),
        lightmap.count(TexelState::dilated));

    // The same view drawn twice: B interpolated from the vertices, and the lightmap sampled.
    const Camera camera{{278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3};
    const RenderOptions view{.width = 256, .height = 256, .cull_back_faces = true};
    const Image direct = render(baked.shaded, camera, view);
    const Image textured = render_lightmapped(baked.shaded, lightmap.image, camera, view);
    double difference = 0.0, total = 0.0;
    for (std::size_t i = 0; i < direct.pixels.size(); ++i) {
        difference += glm::length(direct.pixels[i] - textured.pixels[i]);
        total += glm::length(direct.pixels[i]);
    }
    const double relative = difference / total;
    std::printf("mean difference between the two pictures: %.2f%% of the mean value\n",
                100.0 * relative);

    // The texture beside the view drawn with it, for the README.
    const double scale = exposure_scale(lightmap.image.pixels, {});
    Image both{512, 256, std::vector<glm::vec3>(512 * 256)};
    const double view_scale = exposure_scale(textured.pixels, {});
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            both.at(x, y) =
                lightmap.image.at(x * lightmap.image.width / 256, y * lightmap.image.height / 256) *
                float(scale / view_scale);
            both.at(256 + x, y) = textured.at(x, y);
        }
    write_png(both, "cornell_lightmap.png",
              {.auto_exposure = false, .scale = view_scale * std::numbers::pi});
    write_gltf_lightmapped(baked.shaded, lightmap.image, "cornell_lightmap.glb", scale);
    std::printf(
        "wrote cornell_lightmap.png (the lightmap, and the box drawn with it) and "
        "cornell_lightmap.glb\n");
    return std::isfinite(relative) && relative < 0.02 ? 0 : 1;
}
