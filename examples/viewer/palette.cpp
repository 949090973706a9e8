// Colours that are not light (palette.hpp).
#include "palette.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace radiosity::view {

glm::vec3 srgb_to_linear(const glm::vec3& display) {
    auto decode = [](float c) {
        c = std::clamp(c, 0.0f, 1.0f);
        return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    };
    return {decode(display.r), decode(display.g), decode(display.b)};
}

glm::vec3 false_colour(double t) {
    // Control points of the scale, chosen by eye, lightness rising from each to the next.
    static constexpr std::array<std::array<float, 3>, 6> stops{{{0.05f, 0.03f, 0.25f},
                                                                {0.32f, 0.06f, 0.55f},
                                                                {0.65f, 0.12f, 0.50f},
                                                                {0.90f, 0.30f, 0.25f},
                                                                {0.99f, 0.62f, 0.10f},
                                                                {0.99f, 0.95f, 0.60f}}};
    const double x = std::clamp(t, 0.0, 1.0) * double(stops.size() - 1);
    const auto k = std::min(static_cast<std::size_t>(x), stops.size() - 2);
    const auto f = static_cast<float>(x - double(k));
    const glm::vec3 a(stops[k][0], stops[k][1], stops[k][2]);
    const glm::vec3 b(stops[k + 1][0], stops[k + 1][1], stops[k + 1][2]);
    return glm::mix(a, b, f);
}

double log_position(double F, double lo, double hi) {
    if (!(F > 0.0)) return -1.0;
    if (!(hi > lo) || !(lo > 0.0)) return 1.0;
    return std::clamp(std::log(F / lo) / std::log(hi / lo), 0.0, 1.0);
}

glm::vec3 id_colour(std::int32_t id) {
    if (id < 0) return glm::vec3(0.0f);
    const auto h = static_cast<std::uint32_t>(id) * 2654435761u;  // Knuth's multiplicative hash
    return {0.2f + 0.8f * float(h & 255u) / 255.0f, 0.2f + 0.8f * float((h >> 8) & 255u) / 255.0f,
            0.2f + 0.8f * float((h >> 16) & 255u) / 255.0f};
}

}  // namespace radiosity::view
