#pragma once
/// @file gltf_constants.hpp  The numbers of the glTF 2.0 specification (Khronos Group 2017) that
/// the writer (gltf.hpp) and the reader (gltf_buffers.hpp, gltf_read.hpp) share, by name:
/// accessor component types (section 3.6.2, the OpenGL enums), buffer-view targets, primitive
/// modes, and the .glb container's magic and chunk types (section 4.4).

#include <cstdint>

namespace radiosity::gltf {

/// Accessor componentType values.
enum ComponentType : std::uint32_t {
    signed_byte = 5120,
    unsigned_byte = 5121,
    signed_short = 5122,
    unsigned_short = 5123,
    unsigned_int = 5125,
    float32 = 5126,
};

/// bufferView target values: vertex attributes and indices.
enum Target : std::uint32_t { array_buffer = 34962, element_array_buffer = 34963 };

/// Primitive mode values with an area: triangle lists, strips and fans (0-3 are points and lines).
enum Mode : std::uint32_t { triangles = 4, triangle_strip = 5, triangle_fan = 6 };

/// The .glb header's magic ("glTF" read as a little-endian integer) and the chunk types.
inline constexpr std::uint32_t glb_magic = 0x46546C67u;
inline constexpr std::uint32_t glb_json_chunk = 0x4E4F534Au;  ///< "JSON"
inline constexpr std::uint32_t glb_bin_chunk = 0x004E4942u;   ///< "BIN\0"

}  // namespace radiosity::gltf
