// Writes the built-in scenes as seeds of the fuzz corpora, in the harnesses' input forms:
// fuzz_seeds FOLDER obj|rrv|gltf. The Cornell box (with and without its blocks) as OBJ + MTL,
// as an RRV scene (write_rrv), and as glTF: a .glb and a .gltf with its buffer.
#include <radiosity/io/gltf.hpp>
#include <radiosity/io/rrv.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/shading/vertex_shading.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using namespace radiosity;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void put(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

/// A scene as an OBJ text naming fuzz.mtl, "#mtl", and the MTL text (fuzz_obj's input form).
std::string obj_seed(const Scene<Rgb>& s) {
    std::ostringstream obj, mtl;
    obj.precision(9);
    mtl.precision(9);
    obj << "# " << s.source << "\nmtllib fuzz.mtl\n";
    for (const Vec3& p : s.positions) obj << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
        obj << "usemtl m" << s.face_material[f] << "\nf";
        for (auto v : s.faces[f]) obj << ' ' << v + 1;
        obj << '\n';
    }
    for (std::size_t m = 0; m < s.materials.size(); ++m) {
        const auto e = to_rgb(s.materials[m].emission), r = to_rgb(s.materials[m].reflectance);
        mtl << "newmtl m" << m << "\nKd " << r[0] << ' ' << r[1] << ' ' << r[2] << "\nKe " << e[0]
            << ' ' << e[1] << ' ' << e[2] << '\n';
    }
    return obj.str() + "\n#mtl\n" + mtl.str();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: fuzz_seeds FOLDER obj|rrv|gltf\n");
        return 2;
    }
    const fs::path dir = argv[1];
    const std::string kind = argv[2];
    fs::create_directories(dir);
    try {
        for (const auto& name : builtin_scene_names()) {
            const Scene<Rgb> scene = builtin_scene<Rgb>(name);
            const fs::path base = dir / ("builtin_" + name);
            if (kind == "obj") {
                put(base.string() + ".obj", obj_seed(scene));
            } else if (kind == "rrv") {
                write_rrv(build_mesh(scene), base.string() + ".xml");
            } else if (kind == "gltf") {
                const ShadedMesh shaded = flat_shading(build_mesh(scene));
                write_gltf(shaded, base.string() + ".glb", 1.0);
                const fs::path json = base.string() + "_json.gltf",
                               bin = base.string() + "_json.bin";
                write_gltf(shaded, json.string(), 1.0);
                std::string text = slurp(json);
                const std::string uri = bin.filename().string();
                text.replace(text.find(uri), uri.size(), "fuzz.bin");
                put(json, text + "\n#bin\n" + slurp(bin));
                fs::remove(bin);
            } else {
                std::fprintf(stderr, "fuzz_seeds: unknown kind '%s'\n", kind.c_str());
                return 2;
            }
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "fuzz_seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
