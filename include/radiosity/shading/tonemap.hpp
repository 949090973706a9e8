#pragma once
/// @file tonemap.hpp  From radiant exitance to display values: B/pi is the radiance of a
/// Lambertian patch; an exposure scales it; the sRGB transfer curve (IEC 61966-2-1) encodes it.

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace radiosity {

/// Exposure settings: display value = exposure_scale(B values, options) * B, clamped to [0, 1].
struct ToneMapOptions {
    double stops = 0.0;         ///< exposure compensation in photographic stops
    bool auto_exposure = true;  ///< choose the scale from the image (see auto_exposure_scale)
    double scale = 1.0;         ///< the scale used when auto_exposure is off
};

/// Encodes a linear value in [0, 1] with the sRGB transfer curve (IEC 61966-2-1).
inline float srgb_encode(float linear) {
    linear = std::clamp(linear, 0.0f, 1.0f);
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

/// Encodes a linear value as an 8-bit sRGB code (clamped).
inline std::uint8_t srgb8(float linear) {
    return static_cast<std::uint8_t>(std::lround(255.0f * srgb_encode(linear)));
}

/// Rec. 709 luminance of a linear RGB value.
inline float luminance(const glm::vec3& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

/// Chooses the scale that maps the 95th percentile of the luminance of the non-black values to
/// 0.8, so that emitters may saturate but lit surfaces keep their gradation. 1 if all are black.
inline double auto_exposure_scale(std::span<const glm::vec3> linear) {
    std::vector<float> lum;
    lum.reserve(linear.size());
    for (const auto& c : linear)
        if (const float l = luminance(c); l > 0.0f && std::isfinite(l)) lum.push_back(l);
    if (lum.empty()) return 1.0;
    const auto k = static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(lum.size() - 1));
    std::nth_element(lum.begin(), lum.begin() + k, lum.end());
    return 0.8 / static_cast<double>(lum[static_cast<std::size_t>(k)]);
}

/// The factor that turns radiant exitance B into display values under the given options:
/// with auto exposure, the one that maps the image's 95th percentile to 0.8 (see above); with
/// a fixed scale, scale / pi (radiance L = B / pi of a Lambertian surface); times 2^stops.
inline double exposure_scale(std::span<const glm::vec3> exitance, const ToneMapOptions& o) {
    const double base =
        o.auto_exposure ? auto_exposure_scale(exitance) : o.scale / std::numbers::pi;
    return base * std::exp2(o.stops);
}

}  // namespace radiosity
