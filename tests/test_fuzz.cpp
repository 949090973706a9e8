// Deterministic mutation fuzzing of the readers, in the normal suite: thousands of seeded
// mutations of valid input files (bytes flipped, lines dropped, duplicated or cut, numbers
// replaced by hostile ones) must each either load into a valid scene or be refused with a
// radiosity::Error, never crash, hang or throw anything else. Run it under the sanitizer build
// (README) to catch memory errors too.
#include <radiosity/geometry/patch_table.hpp>
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/io/gltf.hpp>
#include <radiosity/io/gltf_read.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <unistd.h>

using namespace radiosity;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// A random index below n.
std::size_t pick_below(Rng& rng, std::size_t n) {
    return static_cast<std::size_t>(rng.uniform() * double(n));
}

/// One random mutation of a text: a byte changed, a line dropped, doubled or cut short, a
/// number swapped for a hostile one, or a hostile line inserted.
std::string mutate(std::string text, Rng& rng) {
    static const std::vector<std::string> hostile{"nan",
                                                  "-inf",
                                                  "1e308",
                                                  "-1",
                                                  "0",
                                                  "99999999",
                                                  "1.5",
                                                  "",
                                                  "f",
                                                  "v",
                                                  "#",
                                                  "/",
                                                  "//",
                                                  "-0",
                                                  "f 1 2 3 4 5 6 7 8",
                                                  "usemtl nowhere",
                                                  "mtllib missing.mtl",
                                                  "v 1 2",
                                                  "f 0 0 0",
                                                  "f -1 -2 -3",
                                                  "newmtl",
                                                  "Kd 2 2 2",
                                                  "Ke -5 0 0",
                                                  "Kd nan 0 0",
                                                  "f 1/2/3 4/5/6 7/8/9"};
    auto pick = [&rng](std::size_t n) { return pick_below(rng, n); };
    if (text.empty()) return hostile[pick(hostile.size())];
    const std::size_t at = pick(text.size());
    switch (pick(6)) {
        case 0:
            text[at] = static_cast<char>(pick(128));
            break;
        case 1:
            text.erase(at, pick(40));
            break;
        case 2:
            text.insert(at, hostile[pick(hostile.size())] + (rng.uniform() < 0.5 ? "\n" : " "));
            break;
        case 3: {  // double a line
            const std::size_t start =
                text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
            const std::size_t end = text.find('\n', at);
            text.insert(start, text.substr(start, end == std::string::npos ? std::string::npos
                                                                           : end - start + 1));
            break;
        }
        case 4:
            text.resize(at);
            break;
        default: {  // replace the number starting here
            std::size_t end = at;
            while (end < text.size() && text[end] != ' ' && text[end] != '\n') ++end;
            text.replace(at, end - at, hostile[pick(6)]);
        }
    }
    return text;
}

/// One random mutation of a glTF JSON text: mutate()'s edits, or a number (an index, a count,
/// an offset) swapped for one that is out of range, negative, fractional or not a number.
std::string mutate_json(std::string text, Rng& rng) {
    static const std::vector<std::string> hostile{"4294967295", "18446744073709551615",
                                                  "-1",         "0",
                                                  "1",          "3",
                                                  "7",          "1e400",
                                                  "2.5",        "null",
                                                  "[]",         "{}",
                                                  "\"x\"",      "65536",
                                                  "1e18",       "true"};
    auto pick = [&rng](std::size_t n) { return pick_below(rng, n); };
    if (rng.uniform() < 0.4) return mutate(std::move(text), rng);
    const std::size_t at = text.find_first_of("0123456789", pick(text.size()));
    if (at == std::string::npos) return text;
    const std::size_t end = text.find_first_not_of("0123456789.e+-", at);
    return text.replace(at, end == std::string::npos ? std::string::npos : end - at,
                        hostile[pick(hostile.size())]);
}

/// One random mutation of binary data: bytes overwritten, a 32-bit word set to a hostile value
/// (lengths and counts in a .glb header), or the data cut short.
std::vector<std::uint8_t> mutate_bytes(std::vector<std::uint8_t> b, Rng& rng) {
    static const std::vector<std::uint32_t> words{
        0, 1, 2, 3, 0xFFFFFFFFu, 0x7FFFFFFFu, 12, 20, 0x4E4F534Au, 0x004E4942u, 0x7FC00000u};
    auto pick = [&rng](std::size_t n) { return pick_below(rng, n); };
    if (b.empty()) return b;
    const std::size_t at = pick(b.size());
    switch (pick(3)) {
        case 0:
            for (std::size_t k = at; k < std::min(b.size(), at + 1 + pick(8)); ++k)
                b[k] = static_cast<std::uint8_t>(pick(256));
            break;
        case 1: {  // header words are where a .glb keeps its lengths: aim there often
            const std::size_t w = rng.uniform() < 0.5 ? 4 * pick(6) : at & ~std::size_t(3);
            const std::uint32_t v = words[pick(words.size())];
            for (std::size_t k = 0; k < 4 && w + k < b.size(); ++k)
                b[w + k] = static_cast<std::uint8_t>(v >> (8 * k));
            break;
        }
        default:
            b.resize(at);
    }
    return b;
}

std::vector<std::uint8_t> slurp_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& b) {
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// A small lightmapped glTF of our own writer: two quads at an angle, with UVs.
void write_fuzz_seed(const fs::path& path) {
    ShadedMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 1, 1}, {1, 1, 1}};
    m.colours.assign(m.positions.size(), glm::vec3(0.5f));
    m.uvs = {{0, 0}, {0.5f, 0}, {0.5f, 0.5f}, {0, 0.5f}, {0, 1}, {0.5f, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 5}, {3, 5, 4}};
    write_gltf_lightmapped(m, Image{1, 1, {glm::vec3(0.5f)}}, path.string(), 1.0);
}

/// Reads a mutated glTF: +1 loaded (and built into a mesh), 0 refused with Error, -1 other.
int try_gltf(const fs::path& path) {
    try {
        const Mesh<Rgb> mesh = build_mesh(read_gltf<Rgb>(path.string()));
        REQUIRE(mesh.n_faces() > 0);
        return 1;
    } catch (const Error&) {
        return 0;
    } catch (...) {
        return -1;
    }
}

}  // namespace

TEST_CASE("glTF reader: 2000 mutated .gltf and 2000 mutated .glb files load or are refused") {
    const fs::path dir =
        fs::temp_directory_path() / ("radiosity_fuzz_gltf_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    write_fuzz_seed(dir / "seed.gltf");
    write_fuzz_seed(dir / "seed.glb");
    const std::string json = slurp(dir / "seed.gltf");
    const std::vector<std::uint8_t> bin = slurp_bytes(dir / "seed.bin"),
                                    glb = slurp_bytes(dir / "seed.glb");
    Rng rng(5);
    int loaded = 0, refused = 0, other = 0;
    auto count = [&](int r) { (r > 0 ? loaded : r == 0 ? refused : other) += 1; };
    for (int k = 0; k < 2000; ++k) {  // the JSON (and now and then the .bin beside it)
        std::string text = json;
        const int edits = 1 + static_cast<int>(rng.uniform() * 3);
        for (int e = 0; e < edits; ++e) text = mutate_json(text, rng);
        std::ofstream(dir / "seed.gltf") << text;
        write_bytes(dir / "seed.bin", rng.uniform() < 0.2 ? mutate_bytes(bin, rng) : bin);
        count(try_gltf(dir / "seed.gltf"));
    }
    const int gltf_loaded = loaded;
    for (int k = 0; k < 2000; ++k) {  // the .glb's bytes: header, chunks, JSON and buffer alike
        std::vector<std::uint8_t> b = glb;
        const int edits = 1 + static_cast<int>(rng.uniform() * 2);
        for (int e = 0; e < edits; ++e) b = mutate_bytes(b, rng);
        write_bytes(dir / "mutated.glb", b);
        count(try_gltf(dir / "mutated.glb"));
    }
    fs::remove_all(dir);
    CHECK(other == 0);
    CHECK(gltf_loaded > 100);
    CHECK(loaded - gltf_loaded > 50);  // most bytes of a .glb are its header and JSON
    CHECK(refused > 1000);
    MESSAGE("loaded " << loaded << " (" << gltf_loaded << " .gltf), refused " << refused);
}

TEST_CASE("OBJ/MTL reader: 3000 mutated files load (and subdivide) or are refused cleanly") {
    const fs::path data = RADIOSITY_TEST_DATA_DIR;
    const std::string obj = slurp(data / "cli_two_squares.obj"),
                      mtl = slurp(data / "cli_two_squares.mtl");
    const fs::path dir =
        fs::temp_directory_path() / ("radiosity_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    Rng rng(2026);
    int loaded = 0, refused = 0, other = 0;
    for (int k = 0; k < 3000; ++k) {
        std::string o = obj, m = mtl;
        const int edits = 1 + static_cast<int>(rng.uniform() * 4);
        for (int e = 0; e < edits; ++e) {
            if (rng.uniform() < 0.7)
                o = mutate(o, rng);
            else
                m = mutate(m, rng);
        }
        std::ofstream(dir / "cli_two_squares.obj") << o;
        std::ofstream(dir / "cli_two_squares.mtl") << m;
        try {
            const auto scene = read_obj<Rgb>((dir / "cli_two_squares.obj").string());
            const auto mesh = build_mesh(scene);
            const PatchTable t =
                make_patch_table(subdivide(mesh, {.max_edge = 0.4}));  // valid, finite
            for (std::size_t i = 0; i < t.size(); ++i) REQUIRE(std::isfinite(t.area(i)));
            ++loaded;
        } catch (const Error&) {
            ++refused;
        } catch (...) {
            ++other;
        }
    }
    fs::remove_all(dir);
    CHECK(other == 0);
    CHECK(loaded > 100);   // the mutations leave many files valid
    CHECK(refused > 100);  // and break many
    MESSAGE("loaded " << loaded << ", refused " << refused);
}

TEST_CASE("RRV XML reader: 600 mutated rooms load or are refused cleanly") {
    const std::string rrv = std::string(RADIOSITY_REFDATA_DIR) + "/../rrv";
    const std::string room = slurp(fs::path(rrv) / "room2.xml");
    const fs::path dir =
        fs::temp_directory_path() / ("radiosity_fuzz_rrv_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    RrvOptions options;
    options.teapot_obj = rrv + "/teapot.obj";
    Rng rng(7);
    int loaded = 0, refused = 0, other = 0;
    for (int k = 0; k < 600; ++k) {
        std::string text = room;
        const int edits = 1 + static_cast<int>(rng.uniform() * 3);
        for (int e = 0; e < edits; ++e) text = mutate(text, rng);
        std::ofstream(dir / "room.xml") << text;
        try {
            const Mesh<Rgb> mesh = build_mesh(read_rrv<Rgb>((dir / "room.xml").string(), options));
            REQUIRE(mesh.n_faces() > 0);
            ++loaded;
        } catch (const Error&) {
            ++refused;
        } catch (...) {
            ++other;
        }
    }
    fs::remove_all(dir);
    CHECK(other == 0);
    CHECK(loaded > 50);
    CHECK(refused > 50);
    MESSAGE("loaded " << loaded << ", refused " << refused);
}
