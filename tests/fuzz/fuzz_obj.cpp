// libFuzzer harness of the OBJ/MTL reader (read_obj). An input is an OBJ text, optionally
// followed by a line "#mtl" and the text of the material file fuzz.mtl that it may name
// (`mtllib fuzz.mtl`). tinyobjloader is compiled here, with the sanitizers and coverage.
#define TINYOBJLOADER_IMPLEMENTATION
#include <radiosity/io/obj.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace radiosity;
    const auto [obj, mtl] = fuzz::split({reinterpret_cast<const char*>(data), size}, "\n#mtl\n");
    const std::string path = fuzz::write("fuzz.obj", obj);
    std::error_code ec;
    if (mtl)
        fuzz::write("fuzz.mtl", *mtl);
    else
        std::filesystem::remove(fuzz::scratch() / "fuzz.mtl", ec);
    return fuzz::run([&] { return read_obj<Rgb>(path); });
}
