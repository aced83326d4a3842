// The resampling rule of spectral/resampling.h, rule by rule, with known answers. Sprague against
// colour-science: tests/data/spectral/sprague_reference.csv (tests/reference/make_sprague_reference.py).
#include "spectral/resampling.h"

#include "support/scene_builders.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

using namespace metamer;

namespace {

Spectrum sampled(std::vector<double> nm, std::vector<double> v) { return test::sampledSpectrum(nm, v, "test"); }

Grid withRule(Grid g, Resampling r) {
    g.resampling = r;
    return g;
}

// Tabulated data with a kink at every sample (values drawn at random), every `step` nm.
Spectrum kinked(double start, double end, double step, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    std::vector<double> nm, v;
    for (int i = 0; start + i * step <= end + 1e-9; ++i) {
        nm.push_back(start + i * step);
        v.push_back(u(rng));
    }
    return sampled(nm, v);
}

// A narrow emission line (FWHM ≈ 0.47 nm) sampled every 0.1 nm at wavelengths ending in .x6, so
// that no band centre of the grids below is a data point.
Spectrum line(double centre, double sigma = 0.2) {
    std::vector<double> nm, v;
    for (int k = -50; k <= 50; ++k) {
        const double l = centre + 0.1 * k;
        nm.push_back(l);
        v.push_back(std::exp(-0.5 * std::pow((l - centre) / sigma, 2)));
    }
    return sampled(nm, v);
}

}  // namespace

TEST(Resample, TabulatedValuesOnTheDataGridAreCopiedBitForBit) {
    // Every band, the first and the last included, is the data value itself, under both
    // interpolating rules; on a 10 nm grid over 5 nm data every other value.
    for (double step : {1.0, 5.0, 10.0}) {
        const Spectrum s = kinked(300, 740, step, unsigned(step));
        for (Resampling rule : {Resampling::Interpolate, Resampling::Sprague}) {
            const std::vector<double> v = resample(s, withRule(Grid{300, 740, step}, rule));
            ASSERT_EQ(v.size(), s.values.size());
            for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], s.values[i]) << step << " nm, band " << i;
        }
    }
    const Spectrum five = kinked(380, 780, 5, 7);
    const std::vector<double> v = resample(five, Grid{380, 780, 10});
    for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], five.values[2 * i]);
    // Band centres that are start + i·step with rounding still find their data point.
    const Spectrum tenth = kinked(400.1, 401.0, 0.1, 3);
    const std::vector<double> t = resample(tenth, Grid{400.5, 400.5, 0.5});
    EXPECT_EQ(t[0], tenth.values[4]);
}

TEST(Resample, BandMeansWouldHaveChangedEveryKinkedBand) {
    // The reason for the rule: the old band mean of the same data moves every band by about a
    // quarter of the kink (and the first band is 3/4 of its value + the held end).
    const Spectrum s = kinked(300, 740, 5, 5);
    const std::vector<double> mean = resample(s, withRule(Grid{300, 740, 5}, Resampling::BandMean));
    int moved = 0;
    for (size_t i = 1; i + 1 < mean.size(); ++i) moved += mean[i] != s.values[i];
    EXPECT_GT(moved, 80);
    // The band mean over [c − 2.5, c + 2.5] of a piecewise-linear function through the data:
    // (v₋ + 6·v + v₊)/8.
    EXPECT_NEAR(mean[10], (s.values[9] + 6 * s.values[10] + s.values[11]) / 8, 1e-15);
}

TEST(Resample, FinerOrOffsetGridsTakeTheLinearInterpolant) {
    const Spectrum s = kinked(380, 780, 5, 11);
    for (const Grid& g : {Grid{380, 780, 1}, Grid{382.5, 777.5, 5}, Grid{381, 776, 5}, Grid{380.25, 779.75, 0.5}}) {
        const std::vector<double> v = resample(s, g);
        for (int i = 0; i < g.bands(); ++i) ASSERT_NEAR(v[size_t(i)], s.at(g.wavelength(i)), 1e-15) << g.str() << " " << i;
    }
    // Linear data are reproduced by every rule.
    const Spectrum ramp = sampled({300, 800}, {0.0, 1.0});
    for (Resampling rule : {Resampling::Interpolate, Resampling::Sprague, Resampling::BandMean}) {
        const Grid g = withRule(Grid{400, 700, 7.5}, rule);
        const std::vector<double> v = resample(ramp, g);
        for (int i = 0; i < g.bands(); ++i) EXPECT_NEAR(v[size_t(i)], (g.wavelength(i) - 300) / 500, 1e-12);
    }
}

TEST(Resample, CoarserGridsTakeTheBandMeanSoANarrowLineKeepsItsEnergy) {
    // The sum of band values × step equals the line's integral, whatever the step, when no band
    // centre falls on one of its data points.
    const Spectrum l = line(404.66);
    const double area = l.integral();
    for (double step : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0}) {
        const Grid g{300, 800, step};
        const std::vector<double> v = resample(l, g);
        double sum = 0;
        for (double x : v) sum += x * step;
        EXPECT_NEAR(sum, area, 1e-9 * area) << "step " << step;
        int meanBands = 0;
        for (int i = 0; i < g.bands(); ++i) meanBands += bandRule(l.wavelengths_nm, g, i) == BandRule::BandMean;
        EXPECT_GT(meanBands, 0);
    }
}

TEST(Resample, ACentreOnADataPointReadsThatPointEvenOnACoarseGrid) {
    // The coincidence rule comes first (no rule invents a value for a band centred on a tabulated
    // point): a line whose peak is a band centre of a 10 nm grid is point-sampled there.
    const Spectrum l = sampled({549.5, 550, 550.5}, {0, 1, 0});
    const Grid g{500, 600, 10};
    const std::vector<double> v = resample(l, g);
    EXPECT_EQ(v[5], 1.0);
    EXPECT_EQ(bandRule(l.wavelengths_nm, g, 5), BandRule::Tabulated);
    // Band means keep its energy (0.5 nm·1 over a 10 nm band).
    EXPECT_DOUBLE_EQ(resample(l, withRule(g, Resampling::BandMean))[5], 0.05);
}

TEST(Resample, BandsOutsideTheDataAreZeroAndBandMeansHoldTheEndValue) {
    const Spectrum s = sampled({380, 780}, {0.5, 0.5});
    for (Resampling rule : {Resampling::Interpolate, Resampling::BandMean}) {
        const std::vector<double> v = resample(s, withRule(Grid{300, 740, 5}, rule));
        EXPECT_EQ(v[0], 0.0);                       // 300 nm: outside
        EXPECT_EQ(v[(375 - 300) / 5], 0.0);         // 375 nm: no data in the band
        EXPECT_DOUBLE_EQ(v[(380 - 300) / 5], 0.5);  // 380 nm: a data point / the end value held
        EXPECT_DOUBLE_EQ(v[(740 - 300) / 5], 0.5);
    }
    // A band mean across the data's end holds the end value when the centre is inside.
    const Spectrum fine = kinked(380, 400, 0.5, 2);
    const std::vector<double> m = resample(fine, Grid{381.25, 391.25, 5});
    EXPECT_NEAR(m[0], (fine.integrate(380, 383.75) + fine.values.front() * 1.25) / 5, 1e-15);
}

TEST(Resample, ConstantIsPreservedOnEveryGridAndRule) {
    for (Resampling rule : {Resampling::Interpolate, Resampling::Sprague, Resampling::BandMean})
        for (double step : {0.5, 1.0, 5.0, 50.0}) {
            for (double x : resample(Spectrum::makeConstant(0.37), withRule(Grid{300, 700, step}, rule)))
                EXPECT_EQ(x, 0.37);
            for (double x : resample(sampled({200, 2500}, {2.0, 2.0}), withRule(Grid{300, 700, step}, rule)))
                EXPECT_NEAR(x, 2.0, 1e-12);
        }
}

TEST(Resample, WeightsAreLinearInTheValues) {
    // What textures and matrices rely on: bandWeights(w)·v is resample of (w, v).
    const Spectrum s = kinked(400, 700, 5, 9);
    for (Resampling rule : {Resampling::Interpolate, Resampling::Sprague, Resampling::BandMean})
        for (const Grid& g0 : {Grid{300, 740, 5}, Grid{401, 699, 2}, Grid{300, 740, 20}}) {
            const Grid g = withRule(g0, rule);
            const std::vector<double> a = resample(s, g), b = bandWeights(s.wavelengths_nm, g).apply(s.values);
            for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]);
        }
}

TEST(Resample, SpragueMatchesColourScience) {
    // colour-science 0.4.7's SpragueInterpolator on the same data, at 1 nm and at offset points.
    std::ifstream in(std::string(METAMER_TEST_DATA_DIR) + "/spectral/sprague_reference.csv");
    ASSERT_TRUE(in) << "missing tests/data/spectral/sprague_reference.csv";
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line, "set,kind,wavelength_nm,value");
    std::map<std::string, std::vector<double>> dataNm, dataV, atNm, atV;
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::string set, kind, a, b;
        std::getline(ss, set, ',');
        std::getline(ss, kind, ',');
        std::getline(ss, a, ',');
        std::getline(ss, b, ',');
        auto& nm = kind == "data" ? dataNm[set] : atNm[set];
        auto& v = kind == "data" ? dataV[set] : atV[set];
        nm.push_back(std::stod(a));
        v.push_back(std::stod(b));
    }
    ASSERT_GE(dataNm.size(), 2u);
    for (const auto& [set, nm] : dataNm) {
        const Spectrum s = sampled(nm, dataV[set]);
        double worst = 0;
        for (size_t k = 0; k < atNm[set].size(); ++k) {
            const double x = atNm[set][k];
            const Grid g = withRule(Grid{x, x, 1.0}, Resampling::Sprague);
            const double ours = resample(s, g)[0];
            worst = std::max(worst, std::fabs(ours - atV[set][k]));
        }
        double peak = 0;
        for (double v : dataV[set]) peak = std::max(peak, std::fabs(v));
        std::printf("  Sprague %s: %zu points, worst |ours − colour-science| %.3g (peak %.3g)\n", set.c_str(),
                    atNm[set].size(), worst, peak);
        EXPECT_LE(worst, 1e-12 * peak) << set;
    }
}

TEST(Resample, SpragueFallsBackToLinearForNonUniformOrShortData) {
    const Spectrum uneven = sampled({400, 410, 425, 430, 450, 470, 480}, {0.1, 0.5, 0.2, 0.9, 0.4, 0.6, 0.3});
    const Spectrum shortData = sampled({400, 410, 420, 430, 440}, {0.1, 0.5, 0.2, 0.9, 0.4});
    for (const Spectrum& s : {uneven, shortData}) {
        const Grid g = withRule(Grid{401, 439, 1}, Resampling::Sprague);
        const std::vector<double> v = resample(s, g);
        for (int i = 0; i < g.bands(); ++i) EXPECT_NEAR(v[size_t(i)], s.at(g.wavelength(i)), 1e-15);
    }
}

TEST(Resample, RulesAreNamedAndParsed) {
    for (Resampling r : {Resampling::Interpolate, Resampling::Sprague, Resampling::BandMean})
        EXPECT_EQ(parseResampling(resamplingName(r), Where{}), r);
    try {
        parseResampling("band_mean", Where{"s.json", "grid.resample"});
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("s.json: grid.resample"), std::string::npos) << what;
        EXPECT_NE(what.find("did you mean 'band-mean'"), std::string::npos) << what;
    }
}
