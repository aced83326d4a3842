// CIEDE2000 against the published test data of Sharma, Wu & Dalal (2005), and against
// colour-science on further pairs (tests/data/color/colorimetry/delta_e2000.txt).
#include "color/delta_e.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace metamer;

namespace {

struct Pair {
    glm::dvec3 lab1, lab2;
    double deltaE;
};

// Sharma, G., Wu, W. & Dalal, E. N. (2005), "The CIEDE2000 color-difference formula:
// implementation notes, supplementary test data, and mathematical observations", Color Research
// and Application 30(1): 21–30, Table 1 — all 34 pairs, ΔE00 as published (4 decimals).
// Pairs 7–16 exercise the hue conventions (a neutral, hues 180° apart on either side of the
// branch), 17–24 large and unit differences, 25–34 the RIT-DuPont data.
const Pair kSharma2005[34] = {
    {{50.0000, 2.6772, -79.7751}, {50.0000, 0.0000, -82.7485}, 2.0425},
    {{50.0000, 3.1571, -77.2803}, {50.0000, 0.0000, -82.7485}, 2.8615},
    {{50.0000, 2.8361, -74.0200}, {50.0000, 0.0000, -82.7485}, 3.4412},
    {{50.0000, -1.3802, -84.2814}, {50.0000, 0.0000, -82.7485}, 1.0000},
    {{50.0000, -1.1848, -84.8006}, {50.0000, 0.0000, -82.7485}, 1.0000},
    {{50.0000, -0.9009, -85.5211}, {50.0000, 0.0000, -82.7485}, 1.0000},
    {{50.0000, 0.0000, 0.0000}, {50.0000, -1.0000, 2.0000}, 2.3669},
    {{50.0000, -1.0000, 2.0000}, {50.0000, 0.0000, 0.0000}, 2.3669},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0009}, 7.1792},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0010}, 7.1792},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0011}, 7.2195},
    {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0012}, 7.2195},
    {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0009, -2.4900}, 4.8045},
    {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0010, -2.4900}, 4.8045},
    {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0011, -2.4900}, 4.7461},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 0.0000, -2.5000}, 4.3065},
    {{50.0000, 2.5000, 0.0000}, {73.0000, 25.0000, -18.0000}, 27.1492},
    {{50.0000, 2.5000, 0.0000}, {61.0000, -5.0000, 29.0000}, 22.8977},
    {{50.0000, 2.5000, 0.0000}, {56.0000, -27.0000, -3.0000}, 31.9030},
    {{50.0000, 2.5000, 0.0000}, {58.0000, 24.0000, 15.0000}, 19.4535},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 3.1736, 0.5854}, 1.0000},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 3.2972, 0.0000}, 1.0000},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 1.8634, 0.5757}, 1.0000},
    {{50.0000, 2.5000, 0.0000}, {50.0000, 3.2592, 0.3350}, 1.0000},
    {{60.2574, -34.0099, 36.2677}, {60.4626, -34.1751, 39.4387}, 1.2644},
    {{63.0109, -31.0961, -5.8663}, {62.8187, -29.7946, -4.0864}, 1.2630},
    {{61.2901, 3.7196, -5.3901}, {61.4292, 2.2480, -4.9620}, 1.8731},
    {{35.0831, -44.1164, 3.7933}, {35.0232, -40.0716, 1.5901}, 1.8645},
    {{22.7233, 20.0904, -46.6940}, {23.0331, 14.9730, -42.5619}, 2.0373},
    {{36.4612, 47.8580, 18.3852}, {36.2715, 50.5065, 21.2231}, 1.4146},
    {{90.8027, -2.0831, 1.4410}, {91.1528, -1.6435, 0.0447}, 1.4441},
    {{90.9257, -0.5406, -0.9208}, {88.6381, -0.8985, -0.7239}, 1.5381},
    {{6.7747, -0.2908, -2.4247}, {5.8714, -0.0985, -2.2286}, 0.6377},
    {{2.0776, 0.0795, -1.1350}, {0.9033, -0.0636, -0.5514}, 0.9082},
};

}  // namespace

TEST(DeltaE2000, SharmaWuDalal2005TestData) {
    for (int i = 0; i < 34; ++i) {
        const Pair& p = kSharma2005[i];
        // The published values are rounded to 4 decimals.
        EXPECT_NEAR(deltaE2000(p.lab1, p.lab2), p.deltaE, 1e-4) << "pair " << i + 1;
    }
}

TEST(DeltaE2000, IsSymmetric) {
    for (int i = 0; i < 34; ++i) {
        const Pair& p = kSharma2005[i];
        EXPECT_NEAR(deltaE2000(p.lab1, p.lab2), deltaE2000(p.lab2, p.lab1), 1e-12) << "pair " << i + 1;
    }
}

TEST(DeltaE2000, IdenticalColoursHaveNoDifference) {
    for (const Pair& p : kSharma2005) EXPECT_EQ(deltaE2000(p.lab1, p.lab1), 0.0);
    EXPECT_EQ(deltaE2000(glm::dvec3(50.0, 0.0, 0.0), glm::dvec3(50.0, 0.0, 0.0)), 0.0);
}

TEST(DeltaE2000, MatchesColourScience) {
    std::ifstream in(std::filesystem::path(METAMER_TEST_DATA_DIR) / "color" / "colorimetry" / "delta_e2000.txt");
    ASSERT_TRUE(in);
    int rows = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        glm::dvec3 a, b;
        double expected;
        ASSERT_TRUE(s >> a.x >> a.y >> a.z >> b.x >> b.y >> b.z >> expected) << line;
        EXPECT_NEAR(deltaE2000(a, b), expected, 1e-9 * std::max(1.0, expected)) << line;
        ++rows;
    }
    EXPECT_GE(rows, 38);
}

TEST(DeltaE76, IsEuclidean) {
    EXPECT_DOUBLE_EQ(deltaE76(glm::dvec3(50.0, 0.0, 0.0), glm::dvec3(53.0, 4.0, 12.0)), 13.0);
    // Sharma pair 1: √(2.6772² + 2.9734²).
    EXPECT_NEAR(deltaE76(kSharma2005[0].lab1, kSharma2005[0].lab2), 4.0011, 1e-4);
}
