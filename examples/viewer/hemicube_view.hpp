#pragma once
/// @file hemicube_view.hpp  A patch's hemicube as the lecture draws it (Cohen & Greenberg 1985;
/// examples/03_hemicube.cpp): the five faces unfolded into one 2r x 2r picture, the top face in
/// the middle and the four half side faces folded out around it, each pixel holding the patch it
/// sees (the item buffer's z-buffer winner) and its delta form factor, 1 / (pi (x^2 + y^2 + 1)^2)
/// on the top and z / (pi (x^2 + z^2 + 1)^2) on the sides. F_ij is the sum of the delta form
/// factors of the pixels that see patch j.

#include <radiosity/form_factor/hemicube.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace radiosity::view {

/// One patch's hemicube, unfolded (see the file comment).
struct UnfoldedHemicube {
    std::size_t patch = 0;           ///< whose hemicube
    int size = 0;                    ///< the picture is size x size (twice the resolution)
    std::vector<std::int32_t> seen;  ///< patch seen at each pixel; -1: none or no face
    std::vector<double> delta;       ///< delta form factor of each pixel (0 off the faces)
    std::vector<std::int8_t> face;   ///< 0 top, 1..4 the sides; -1 the corners off the faces
    std::vector<int> face_pixel;     ///< the pixel's index in its face's item buffer
    double covered = 0.0;            ///< sum of the delta form factors of pixels that see
    double total = 0.0;              ///< sum of all delta form factors (1 up to the grid)

    /// The delta form factors of the pixels that see patch j (the hemicube's F_ij before
    /// back faces are dropped).
    double seen_sum(std::int32_t j) const;
};

/// The hemicube of patch i, from the method's own item buffers. Cost: one hemicube.
UnfoldedHemicube unfold_hemicube(const radiosity::Hemicube& hemicube, std::size_t i);

/// The name of face k: "top", "side +u", "side -u", "side +v", "side -v".
std::string hemicube_face_name(int k);

/// RGBA8 pictures of the unfolded hemicube (row 0 at the top): each pixel in the display
/// colour of the patch it sees (`colours`, one per patch, sRGB in [0, 1]); in a colour per
/// patch id; or grey from its delta form factor (the largest, straight up, white).
std::vector<std::uint8_t> hemicube_seen_picture(const UnfoldedHemicube& h,
                                                const std::vector<glm::vec3>& colours);
std::vector<std::uint8_t> hemicube_id_picture(const UnfoldedHemicube& h);
std::vector<std::uint8_t> hemicube_delta_picture(const UnfoldedHemicube& h);

}  // namespace radiosity::view
