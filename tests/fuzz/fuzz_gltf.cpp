// libFuzzer harness of the glTF reader (read_gltf). An input that starts with "glTF" is a .glb;
// any other is a .gltf (JSON), optionally followed by a line "#bin" and the bytes of the buffer
// file fuzz.bin that it may name (`"uri": "fuzz.bin"`).
#include <radiosity/io/gltf_read.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace radiosity;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    std::string path;
    if (input.substr(0, 4) == "glTF") {
        path = fuzz::write("fuzz.glb", input);
    } else {
        const auto [json, bin] = fuzz::split(input, "\n#bin\n");
        path = fuzz::write("fuzz.gltf", json);
        std::error_code ec;
        if (bin)
            fuzz::write("fuzz.bin", *bin);
        else
            std::filesystem::remove(fuzz::scratch() / "fuzz.bin", ec);
    }
    return fuzz::run([&] { return read_gltf<Rgb>(path); });
}
