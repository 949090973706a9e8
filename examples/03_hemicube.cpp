// Lecture example 3: the hemicube of one patch, as pictures.
//
// Around the centre of the floor of the Cornell box, every other patch is projected onto the
// five faces of a half cube; a z-buffer keeps the nearest. Each pixel carries a delta form
// factor, dA / (pi (x^2 + y^2 + 1)^2) on the top and z dA / (pi (x^2 + z^2 + 1)^2) on the sides,
// and F_ij is the sum over the pixels that see patch j. We write two pictures of the unfolded
// hemicube (the top in the middle, the four sides folded out around it):
//   hemicube_items.png   which patch each pixel sees (a colour per patch)
//   hemicube_delta.png   the delta form factors (brightest straight up)
// and check that the delta form factors add up to 1 (exit status 1 if not).
#include <radiosity/form_factor/hemicube.hpp>
#include <radiosity/io/image.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include <cmath>
#include <cstdio>

int main() {
    using namespace radiosity;
    const Mesh<float> mesh = subdivide(build_mesh(cornell_box<float>()), {.max_edge = 100.0});
    const PatchTable patches = make_patch_table(mesh);
    std::size_t floor = 0;  // the floor patch nearest the middle of the floor
    for (std::size_t i = 0; i < patches.size(); ++i)
        if (patches.centroid(i).y < 1e-6 &&
            glm::distance(patches.centroid(i), Vec3(278, 0, 280)) <
                glm::distance(patches.centroid(floor), Vec3(278, 0, 280)))
            floor = i;

    const int r = 128;
    Hemicube hemicube({r, false});
    hemicube.prepare(patches);
    const auto ids = hemicube.item_buffers(floor);
    // Unfolded: a 2r x 2r picture, the top face in the middle (r x r), each side (r x r/2)
    // against the top edge it shares; corners stay black.
    Image items{2 * r, 2 * r, std::vector<glm::vec3>(4 * r * r, glm::vec3(0.0f))};
    Image delta = items;
    auto colour_of = [](std::int32_t id) {
        if (id < 0) return glm::vec3(0.0f);
        const auto h = static_cast<std::uint32_t>(id) * 2654435761u;
        return glm::vec3(0.2f + 0.8f * float(h & 255) / 255.0f,
                         0.2f + 0.8f * float((h >> 8) & 255) / 255.0f,
                         0.2f + 0.8f * float((h >> 16) & 255) / 255.0f);
    };
    const auto& top = hemicube.top_delta_form_factors();
    const auto& side = hemicube.side_delta_form_factors();
    const double peak = top[(r / 2) * r + r / 2];
    for (int y = 0; y < r; ++y)
        for (int x = 0; x < r; ++x) {
            const auto k = static_cast<std::size_t>(y * r + x);
            items.at(r / 2 + x, r / 2 + y) = colour_of(ids[0][k]);
            delta.at(r / 2 + x, r / 2 + y) = glm::vec3(float(top[k] / peak));
        }
    // Side rows run from the top edge (row 0, height 1) down to the horizon (last row), so
    // row y lies y pixels out from the top face; the four sides go right, left, below, above.
    for (int y = 0; y < r / 2; ++y)
        for (int x = 0; x < r; ++x) {
            const auto k = static_cast<std::size_t>(y * r + x);
            const std::array<std::pair<int, int>, 4> at{{{3 * r / 2 + y, r / 2 + x},
                                                         {r / 2 - 1 - y, r / 2 + x},
                                                         {r / 2 + x, 3 * r / 2 + y},
                                                         {r / 2 + x, r / 2 - 1 - y}}};
            for (std::size_t s = 0; s < 4; ++s) {
                items.at(at[s].first, at[s].second) = colour_of(ids[s + 1][k]);
                delta.at(at[s].first, at[s].second) = glm::vec3(float(side[k] / peak));
            }
        }
    ToneMapOptions fixed;
    fixed.auto_exposure = false;
    fixed.scale = 3.14159265358979;  // display the values as they are
    write_png(items, "hemicube_items.png", fixed);
    write_png(delta, "hemicube_delta.png", fixed);
    const double sum = hemicube.delta_form_factor_sum();
    std::printf(
        "patch %zu of %zu; the delta form factors add up to %.6f; wrote "
        "hemicube_items.png and hemicube_delta.png\n",
        floor, patches.size(), sum);
    return std::abs(sum - 1.0) < 1e-3 ? 0 : 1;
}
