#pragma once
/// @file gltf_buffers.hpp  The lower half of the glTF 2.0 reader (Khronos Group 2017, the glTF
/// 2.0 specification, sections 3.6 "Buffers" to 4.4 "GLB"): the JSON document of a .gltf or the
/// chunks of a .glb, buffers from files or base64 data URIs, and accessors checked against the
/// bytes they read. Every check comes before the read or the allocation it guards, and every
/// failure is a one-line radiosity::Error naming the file and the element. Internal: use
/// io/gltf_read.hpp.

#include <radiosity/error.hpp>
#include <radiosity/io/gltf_constants.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace radiosity::detail {

using Json = nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

/// A glTF file being read: its name (for messages), its folder (where relative URIs point), the
/// JSON document, the BIN chunk of a .glb, and the buffers loaded so far.
struct GltfSource {
    std::string path;                        ///< the file, as the caller named it
    std::filesystem::path folder;            ///< base of relative buffer URIs
    Json doc;                                ///< the JSON document
    std::optional<Bytes> glb_bin;            ///< the BIN chunk of a .glb, if it has one
    std::vector<std::optional<Bytes>> bufs;  ///< buffers[i], loaded when first needed
};

/// Throws the reader's one-line Error: "file: element: what".
[[noreturn]] inline void gltf_fail(const GltfSource& g, const std::string& element,
                                   const std::string& what) {
    throw Error(g.path + ": " + element + ": " + what);
}

/// Member `key` of a JSON object, or nullptr if absent (or if o is not an object).
inline const Json* member(const Json& o, const char* key) {
    const auto it = o.find(key);  // find() on a non-object finds nothing
    return it == o.end() ? nullptr : &*it;
}

/// A non-negative integer member (an index, a count, a byte offset); `fallback` if absent, an
/// Error if absent without a fallback or not a non-negative integer.
inline std::uint64_t get_uint(const GltfSource& g, const Json& o, const std::string& where,
                              const char* key,
                              std::optional<std::uint64_t> fallback = std::nullopt) {
    const Json* v = member(o, key);
    if (!v) {
        if (!fallback) gltf_fail(g, where, std::string("missing required '") + key + "'");
        return *fallback;
    }
    if (!v->is_number_unsigned())
        gltf_fail(g, where, std::string("'") + key + "' is not a non-negative integer");
    return v->get<std::uint64_t>();
}

/// A member that is an array of exactly N finite numbers, or for N = 1 also a plain number;
/// `fallback` if absent.
template <std::size_t N>
std::array<double, N> get_numbers(const GltfSource& g, const Json& o, const std::string& where,
                                  const char* key, const std::array<double, N>& fallback) {
    const Json* v = member(o, key);
    if (!v) return fallback;
    if (N == 1 && v->is_number() && std::isfinite(v->get<double>())) return {v->get<double>()};
    if (!v->is_array() || v->size() != N)
        gltf_fail(g, where,
                  std::string("'") + key + "' is not " +
                      (N == 1 ? std::string("a number")
                              : "an array of " + std::to_string(N) + " numbers"));
    std::array<double, N> out{};
    for (std::size_t k = 0; k < N; ++k) {
        if (!(*v)[k].is_number() || !std::isfinite((*v)[k].get<double>()))
            gltf_fail(g, where, std::string("'") + key + "' has an entry that is not a number");
        out[k] = (*v)[k].get<double>();
    }
    return out;
}

/// A top-level array of the document ("meshes", "nodes", ...); empty if absent.
inline const Json& top_array(const GltfSource& g, const char* name) {
    static const Json empty = Json::array();
    const Json* a = member(g.doc, name);
    if (!a) return empty;
    if (!a->is_array()) gltf_fail(g, name, "is not an array");
    return *a;
}

/// Element i of a top-level array, which must exist and be an object.
inline const Json& gltf_element(const GltfSource& g, const char* name, std::uint64_t i) {
    const Json& a = top_array(g, name);
    const std::string at = std::string(name) + "[" + std::to_string(i) + "]";
    if (i >= a.size())
        gltf_fail(g, at, "does not exist (the file has " + std::to_string(a.size()) + ")");
    if (!a[i].is_object()) gltf_fail(g, at, "is not an object");
    return a[i];
}

/// Decodes base64 (RFC 4648, padding optional); nullopt for a character outside the alphabet.
inline std::optional<Bytes> decode_base64(std::string_view s) {
    while (!s.empty() && s.back() == '=') s.remove_suffix(1);
    Bytes out;
    out.reserve(s.size() / 4 * 3 + 2);
    std::uint32_t bits = 0;
    int held = 0;
    for (char c : s) {
        int v = -1;
        if (c >= 'A' && c <= 'Z') v = c - 'A';
        if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
        if (c >= '0' && c <= '9') v = c - '0' + 52;
        if (c == '+') v = 62;
        if (c == '/') v = 63;
        if (v < 0) return std::nullopt;
        bits = (bits << 6) | static_cast<std::uint32_t>(v);
        held += 6;
        if (held >= 8) {
            held -= 8;
            out.push_back(static_cast<std::uint8_t>(bits >> held));
        }
    }
    return out;
}

/// Undoes URI percent-encoding ("my%20mesh.bin"); nullopt for a malformed escape.
inline std::optional<std::string> percent_decode(std::string_view s) {
    std::string out;
    for (std::size_t k = 0; k < s.size(); ++k) {
        if (s[k] != '%') {
            out.push_back(s[k]);
            continue;
        }
        if (k + 2 >= s.size()) return std::nullopt;
        const std::string hex(s.substr(k + 1, 2));
        if (hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
            return std::nullopt;
        out.push_back(static_cast<char>(std::stoi(hex, nullptr, 16)));
        k += 2;
    }
    return out;
}

/// The scheme of a URI ("data", "http"), or empty for a relative reference (a file name).
inline std::string uri_scheme(std::string_view uri) {
    const std::size_t colon = uri.find(':');
    if (colon == std::string_view::npos || colon == 0) return {};
    for (std::size_t k = 0; k < colon; ++k) {
        const char c = uri[k];
        const bool alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
        if (!alpha && (k == 0 || !((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.')))
            return {};
    }
    return std::string(uri.substr(0, colon));
}

/// The bytes of a buffer stored as a base64 data URI.
inline Bytes data_uri_bytes(const GltfSource& g, const std::string& at, std::string_view uri) {
    static constexpr std::array<std::string_view, 2> prefixes{
        "data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"};
    for (std::string_view p : prefixes)
        if (uri.substr(0, p.size()) == p) {
            auto bytes = decode_base64(uri.substr(p.size()));
            if (!bytes) gltf_fail(g, at, "the data URI is not valid base64");
            return std::move(*bytes);
        }
    gltf_fail(g, at, "a data URI must be application/octet-stream or gltf-buffer, in base64");
}

/// The first `length` bytes of a buffer's file, after checking it has that many.
inline Bytes file_bytes(const GltfSource& g, const std::string& at, std::string_view uri,
                        std::uint64_t length) {
    const std::optional<std::string> name = percent_decode(uri);
    if (!name) gltf_fail(g, at, "the uri has a malformed %-escape");
    const std::filesystem::path file = g.folder / *name;
    std::error_code ec;
    const auto size = std::filesystem::is_regular_file(file, ec)
                          ? std::filesystem::file_size(file, ec)
                          : static_cast<std::uintmax_t>(-1);
    if (ec || size == static_cast<std::uintmax_t>(-1))
        gltf_fail(g, at, "cannot read '" + file.string() + "'");
    if (size < length)
        gltf_fail(g, at,
                  "'" + *name + "' has " + std::to_string(size) + " bytes, byteLength is " +
                      std::to_string(length));
    std::ifstream in(file, std::ios::binary);
    Bytes bytes(static_cast<std::size_t>(length));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(length));
    if (!in) gltf_fail(g, at, "cannot read '" + file.string() + "'");
    return bytes;
}

/// Buffer i, loaded on first use from its uri (a file beside the glTF, or base64 data) or, in
/// a .glb, from the BIN chunk; at least byteLength bytes long.
inline const Bytes& gltf_buffer(GltfSource& g, std::uint64_t i) {
    const Json& b = gltf_element(g, "buffers", i);
    if (g.bufs.size() <= i) g.bufs.resize(static_cast<std::size_t>(i) + 1);
    auto& slot = g.bufs[static_cast<std::size_t>(i)];
    if (slot) return *slot;
    const std::string at = "buffers[" + std::to_string(i) + "]";
    const std::uint64_t length = get_uint(g, b, at, "byteLength");
    const Json* uri = member(b, "uri");
    if (!uri) {  // only the first buffer of a .glb may leave out its uri: it is the BIN chunk
        if (i != 0 || !g.glb_bin) gltf_fail(g, at, "has no uri (and is not a .glb's BIN chunk)");
        slot = std::move(*g.glb_bin);  // buffer 0 is loaded once: the chunk is not needed again
    } else if (!uri->is_string()) {
        gltf_fail(g, at, "'uri' is not a string");
    } else {
        const std::string u = uri->get<std::string>(), scheme = uri_scheme(u);
        if (scheme == "data")
            slot = data_uri_bytes(g, at, u);
        else if (scheme.empty())
            slot = file_bytes(g, at, u, length);
        else
            gltf_fail(g, at, "uri scheme '" + scheme + "' is not supported (only files, data)");
    }
    if (slot->size() < length)
        gltf_fail(g, at,
                  "holds " + std::to_string(slot->size()) + " bytes, byteLength is " +
                      std::to_string(length));
    slot->resize(static_cast<std::size_t>(length));  // a .glb pads its BIN chunk
    return *slot;
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

/// Bytes of one component of a glTF componentType, 0 for an unknown one.
inline std::size_t component_size(std::uint64_t type) {
    switch (type) {
        case gltf::signed_byte:
        case gltf::unsigned_byte:
            return 1;
        case gltf::signed_short:
        case gltf::unsigned_short:
            return 2;
        case gltf::unsigned_int:
        case gltf::float32:
            return 4;
        default:
            return 0;
    }
}

/// Components per element of a glTF accessor type, 0 for an unknown one.
inline std::size_t type_components(const std::string& type) {
    static const std::array<std::pair<const char*, std::size_t>, 7> types{{{"SCALAR", 1},
                                                                           {"VEC2", 2},
                                                                           {"VEC3", 3},
                                                                           {"VEC4", 4},
                                                                           {"MAT2", 4},
                                                                           {"MAT3", 9},
                                                                           {"MAT4", 16}}};
    for (const auto& [name, n] : types)
        if (type == name) return n;
    return 0;
}

/// The buffer view's bytes, checked to lie inside its buffer; stride is 0 if not given.
inline std::pair<std::span<const std::uint8_t>, std::uint64_t> gltf_view(GltfSource& g,
                                                                         std::uint64_t i) {
    const Json& v = gltf_element(g, "bufferViews", i);
    const std::string at = "bufferViews[" + std::to_string(i) + "]";
    const std::uint64_t offset = get_uint(g, v, at, "byteOffset", 0),
                        length = get_uint(g, v, at, "byteLength"),
                        stride = get_uint(g, v, at, "byteStride", 0);
    const std::uint64_t buffer = get_uint(g, v, at, "buffer");
    const Bytes& bytes = gltf_buffer(g, buffer);
    if (span_bytes(offset, 1, 1, length) > bytes.size())
        gltf_fail(g, at,
                  "bytes " + std::to_string(offset) + " + " + std::to_string(length) +
                      " lie outside buffers[" + std::to_string(buffer) + "] (" +
                      std::to_string(bytes.size()) + " bytes)");
    if (member(v, "byteStride") && (stride < 4 || stride > 252 || stride % 4 != 0))
        gltf_fail(g, at, "byteStride " + std::to_string(stride) + " is not 4..252 in steps of 4");
    return {{bytes.data() + offset, static_cast<std::size_t>(length)}, stride};
}

/// Accessor i, which must have the given type ("VEC3") and one of the component types, lie in
/// its buffer view, and not be sparse (sparse accessors store morph targets and animation, not
/// the geometry a scene needs, so the reader leaves them out).
inline AccessorData gltf_accessor(GltfSource& g, std::uint64_t i, const std::string& type,
                                  std::initializer_list<int> component_types) {
    const Json& a = gltf_element(g, "accessors", i);
    AccessorData d;
    d.name = "accessors[" + std::to_string(i) + "]";
    if (member(a, "sparse")) gltf_fail(g, d.name, "sparse accessors are not supported");
    const Json* t = member(a, "type");
    if (!t || !t->is_string() || type_components(t->get<std::string>()) == 0)
        gltf_fail(g, d.name, "missing or unknown 'type'");
    if (t->get<std::string>() != type)
        gltf_fail(g, d.name, "type is " + t->get<std::string>() + ", expected " + type);
    const std::uint64_t ct = get_uint(g, a, d.name, "componentType");
    if (std::find(component_types.begin(), component_types.end(), static_cast<int>(ct)) ==
        component_types.end())
        gltf_fail(g, d.name, "componentType " + std::to_string(ct) + " is not allowed here");
    d.component_type = static_cast<int>(ct);
    const Json* norm = member(a, "normalized");
    if (norm && !norm->is_boolean()) gltf_fail(g, d.name, "'normalized' is not true or false");
    d.normalized = norm && norm->get<bool>();
    const std::uint64_t count = get_uint(g, a, d.name, "count"),
                        offset = get_uint(g, a, d.name, "byteOffset", 0);
    // Without a bufferView the elements are all zeros: no geometry a scene could use.
    const std::uint64_t view = get_uint(g, a, d.name, "bufferView");
    const auto [bytes, given_stride] = gltf_view(g, view);
    const std::uint64_t element = component_size(ct) * type_components(type);
    d.stride = static_cast<std::size_t>(given_stride != 0 ? given_stride : element);
    if (given_stride != 0 && given_stride < element)
        gltf_fail(g, d.name,
                  "elements of " + std::to_string(element) + " bytes do not fit bufferViews[" +
                      std::to_string(view) + "]'s byteStride " + std::to_string(given_stride));
    const std::uint64_t needed = span_bytes(offset, d.stride, count, element);
    if (needed > bytes.size())
        gltf_fail(g, d.name,
                  "needs " + std::to_string(needed) + " bytes, bufferViews[" +
                      std::to_string(view) + "] has " + std::to_string(bytes.size()));
    d.first = bytes.data() + offset;
    d.count = static_cast<std::size_t>(count);
    return d;
}

/// Component k of element e of an accessor, as a double (normalized unsigned integers mapped
/// to [0, 1] as the glTF specification's section 3.11 says). Signed types are admitted by no
/// caller (indices and UVs are unsigned or float), so they are not read.
inline double accessor_value(const AccessorData& d, std::size_t e, std::size_t k) {
    const std::uint8_t* p = d.first + e * d.stride + k * component_size(d.component_type);
    auto load = [p]<class T>(T) {
        T v;
        std::memcpy(&v, p, sizeof v);  // glTF data need not be aligned for this machine
        return v;
    };
    switch (d.component_type) {  // the types gltf_accessor's callers admit
        case gltf::unsigned_byte:
            return d.normalized ? load(std::uint8_t{}) / 255.0 : load(std::uint8_t{});
        case gltf::unsigned_short:
            return d.normalized ? load(std::uint16_t{}) / 65535.0 : load(std::uint16_t{});
        case gltf::unsigned_int:
            return load(std::uint32_t{});
        default:
            return load(float{});
    }
}

/// Parses JSON text, turning a syntax error into a one-line Error naming the file.
inline Json parse_gltf_json(const std::string& path, std::string_view text) {
    try {
        return Json::parse(text.begin(), text.end());
    } catch (const Json::exception& e) {
        throw Error(path + ": not valid JSON: " + e.what());
    }
}

/// Reads a little-endian 32-bit word (the .glb header and chunk headers).
inline std::uint32_t le32(const Bytes& b, std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
}

/// Splits a .glb (specification section 4.4): a 12-byte header (magic "glTF", version 2, total
/// length), a JSON chunk, then chunks of which the first BIN one is buffer 0; each length is
/// checked against what is left of the file.
inline void split_glb(GltfSource& g, const Bytes& file) {
    auto fail = [&](const std::string& what) { throw Error(g.path + ": GLB " + what); };
    if (file.size() < 20)
        fail("header: the file has only " + std::to_string(file.size()) + " bytes");
    if (le32(file, 4) != 2) fail("header: version " + std::to_string(le32(file, 4)) + ", not 2");
    if (le32(file, 8) != file.size())
        fail("header: length " + std::to_string(le32(file, 8)) + ", but the file has " +
             std::to_string(file.size()) + " bytes");
    std::size_t at = 12;
    for (int chunk = 0; at < file.size(); ++chunk) {
        const std::string name = "chunk " + std::to_string(chunk);
        if (file.size() - at < 8) fail(name + ": header cut short");
        const std::uint32_t length = le32(file, at), type = le32(file, at + 4);
        at += 8;
        if (length > file.size() - at)
            fail(name + ": length " + std::to_string(length) + " runs past the end of the file");
        const auto* data = file.data() + at;
        if (chunk == 0 && type != gltf::glb_json_chunk)
            fail(name + ": the first chunk is not JSON");
        if (chunk == 0)
            g.doc = parse_gltf_json(g.path, {reinterpret_cast<const char*>(data), length});
        else if (type == gltf::glb_bin_chunk && !g.glb_bin)
            g.glb_bin = Bytes(data, data + length);
        at += length;  // chunks of other types are to be ignored (section 4.4.3.1)
    }
}

/// Opens a .gltf (JSON) or .glb (told apart by the magic "glTF", not by the name).
inline GltfSource open_gltf(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": no such file");
    std::ifstream in(path, std::ios::binary);
    const Bytes file{std::istreambuf_iterator<char>(in), {}};
    if (!in.good() && !in.eof()) throw Error(path + ": cannot read the file");
    GltfSource g;
    g.path = path;
    g.folder = std::filesystem::path(path).parent_path();
    if (file.size() >= 4 && le32(file, 0) == gltf::glb_magic)  // "glTF"
        split_glb(g, file);
    else
        g.doc = parse_gltf_json(path, {reinterpret_cast<const char*>(file.data()), file.size()});
    if (!g.doc.is_object()) throw Error(path + ": the JSON document is not an object");
    return g;
}

}  // namespace radiosity::detail
