// Small cubes and a scratch folder for the compare tests (compare_test, tolerance_test,
// heatmap_test, compare_cli_test).
#pragma once

#include "spectral/cube.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

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

// A fresh folder per test, named after it, removed afterwards.
class ScratchDir : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = std::filesystem::temp_directory_path() /
              fmt::format("metamer-compare-{}-{}-{}", ::getpid(), info->test_suite_name(), info->name());
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }

    std::filesystem::path write(const std::string& name, const std::string& text) const {
        std::filesystem::path p = dir / name;
        std::ofstream(p) << text;
        return p;
    }

    std::filesystem::path dir;
};

}  // namespace metamer::test
