#pragma once
/// @file image.hpp  Writing pictures: PNG (8-bit sRGB after exposure) and Radiance HDR (linear
/// radiance, for tone mapping elsewhere), through stb_image_write (Sean Barrett, public domain;
/// Debian's libstb-dev). stb is compiled into each translation unit as static functions, so
/// including this header in several files is safe.

#include <radiosity/error.hpp>
#include <radiosity/shading/camera.hpp>
#include <radiosity/shading/tonemap.hpp>

#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#if !defined(STB_IMAGE_WRITE_IMPLEMENTATION)
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#endif
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace radiosity {

/// Writes a PNG: each pixel's B times exposure_scale (tonemap.hpp), clamped and encoded with the
/// sRGB curve into 8 bits. Throws Error naming the path if it cannot be written.
inline void write_png(const Image& image, const std::string& path,
                      const ToneMapOptions& tone = {}) {
    const double scale = exposure_scale(image.pixels, tone);
    std::vector<std::uint8_t> bytes;
    bytes.reserve(image.pixels.size() * 3);
    for (const glm::vec3& c : image.pixels)
        for (int k = 0; k < 3; ++k) bytes.push_back(srgb8(static_cast<float>(scale * c[k])));
    if (image.width < 1 || image.height < 1 ||
        !stbi_write_png(path.c_str(), image.width, image.height, 3, bytes.data(), image.width * 3))
        throw Error("cannot write '" + path + "'");
}

/// Writes a Radiance RGBE (.hdr) picture of the linear radiance B / pi (Ward 1991). Throws
/// Error naming the path if it cannot be written.
inline void write_hdr(const Image& image, const std::string& path) {
    std::vector<float> radiance;
    radiance.reserve(image.pixels.size() * 3);
    for (const glm::vec3& c : image.pixels)
        for (int k = 0; k < 3; ++k) radiance.push_back(c[k] / std::numbers::pi_v<float>);
    if (image.width < 1 || image.height < 1 ||
        !stbi_write_hdr(path.c_str(), image.width, image.height, 3, radiance.data()))
        throw Error("cannot write '" + path + "'");
}

}  // namespace radiosity
