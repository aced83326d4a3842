// Writes one cube with a known pattern in every cube format, for tests/python/check_cube_formats.py:
// value(x, y, band) = band + 0.25·x + 0.5·y on 380:1020:20 (33 bands), 7×5 pixels, exact in float32.
// Files: pattern.exr, pattern.h5 (gzip 6), pattern_bsq.hdr/.img, pattern_bil.hdr/.img, each written
// by its strip writer in two strips of uneven height.
// Usage: write_cube_formats OUT_DIR
#include "core/error.h"
#include "io/envi_cube.h"
#include "io/hdf5_cube.h"
#include "io/spectral_exr.h"

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
    using namespace metamer;
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
        return 2;
    }
    try {
        const std::filesystem::path out = argv[1];
        SpectralCube cube(7, 5, Grid{380, 1020, 20});
        for (int y = 0; y < cube.height; ++y)
            for (int x = 0; x < cube.width; ++x)
                for (int b = 0; b < cube.bands(); ++b) cube.at(x, y, b) = b + 0.25f * x + 0.5f * y;
        const StringAttributes attributes = {{"metamer:scene", "pattern"}};
        auto strips = [&](auto& writer) {
            writer.writeRows(0, 2, cube.pixel(0, 0));
            writer.writeRows(2, 3, cube.pixel(0, 2));
            writer.commit();
        };
        SpectralExrWriter exr(out / "pattern.exr", cube.width, cube.height, cube.grid, {.extraAttributes = attributes});
        strips(exr);
        Hdf5CubeWriter h5(out / "pattern.h5", cube.width, cube.height, cube.grid,
                          {.gzipLevel = 6, .attributes = attributes});
        strips(h5);
        EnviCubeWriter bsq(out / "pattern_bsq.hdr", cube.width, cube.height, cube.grid,
                           {.interleave = EnviInterleave::Bsq, .attributes = attributes});
        strips(bsq);
        EnviCubeWriter bil(out / "pattern_bil.hdr", cube.width, cube.height, cube.grid,
                           {.interleave = EnviInterleave::Bil, .attributes = attributes});
        strips(bil);
    } catch (const Error& e) {
        std::fprintf(stderr, "write_cube_formats: %s\n", e.what());
        return 1;
    }
    return 0;
}
