// Checks the picture that the README's first snippet draws of examples/data/room.obj from
// outside the room: with back faces culled the near wall lets the camera in, so the middle of
// the picture is the far wall (the room's only blue surface) and the lamp shows (saturated
// white); drawn with back faces, the near wall's grey outside covers everything.
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) return std::fprintf(stderr, "usage: readme_picture_check PNG\n"), 2;
    int w = 0, h = 0, channels = 0;
    unsigned char* p = stbi_load(argv[1], &w, &h, &channels, 3);
    if (!p) return std::fprintf(stderr, "%s: cannot read\n", argv[1]), 1;
    const unsigned char* centre = p + 3 * ((h / 2) * w + w / 2);
    const bool blue = centre[2] > 1.3 * centre[0] && centre[2] > 1.3 * centre[1];
    int lamp = 0;
    for (int i = 0; i < w * h; ++i)
        lamp += p[3 * i] >= 250 && p[3 * i + 1] >= 250 && p[3 * i + 2] >= 250;
    std::printf("%s: %dx%d, centre (%d, %d, %d), %d saturated pixels\n", argv[1], w, h, centre[0],
                centre[1], centre[2], lamp);
    stbi_image_free(p);
    if (!blue)
        return std::fprintf(stderr, "the middle of the picture is not the blue far wall\n"), 1;
    if (lamp < 20) return std::fprintf(stderr, "the lamp is not in the picture\n"), 1;
    return 0;
}
