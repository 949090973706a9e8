// Lecture example 4: flat versus smooth shading of the Cornell box, side by side.
//
// The solve gives one radiosity B per patch. Flat shading paints each patch in its own B: the
// patches show. Smooth shading (Gouraud) gives each vertex the area-weighted mean B of the
// patches around it, not across creases or materials, and interpolates across the triangles.
// Writes flat_vs_smooth.png (flat on the left); exit status 1 if the two pictures do not differ
// or a pixel is not a finite number.
#include <radiosity/radiosity.hpp>

#include <cmath>
#include <cstdio>

int main() {
    using namespace radiosity;
    const Mesh<Rgb> scene = build_mesh(cornell_box<Rgb>());
    SolveOptions options;
    options.subdivision.max_edge = 60.0;  // coarse on purpose: the facets show when flat
    const SolveResult<Rgb> result = solve(scene, options);

    const Camera camera{{278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3};
    const Image flat = render(flat_shading(result.mesh), camera, {.width = 256, .height = 256});
    const Image smooth = render(smooth_shading(result.mesh), camera, {.width = 256, .height = 256});
    Image both{512, 256, std::vector<glm::vec3>(512 * 256)};
    double difference = 0.0;
    bool finite = true;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            both.at(x, y) = flat.at(x, y);
            both.at(256 + x, y) = smooth.at(x, y);
            difference += glm::length(flat.at(x, y) - smooth.at(x, y));
            finite = finite && std::isfinite(glm::length(smooth.at(x, y)));
        }
    write_png(both, "flat_vs_smooth.png");
    std::printf("%zu patches; mean difference per pixel %.3f; wrote flat_vs_smooth.png\n",
                result.patches.size(), difference / (256.0 * 256.0));
    return finite && difference > 0.0 ? 0 : 1;
}
