// glTF export read back by an independent reader (nlohmann::json plus our own buffer walk): the
// document is valid JSON, accessor counts and buffer sizes agree with the mesh, the colours are
// the clamped linear values, and the .glb container has the right header and chunks.
#include <radiosity/io/gltf.hpp>

#include "support/approx.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

using namespace radiosity;
namespace fs = std::filesystem;

namespace {

ShadedMesh quad() {
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    m.colours = {glm::vec3(0.25f), glm::vec3(0.5f, 0.0f, 1.0f), glm::vec3(3.0f), glm::vec3(0.0f)};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

std::vector<std::uint8_t> read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

/// Checks the document against the mesh, reading the accessors out of the binary buffer.
void check_document(const nlohmann::json& doc, const std::vector<std::uint8_t>& bin,
                    const ShadedMesh& m, double scale) {
    CHECK(doc["asset"]["version"] == "2.0");
    REQUIRE(doc["buffers"][0]["byteLength"].get<std::size_t>() == bin.size());
    const auto& prim = doc["meshes"][0]["primitives"][0];
    const auto& acc = doc["accessors"];
    const auto& views = doc["bufferViews"];
    auto floats = [&](int a) {
        const auto& v = views[acc[a]["bufferView"].get<int>()];
        const std::size_t n = acc[a]["count"].get<std::size_t>() * 3;
        REQUIRE(v["byteLength"].get<std::size_t>() == n * 4);
        const std::size_t offset = v.value("byteOffset", std::size_t{0});  // 0 may be left out
        REQUIRE(offset + n * 4 <= bin.size());
        std::vector<float> out(n);
        std::memcpy(out.data(), bin.data() + offset, n * 4);
        return out;
    };
    const auto position = floats(prim["attributes"]["POSITION"].get<int>());
    const auto colour = floats(prim["attributes"]["COLOR_0"].get<int>());
    REQUIRE(position.size() == m.positions.size() * 3);
    for (std::size_t v = 0; v < m.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            CHECK(position[3 * v + k] == static_cast<float>(m.positions[v][k]));
            CHECK(colour[3 * v + k] == test::approx(std::clamp(scale * m.colours[v][k], 0.0, 1.0)));
        }
    CHECK(acc[prim["indices"].get<int>()]["count"] == m.triangles.size() * 3);
    CHECK(acc[prim["attributes"]["POSITION"].get<int>()]["max"][0] == 2.0);
}

}  // namespace

TEST_CASE("glTF: .gltf with .bin beside it") {
    const fs::path dir =
        fs::temp_directory_path() / ("radiosity_gltf_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const ShadedMesh m = quad();
    write_gltf(m, (dir / "quad.gltf").string(), 0.5);
    std::ifstream in(dir / "quad.gltf");
    const nlohmann::json doc = nlohmann::json::parse(in);
    CHECK(doc["buffers"][0]["uri"] == "quad.bin");
    check_document(doc, read_all(dir / "quad.bin"), m, 0.5);
    fs::remove_all(dir);
}

TEST_CASE("glTF: one .glb with header, JSON chunk and BIN chunk") {
    const fs::path path =
        fs::temp_directory_path() / ("radiosity_gltf_" + std::to_string(::getpid()) + ".glb");
    const ShadedMesh m = quad();
    write_gltf(m, path.string(), 1.0);
    const auto bytes = read_all(path);
    fs::remove(path);
    REQUIRE(bytes.size() >= 28);
    std::uint32_t header[5];
    std::memcpy(header, bytes.data(), sizeof header);
    CHECK(header[0] == 0x46546C67u);  // "glTF"
    CHECK(header[1] == 2u);
    CHECK(header[2] == bytes.size());
    CHECK(header[4] == 0x4E4F534Au);  // "JSON"
    const std::size_t json_size = header[3];
    CHECK(json_size % 4 == 0);
    const nlohmann::json doc = nlohmann::json::parse(
        bytes.begin() + 20, bytes.begin() + 20 + static_cast<long>(json_size));
    std::uint32_t chunk[2];
    std::memcpy(chunk, bytes.data() + 20 + json_size, sizeof chunk);
    CHECK(chunk[1] == 0x004E4942u);  // "BIN\0"
    const std::vector<std::uint8_t> bin(bytes.begin() + 28 + static_cast<long>(json_size),
                                        bytes.end());
    CHECK(bin.size() == chunk[0]);
    check_document(doc, bin, m, 1.0);
    CHECK_THROWS_AS(write_gltf(m, "/no/such/folder/x.glb", 1.0), Error);
}
