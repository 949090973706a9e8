// A patch's hemicube, unfolded (hemicube_view.hpp).
#include "hemicube_view.hpp"

#include "palette.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace radiosity::view {

double UnfoldedHemicube::seen_sum(std::int32_t j) const {
    double s = 0.0;
    for (std::size_t k = 0; k < seen.size(); ++k)
        if (seen[k] == j) s += delta[k];
    return s;
}

UnfoldedHemicube unfold_hemicube(const radiosity::Hemicube& hemicube, std::size_t i) {
    const int r = hemicube.options().resolution;
    const auto ids = hemicube.item_buffers(i);
    const auto& top = hemicube.top_delta_form_factors();
    const auto& side = hemicube.side_delta_form_factors();
    UnfoldedHemicube u;
    u.patch = i;
    u.size = 2 * r;
    const auto pixels = static_cast<std::size_t>(u.size) * static_cast<std::size_t>(u.size);
    u.seen.assign(pixels, -1);
    u.delta.assign(pixels, 0.0);
    u.face.assign(pixels, -1);
    u.face_pixel.assign(pixels, -1);
    auto put = [&](int x, int y, int face, int k, double dF) {
        const auto at = static_cast<std::size_t>(y) * static_cast<std::size_t>(u.size) +
                        static_cast<std::size_t>(x);
        const std::int32_t j = ids[static_cast<std::size_t>(face)][static_cast<std::size_t>(k)];
        u.seen[at] = j;
        u.delta[at] = dF;
        u.face[at] = static_cast<std::int8_t>(face);
        u.face_pixel[at] = k;
        u.total += dF;
        if (j >= 0) u.covered += dF;
    };
    for (int y = 0; y < r; ++y)
        for (int x = 0; x < r; ++x)
            put(r / 2 + x, r / 2 + y, 0, y * r + x, top[static_cast<std::size_t>(y * r + x)]);
    // Side rows run from the top face's edge (row 0) down to the horizon, so row y lies y pixels
    // out from the top face; the four sides go right, left, below and above it.
    for (int y = 0; y < r / 2; ++y)
        for (int x = 0; x < r; ++x) {
            const std::array<std::pair<int, int>, 4> at{{{3 * r / 2 + y, r / 2 + x},
                                                         {r / 2 - 1 - y, r / 2 + x},
                                                         {r / 2 + x, 3 * r / 2 + y},
                                                         {r / 2 + x, r / 2 - 1 - y}}};
            const double dF = side[static_cast<std::size_t>(y * r + x)];
            for (int s = 0; s < 4; ++s)
                put(at[static_cast<std::size_t>(s)].first, at[static_cast<std::size_t>(s)].second,
                    s + 1, y * r + x, dF);
        }
    return u;
}

std::string hemicube_face_name(int k) {
    static const std::array<const char*, 5> names{"top", "side +u", "side -u", "side +v",
                                                  "side -v"};
    return k >= 0 && k < 5 ? names[static_cast<std::size_t>(k)] : "none";
}

namespace {
template <class Colour>
std::vector<std::uint8_t> picture(const UnfoldedHemicube& h, Colour&& colour_at) {
    std::vector<std::uint8_t> rgba(h.seen.size() * 4);
    for (std::size_t k = 0; k < h.seen.size(); ++k) {
        const glm::vec3 c = glm::clamp(colour_at(k), glm::vec3(0.0f), glm::vec3(1.0f));
        for (int b = 0; b < 3; ++b)
            rgba[4 * k + std::size_t(b)] = static_cast<std::uint8_t>(std::lround(255.0f * c[b]));
        rgba[4 * k + 3] = h.face[k] < 0 ? 0 : 255;  // the corners off the faces are clear
    }
    return rgba;
}
}  // namespace

std::vector<std::uint8_t> hemicube_seen_picture(const UnfoldedHemicube& h,
                                                const std::vector<glm::vec3>& colours) {
    return picture(h, [&](std::size_t k) {
        const std::int32_t j = h.seen[k];
        return j >= 0 && static_cast<std::size_t>(j) < colours.size()
                   ? colours[static_cast<std::size_t>(j)]
                   : glm::vec3(0.0f);
    });
}

std::vector<std::uint8_t> hemicube_id_picture(const UnfoldedHemicube& h) {
    return picture(h, [&](std::size_t k) { return id_colour(h.seen[k]); });
}

std::vector<std::uint8_t> hemicube_delta_picture(const UnfoldedHemicube& h) {
    const double peak = *std::max_element(h.delta.begin(), h.delta.end());
    return picture(h, [&](std::size_t k) {
        return glm::vec3(peak > 0.0 ? static_cast<float>(h.delta[k] / peak) : 0.0f);
    });
}

}  // namespace radiosity::view
