#pragma once
// Shared by the libFuzzer harnesses (scripts/fuzz.sh): the readers take paths, so each input is
// written to files in a scratch folder of this process; and the checks that every scene a reader
// returns must pass. A reader may refuse an input with radiosity::Error; anything else that
// escapes (another exception, a crash, a sanitizer report, a scene that fails a check) is a
// finding: libFuzzer stops and keeps the input.
#include <radiosity/mesh/mesh.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <unistd.h>
#include <utility>

namespace radiosity::fuzz {

/// This process's scratch folder (libFuzzer's -jobs run several processes side by side).
inline const std::filesystem::path& scratch() {
    static const std::filesystem::path dir = [] {
        const auto d = std::filesystem::temp_directory_path() /
                       ("radiosity_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratch(), ec);
        });
        return d;
    }();
    return dir;
}

/// Writes bytes to a file of the scratch folder and returns its path.
inline std::string write(const std::string& name, std::string_view bytes) {
    const std::filesystem::path p = scratch() / name;
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return p.string();
}

/// The input split at the first `separator` into the part before and the part after (empty and
/// absent if there is none): one input can hold a file and the file it names.
inline std::pair<std::string_view, std::optional<std::string_view>> split(
    std::string_view input, std::string_view separator) {
    const std::size_t at = input.find(separator);
    if (at == std::string_view::npos) return {input, std::nullopt};
    return {input.substr(0, at), input.substr(at + separator.size())};
}

/// Stops the fuzzer with a message: a check that a scene failed.
[[noreturn]] inline void finding(const char* what) {
    std::fprintf(stderr, "radiosity fuzz finding: %s\n", what);
    std::abort();
}

/// The checks of a scene a reader returned: every position finite (a reader must refuse what
/// is not); then, if build_mesh accepts it, a mesh of faces with finite, positive areas.
template <SpectrumType S>
void check_scene(const Scene<S>& scene) {
    for (const Vec3& p : scene.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            finding("a reader returned a point that is not finite");
    if (scene.faces.empty()) finding("a reader returned a scene without faces");
    const Mesh<S> mesh = build_mesh(scene);  // may refuse (zero-area faces and the like)
    if (mesh.n_faces() != scene.faces.size()) finding("build_mesh lost or added faces");
    for (auto f : mesh.faces()) {
        const double a = polygon_area(face_polygon(mesh, f));
        if (!std::isfinite(a) || !(a > 0.0)) finding("a face of the mesh has no finite area");
    }
}

/// Runs a reader on the files written and checks what it returns; an Error is a refusal.
template <class Read>
int run(Read&& read) {
    try {
        check_scene(read());
    } catch (const Error&) {
    }
    return 0;
}

}  // namespace radiosity::fuzz
