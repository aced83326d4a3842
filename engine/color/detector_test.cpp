#include "color/detector.h"
#include "color/detector_registry.h"

#include "color/cie_xyz.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <numeric>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const Grid kDefaultGrid{300, 740, 5};
const Grid kFineGrid{380, 780, 1};

std::string dataFile(const std::string& name) {
    return std::string(METAMER_TEST_DATA_DIR) + "/color/detectors/" + name;
}

// Collects warnings while alive.
struct CaptureWarnings {
    CaptureWarnings() : old_(setWarningSink(&CaptureWarnings::sink)) { lines().clear(); }
    ~CaptureWarnings() { setWarningSink(old_); }
    static std::vector<std::string>& lines() {
        static std::vector<std::string> l;
        return l;
    }
    static void sink(const std::string& line) { lines().push_back(line); }
    WarningSink old_;
};

// The input error `f` throws, or a test failure.
template <typename F>
Error inputError(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
        return e;
    }
    ADD_FAILURE() << "expected an input error";
    return Error(ExitCode::Ok, Where{}, "");
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

}  // namespace

TEST(Detector, RiemannWeightIsTheStepInEveryBand) {
    for (const Grid& g : {kDefaultGrid, kFineGrid, Grid{400, 700, 0.5}}) {
        std::vector<double> q = quadratureWeights(g, Integration::Riemann);
        ASSERT_EQ(q.size(), static_cast<size_t>(g.bands()));
        for (double w : q) EXPECT_EQ(w, g.step_nm);
    }
}

TEST(Detector, TrapezoidHalvesOnlyTheEndBands) {
    std::vector<double> q = quadratureWeights(kDefaultGrid, Integration::Trapezoid);
    ASSERT_EQ(q.size(), 89u);
    EXPECT_EQ(q.front(), 2.5);
    EXPECT_EQ(q.back(), 2.5);
    for (size_t b = 1; b + 1 < q.size(); ++b) EXPECT_EQ(q[b], 5.0);
    // Σq spans first centre to last centre; Riemann spans the bands' full extent.
    EXPECT_DOUBLE_EQ(sum(q), 440.0);
    EXPECT_DOUBLE_EQ(sum(quadratureWeights(kDefaultGrid, Integration::Riemann)), 445.0);
    // A one-band grid has no interval between centres: it keeps its band width either way.
    EXPECT_EQ(quadratureWeights(Grid{550, 550, 10}, Integration::Trapezoid), std::vector<double>{10.0});
}

TEST(Detector, TrapezoidIntegratesALinearFunctionExactly) {
    for (const Grid& g : {kDefaultGrid, kFineGrid, Grid{412.5, 687.5, 2.5}}) {
        std::vector<double> q = quadratureWeights(g, Integration::Trapezoid);
        auto f = [](double l) { return 0.37 * l - 20.0; };
        double s = 0.0;
        for (int b = 0; b < g.bands(); ++b) s += q[b] * f(g.wavelength(b));
        auto antiderivative = [](double l) { return 0.185 * l * l - 20.0 * l; };
        double exact = antiderivative(g.end_nm) - antiderivative(g.start_nm);
        EXPECT_NEAR(s, exact, 1e-9 * std::abs(exact)) << g.str();
    }
}

TEST(Detector, ParsesIntegrationNames) {
    EXPECT_EQ(parseIntegration("riemann", Where{}), Integration::Riemann);
    EXPECT_EQ(parseIntegration("trapezoid", Where{}), Integration::Trapezoid);
    EXPECT_EQ(parseIntegration("astm-e308", Where{}), Integration::AstmE308);
    for (Integration i : {Integration::Riemann, Integration::Trapezoid, Integration::AstmE308})
        EXPECT_EQ(parseIntegration(integrationName(i), Where{}), i);
    Error e = inputError([] { parseIntegration("simpson", Where{"", "output.integration"}); });
    EXPECT_TRUE(contains(e.what(), "output.integration")) << e.what();
    EXPECT_TRUE(contains(e.what(), "trapezoid")) << e.what();
    EXPECT_TRUE(contains(e.what(), "astm-e308")) << e.what();
    Error typo = inputError([] { parseIntegration("astm_e308", Where{}); });
    EXPECT_TRUE(contains(typo.what(), "did you mean 'astm-e308'")) << typo.what();
}

TEST(Detector, NamesListObserversThenCamerasThenFilms) {
    std::vector<std::string> names = detectorNames(library());
    std::vector<std::string> expected = {"cie1931", "cie1964", "camera:canon_eos_5d_mark_ii", "camera:nikon_d5100",
                                         "camera:sigma_sd_merrill", "film:reversal"};
    EXPECT_EQ(names, expected);
}

TEST(Detector, EveryBuiltInLoadsOnTheDefaultAndA1nmGrid) {
    for (const Grid& g : {kDefaultGrid, kFineGrid}) {
        for (const auto& spec : detectorNames(library())) {
            SCOPED_TRACE(spec + " on " + g.str());
            Detector d = makeDetector(spec, library(), g, Integration::Riemann, Where{});
            EXPECT_EQ(d.name, spec);
            EXPECT_EQ(d.grid, g);
            ASSERT_EQ(d.channels.size(), 3u);
            ASSERT_EQ(d.weights.size(), 3u);
            std::vector<std::string> expected;
            DetectorKind kind;
            if (spec.rfind("cie", 0) == 0) {
                expected = {"X", "Y", "Z"};
                kind = DetectorKind::Observer;
            } else if (spec.rfind("camera:", 0) == 0) {
                expected = {"R", "G", "B"};
                kind = DetectorKind::Camera;
            } else {
                expected = {"blue", "green", "red"};
                kind = DetectorKind::Film;
            }
            EXPECT_EQ(d.channels, expected);
            EXPECT_EQ(d.kind, kind);
            EXPECT_FALSE(d.units.empty());
            for (const auto& w : d.weights) {
                ASSERT_EQ(w.size(), static_cast<size_t>(g.bands()));
                for (double v : w) EXPECT_GE(v, 0.0);
                EXPECT_GT(sum(w), 0.0);
            }
        }
    }
}

TEST(Detector, Cie1931EqualEnergyGivesTheTableSums) {
    // Σ x̄, ȳ, z̄ of the 1 nm CIE 1931 table (360–830 nm) are 106.865, 106.857, 106.892: a 1 nm
    // grid over the table's range must reproduce them (band averages of 1 nm data sum to the
    // same, up to the two end half-bands).
    Grid g{360, 830, 1};
    Detector d = makeDetector("cie1931", library(), g, Integration::Riemann, Where{});
    std::vector<double> ones(g.bands(), 1.0);
    glm::dvec3 xyz = detectorResponse3(d, ones.data());
    EXPECT_NEAR(xyz.x, 106.865, 0.002);
    EXPECT_NEAR(xyz.y, 106.857, 0.002);
    EXPECT_NEAR(xyz.z, 106.892, 0.002);
    // On the default grid only the negligible 745–830 nm tail is lost.
    Detector d5 = makeDetector("cie1931", library(), kDefaultGrid, Integration::Riemann, Where{});
    std::vector<double> ones5(kDefaultGrid.bands(), 1.0);
    glm::dvec3 xyz5 = detectorResponse3(d5, ones5.data());
    EXPECT_NEAR(xyz5.y, 106.857, 0.01);
    EXPECT_NEAR(xyz5.x, 106.865, 0.05);
    EXPECT_NEAR(xyz5.z, 106.892, 0.05);
}

TEST(Detector, Cie1964EqualEnergyGivesTheTableSum) {
    Grid g{360, 830, 1};
    Detector d = makeDetector("cie1964", library(), g, Integration::Riemann, Where{});
    std::vector<double> ones(g.bands(), 1.0);
    EXPECT_NEAR(detectorResponse3(d, ones.data()).y, 116.661877, 0.002);
}

TEST(Detector, Cie1931WeightsAreTheQuickLookCmfsTimesTheQuadrature) {
    ColorMatchingFunctions cmfs = loadCie1931(library(), kDefaultGrid);
    for (Integration integ : {Integration::Riemann, Integration::Trapezoid}) {
        Detector d = makeDetector("cie1931", library(), kDefaultGrid, integ, Where{});
        std::vector<double> q = quadratureWeights(kDefaultGrid, integ);
        for (int b = 0; b < kDefaultGrid.bands(); ++b) {
            EXPECT_DOUBLE_EQ(d.weights[0][b], cmfs.x[b] * q[b]);
            EXPECT_DOUBLE_EQ(d.weights[1][b], cmfs.y[b] * q[b]);
            EXPECT_DOUBLE_EQ(d.weights[2][b], cmfs.z[b] * q[b]);
        }
    }
}

TEST(Detector, ObserversAreZeroOutside360To830nm) {
    Grid g{200, 1000, 5};
    for (const char* spec : {"cie1931", "cie1964"}) {
        Detector d = makeDetector(spec, library(), g, Integration::Riemann, Where{});
        for (int b = 0; b < g.bands(); ++b) {
            double l = g.wavelength(b);
            // A band reaches the data when it overlaps 360–830 nm (its half-width is 2.5 nm).
            if (l + 2.5 <= 360.0 || l - 2.5 >= 830.0)
                for (int c = 0; c < 3; ++c) EXPECT_EQ(d.weights[c][b], 0.0) << spec << " at " << l;
        }
    }
}

TEST(Detector, ResponseIsTheWeightedSum) {
    Detector d = makeDetector("camera:nikon_d5100", library(), kDefaultGrid, Integration::Riemann, Where{});
    std::vector<double> l(kDefaultGrid.bands());
    for (size_t b = 0; b < l.size(); ++b) l[b] = 0.01 * static_cast<double>(b % 7);
    std::vector<double> r = detectorResponse(d, l.data());
    std::vector<float> lf(l.begin(), l.end());
    glm::dvec3 r3 = detectorResponse3(d, lf.data());
    for (int c = 0; c < 3; ++c) {
        double expected = 0.0;
        for (size_t b = 0; b < l.size(); ++b) expected += d.weights[c][b] * l[b];
        EXPECT_DOUBLE_EQ(r[c], expected);
        EXPECT_NEAR(r3[c], expected, 1e-6 * expected);
    }
}

TEST(Detector, CsvWithOneChannelUsesItsHeaderName) {
    Detector d = makeDetector("csv:" + dataFile("one_channel.csv"), library(), kDefaultGrid, Integration::Riemann, Where{});
    EXPECT_EQ(d.kind, DetectorKind::Custom);
    EXPECT_EQ(d.channels, std::vector<std::string>{"mono"});
    ASSERT_EQ(d.weights.size(), 1u);
    // A flat unit sensitivity over the whole grid: the response to unit radiance is the grid's width.
    std::vector<double> ones(kDefaultGrid.bands(), 1.0);
    EXPECT_NEAR(detectorResponse(d, ones.data())[0], 445.0, 1e-9);
    EXPECT_NEAR(detectorResponse(makeDetector("csv:" + dataFile("one_channel.csv"), library(), kDefaultGrid,
                                              Integration::Trapezoid, Where{}),
                                 ones.data())[0],
                440.0, 1e-9);
}

TEST(Detector, CsvWithFiveChannelsUsesTheHeaderNames) {
    CaptureWarnings warnings;  // the table covers 400–700 nm only
    Detector d = makeDetector("csv:" + dataFile("five_channels.csv"), library(), kFineGrid, Integration::Riemann, Where{});
    std::vector<std::string> expected = {"violet", "blue", "green", "yellow", "red"};
    EXPECT_EQ(d.channels, expected);
    ASSERT_EQ(d.weights.size(), 5u);
    // Each box is ~60 nm wide; a flat unit radiance gives about 60 per channel (the 1 nm ramps
    // between boxes and the ends shave a fraction of a nm).
    std::vector<double> ones(kFineGrid.bands(), 1.0);
    std::vector<double> r = detectorResponse(d, ones.data());
    for (double v : r) EXPECT_NEAR(v, 60.0, 1.0);
    EXPECT_EQ(warnings.lines().size(), 1u);
}

TEST(Detector, CsvWithoutHeaderNumbersTheChannels) {
    Detector d = makeDetector("csv:" + dataFile("no_header.csv"), library(), Grid{400, 700, 5}, Integration::Riemann,
                              Where{});
    EXPECT_EQ(d.channels, (std::vector<std::string>{"ch1", "ch2"}));
}

TEST(Detector, CsvRelativePathIsResolvedFromTheCurrentDirectory) {
    fs::path old = fs::current_path();
    fs::current_path(std::string(METAMER_TEST_DATA_DIR) + "/color");
    Detector d;
    EXPECT_NO_THROW(d = makeDetector("csv:detectors/one_channel.csv", library(), kDefaultGrid, Integration::Riemann,
                                     Where{}));
    fs::current_path(old);
    EXPECT_EQ(d.channels, std::vector<std::string>{"mono"});
    EXPECT_TRUE(fs::path(d.source).is_absolute()) << d.source;
}

TEST(Detector, CsvPartialCoverageWarnsAndIsBlindOutside) {
    CaptureWarnings warnings;
    Detector d = makeDetector("csv:" + dataFile("partial.csv"), library(), kDefaultGrid, Integration::Riemann, Where{});
    ASSERT_EQ(warnings.lines().size(), 1u);
    EXPECT_TRUE(contains(warnings.lines()[0], "partial.csv")) << warnings.lines()[0];
    EXPECT_TRUE(contains(warnings.lines()[0], "500–600 nm")) << warnings.lines()[0];
    for (int b = 0; b < kDefaultGrid.bands(); ++b) {
        double l = kDefaultGrid.wavelength(b);
        if (l < 495 || l > 605) EXPECT_EQ(d.weights[0][b], 0.0) << l;
        if (l >= 500 && l <= 600) EXPECT_DOUBLE_EQ(d.weights[0][b], 5.0) << l;
    }
    // Full coverage: no warning.
    warnings.lines().clear();
    makeDetector("csv:" + dataFile("one_channel.csv"), library(), kDefaultGrid, Integration::Riemann, Where{});
    EXPECT_TRUE(warnings.lines().empty());
}

TEST(Detector, CsvErrorsNameTheFile) {
    struct Case {
        const char* file;
        const char* says;
    };
    for (const Case& c : {Case{"zero_channels.csv", "wavelength_nm,value"}, Case{"nine_channels.csv", "1 to 8"},
                          Case{"not_numeric.csv", "not a finite number"}, Case{"missing.csv", "not found"},
                          Case{"outside.csv", "entirely outside"}}) {
        SCOPED_TRACE(c.file);
        Error e = inputError([&] {
            makeDetector(std::string("csv:") + dataFile(c.file), library(), kDefaultGrid, Integration::Riemann,
                         Where{"", "output.detector"});
        });
        EXPECT_TRUE(contains(e.what(), c.file)) << e.what();
        EXPECT_TRUE(contains(e.what(), c.says)) << e.what();
    }
    Error e = inputError([] { makeDetector("csv:", library(), kDefaultGrid, Integration::Riemann, Where{}); });
    EXPECT_TRUE(contains(e.what(), "csv:PATH")) << e.what();
}

TEST(Detector, UnknownSpecSuggestsTheClosestName) {
    struct Case {
        const char* spec;
        const char* suggestion;
    };
    for (const Case& c : {Case{"cie1913", "cie1931"}, Case{"CIE1964", "cie1964"},
                          Case{"camera:nikon_d5010", "camera:nikon_d5100"}, Case{"camera:nikon", "camera:nikon_d5100"},
                          Case{"film:revrsal", "film:reversal"}, Case{"camera:sigma", "camera:sigma_sd_merrill"}}) {
        SCOPED_TRACE(c.spec);
        Error e = inputError([&] {
            makeDetector(c.spec, library(), kDefaultGrid, Integration::Riemann, Where{"scene.json", "output.detector"});
        });
        EXPECT_TRUE(contains(e.what(), std::string("did you mean '") + c.suggestion + "'")) << e.what();
        EXPECT_TRUE(contains(e.what(), "scene.json")) << e.what();
        EXPECT_TRUE(contains(e.what(), "output.detector")) << e.what();
    }
    Error e = inputError([] { makeDetector("human", library(), kDefaultGrid, Integration::Riemann, Where{}); });
    EXPECT_FALSE(contains(e.what(), "did you mean")) << e.what();
    // The message lists what exists, so a user can pick without reading the docs.
    EXPECT_TRUE(contains(e.what(), "cie1931, cie1964, camera:")) << e.what();
    EXPECT_TRUE(contains(e.what(), "csv:PATH")) << e.what();
}
