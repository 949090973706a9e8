#pragma once
/// @file image.hpp  A picture of linear values (what the camera renders and the bake fills), and
/// the texture lookup that reads one back. Writing pictures to files is io/image.hpp's.

#include <radiosity/geometry/vec.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace radiosity {

/// A picture of linear RGB values, row 0 at the top.
struct Image {
    int width = 0;                  ///< pixels per row
    int height = 0;                 ///< rows
    std::vector<glm::vec3> pixels;  ///< width * height values, row after row
    /// The pixel in column x of row y.
    glm::vec3& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
    const glm::vec3& at(int x, int y) const {
        return pixels[static_cast<std::size_t>(y) * width + x];
    }
};

/// Texture lookup as graphics hardware does it (bilinear filtering, clamp to edge): the value at
/// uv of a picture whose texel (x, y) has its centre at ((x + 0.5) / W, (y + 0.5) / H).
/// Cost: four texel reads.
inline glm::vec3 sample_bilinear(const Image& texture, glm::vec2 uv) {
    const float x = uv.x * float(texture.width) - 0.5f, y = uv.y * float(texture.height) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y), tx = x - fx, ty = y - fy;
    auto at = [&](float i, float j) {
        return texture.at(std::clamp(int(i), 0, texture.width - 1),
                          std::clamp(int(j), 0, texture.height - 1));
    };
    return (1 - ty) * ((1 - tx) * at(fx, fy) + tx * at(fx + 1, fy)) +
           ty * ((1 - tx) * at(fx, fy + 1) + tx * at(fx + 1, fy + 1));
}

}  // namespace radiosity
