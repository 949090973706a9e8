// glTF 2.0 reader: a round trip through our own writer (.gltf and .glb), hand-written files
// whose answers are known (node transforms, strips and fans, index and UV encodings, materials),
// and malformed files that must each be refused with one line naming the file and the element.
#include <radiosity/io/gltf.hpp>
#include <radiosity/io/gltf_read.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <unistd.h>

using namespace radiosity;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A folder of its own for this test process, removed at exit.
struct TempDir {
    fs::path path =
        fs::temp_directory_path() / ("radiosity_gltf_read_" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() { fs::remove_all(path); }
    std::string operator/(const std::string& name) const { return (path / name).string(); }
};
const TempDir dir;

/// A glTF document under construction and its one binary buffer.
struct Gltf {
    json doc;
    std::vector<std::uint8_t> bin;

    /// Appends values as a buffer view with an accessor over them; returns the accessor index.
    template <class T>
    int accessor(const std::vector<T>& values, int component_type, const char* type,
                 std::size_t count, bool normalized = false) {
        const std::size_t at = bin.size();
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(values.data());
        bin.insert(bin.end(), bytes, bytes + values.size() * sizeof(T));
        while (bin.size() % 4 != 0) bin.push_back(0);
        doc["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", at}, {"byteLength", values.size() * sizeof(T)}});
        json a = {{"bufferView", doc["bufferViews"].size() - 1},
                  {"componentType", component_type},
                  {"count", count},
                  {"type", type}};
        if (normalized) a["normalized"] = true;
        doc["accessors"].push_back(a);
        return static_cast<int>(doc["accessors"].size()) - 1;
    }
    int positions(const std::vector<float>& p) { return accessor(p, 5126, "VEC3", p.size() / 3); }
    int uvs(const std::vector<float>& t) { return accessor(t, 5126, "VEC2", t.size() / 2); }
};

/// One mesh of one primitive over `positions`, drawn by one node of the default scene.
Gltf single_primitive(const std::vector<float>& positions) {
    Gltf g;
    g.doc = {{"asset", {{"version", "2.0"}}}, {"scene", 0},
             {"scenes", {{{"nodes", {0}}}}},  {"nodes", {{{"mesh", 0}}}},
             {"bufferViews", json::array()},  {"accessors", json::array()}};
    const int p = g.positions(positions);
    g.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", p}}}}}}}};
    return g;
}

/// The unit right triangle in the xy plane, facing +z.
Gltf triangle() {
    return single_primitive({0, 0, 0, 1, 0, 0, 0, 1, 0});
}

json& primitive(Gltf& g) {
    return g.doc["meshes"][0]["primitives"][0];
}

std::string base64(const std::vector<std::uint8_t>& b) {
    static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t k = 0; k < b.size(); k += 3) {
        const std::uint32_t n = std::uint32_t(b[k]) << 16 |
                                (k + 1 < b.size() ? std::uint32_t(b[k + 1]) << 8 : 0) |
                                (k + 2 < b.size() ? b[k + 2] : 0);
        out += abc[n >> 18];
        out += abc[(n >> 12) & 63];
        out += k + 1 < b.size() ? abc[(n >> 6) & 63] : '=';
        out += k + 2 < b.size() ? abc[n & 63] : '=';
    }
    return out;
}

std::vector<std::uint8_t> glb_bytes(const json& doc, std::vector<std::uint8_t> bin) {
    std::string text = doc.dump();
    while (text.size() % 4 != 0) text.push_back(' ');
    while (bin.size() % 4 != 0) bin.push_back(0);
    std::vector<std::uint8_t> out;
    auto word = [&](std::uint32_t w) {
        for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(w >> (8 * k)));
    };
    word(0x46546C67u);
    word(2);
    word(static_cast<std::uint32_t>(20 + text.size() + (bin.empty() ? 0 : 8 + bin.size())));
    word(static_cast<std::uint32_t>(text.size()));
    word(0x4E4F534Au);
    out.insert(out.end(), text.begin(), text.end());
    if (bin.empty()) return out;  // the BIN chunk is optional
    word(static_cast<std::uint32_t>(bin.size()));
    word(0x004E4942u);
    out.insert(out.end(), bin.begin(), bin.end());
    return out;
}

/// Overwrites the little-endian 32-bit word at byte `at`.
void set_word(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t word) {
    REQUIRE(at + 4 <= b.size());
    for (std::size_t k = 0; k < 4; ++k) b.at(at + k) = static_cast<std::uint8_t>(word >> (8 * k));
}

void write_file(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
}

enum class Storage { file, base64, glb };

/// Saves the document as NAME.gltf + NAME.bin, a .gltf with a data URI, or a .glb; returns
/// the path to read.
std::string save(Gltf g, const std::string& name, Storage storage = Storage::file) {
    if (!g.doc.contains("buffers")) g.doc["buffers"] = {{{"byteLength", g.bin.size()}}};
    if (!g.doc["buffers"][0].contains("byteLength"))
        g.doc["buffers"][0]["byteLength"] = g.bin.size();
    if (storage == Storage::glb) {
        write_file(dir / (name + ".glb"), glb_bytes(g.doc, g.bin));
        return dir / (name + ".glb");
    }
    if (g.doc["buffers"][0].contains("uri")) {
        write_file(dir / (name + ".bin"), g.bin);  // a test's own uri, and a file to find
    } else if (storage == Storage::base64) {
        g.doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(g.bin);
    } else {
        g.doc["buffers"][0]["uri"] = name + ".bin";
        write_file(dir / (name + ".bin"), g.bin);
    }
    std::ofstream(dir / (name + ".gltf")) << g.doc.dump(1);
    return dir / (name + ".gltf");
}

/// Positions of face f's corners.
std::vector<Vec3> corners(const Scene<Rgb>& s, std::size_t f) {
    std::vector<Vec3> p;
    for (std::uint32_t v : s.faces[f]) p.push_back(s.positions[v]);
    return p;
}

ShadedMesh uv_quads() {
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}, {0, 1, 0.1}, {0.3, 2.7, 1.9}};
    m.colours.assign(m.positions.size(), glm::vec3(0.5f));
    m.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 0.25f}, {0.0f, 0.5f}, {0.3f, 0.7f}, {0.9f, 1.0f}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 4, 5}};
    return m;
}

}  // namespace

TEST_CASE("glTF reader: round trip through write_gltf_lightmapped, .gltf and .glb") {
    const ShadedMesh m = uv_quads();
    Image lightmap{2, 2, std::vector<glm::vec3>(4, glm::vec3(0.5f))};
    for (const std::string ext : {".gltf", ".glb"}) {
        CAPTURE(ext);
        const std::string path = dir / ("round_trip" + ext);
        write_gltf_lightmapped(m, lightmap, path, 1.0);
        const Scene<Rgb> s = read_gltf<Rgb>(path);
        CHECK(s.source == path);
        REQUIRE(s.faces.size() == m.triangles.size());
        REQUIRE(s.face_uvs.size() == m.triangles.size());
        CHECK(s.positions.size() == m.positions.size());
        for (std::size_t f = 0; f < s.faces.size(); ++f)
            for (std::size_t k = 0; k < 3; ++k) {
                const Vec3& p = m.positions[m.triangles[f][k]];
                const Vec3& q = s.positions[s.faces[f][k]];
                // The file holds floats: q is p rounded to float, exactly.
                CHECK(float(q.x) == float(p.x));
                CHECK(float(q.y) == float(p.y));
                CHECK(float(q.z) == float(p.z));
                CHECK(glm::length(q - p) < 1e-6);
                CHECK(s.face_uvs[f][k] == m.uvs[m.triangles[f][k]]);
            }
        REQUIRE(s.materials.size() == 1);
        CHECK(s.materials[0].reflectance == Rgb(0.99f));  // white clamped below 1
        CHECK(s.materials[0].emission == Rgb(0.0f));
        CHECK_NOTHROW(build_mesh(s));
    }
}

TEST_CASE("glTF reader: a node hierarchy of TRS and matrix transforms, positions exact") {
    Gltf g = triangle();
    // node 0: translate (10, 0, 0) * rotate 180 degrees about z * scale 2, then node 1: a matrix
    // that scales z by 3 and translates by (0, 0, 5); node 2 is not in the scene.
    g.doc["nodes"] = {{{"translation", {10, 0, 0}},
                       {"rotation", {0, 0, 1, 0}},
                       {"scale", {2, 2, 2}},
                       {"children", {1}},
                       {"mesh", 0}},
                      {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 3, 0, 0, 0, 5, 1}}, {"mesh", 0}},
                      {{"mesh", 0}}};
    const Scene<Rgb> s = read_gltf<Rgb>(save(g, "hierarchy"));
    REQUIRE(s.faces.size() == 2);
    // Node 0: p -> (10 - 2x, -2y, 2z).
    CHECK(corners(s, 0) == std::vector<Vec3>{{10, 0, 0}, {8, 0, 0}, {10, -2, 0}});
    // Node 1: p -> (x, y, 3z + 5), then node 0's transform.
    CHECK(corners(s, 1) == std::vector<Vec3>{{10, 0, 10}, {8, 0, 10}, {10, -2, 10}});
    CHECK(s.materials.size() == 1);  // the default grey one
    CHECK(s.materials[0].reflectance == Rgb(0.5f));
    CHECK(s.face_uvs.empty());

    SUBCASE("a quarter turn about z") {
        g.doc["nodes"] = {{{"rotation", {0, 0, std::sqrt(0.5), std::sqrt(0.5)}}, {"mesh", 0}}};
        const Scene<Rgb> r = read_gltf<Rgb>(save(g, "quarter"));
        const std::vector<Vec3> p = corners(r, 0), want{{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
        for (std::size_t k = 0; k < 3; ++k) CHECK(glm::length(p[k] - want[k]) < 1e-15);
    }
    SUBCASE("no scenes: every root node") {
        g.doc.erase("scene");
        g.doc.erase("scenes");
        CHECK(read_gltf<Rgb>(save(g, "roots")).faces.size() == 3);  // nodes 0, 1 (child), 2
    }
    SUBCASE("a mirroring scale keeps the front side in front") {
        g.doc["nodes"] = {{{"scale", {-1, 1, 1}}, {"mesh", 0}}};
        const Scene<Rgb> r = read_gltf<Rgb>(save(g, "mirror"));
        CHECK(newell_vector(corners(r, 0)).z > 0.0);
    }
}

TEST_CASE("glTF reader: TEXCOORD_1 is the lightmap UV when both are present") {
    Gltf g = triangle();
    const int t0 = g.uvs({0.1f, 0.1f, 0.2f, 0.1f, 0.1f, 0.2f});
    const int t1 = g.uvs({0.5f, 0.5f, 1.0f, 0.5f, 0.5f, 1.0f});
    primitive(g)["attributes"]["TEXCOORD_0"] = t0;
    const Scene<Rgb> only0 = read_gltf<Rgb>(save(g, "uv0"));
    REQUIRE(only0.face_uvs.size() == 1);
    CHECK(only0.face_uvs[0][1] == glm::vec2(0.2f, 0.1f));
    primitive(g)["attributes"]["TEXCOORD_1"] = t1;
    const Scene<Rgb> both = read_gltf<Rgb>(save(g, "uv01"));
    REQUIRE(both.face_uvs.size() == 1);
    CHECK(both.face_uvs[0] == std::vector<glm::vec2>{{0.5f, 0.5f}, {1.0f, 0.5f}, {0.5f, 1.0f}});
}

TEST_CASE("glTF reader: normalized unsigned byte and short UVs") {
    Gltf g = triangle();
    const int u16 =
        g.accessor(std::vector<std::uint16_t>{0, 0, 65535, 0, 32768, 65535}, 5123, "VEC2", 3, true);
    primitive(g)["attributes"]["TEXCOORD_0"] = u16;
    Scene<Rgb> s = read_gltf<Rgb>(save(g, "u16"));
    REQUIRE(s.face_uvs.size() == 1);
    CHECK(s.face_uvs[0][1] == glm::vec2(1.0f, 0.0f));
    CHECK(s.face_uvs[0][2].x == test::approx(32768.0 / 65535.0));
    CHECK(s.face_uvs[0][2].y == 1.0f);
    const int u8 =
        g.accessor(std::vector<std::uint8_t>{0, 0, 255, 0, 51, 255}, 5121, "VEC2", 3, true);
    primitive(g)["attributes"]["TEXCOORD_0"] = u8;
    s = read_gltf<Rgb>(save(g, "u8"));
    REQUIRE(s.face_uvs.size() == 1);
    CHECK(s.face_uvs[0][2] == glm::vec2(0.2f, 1.0f));
    g.doc["accessors"][u8].erase("normalized");
    CHECK_THROWS_WITH_AS(read_gltf<Rgb>(save(g, "u8raw")), doctest::Contains("must be normalized"),
                         Error);
}

TEST_CASE("glTF reader: unsigned byte, short and int indices give the same triangles") {
    Gltf g = single_primitive({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    const int i8 = g.accessor(std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3}, 5121, "SCALAR", 6);
    const int i16 = g.accessor(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}, 5123, "SCALAR", 6);
    const int i32 = g.accessor(std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}, 5125, "SCALAR", 6);
    for (int i : {i8, i16, i32}) {
        CAPTURE(i);
        primitive(g)["indices"] = i;
        const Scene<Rgb> s = read_gltf<Rgb>(save(g, "indices" + std::to_string(i)));
        REQUIRE(s.faces.size() == 2);
        CHECK(corners(s, 1) == std::vector<Vec3>{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}});
        CHECK(s.positions.size() == 4);
    }
}

TEST_CASE("glTF reader: triangle strips and fans become triangles facing the same way") {
    // A strip over a row of four points zigzagging: two triangles, both facing +z.
    Gltf g = single_primitive({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0});
    primitive(g)["mode"] = 5;
    Scene<Rgb> s = read_gltf<Rgb>(save(g, "strip"));
    REQUIRE(s.faces.size() == 3);
    for (std::size_t f = 0; f < 3; ++f) CHECK(newell_vector(corners(s, f)).z > 0.0);
    CHECK(corners(s, 1) == std::vector<Vec3>{{1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    Gltf fan = single_primitive({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0});
    primitive(fan)["mode"] = 6;  // around point 0, counter-clockwise
    s = read_gltf<Rgb>(save(fan, "fan"));
    REQUIRE(s.faces.size() == 3);
    for (std::size_t f = 0; f < 3; ++f) CHECK(newell_vector(corners(s, f)).z > 0.0);
    CHECK(corners(s, 2) == std::vector<Vec3>{{0, 1, 0}, {-1, 1, 0}, {0, 0, 0}});
}

TEST_CASE("glTF reader: zero-area triangles are dropped and points and lines skipped, counted") {
    Gltf g = single_primitive({0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0});
    const int list =
        g.accessor(std::vector<std::uint16_t>{0, 1, 2, 0, 0, 1, 0, 1, 3}, 5123, "SCALAR", 9);
    primitive(g)["indices"] = list;  // a good one, a repeated index, three points on a line
    json points = primitive(g);
    points.erase("indices");
    points["mode"] = 0;
    json lines = points;
    lines["mode"] = 1;
    g.doc["meshes"][0]["primitives"].push_back(points);
    g.doc["meshes"][0]["primitives"].push_back(lines);
    const GltfReadResult<Rgb> r = read_gltf_result<Rgb>(save(g, "degenerate"));
    CHECK(r.scene.faces.size() == 1);
    CHECK(r.scene.positions.size() == 3);  // the vertices of what was left out are not kept
    CHECK(r.dropped_triangles == 2);
    CHECK(r.skipped_primitives == 2);
    CHECK_NOTHROW(build_mesh(r.scene));
}

TEST_CASE("glTF reader: an embedded base64 buffer reads as the same scene as a .bin file") {
    Gltf g = single_primitive({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 3});
    primitive(g)["indices"] =
        g.accessor(std::vector<std::uint8_t>{0, 1, 4, 1, 2, 4, 2, 3, 4}, 5121, "SCALAR", 9);
    primitive(g)["attributes"]["TEXCOORD_0"] = g.uvs({0, 0, 1, 0, 1, 1, 0, 1, 0.5f, 0.5f});
    const Scene<Rgb> file = read_gltf<Rgb>(save(g, "as_file"));
    const Scene<Rgb> embedded = read_gltf<Rgb>(save(g, "embedded", Storage::base64));
    const Scene<Rgb> glb = read_gltf<Rgb>(save(g, "binary", Storage::glb));
    REQUIRE(file.faces.size() == 3);
    for (const Scene<Rgb>* s : {&embedded, &glb}) {
        CHECK(s->positions == file.positions);
        CHECK(s->faces == file.faces);
        CHECK(s->face_uvs == file.face_uvs);
    }
    g.doc["buffers"] = {{{"byteLength", g.bin.size()}}};
    g.bin.push_back(7);  // a BIN chunk may be longer than byteLength says (padding) ...
    CHECK(read_gltf<Rgb>(save(g, "longer", Storage::glb)).positions == file.positions);
    // ... but tinygltf 2.7 wants a data URI or a file of exactly byteLength bytes, although the
    // Khronos validator accepts longer ones (a known loss, see io/gltf_load.hpp)
    CHECK_THROWS_WITH_AS(read_gltf<Rgb>(save(g, "longer", Storage::base64)),
                         doctest::Contains("Failed to decode 'uri'"), Error);
    const std::size_t n = g.bin.size();
    g.doc["buffers"] = {{{"byteLength", n - 1}, {"uri", "longer.bin"}}};
    const std::string mismatch =
        "requestedBytes " + std::to_string(n - 1) + ", but got " + std::to_string(n);
    CHECK_THROWS_WITH_AS(read_gltf<Rgb>(save(g, "longer")), doctest::Contains(mismatch.c_str()),
                         Error);
}

TEST_CASE("glTF reader: baseColorFactor and emissiveFactor become the materials") {
    Gltf g = triangle();
    json second = primitive(g);
    primitive(g)["material"] = 1;
    g.doc["meshes"][0]["primitives"].push_back(second);  // no material: the default grey
    g.doc["materials"] = {
        {{"name", "white"}},  // glTF's default base colour 1, clamped to 0.99
        {{"name", "lamp"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 1.5, 0.5}}}},
         {"emissiveFactor", {1.0, 0.5, 0.0}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 10.0}}}}}}};
    const Scene<Rgb> s = read_gltf<Rgb>(save(g, "materials"));
    REQUIRE(s.materials.size() == 3);
    CHECK(s.materials[0].name == "white");
    CHECK(s.materials[0].reflectance == Rgb(0.99f));
    CHECK(s.materials[1].name == "lamp");
    CHECK(s.materials[1].reflectance == Rgb(0.2f, 0.4f, 0.99f));
    CHECK(s.materials[1].emission == Rgb(10.0f, 5.0f, 0.0f));
    CHECK(s.materials[2].reflectance == Rgb(0.5f));
    CHECK(s.face_material == std::vector<std::uint32_t>{1, 2});
    CHECK(read_gltf<float>(save(g, "materials")).materials[1].emission ==
          test::approx(5.0f));  // grey: the mean of r, g and b
    CHECK_NOTHROW(build_mesh(s));
}

TEST_CASE("glTF reader: lightmap UVs only when every face has them, all in [0, 1]") {
    Gltf g = triangle();
    primitive(g)["attributes"]["TEXCOORD_0"] = g.uvs({0, 0, 1, 0, 0, 1});
    json bare = primitive(g);
    bare["attributes"].erase("TEXCOORD_0");
    CHECK(read_gltf<Rgb>(save(g, "uv_all")).face_uvs.size() == 1);
    g.doc["meshes"][0]["primitives"].push_back(bare);
    CHECK(read_gltf<Rgb>(save(g, "uv_some")).face_uvs.empty());
    g.doc["meshes"][0]["primitives"].erase(1);
    primitive(g)["attributes"]["TEXCOORD_0"] = g.uvs({0, 0, 1.5f, 0, 0, 1});  // tiled
    CHECK(read_gltf<Rgb>(save(g, "uv_tiled")).face_uvs.empty());
}

namespace {

/// Reads the file, which must be refused with one line that starts with its path and contains
/// `what`.
void check_refused(const std::string& path, const std::string& what) {
    CAPTURE(path);
    try {
        (void)read_gltf<Rgb>(path);
        FAIL("read, but should have been refused: " << what);
    } catch (const Error& e) {
        const std::string m = e.what();
        CAPTURE(m);
        CHECK(m.rfind(path + ": ", 0) == 0);
        CHECK(m.find('\n') == std::string::npos);
        CHECK(m.find(what) != std::string::npos);
    }
}

/// Sets a JSON pointer in a copy of the triangle's document, saves it, and checks the message.
void check_refused_with(const std::string& pointer, const json& value, const std::string& what,
                        Storage storage = Storage::file) {
    Gltf g = triangle();
    primitive(g)["indices"] = g.accessor(std::vector<std::uint16_t>{0, 1, 2}, 5123, "SCALAR", 3);
    if (value.is_null())
        g.doc[json::json_pointer(pointer).parent_pointer()].erase(
            json::json_pointer(pointer).back());
    else
        g.doc[json::json_pointer(pointer)] = value;
    CAPTURE(pointer);
    check_refused(save(g, "bad", storage), what);
}

}  // namespace

TEST_CASE("glTF reader: malformed documents are refused naming the element") {
    const std::uint64_t big = 1'000'000'000'000'000'000;
    check_refused(dir / "missing.gltf", "no such file");
    std::ofstream(dir / "not_json.gltf") << "{\"asset\": {\"version\": \"2.0\"},";
    check_refused(dir / "not_json.gltf", "parse error at line 1, column 30");
    check_refused_with("/asset", nullptr, "\"asset\" object not found");
    check_refused_with("/asset/version", "1.0", "asset: version 1.0 is not 2.x");
    check_refused_with("/extensionsRequired", {"KHR_draco_mesh_compression"},
                       "extensionsRequired: KHR_draco_mesh_compression is not supported");
    check_refused_with("/scene", 4, "scenes[4]: does not exist (the file has 1)");
    check_refused_with("/scenes/0/nodes/0", 9, "nodes[9]: does not exist");
    check_refused_with("/nodes/0/children", {0}, "nodes[0]: is reached twice");
    // tinygltf reads a negative index as "none": the one node then draws nothing.
    check_refused_with("/nodes/0/mesh", -1, "scene: has no triangles");
    check_refused_with("/nodes/0/mesh", 3, "meshes[3]: does not exist");
    check_refused_with("/nodes/0/rotation", {0, 0, 0, 0}, "nodes[0]: 'rotation' is not a rotation");
    check_refused_with("/nodes/0/matrix", {1, 2, 3}, "nodes[0]: 'matrix' is not an array of 16");
    check_refused_with("/meshes/0/primitives/0/mode", 7, "primitives[0]: mode 7 is not 0..6");
    check_refused_with("/meshes/0/primitives/0/attributes/POSITION", nullptr,
                       "meshes[0].primitives[0].attributes: missing required 'POSITION'");
    check_refused_with("/meshes/0/primitives/0/material", 2, "materials[2]: does not exist");
    check_refused_with("/meshes/0/primitives/0/attributes/TEXCOORD_0", 1,
                       "accessors[1]: type is SCALAR, expected VEC2");
    check_refused_with("/accessors/0/componentType", 5125,
                       "accessors[0]: componentType 5125 is not allowed here");
    check_refused_with("/accessors/0/type", "VEC2", "accessors[0]: type is VEC2, expected VEC3");
    check_refused_with("/accessors/0/type", "VEC5", "Unsupported `type` for accessor object");
    check_refused_with("/accessors/0/count", 4,
                       "accessors[0]: needs 48 bytes, bufferViews[0] has 36");
    check_refused_with("/accessors/0/count", big, "accessors[0]: needs");
    check_refused_with("/accessors/0/byteOffset", 4, "accessors[0]: needs 40 bytes");
    check_refused_with("/accessors/0/sparse", {{"count", 1}},
                       "the sparse object of this accessor doesn't have indices");
    check_refused_with("/accessors/0/sparse",
                       {{"count", 1},
                        {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                        {"values", {{"bufferView", 0}}}},
                       "accessors[0]: sparse accessors are not supported");
    check_refused_with("/accessors/0/bufferView", nullptr, "accessors[0]: has no bufferView");
    check_refused_with("/accessors/1/count", 2, "primitives[0]: 2 indices are not whole triangles");
    check_refused_with("/bufferViews/0/byteLength", 100,
                       "bufferViews[0]: bytes 0 + 100 lie outside buffers[0] (44 bytes)");
    check_refused_with("/bufferViews/0/byteStride", 8, "do not fit bufferViews[0]'s byteStride 8");
    check_refused_with("/bufferViews/0/byteStride", 2,
                       "`byteStride' must be the multiple of 4 : 2");
    check_refused_with("/bufferViews/0/buffer", 1, "buffers[1]: does not exist");
    check_refused_with("/buffers/0/byteLength", 100, "bad.bin, requestedBytes 100, but got 44");
    check_refused_with("/buffers/0/uri", "http://example.com/bad.bin",
                       "File not found : http://example.com/bad.bin");
    check_refused_with("/buffers/0/uri", "nowhere.bin", "File not found : nowhere.bin");
    check_refused_with("/buffers/0/uri", "data:application/octet-stream;base64,A*A=",
                       "Failed to decode 'uri' : data:application/octet-stream;base64,A*A=");
    check_refused_with("/buffers/0/uri", "data:application/gltf-buffer;base64,AAAAAA",
                       "Failed to decode 'uri'");  // 4 bytes, byteLength 44
    check_refused_with("/buffers/0/uri", "data:text/plain,hello",
                       "File not found : data:text/plain,hello");
    check_refused_with("/materials", {{{"emissiveFactor", {1, -1, 0}}}},
                       "materials[0]: emission is negative");
    check_refused_with("/materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1}}}}}},
                       "`baseColorFactor` parameter in pbrMetallicRoughness must be 4, but got 2");
    check_refused_with("/scenes/0/nodes", json::array(), "scene: has no triangles");
    std::ofstream(dir / "array.gltf") << "[1, 2]";
    check_refused(dir / "array.gltf", "Root element is not a JSON object");
}

TEST_CASE("glTF reader: bad data in the buffers is refused naming the accessor") {
    Gltf g = triangle();
    const int i = g.accessor(std::vector<std::uint32_t>{0, 1, 3}, 5125, "SCALAR", 3);
    primitive(g)["indices"] = i;
    check_refused(save(g, "index_range"), "accessors[1]: index 3 is out of range (POSITION has 3");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Gltf h = single_primitive({0, 0, 0, 1, 0, 0, 0, nan, 0});
    check_refused(save(h, "nan"), "accessors[0]: element 2 is not a finite point");
    h = triangle();
    h.doc["nodes"] = {{{"scale", {1e300, 1e300, 1e300}}, {"children", {1}}},
                      {{"scale", {1e300, 1e300, 1e300}}, {"mesh", 0}}};
    check_refused(save(h, "overflow"), "scene: has no triangles");  // areas overflow: dropped
}

TEST_CASE("glTF reader: broken .glb containers are refused naming the part") {
    const Gltf g = triangle();
    json doc = g.doc;
    doc["buffers"] = {{{"byteLength", g.bin.size()}}};
    const std::vector<std::uint8_t> good = glb_bytes(doc, g.bin);
    const std::string path = dir / "broken.glb";
    write_file(path, good);
    CHECK(read_gltf<Rgb>(path).faces.size() == 1);
    auto broken = [&](std::size_t at, std::uint32_t word, const std::string& what) {
        std::vector<std::uint8_t> b = good;
        set_word(b, at, word);
        write_file(path, b);
        check_refused(path, what);
    };
    broken(4, 1, "GLB header: version 1, not 2");
    broken(8, 12345, "GLB header: length 12345, but the file has");
    broken(12, 100000, "GLB chunk 0: length 100000 runs past the end");
    broken(16, 0x004E4942u, "GLB chunk 0: the first chunk is not JSON");
    const std::size_t bin_chunk = 20 + (good[12] | good[13] << 8);
    broken(bin_chunk, 1000, "GLB chunk 1: length 1000 runs past the end");
    // A length that counts the chunk's own 8-byte header: tinygltf 2.7.0 alone accepts it and
    // copies the buffer from past the end of the file.
    const auto bin_length = static_cast<std::uint32_t>(good.size() - bin_chunk - 8);
    broken(bin_chunk, bin_length + 8,
           "GLB chunk 1: length " + std::to_string(bin_length + 8) + " runs past the end");
    std::vector<std::uint8_t> cut(good.begin(), good.begin() + 16);
    write_file(path, cut);
    check_refused(path, "GLB header: the file has only 16 bytes");
    cut = good;
    cut.resize(good.size() - 4);
    set_word(cut, 8, static_cast<std::uint32_t>(cut.size()));
    write_file(path, cut);
    check_refused(path, "GLB chunk 1: length 36 runs past the end of the file");
    write_file(path, glb_bytes(doc, {}));  // no BIN chunk: buffer 0 has nothing to point at
    check_refused(path, "GLB with empty BIN chunk");
    json empty = doc;  // tinygltf 2.7.0 throws std::out_of_range for a buffer of 0 bytes
    empty["buffers"][0]["byteLength"] = 0;
    write_file(path, glb_bytes(empty, g.bin));
    check_refused(path, "tinygltf failed");
}

TEST_CASE("glTF reader: JSON nested deeper than tinygltf's recursion can take is refused") {
    // tinygltf copies `extras` by recursion: 30,000 nested arrays overflow an 8 MiB stack.
    auto with_extras = [](int depth, const std::string& name) {
        Gltf g = triangle();
        g.doc["extras"] = "nested";
        const std::string path = save(g, name);
        std::ifstream in(path);
        std::string text{std::istreambuf_iterator<char>(in), {}};
        const std::size_t at = text.find("\"nested\"");
        REQUIRE(at != std::string::npos);
        const auto d = static_cast<std::size_t>(depth);
        text.replace(at, 8, std::string(d, '[') + std::string(d, ']'));
        std::ofstream(path) << text;
        return path;
    };
    CHECK(read_gltf<Rgb>(with_extras(400, "deep400")).faces.size() == 1);  // 401 levels in all
    check_refused(with_extras(100000, "deep"), "JSON nested deeper than 512 levels");
}

TEST_CASE("glTF reader: a buffer is looked for beside the glTF, not in the working directory") {
    struct Cwd {  // puts the working directory back whatever happens
        fs::path was = fs::current_path();
        ~Cwd() { fs::current_path(was); }
    } cwd;
    Gltf g = triangle();
    g.doc["buffers"] = {{{"byteLength", g.bin.size()}, {"uri", "side.bin"}}};
    fs::create_directories(dir.path / "sub");
    std::ofstream(dir / "sub/side.gltf") << g.doc.dump();
    write_file(dir / "side.bin", g.bin);  // in the working directory only
    fs::current_path(dir.path);
    check_refused("sub/side.gltf", "File not found : side.bin");  // tinygltf alone would read it
    write_file(dir / "sub/side.bin", g.bin);
    CHECK(read_gltf<Rgb>("sub/side.gltf").faces.size() == 1);  // a relative path to the glTF
    fs::current_path(dir.path / "sub");
    CHECK(read_gltf<Rgb>("side.gltf").faces.size() == 1);  // a bare name: the working directory
}
