// libFuzzer harness of the RRV reader (read_rrv). An input is an RRV scene (XML); its teapot is
// a tetrahedron written once, and the scene is bounded at 200,000 triangles so that an input
// that places large objects many times is refused in milliseconds rather than read for seconds.
#include <radiosity/io/rrv.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace radiosity;
    static const RrvOptions options{
        .teapot_obj = fuzz::write("teapot.obj",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                  "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"),
        .max_triangles = 200'000};
    const std::string path = fuzz::write("fuzz.xml", {reinterpret_cast<const char*>(data), size});
    return fuzz::run([&] { return read_rrv<Rgb>(path, options); });
}
