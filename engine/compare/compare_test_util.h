// Small cubes and a scratch folder for the compare tests (compare_test, tolerance_test,
// heatmap_test, compare_cli_test).
#pragma once

#include "spectral/cube.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace metamer::test {

// A smooth, positive spectrum per pixel that varies across the image: each pixel a different
// colour, all well above zero.
inline SpectralCube smoothCube(int w, int h, const Grid& grid) {
    SpectralCube cube(w, h, grid);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int b = 0; b < grid.bands(); ++b) {
                double l = grid.wavelength(b);
                cube.at(x, y, b) = float(0.02 * (1.5 + std::sin(l / 40.0 + 0.7 * x + 1.3 * y)));
            }
    return cube;
}

// The shared fresh folder per test (tests/support/temp_folder.h), with a helper to write files in it.
class ScratchDir : public TempFolderTest {
protected:
    std::filesystem::path write(const std::string& name, const std::string& text) const {
        std::filesystem::path p = dir / name;
        std::ofstream(p) << text;
        return p;
    }
};

}  // namespace metamer::test
