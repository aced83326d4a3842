// CIELAB against colour-science (tests/data/color/colorimetry/lab.txt, written by generate.py
// there) and its own inverse.
#include "color/lab.h"

#include "color/srgb.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace metamer;

namespace {

// One row of numbers per line; '#' lines are comments.
std::vector<std::vector<double>> readTable(const std::string& name) {
    std::ifstream in(std::filesystem::path(METAMER_TEST_DATA_DIR) / "color" / "colorimetry" / name);
    EXPECT_TRUE(in) << name;
    std::vector<std::vector<double>> rows;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::vector<double> row;
        for (double v; s >> v;) row.push_back(v);
        rows.push_back(row);
    }
    return rows;
}

// |a − b| within `rel` of the larger magnitude, or of 1 for values near 0 (a*, b* of neutrals).
void expectClose(double actual, double expected, double rel, const std::string& what) {
    EXPECT_NEAR(actual, expected, rel * std::max(1.0, std::abs(expected))) << what;
}

}  // namespace

TEST(Lab, WhiteIsL100Neutral) {
    glm::dvec3 lab = xyzToLab(kD65WhiteXyz, kD65WhiteXyz);
    EXPECT_DOUBLE_EQ(lab.x, 100.0);
    EXPECT_DOUBLE_EQ(lab.y, 0.0);
    EXPECT_DOUBLE_EQ(lab.z, 0.0);
    // Any scale: a white of Y = 100 and Y = 1 give the same L*a*b*.
    glm::dvec3 lab100 = xyzToLab(100.0 * kD65WhiteXyz, 100.0 * kD65WhiteXyz);
    EXPECT_NEAR(lab100.x, 100.0, 1e-12);
    EXPECT_NEAR(lab100.y, 0.0, 1e-12);
    EXPECT_NEAR(lab100.z, 0.0, 1e-12);
}

TEST(Lab, BlackIsZero) {
    glm::dvec3 lab = xyzToLab(glm::dvec3(0.0), kD65WhiteXyz);
    EXPECT_NEAR(lab.x, 0.0, 1e-12);
    EXPECT_NEAR(lab.y, 0.0, 1e-12);
    EXPECT_NEAR(lab.z, 0.0, 1e-12);
}

TEST(Lab, MatchesColourScience) {
    auto rows = readTable("lab.txt");
    ASSERT_GE(rows.size(), 36u);
    for (size_t i = 0; i < rows.size(); ++i) {
        const auto& r = rows[i];
        ASSERT_EQ(r.size(), 9u) << "row " << i;
        glm::dvec3 lab = xyzToLab({r[0], r[1], r[2]}, {r[3], r[4], r[5]});
        const std::string what = "row " + std::to_string(i);
        expectClose(lab.x, r[6], 1e-9, what + " L*");
        expectClose(lab.y, r[7], 1e-9, what + " a*");
        expectClose(lab.z, r[8], 1e-9, what + " b*");
    }
}

TEST(Lab, RoundTripsThroughXyz) {
    // Every table colour (dark ones below the knee, a negative X, brighter than white), on its
    // own white and scale.
    for (const auto& r : readTable("lab.txt")) {
        glm::dvec3 xyz(r[0], r[1], r[2]), white(r[3], r[4], r[5]);
        glm::dvec3 back = labToXyz(xyzToLab(xyz, white), white);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], xyz[c], 1e-12 * white.y) << c;
    }
}

TEST(Lab, KneeIsContinuous) {
    // Y/Yn just below and above 216/24389: L* must not jump (it is 8 at the knee).
    const double knee = 216.0 / 24389.0;
    glm::dvec3 white(1.0);
    double below = xyzToLab(glm::dvec3(std::nextafter(knee, 0.0)), white).x;
    double above = xyzToLab(glm::dvec3(std::nextafter(knee, 1.0)), white).x;
    EXPECT_NEAR(below, 8.0, 1e-9);
    EXPECT_NEAR(above, 8.0, 1e-9);
}
