// Cubes for the io tests (engine/io/*_test.cpp): random and patterned content, bit-exact
// comparison, and the check that a reader's input error names the file, the key and the problem.
#pragma once

#include "core/error.h"
#include "spectral/cube.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <random>
#include <string>

namespace metamer::test {

inline SpectralCube randomCube(int w, int h, const Grid& g, unsigned seed, float lo = 0.0f, float hi = 10.0f) {
    SpectralCube cube(w, h, g);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> dist(lo, hi);
    for (float& v : cube.data) v = dist(rng);
    return cube;
}

// value(x, y, band) = band + 0.25·x + 0.5·y + 100: distinct everywhere, exact in float.
inline SpectralCube patternCube(int w, int h, const Grid& g) {
    SpectralCube cube(w, h, g);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int b = 0; b < g.bands(); ++b) cube.at(x, y, b) = float(b) + 0.25f * float(x) + 0.5f * float(y) + 100;
    return cube;
}

inline void expectBitExact(const SpectralCube& a, const SpectralCube& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.grid, b.grid) << a.grid.str() << " vs " << b.grid.str();
    ASSERT_EQ(a.data.size(), b.data.size());
    EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
}

// Runs `f` and checks that it throws an input error at `file` and `key` (and `line`, when > 0)
// whose message holds `fragment`.
inline void expectInputError(const std::function<void()>& f, const std::string& file, const std::string& key,
                             const std::string& fragment, int line = 0) {
    try {
        f();
        ADD_FAILURE() << "expected an input error for " << file << " " << key;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput) << e.text();
        EXPECT_EQ(e.where().file, file) << e.text();
        EXPECT_EQ(e.where().key, key) << e.text();
        EXPECT_NE(e.message().find(fragment), std::string::npos) << e.text();
        if (line > 0) EXPECT_EQ(e.where().line, line) << e.text();
    }
}

}  // namespace metamer::test
