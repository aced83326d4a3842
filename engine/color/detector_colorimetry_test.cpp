// The CIE 1931 detector and the colour functions downstream of it against colour-science: the 24
// ColorChecker patches under D65, A and FL2 on the default grid, from the table written by
// tests/reference/make_colorchecker_table.py (which resamples our library files the way
// spectral/spectrum.cpp does, so only the colorimetry is compared).
#include "color/adaptation.h"
#include "color/detector_registry.h"
#include "spectral/resampling.h"
#include "color/camera_characterization.h"
#include "color/delta_e.h"
#include "color/detector.h"
#include "color/display_model.h"
#include "color/lab.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

using namespace metamer;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const Grid kGrid{300, 740, 5};

struct Row {
    std::string illuminant, patch;
    glm::dvec3 xyz, lab, counts;
};

std::vector<Row> readTable() {
    std::string path = std::string(METAMER_TEST_DATA_DIR) + "/color/colorchecker_reference.csv";
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    std::vector<Row> rows;
    std::string line;
    std::getline(in, line);  // header
    EXPECT_EQ(line, "illuminant,patch,X,Y,Z,L,a,b,R8,G8,B8");
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        std::stringstream ss(line);
        std::vector<std::string> f;
        std::string field;
        while (std::getline(ss, field, ',')) f.push_back(field);
        EXPECT_EQ(f.size(), 11u) << line;
        if (f.size() != 11) continue;
        Row r;
        r.illuminant = f[0];
        r.patch = f[1];
        for (int i = 0; i < 3; ++i) {
            r.xyz[i] = std::strtod(f[2 + i].c_str(), nullptr);
            r.lab[i] = std::strtod(f[5 + i].c_str(), nullptr);
            r.counts[i] = std::strtod(f[8 + i].c_str(), nullptr);
        }
        rows.push_back(r);
    }
    return rows;
}

// Our side of the table: XYZ of each patch relative to the perfect diffuser (Y = 100).
struct Ours {
    glm::dvec3 white;                      // Y = 100
    std::map<std::string, glm::dvec3> xyz;
};

Ours compute(const std::string& illuminant) {
    Detector cie = makeDetector("cie1931", library(), kGrid, Integration::Riemann, Where{});
    std::vector<double> e = resample(library().get("illuminants/" + illuminant, Where{}), kGrid);
    Ours o;
    glm::dvec3 w = detectorResponse3(cie, e.data());
    o.white = w * (100.0 / w.y);
    std::vector<double> lit(e.size());
    for (const auto& p : colorCheckerPatchNames()) {
        std::vector<double> rho = resample(library().get("colorchecker/" + p, Where{}), kGrid);
        for (size_t b = 0; b < e.size(); ++b) lit[b] = rho[b] * e[b];
        o.xyz[p] = detectorResponse3(cie, lit.data()) * (100.0 / w.y);
    }
    return o;
}

}  // namespace

TEST(DetectorColorimetry, TableCoversThreeIlluminantsAnd24Patches) {
    std::vector<Row> rows = readTable();
    ASSERT_EQ(rows.size(), 72u);
    std::map<std::string, int> perLight;
    for (const Row& r : rows) ++perLight[r.illuminant];
    EXPECT_EQ(perLight, (std::map<std::string, int>{{"A", 24}, {"D65", 24}, {"FL2", 24}}));
}

TEST(DetectorColorimetry, Cie1931XyzAndLabMatchColourScience) {
    std::map<std::string, Ours> ours;
    double worst = 0.0;
    for (const Row& r : readTable()) {
        SCOPED_TRACE(r.illuminant + " " + r.patch);
        if (!ours.count(r.illuminant)) ours[r.illuminant] = compute(r.illuminant);
        const Ours& o = ours[r.illuminant];
        glm::dvec3 xyz = o.xyz.at(r.patch);
        // Same resampled data, same Riemann sum: XYZ agree to rounding.
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(xyz[i], r.xyz[i], 1e-9 * (1.0 + r.xyz[i]));
        double de = deltaE2000(xyzToLab(xyz, o.white), r.lab);
        EXPECT_LE(de, 0.01);
        worst = std::max(worst, de);
    }
    std::printf("    worst ΔE2000 against colour-science over 72 patches: %.2e\n", worst);
}

TEST(DetectorColorimetry, SrgbCountsAfterBradfordMatchColourScienceWithinOneCount) {
    DisplayModel srgb = parseDisplay("srgb", 8, Where{});
    std::map<std::string, Ours> ours;
    int off = 0;
    for (const Row& r : readTable()) {
        SCOPED_TRACE(r.illuminant + " " + r.patch);
        if (!ours.count(r.illuminant)) ours[r.illuminant] = compute(r.illuminant);
        const Ours& o = ours[r.illuminant];
        glm::dmat3 cat = adaptationMatrix(Adaptation::Bradford, o.white / 100.0, srgb.whiteXyz);
        EncodeResult e = encodeXyz(srgb, cat * (o.xyz.at(r.patch) / 100.0));
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(e.counts[i], r.counts[i], 1.0);
            if (e.counts[i] != r.counts[i]) ++off;
        }
    }
    // Rounding at a half count may differ; more than a few would mean a real difference.
    EXPECT_LE(off, 10);
    std::printf("    sRGB counts differing by one from colour-science: %d of 216\n", off);
}
