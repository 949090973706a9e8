#pragma once
/// @file image.hpp  Writing pictures: PNG (8-bit sRGB after exposure) and Radiance HDR (linear
/// radiance, for tone mapping elsewhere), through stb_image_write (Sean Barrett, public domain;
/// Debian's libstb-dev), and OpenEXR (linear radiance in 32-bit floats) through tinyexr (Syoyo
/// Fujita; Debian's libtinyexr-dev). stb is compiled into each translation unit as static
/// functions, so including this header in several files is safe.

#include <radiosity/error.hpp>
#include <radiosity/shading/image.hpp>
#include <radiosity/shading/tonemap.hpp>

#include <tinyexr.h>

#include <cstdint>
#include <filesystem>
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

namespace detail {
/// The pixels as 8-bit sRGB triples after multiplying by scale (clamped).
inline std::vector<std::uint8_t> srgb_bytes(const Image& image, double scale) {
    std::vector<std::uint8_t> bytes;
    bytes.reserve(image.pixels.size() * 3);
    for (const glm::vec3& c : image.pixels)
        for (int k = 0; k < 3; ++k) bytes.push_back(srgb8(static_cast<float>(scale * c[k])));
    return bytes;
}

/// The linear radiance B / pi of every pixel, as interleaved RGB floats.
inline std::vector<float> radiance_floats(const Image& image) {
    std::vector<float> radiance;
    radiance.reserve(image.pixels.size() * 3);
    for (const glm::vec3& c : image.pixels)
        for (int k = 0; k < 3; ++k) radiance.push_back(c[k] / std::numbers::pi_v<float>);
    return radiance;
}
}  // namespace detail

/// Writes a PNG: each pixel's B times exposure_scale (tonemap.hpp), clamped and encoded with the
/// sRGB curve into 8 bits. Throws Error naming the path if it cannot be written.
inline void write_png(const Image& image, const std::string& path,
                      const ToneMapOptions& tone = {}) {
    const auto bytes = detail::srgb_bytes(image, exposure_scale(image.pixels, tone));
    if (image.width < 1 || image.height < 1 ||
        !stbi_write_png(path.c_str(), image.width, image.height, 3, bytes.data(), image.width * 3))
        throw Error("cannot write '" + path + "'");
}

/// A PNG file's bytes in memory (for embedding, e.g. a glTF texture): each pixel's B times
/// scale, clamped, sRGB-encoded in 8 bits. Throws Error for an empty image.
inline std::vector<std::uint8_t> png_bytes(const Image& image, double scale) {
    const auto pixels = detail::srgb_bytes(image, scale);
    std::vector<std::uint8_t> out;
    auto append = [](void* context, void* data, int size) {
        auto* o = static_cast<std::vector<std::uint8_t>*>(context);
        o->insert(o->end(), static_cast<std::uint8_t*>(data),
                  static_cast<std::uint8_t*>(data) + size);
    };
    if (image.width < 1 || image.height < 1 ||
        !stbi_write_png_to_func(append, &out, image.width, image.height, 3, pixels.data(),
                                image.width * 3))
        throw Error("cannot encode an empty picture as PNG");
    return out;
}

/// Writes a Radiance RGBE (.hdr) picture of the linear radiance B / pi (Ward 1991). Throws
/// Error naming the path if it cannot be written.
inline void write_hdr(const Image& image, const std::string& path) {
    const auto radiance = detail::radiance_floats(image);
    if (image.width < 1 || image.height < 1 ||
        !stbi_write_hdr(path.c_str(), image.width, image.height, 3, radiance.data()))
        throw Error("cannot write '" + path + "'");
}

/// Writes an OpenEXR picture of the linear radiance B / pi in 32-bit floats (ZIP-compressed;
/// Kainz et al., "Technical Introduction to OpenEXR"). Throws Error naming the path on failure.
inline void write_exr(const Image& image, const std::string& path) {
    const auto radiance = detail::radiance_floats(image);
    const char* message = nullptr;
    if (image.width < 1 || image.height < 1)
        throw Error("cannot write '" + path + "': the picture is empty");
    if (SaveEXR(radiance.data(), image.width, image.height, 3, 0, path.c_str(), &message) != 0) {
        const std::string why = message ? message : "unknown error";
        FreeEXRErrorMessage(message);
        throw Error("cannot write '" + path + "': " + why);
    }
}

/// The picture formats write_image knows.
enum class PictureFormat { png, hdr, exr };

/// The format a file name's extension names: .png, .hdr or .exr. Throws Error for others, so a
/// program can refuse a bad output name before it computes anything.
inline PictureFormat picture_format(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".png") return PictureFormat::png;
    if (ext == ".hdr") return PictureFormat::hdr;
    if (ext == ".exr") return PictureFormat::exr;
    throw Error("'" + path + "': unknown picture format (use .png, .hdr or .exr)");
}

/// Writes a picture in the format its extension names: .png (8-bit sRGB after the tone map),
/// .hdr (Radiance) or .exr (OpenEXR), both linear radiance. Throws Error for other names.
inline void write_image(const Image& image, const std::string& path,
                        const ToneMapOptions& tone = {}) {
    switch (picture_format(path)) {
        case PictureFormat::png:
            return write_png(image, path, tone);
        case PictureFormat::hdr:
            return write_hdr(image, path);
        case PictureFormat::exr:
            return write_exr(image, path);
    }
}

}  // namespace radiosity
