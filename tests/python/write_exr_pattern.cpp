// Writes a spectral EXR with a known pattern for tests/python/check_exr_colour.py:
// value(x, y, band) = band + 0.25·x + 0.5·y, exact in float32 and in half.
// Usage: write_exr_pattern OUT.exr float|half
#include "core/error.h"
#include "io/spectral_exr.h"

#include <cstdio>
#include <cstring>

int main(int argc, char** argv) {
    using namespace metamer;
    if (argc != 3 || (std::strcmp(argv[2], "float") != 0 && std::strcmp(argv[2], "half") != 0)) {
        std::fprintf(stderr, "usage: %s OUT.exr float|half\n", argv[0]);
        return 2;
    }
    try {
        // Crosses 1000 nm, so the file's alphabetical channel order differs from wavelength order.
        SpectralCube cube(5, 3, Grid{380, 1020, 20});
        for (int y = 0; y < cube.height; ++y)
            for (int x = 0; x < cube.width; ++x)
                for (int b = 0; b < cube.bands(); ++b) cube.at(x, y, b) = b + 0.25f * x + 0.5f * y;
        ExrWriteOptions options;
        options.half = std::strcmp(argv[2], "half") == 0;
        writeSpectralExr(argv[1], cube, options);
    } catch (const Error& e) {
        std::fprintf(stderr, "write_exr_pattern: %s\n", e.what());
        return 1;
    }
    return 0;
}
