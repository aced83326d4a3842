// Chromatic adaptation: the cone matrices against their publications, the white-to-white
// property, Lindbloom's D65→D50 Bradford matrix, and every transform against colour-science
// (tests/data/color/colorimetry/adaptation.txt, written by generate.py there).
#include "color/adaptation.h"

#include "color/srgb.h"

#include <gtest/gtest.h>

#include <glm/matrix.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

using namespace metamer;

namespace {

// Compares a glm matrix (m[column][row]) with a table printed row by row.
void expectRows(const glm::dmat3& m, const double (&rows)[3][3], double tolerance, const std::string& what) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c][r], rows[r][c], tolerance) << what << " row " << r << " col " << c;
}

const Adaptation kAll[] = {Adaptation::None,     Adaptation::VonKriesXyz, Adaptation::VonKriesLms,
                           Adaptation::Bradford, Adaptation::Cat02,       Adaptation::Cat16};

// Lindbloom's (brucelindbloom.com, "Chromatic Adaptation") white points, Y = 1.
const glm::dvec3 kD50Lindbloom{0.96422, 1.0, 0.82521};

}  // namespace

TEST(Adaptation, ConeMatricesMatchPublishedTables) {
    // Lam (1985) as given in ICC.1 Annex E and by Lindbloom.
    const double bradford[3][3] = {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};
    // CIE 159:2004, M_CAT02.
    const double cat02[3][3] = {{0.7328, 0.4296, -0.1624}, {-0.7036, 1.6975, 0.0061}, {0.0030, 0.0136, 0.9834}};
    // Li et al. (2017), M16.
    const double cat16[3][3] = {{0.401288, 0.650173, -0.051461},
                                {-0.250268, 1.204414, 0.045854},
                                {-0.002079, 0.048952, 0.953127}};
    // Hunt–Pointer–Estévez normalized to D65 (Lindbloom's "Von Kries").
    const double hpe[3][3] = {{0.40024, 0.70760, -0.08081}, {-0.22630, 1.16532, 0.04570}, {0.0, 0.0, 0.91822}};
    const double identity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    expectRows(catConeMatrix(Adaptation::Bradford), bradford, 1e-4, "Bradford");
    expectRows(catConeMatrix(Adaptation::Cat02), cat02, 1e-4, "CAT02");
    expectRows(catConeMatrix(Adaptation::Cat16), cat16, 1e-4, "CAT16");
    expectRows(catConeMatrix(Adaptation::VonKriesLms), hpe, 1e-4, "HPE");
    expectRows(catConeMatrix(Adaptation::VonKriesXyz), identity, 0.0, "XYZ scaling");
    expectRows(catConeMatrix(Adaptation::None), identity, 0.0, "none");
}

TEST(Adaptation, HpeIsNormalizedToD65) {
    // The normalization that "vonkries" uses: D65 gives equal cone responses (to the table's
    // 5 digits). Rescaling rows does not change adaptationMatrix; this pins which table it is.
    glm::dvec3 lms = catConeMatrix(Adaptation::VonKriesLms) * kD65WhiteXyz;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(lms[i], 1.0, 3e-4) << i;
    // And it is the equal-energy-normalized HPE of CIECAM97s (Hunt; Fairchild, Color Appearance
    // Models) up to a scale per row.
    const double hpeE[3][3] = {{0.38971, 0.68898, -0.07868}, {-0.22981, 1.18340, 0.04641}, {0.0, 0.0, 1.0}};
    glm::dmat3 m = catConeMatrix(Adaptation::VonKriesLms);
    for (int r = 0; r < 3; ++r) {
        double scale = m[r][r] / hpeE[r][r];
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c][r], scale * hpeE[r][c], 2e-5) << r << "," << c;
    }
}

TEST(Adaptation, NoneIsIdentity) {
    glm::dmat3 m = adaptationMatrix(Adaptation::None, glm::dvec3(1.0985, 1.0, 0.35585), kD65WhiteXyz);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_EQ(m[c][r], c == r ? 1.0 : 0.0);
}

TEST(Adaptation, SourceWhiteMapsToDestinationWhite) {
    const glm::dvec3 whites[] = {kD65WhiteXyz, kD50Lindbloom, glm::dvec3(1.09850, 1.0, 0.35585) /* A */,
                                 glm::dvec3(1.0), glm::dvec3(0.9, 1.0, 1.3)};
    for (Adaptation a : kAll) {
        if (a == Adaptation::None) continue;
        for (const auto& s : whites)
            for (const auto& d : whites) {
                glm::dvec3 out = adaptationMatrix(a, s, d) * s;
                for (int i = 0; i < 3; ++i) EXPECT_NEAR(out[i], d[i], 1e-12) << adaptationName(a);
            }
    }
}

TEST(Adaptation, BradfordD65ToD50MatchesLindbloom) {
    // Lindbloom's published Bradford matrix from D65 (0.95047, 1, 1.08883) to D50.
    const double lindbloom[3][3] = {{1.0478112, 0.0228866, -0.0501270},
                                    {0.0295424, 0.9904844, -0.0170491},
                                    {-0.0092345, 0.0150436, 0.7521316}};
    expectRows(adaptationMatrix(Adaptation::Bradford, kD65WhiteXyz, kD50Lindbloom), lindbloom, 1e-4, "D65→D50");
}

TEST(Adaptation, MatchesColourScienceVonKries) {
    std::ifstream in(std::filesystem::path(METAMER_TEST_DATA_DIR) / "color" / "colorimetry" / "adaptation.txt");
    ASSERT_TRUE(in);
    int rows = 0;
    std::set<std::string> seen;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::string name;
        glm::dvec3 ws, wd, xyz, expected;
        ASSERT_TRUE(s >> name >> ws.x >> ws.y >> ws.z >> wd.x >> wd.y >> wd.z >> xyz.x >> xyz.y >> xyz.z >>
                    expected.x >> expected.y >> expected.z)
            << line;
        Adaptation a = parseAdaptation(name, Where{});
        glm::dvec3 out = adaptationMatrix(a, ws, wd) * xyz;
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(out[i], expected[i], 1e-9) << line;
        seen.insert(name);
        ++rows;
    }
    EXPECT_EQ(seen.size(), 5u);  // every transform but None
    EXPECT_GE(rows, 60);
}

TEST(Adaptation, NamesRoundTrip) {
    for (Adaptation a : kAll) EXPECT_EQ(parseAdaptation(adaptationName(a), Where{}), a);
    EXPECT_EQ(adaptationName(Adaptation::VonKriesLms), "vonkries");
    EXPECT_EQ(adaptationName(Adaptation::VonKriesXyz), "vonkries-xyz");
}

TEST(Adaptation, UnknownNameIsAnInputErrorWithSuggestion) {
    try {
        parseAdaptation("bradfrod", Where{"scene.json", "output.adaptation"});
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        std::string what = e.what();
        EXPECT_NE(what.find("scene.json"), std::string::npos) << what;
        EXPECT_NE(what.find("output.adaptation"), std::string::npos) << what;
        EXPECT_NE(what.find("did you mean 'bradford'"), std::string::npos) << what;
        EXPECT_NE(what.find("cat16"), std::string::npos) << "lists the choices: " << what;
    }
    try {
        parseAdaptation("ciecam", Where{"", "adaptation"});
        FAIL() << "no error";
    } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_EQ(what.find("did you mean"), std::string::npos) << what;
        EXPECT_NE(what.find("none, vonkries-xyz, vonkries, bradford, cat02, cat16"), std::string::npos) << what;
    }
}
