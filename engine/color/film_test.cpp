#include "color/film.h"
#include "color/detector_registry.h"
#include "spectral/resampling.h"

#include "color/camera_characterization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

using namespace metamer;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const Grid kGrid{300, 740, 5};
constexpr double kPi = 3.14159265358979323846;

// Radiance of a perfect white diffuser under the library illuminant `name` (scale 0.01, so D65
// gives 1 W·m⁻²·nm⁻¹ at 560 nm): E/π.
std::vector<double> whiteRadiance(const std::string& name, const Grid& g = kGrid) {
    std::vector<double> e = resample(library().get("illuminants/" + name, Where{}), g);
    for (double& v : e) v *= 0.01 / kPi;
    return e;
}

std::vector<double> scaled(std::vector<double> v, double k) {
    for (double& x : v) x *= k;
    return v;
}

glm::dvec2 chromaticity(const glm::dvec3& xyz) { return glm::dvec2(xyz.x, xyz.y) / (xyz.x + xyz.y + xyz.z); }

// The lamp's own chromaticity, from the model's projection weights with no film.
glm::dvec2 lampChromaticity(const FilmModel& f) {
    glm::dvec3 xyz(0.0);
    for (size_t b = 0; b < f.baseDensity.size(); ++b)
        for (int c = 0; c < 3; ++c) xyz[c] += f.projection[c][b];
    return chromaticity(xyz);
}

FilmModel reversal(const std::string& light = "D65", const Grid& g = kGrid, Integration i = Integration::Riemann) {
    return makeFilm("reversal", library(), g, i, whiteRadiance(light, g));
}

}  // namespace

TEST(Film, CurveIsSmoothMonotoneAndBounded) {
    FilmCurve c{0.08, 3.3, -1.1, 1.6, 0.2};
    double previous = std::numeric_limits<double>::infinity();
    for (double x = -12.0; x <= 10.0; x += 0.001) {
        double d = filmCurveDensity(c, x);
        // Reversal: less dye with more light; strictly so until the curve is within a rounding
        // error of its floor or ceiling (a few log units beyond the toe and the shoulder).
        if (x > -4.0 && x < 3.0)
            ASSERT_LT(d, previous) << x;
        else
            ASSERT_LE(d, previous) << x;
        ASSERT_GE(d, c.dMin) << x;
        ASSERT_LE(d, c.dMax) << x;
        previous = d;
    }
    EXPECT_EQ(filmCurveDensity(c, -std::numeric_limits<double>::infinity()), c.dMax);
    EXPECT_EQ(filmCurveDensity(c, std::numeric_limits<double>::infinity()), c.dMin);
    EXPECT_NEAR(filmCurveDensity(c, -300.0), c.dMax, 1e-12);  // no cancellation far out
    EXPECT_NEAR(filmCurveDensity(c, 300.0), c.dMin, 1e-12);
    EXPECT_TRUE(std::isnan(filmCurveDensity(c, std::nan(""))));
}

TEST(Film, CurveMiddleIsHalfwayWithSlopeMinusGamma) {
    for (FilmCurve c : {FilmCurve{0.08, 3.3, -1.1, 1.6, 0.2}, FilmCurve{0.1, 1.0, 0.5, 0.7, 0.3},
                        FilmCurve{0.0, 3.0, 0.0, 1.8, 0.05}}) {
        EXPECT_NEAR(filmCurveDensity(c, c.logH0), 0.5 * (c.dMin + c.dMax), 1e-12);
        double h = 1e-5;
        double slope = (filmCurveDensity(c, c.logH0 + h) - filmCurveDensity(c, c.logH0 - h)) / (2 * h);
        EXPECT_NEAR(slope, -c.gamma, 1e-7);
    }
}

TEST(Film, LoadsWithTheLibraryDescription) {
    FilmModel f = reversal();
    EXPECT_EQ(f.name, "reversal");
    EXPECT_EQ(f.layers.kind, DetectorKind::Film);
    EXPECT_EQ(f.layers.channels, (std::vector<std::string>{"blue", "green", "red"}));
    EXPECT_EQ(f.balanceIlluminant, "illuminants/D65");
    EXPECT_EQ(f.lamp, "film/reversal_lamp");
    ASSERT_EQ(f.dyeDensity.size(), 3u);
    ASSERT_EQ(f.projection.size(), 3u);
    const size_t n = static_cast<size_t>(kGrid.bands());
    EXPECT_EQ(f.baseDensity.size(), n);
    // Published typical figures the model is built to (spectra/README.md, "Film").
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(f.dyeDensity[i].size(), n);
        EXPECT_GT(f.curves[i].dMax, 2.5);
        EXPECT_LT(f.curves[i].dMax, 3.5);
        EXPECT_GT(f.curves[i].gamma, 1.2);
        EXPECT_LT(f.curves[i].gamma, 1.8);
    }
    // Dye peaks: yellow 440–450 nm, magenta 540–560 nm, cyan 650–680 nm.
    auto peak = [&](int i) {
        size_t best = 0;
        for (size_t b = 0; b < n; ++b)
            if (f.dyeDensity[i][b] > f.dyeDensity[i][best]) best = b;
        return kGrid.wavelength(static_cast<int>(best));
    };
    EXPECT_GE(peak(0), 440);
    EXPECT_LE(peak(0), 450);
    EXPECT_GE(peak(1), 540);
    EXPECT_LE(peak(1), 560);
    EXPECT_GE(peak(2), 650);
    EXPECT_LE(peak(2), 680);
    // Clear film: total visual density Dmin + base in the published 0.1–0.2.
    double clear = -std::log10(f.projectedWhiteY / f.openGateY);
    EXPECT_GT(clear, 0.1);
    EXPECT_LT(clear, 0.2);
}

TEST(Film, DetectorSpecGivesTheLayers) {
    Detector d = makeDetector("film:reversal", library(), kGrid, Integration::Trapezoid, Where{});
    FilmModel f = reversal("D65", kGrid, Integration::Trapezoid);
    EXPECT_EQ(d.name, "film:reversal");
    EXPECT_EQ(d.channels, f.layers.channels);
    EXPECT_EQ(d.weights, f.layers.weights);
    EXPECT_EQ(filmNames(library()), std::vector<std::string>{"reversal"});
}

TEST(Film, WhiteIsNearlyClearAndLampColoured) {
    FilmModel f = reversal();
    std::vector<double> white = whiteRadiance("D65");
    glm::dvec3 h = filmExposures(f, white.data());
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(h[i] / f.exposureOfWhite[i], 1.0, 1e-12);  // x = 0
    glm::dvec3 d = filmDensitiesFromExposures(f, h);
    glm::dvec3 xyz = filmXyz(f, white.data());
    // On the toe, a little above Dmin: a slide of a white card is nearly clear. Relative to the
    // clear film (Y = 1) it loses less than 0.1 in density; relative to the open gate its Y is
    // 10^-(Dmin + base) times that.
    for (int i = 0; i < 3; ++i) {
        EXPECT_GT(d[i], f.curves[i].dMin) << i;
        EXPECT_LT(d[i] - f.curves[i].dMin, 0.1) << i;
    }
    EXPECT_LT(xyz.y, 1.0);
    EXPECT_GT(xyz.y, std::pow(10.0, -0.1));
    double clearTransmittance = f.projectedWhiteY / f.openGateY;  // 10^-(Dmin + base), visual
    EXPECT_NEAR(std::log10(xyz.y * clearTransmittance), std::log10(clearTransmittance), 0.1);
    // Balanced for D65: the white projects with (nearly) the lamp's colour.
    glm::dvec2 lamp = lampChromaticity(f), w = chromaticity(xyz);
    EXPECT_NEAR(w.x, lamp.x, 0.003);
    EXPECT_NEAR(w.y, lamp.y, 0.003);
    std::printf("    white: D = %.3f %.3f %.3f, Y = %.3f of the clear film, xy %.4f %.4f (lamp %.4f %.4f); "
                "clear film %.3f of the open gate\n",
                d[0], d[1], d[2], xyz.y, w.x, w.y, lamp.x, lamp.y, clearTransmittance);
}

TEST(Film, MidGreyFallsOnTheStraightPart) {
    FilmModel f = reversal();
    // An 18% grey seen next to a 90% white: exposure 0.2 of the white's, x = −0.70.
    std::vector<double> grey = scaled(whiteRadiance("D65"), 0.2);
    glm::dvec3 d = filmDensitiesFromExposures(f, filmExposures(f, grey.data()));
    for (int i = 0; i < 3; ++i) {
        const FilmCurve& c = f.curves[i];
        double t = (d[i] - c.dMin) / (c.dMax - c.dMin);
        EXPECT_GT(t, 0.2) << i;  // well off the toe ...
        EXPECT_LT(t, 0.5) << i;  // ... and on the light side of the middle (x = logH0 = −1.1)
    }
    glm::dvec3 xyz = filmXyz(f, grey.data());
    EXPECT_GT(-std::log10(xyz.y), 0.7);  // the slide's higher contrast: darker than the 0.2 it was
    EXPECT_LT(-std::log10(xyz.y), 1.3);
    std::printf("    18%% grey: D = %.3f %.3f %.3f, Y = %.3f of the clear film\n", d[0], d[1], d[2], xyz.y);
}

TEST(Film, LessLightMeansMoreDensity) {
    FilmModel f = reversal();
    std::vector<double> white = whiteRadiance("D65");
    // A non-neutral patch too: the layers respond separately.
    std::vector<double> red = resample(library().get("colorchecker/red", Where{}), kGrid);
    for (size_t b = 0; b < red.size(); ++b) red[b] *= white[b];
    for (const auto* base : {&white, &red}) {
        glm::dvec3 previousD(-1.0);
        double previousY = std::numeric_limits<double>::infinity();
        for (int k = 4; k >= -16; --k) {  // 16× over to 65536× under the white
            std::vector<double> l = scaled(*base, std::pow(2.0, k));
            glm::dvec3 d = filmDensitiesFromExposures(f, filmExposures(f, l.data()));
            for (int i = 0; i < 3; ++i) EXPECT_GT(d[i], previousD[i]) << "2^" << k << " layer " << i;
            double y = filmXyz(f, l.data()).y;
            EXPECT_LT(y, previousY) << "2^" << k;
            previousD = d;
            previousY = y;
        }
    }
}

TEST(Film, BlackGivesDMax) {
    FilmModel f = reversal();
    std::vector<double> black(kGrid.bands(), 0.0);
    glm::dvec3 d = filmDensitiesFromExposures(f, filmExposures(f, black.data()));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(d[i], f.curves[i].dMax);
    glm::dvec3 xyz = filmXyz(f, black.data());
    EXPECT_GT(xyz.y, 0.0);  // a real slide's Dmax still passes a little light
    EXPECT_GT(-std::log10(xyz.y), 2.9);
    std::printf("    black: Y = %.2e of the clear film (density %.2f), xy %.3f %.3f\n", xyz.y, -std::log10(xyz.y),
                chromaticity(xyz).x, chromaticity(xyz).y);
    // A very deep shadow is within 0.01 of it.
    glm::dvec3 deep = filmDensitiesFromExposures(f, filmExposures(f, scaled(whiteRadiance("D65"), 1e-4).data()));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(deep[i], f.curves[i].dMax, 0.01);
}

TEST(Film, ChangingTheLightFromD65ToAChangesTheColour) {
    // Films do not adapt: a daylight film exposed under tungsten light renders its white orange.
    FilmModel d65 = reversal("D65"), a = reversal("A");
    glm::dvec3 whiteD65 = filmXyz(d65, whiteRadiance("D65").data());
    glm::dvec3 whiteA = filmXyz(a, whiteRadiance("A").data());
    glm::dvec2 cd = chromaticity(whiteD65), ca = chromaticity(whiteA);
    EXPECT_GT(ca.x - cd.x, 0.02);  // redder
    EXPECT_GT(ca.y - cd.y, 0.01);  // and yellower: the blue layer is underexposed, more yellow dye
    // Metering on the green layer keeps the exposure level: the white stays light.
    EXPECT_GT(whiteA.y, 0.5);
    // The blue layer of the A white is underexposed relative to the film's white point.
    glm::dvec3 hA = filmExposures(a, whiteRadiance("A").data());
    EXPECT_LT(hA.x / a.exposureOfWhite.x, 0.5);
    EXPECT_NEAR(hA.y / a.exposureOfWhite.y, 1.0, 1e-12);
    // Every ColorChecker patch shifts, not only the white.
    for (const auto& n : colorCheckerPatchNames()) {
        std::vector<double> rho = resample(library().get("colorchecker/" + n, Where{}), kGrid);
        std::vector<double> lD65 = whiteRadiance("D65"), lA = whiteRadiance("A");
        for (size_t b = 0; b < rho.size(); ++b) {
            lD65[b] *= rho[b];
            lA[b] *= rho[b];
        }
        glm::dvec2 pd = chromaticity(filmXyz(d65, lD65.data())), pa = chromaticity(filmXyz(a, lA.data()));
        EXPECT_GT(glm::length(pa - pd), 0.005) << n;
    }
    std::printf("    white under D65 xy %.4f %.4f, under A xy %.4f %.4f (Y %.3f)\n", cd.x, cd.y, ca.x, ca.y, whiteA.y);
}

TEST(Film, ExposureScalesWithTheReferenceWhite) {
    // Twice the light on the scene and the white: the metered film gives the same slide.
    FilmModel f1 = reversal();
    FilmModel f2 = makeFilm("reversal", library(), kGrid, Integration::Riemann, scaled(whiteRadiance("D65"), 2.0));
    std::vector<double> rho = resample(library().get("colorchecker/blue_sky", Where{}), kGrid);
    std::vector<double> l1 = whiteRadiance("D65");
    for (size_t b = 0; b < rho.size(); ++b) l1[b] *= rho[b];
    std::vector<double> l2 = scaled(l1, 2.0);
    glm::dvec3 x1 = filmXyz(f1, l1.data()), x2 = filmXyz(f2, l2.data());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(x1[c], x2[c], 1e-12);
}

TEST(Film, LoadsOnA1nmGridAndAgreesWithTheDefaultGrid) {
    Grid fine{380, 780, 1};
    for (Integration integ : {Integration::Riemann, Integration::Trapezoid}) {
        FilmModel f = reversal("D65", fine, integ);
        FilmModel f5 = reversal("D65", kGrid, integ);
        std::vector<double> rho = resample(library().get("colorchecker/orange", Where{}), fine);
        std::vector<double> rho5 = resample(library().get("colorchecker/orange", Where{}), kGrid);
        std::vector<double> l = whiteRadiance("D65", fine), l5 = whiteRadiance("D65", kGrid);
        for (size_t b = 0; b < l.size(); ++b) l[b] *= rho[b];
        for (size_t b = 0; b < l5.size(); ++b) l5[b] *= rho5[b];
        glm::dvec3 a = filmXyz(f, l.data()), b = filmXyz(f5, l5.data());
        // Different grids, different discretization (and 380–780 nm drops the film's UV
        // response): close, not equal.
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.01 * b[c] + 1e-3) << integrationName(integ);
    }
}

TEST(Film, ErrorsNameTheFilmOrTheGrid) {
    try {
        makeFilm("reversl", library(), kGrid, Integration::Riemann, whiteRadiance("D65"), Where{"s.json", "output.detector"});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("did you mean 'reversal'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("output.detector"), std::string::npos) << e.what();
    }
    // A near-infrared grid: no layer is exposed and nothing is visible.
    Grid nir{900, 1500, 10};
    try {
        makeFilm("reversal", library(), nir, Integration::Riemann, std::vector<double>(nir.bands(), 1.0));
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("900:1500:10"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("reversal.json"), std::string::npos) << e.what();
    }
}

TEST(Film, MatchesTheIndependentPythonModel) {
    // tests/reference/make_detector_reference.py evaluates the documented chain with numpy from
    // the same JSON and tables: 24 patches, the perfect white and black under D65 and A.
    std::ifstream in(std::string(METAMER_TEST_DATA_DIR) + "/color/detectors/film_reference.csv");
    ASSERT_TRUE(in.good());
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line, "illuminant,patch,X,Y,Z");
    std::map<std::string, FilmModel> films;
    int rows = 0;
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::vector<std::string> f;
        for (std::string field; std::getline(ss, field, ',');) f.push_back(field);
        ASSERT_EQ(f.size(), 5u) << line;
        SCOPED_TRACE(f[0] + " " + f[1]);
        if (!films.count(f[0])) films.emplace(f[0], reversal(f[0]));
        std::vector<double> l = whiteRadiance(f[0]);
        if (f[1] == "black") {
            l.assign(l.size(), 0.0);
        } else if (f[1] != "perfect_white") {
            std::vector<double> rho = resample(library().get("colorchecker/" + f[1], Where{}), kGrid);
            for (size_t b = 0; b < l.size(); ++b) l[b] *= rho[b];
        }
        glm::dvec3 xyz = filmXyz(films.at(f[0]), l.data());
        for (int c = 0; c < 3; ++c) {
            double expected = std::strtod(f[2 + c].c_str(), nullptr);
            EXPECT_NEAR(xyz[c], expected, 1e-10 * (1.0 + expected));
        }
        ++rows;
    }
    EXPECT_EQ(rows, 52);
}
