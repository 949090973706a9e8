// Deterministic mutation fuzzing of the readers, in the normal suite: thousands of seeded
// mutations of valid input files (bytes flipped, lines dropped, duplicated or cut, numbers
// replaced by hostile ones) must each either load into a valid scene or be refused with a
// radiosity::Error, never crash, hang or throw anything else. Run it under the sanitizer build
// (README) to catch memory errors too.
#include <radiosity/geometry/sampling.hpp>
#include <radiosity/io/obj.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/mesh/patch_table.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
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
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng.uniform() * double(n)); };
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

}  // namespace

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
            const PatchTable t = make_patch_table(subdivide(mesh, {0.4}));  // valid, finite
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
