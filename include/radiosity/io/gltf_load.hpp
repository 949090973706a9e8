#pragma once
/// @file gltf_load.hpp  The lower half of the glTF 2.0 reader (Khronos Group 2017): a .gltf or
/// .glb file parsed by tinygltf (S. Fujita, Debian's libtinygltf 2.7) into its Model, behind the
/// checks that tinygltf leaves out or gets wrong, and accessors checked against the bytes they
/// read. tinygltf parses the JSON, splits the .glb and loads the buffers (files beside the glTF,
/// base64 data URIs, the BIN chunk); it does not check that an index points at an element or
/// that an accessor lies inside its buffer, so that is done here, before every read. Every
/// failure is a one-line radiosity::Error naming the file and the element. What tinygltf 2.7
/// does differently from the reader it replaced: a buffer's data URI or file must hold exactly
/// byteLength bytes (the Khronos validator also accepts more); a property of the wrong JSON type
/// reads as absent, and an index is narrowed to int (2^32 reads as 0); its own messages name the
/// kind of element ("accessor"), not its index. Internal: use io/gltf_read.hpp.

#include <radiosity/error.hpp>

#include <tiny_gltf.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace radiosity::detail {

using Bytes = std::vector<std::uint8_t>;

/// A glTF file read into tinygltf's Model, with its name for messages.
struct GltfSource {
    std::string path;       ///< the file, as the caller named it
    tinygltf::Model model;  ///< what tinygltf read, buffers loaded
};

/// Throws the reader's one-line Error: "file: element: what".
[[noreturn]] inline void gltf_fail(const GltfSource& g, const std::string& element,
                                   const std::string& what) {
    throw Error(g.path + ": " + element + ": " + what);
}

/// Element i of one of the Model's arrays ("meshes", "nodes", ...), which must exist.
template <class T>
const T& gltf_element(const GltfSource& g, const std::vector<T>& all, const char* name,
                      long long i) {
    if (i < 0 || static_cast<unsigned long long>(i) >= all.size())
        gltf_fail(g, std::string(name) + "[" + std::to_string(i) + "]",
                  "does not exist (the file has " + std::to_string(all.size()) + ")");
    return all[static_cast<std::size_t>(i)];
}

/// The .glb container's magic ("glTF" read as a little-endian word) and JSON chunk type
/// (section 4.4; tinygltf checks the BIN chunk's type).
inline constexpr std::uint32_t glb_magic = 0x46546C67u;
inline constexpr std::uint32_t glb_json_chunk = 0x4E4F534Au;  ///< "JSON"

/// Reads a little-endian 32-bit word (the .glb header and chunk headers).
inline std::uint32_t le32(const Bytes& b, std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
}

/// Checks a .glb's container (specification section 4.4: a 12-byte header with magic, version 2
/// and total length, then chunks, the first one JSON) and returns the JSON chunk. tinygltf 2.7.0
/// reads the version without checking it, and checks the BIN chunk's length against the file
/// without the chunk's own 8-byte header, so a BIN chunk that claims up to 8 bytes more than the
/// file holds is copied from past the end of the file (a heap over-read under AddressSanitizer):
/// every chunk's length is checked here against what is left of the file.
inline std::string_view check_glb(const std::string& path, const Bytes& file) {
    auto fail = [&](const std::string& what) { throw Error(path + ": GLB " + what); };
    if (file.size() < 20)
        fail("header: the file has only " + std::to_string(file.size()) + " bytes");
    if (le32(file, 4) != 2) fail("header: version " + std::to_string(le32(file, 4)) + ", not 2");
    if (le32(file, 8) != file.size())
        fail("header: length " + std::to_string(le32(file, 8)) + ", but the file has " +
             std::to_string(file.size()) + " bytes");
    std::string_view json;
    std::size_t at = 12;
    for (int chunk = 0; at < file.size(); ++chunk) {
        const std::string name = "chunk " + std::to_string(chunk);
        if (file.size() - at < 8) fail(name + ": header cut short");
        const std::uint32_t length = le32(file, at), type = le32(file, at + 4);
        at += 8;
        if (length > file.size() - at)
            fail(name + ": length " + std::to_string(length) + " runs past the end of the file");
        if (chunk == 0 && type != glb_json_chunk) fail(name + ": the first chunk is not JSON");
        if (chunk == 0) json = {reinterpret_cast<const char*>(file.data() + at), length};
        at += length;
    }
    return json;
}

/// JSON nesting that the reader accepts: glTF's own structure nests fewer than ten levels, so
/// this leaves hundreds to `extras` and `extensions`. tinygltf 2.7.0 copies those into its Value
/// type by recursion, and a 60 KB file of 30,000 nested brackets overflows an 8 MiB stack (a
/// crash).
inline constexpr std::size_t gltf_max_depth = 512;

/// Refuses JSON text nested deeper than gltf_max_depth arrays and objects (brackets inside
/// strings do not count). One pass over the text, before tinygltf parses it.
inline void check_json_depth(const std::string& path, std::string_view text) {
    std::size_t depth = 0;
    bool in_string = false, escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > gltf_max_depth)
                throw Error(path + ": JSON nested deeper than " + std::to_string(gltf_max_depth) +
                            " levels");
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
}

/// tinygltf's messages as one line: lines joined by "; ", cut at 300 characters (a message
/// may quote a whole base64 data URI).
inline std::string gltf_message(const std::string& message) {
    std::string out;
    for (char c : message) {
        if (c == '\n' || c == '\r') {
            if (!out.empty() && out.back() != ' ') out += "; ";
        } else {
            out.push_back(c);
        }
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
    if (out.size() > 300) out = out.substr(0, 300) + "...";
    return out.empty() ? "tinygltf could not read it" : out;
}

/// tinygltf's test for a buffer's file, narrowed to regular files named from the glTF's folder,
/// which the loader passes as an absolute path: tinygltf also looks in the working directory
/// (a relative "./name"), and would read a file that does not sit beside the glTF.
inline bool gltf_file_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::path(path).is_absolute() && std::filesystem::is_regular_file(path, ec);
}

/// tinygltf's image loader, replaced by one that decodes nothing: the reader samples no
/// textures (a patch has one colour), so pictures in a file are neither decoded nor trusted.
inline bool skip_gltf_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                            const unsigned char*, int, void*) {
    return true;
}

/// Reads a file whole; an Error naming it if it is not a readable regular file.
inline Bytes read_gltf_bytes(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": no such file");
    std::ifstream in(path, std::ios::binary);
    Bytes file{std::istreambuf_iterator<char>(in), {}};
    if (!in.good() && !in.eof()) throw Error(path + ": cannot read the file");
    if (file.size() > std::numeric_limits<unsigned int>::max())  // tinygltf's length type
        throw Error(path + ": larger than 4 GiB");
    return file;
}

/// Opens a .gltf (JSON) or .glb (told apart by the magic "glTF", not by the name) into
/// tinygltf's Model, after the container and nesting checks above. A message from tinygltf is
/// refused even when it reports success: it drops a primitive or a material property that it
/// cannot parse and says so only there. Cost: linear in the file and its buffers.
inline GltfSource open_gltf(const std::string& path) {
    const Bytes file = read_gltf_bytes(path);
    const bool glb = file.size() >= 4 && le32(file, 0) == glb_magic;
    check_json_depth(
        path, glb ? check_glb(path, file)
                  : std::string_view{reinterpret_cast<const char*>(file.data()), file.size()});
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skip_gltf_image, nullptr);
    loader.SetFsCallbacks({&gltf_file_exists, &tinygltf::ExpandFilePath, &tinygltf::ReadWholeFile,
                           &tinygltf::WriteWholeFile, nullptr});
    GltfSource g{path, {}};
    std::string err, warn;  // warnings name images that are not read anyway
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;  // absolute("") fails: a bare file name lies in the working directory
    const std::string folder =
        std::filesystem::absolute(parent.empty() ? "." : parent, ec).string();
    if (ec) throw Error(path + ": cannot find its folder (" + ec.message() + ")");
    const auto size = static_cast<unsigned int>(file.size());
    bool ok = false;
    try {
        ok = glb ? loader.LoadBinaryFromMemory(&g.model, &err, &warn, file.data(), size, folder)
                 : loader.LoadASCIIFromString(&g.model, &err, &warn,
                                              reinterpret_cast<const char*>(file.data()), size,
                                              folder);
    } catch (const std::exception& e) {  // e.g. std::out_of_range for a .glb buffer of 0 bytes
        ok = false;
        err = std::string("tinygltf failed: ") + e.what();
    }
    if (!ok || !err.empty()) throw Error(path + ": " + gltf_message(err));
    return g;
}

/// Bytes from `offset` to `offset + stride * (count - 1) + element`, saturated at the largest
/// integer so that a hostile count or offset cannot wrap round and pass a size check.
inline std::uint64_t span_bytes(std::uint64_t offset, std::uint64_t stride, std::uint64_t count,
                                std::uint64_t element) {
    constexpr std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
    if (count == 0) return offset;
    if (offset > max - element) return max;
    if (stride != 0 && count - 1 > (max - offset - element) / stride) return max;
    return offset + stride * (count - 1) + element;
}

/// An accessor's elements, checked to lie inside its buffer view and buffer.
struct AccessorData {
    const std::uint8_t* first = nullptr;  ///< first byte of element 0
    std::size_t count = 0;                ///< number of elements
    std::size_t stride = 0;               ///< bytes from one element to the next
    int component_type = 0;               ///< glTF componentType (5120 .. 5126)
    bool normalized = false;              ///< integers map to [0, 1] (or [-1, 1])
    std::string name;                     ///< "accessors[i]", for messages
};

/// The name of a tinygltf accessor type code ("VEC3"), for messages.
inline std::string accessor_type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        default:
            return "a matrix";
    }
}

/// The bytes of buffer view i, checked to lie inside its buffer.
inline std::span<const std::uint8_t> gltf_view_bytes(const GltfSource& g, int i) {
    const tinygltf::BufferView& v = gltf_element(g, g.model.bufferViews, "bufferViews", i);
    const std::vector<unsigned char>& bytes =
        gltf_element(g, g.model.buffers, "buffers", v.buffer).data;
    if (span_bytes(v.byteOffset, 1, 1, v.byteLength) > bytes.size())
        gltf_fail(g, "bufferViews[" + std::to_string(i) + "]",
                  "bytes " + std::to_string(v.byteOffset) + " + " + std::to_string(v.byteLength) +
                      " lie outside buffers[" + std::to_string(v.buffer) + "] (" +
                      std::to_string(bytes.size()) + " bytes)");
    return {bytes.data() + v.byteOffset, v.byteLength};
}

/// Accessor i, which must have the given type (TINYGLTF_TYPE_VEC3) and one of the component
/// types, lie in its buffer view, and not be sparse (sparse accessors store morph targets and
/// animation, not the geometry a scene needs, so the reader leaves them out).
inline AccessorData gltf_accessor(const GltfSource& g, int i, int type,
                                  std::initializer_list<int> component_types) {
    const tinygltf::Accessor& a = gltf_element(g, g.model.accessors, "accessors", i);
    AccessorData d;
    d.name = "accessors[" + std::to_string(i) + "]";
    if (a.sparse.isSparse) gltf_fail(g, d.name, "sparse accessors are not supported");
    if (a.type != type)
        gltf_fail(
            g, d.name,
            "type is " + accessor_type_name(a.type) + ", expected " + accessor_type_name(type));
    if (std::find(component_types.begin(), component_types.end(), a.componentType) ==
        component_types.end())
        gltf_fail(g, d.name,
                  "componentType " + std::to_string(a.componentType) + " is not allowed here");
    d.component_type = a.componentType;
    d.normalized = a.normalized;
    // Without a bufferView the elements are all zeros: no geometry a scene could use.
    if (a.bufferView < 0) gltf_fail(g, d.name, "has no bufferView");
    const std::span<const std::uint8_t> bytes = gltf_view_bytes(g, a.bufferView);
    const std::size_t given_stride = g.model.bufferViews[std::size_t(a.bufferView)].byteStride;
    const auto element = static_cast<std::size_t>(
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)) *
        tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(type)));
    d.stride = given_stride != 0 ? given_stride : element;
    const std::string view = "bufferViews[" + std::to_string(a.bufferView) + "]";
    if (d.stride < element)
        gltf_fail(g, d.name,
                  "elements of " + std::to_string(element) + " bytes do not fit " + view +
                      "'s byteStride " + std::to_string(d.stride));
    const std::uint64_t needed = span_bytes(a.byteOffset, d.stride, a.count, element);
    if (needed > bytes.size())
        gltf_fail(g, d.name,
                  "needs " + std::to_string(needed) + " bytes, " + view + " has " +
                      std::to_string(bytes.size()));
    d.first = bytes.data() + a.byteOffset;
    d.count = a.count;
    return d;
}

/// Component k of element e of an accessor, as a double (normalized unsigned integers mapped
/// to [0, 1] as the glTF specification's section 3.11 says). Signed types are admitted by no
/// caller (indices and UVs are unsigned or float), so they are not read.
inline double accessor_value(const AccessorData& d, std::size_t e, std::size_t k) {
    const std::uint8_t* p = d.first + e * d.stride +
                            k * static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(
                                    static_cast<std::uint32_t>(d.component_type)));
    auto load = [p]<class T>(T) {
        T v;
        std::memcpy(&v, p, sizeof v);  // glTF data need not be aligned for this machine
        return v;
    };
    switch (d.component_type) {  // the types gltf_accessor's callers admit
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return d.normalized ? load(std::uint8_t{}) / 255.0 : load(std::uint8_t{});
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return d.normalized ? load(std::uint16_t{}) / 65535.0 : load(std::uint16_t{});
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return load(std::uint32_t{});
        default:
            return load(float{});
    }
}

}  // namespace radiosity::detail
