#include "sensor/capture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>

using namespace metamer;

namespace {

// A sensor built in code: one channel of constant QE (monochrome) unless `channels` > 1.
SensorSpec testSensor(int channels = 1) {
    SensorSpec s;
    s.fNumber = 2.8;
    s.lensTransmittance = Spectrum::makeConstant(0.9);
    s.pitch_um = 5.0;
    s.fillFactor = 0.8;
    for (int c = 0; c < channels; ++c) {
        s.channels.push_back("c" + std::to_string(c));
        s.quantumEfficiency.push_back(Spectrum::makeConstant(0.5 / (c + 1)));
    }
    if (channels == 1) {
        s.cfa = {{0}};
    } else {
        s.cfa = {{0, 1}, {1, 2 % channels}};
    }
    s.exposure_s = 0.01;
    s.fullWell_e = 1e9;
    s.gain_dn_per_e = 1.0;
    s.adcBits = 16;
    return s;
}

struct Moments {
    double mean = 0.0, variance = 0.0;
};
Moments moments(const std::vector<uint16_t>& v) {
    Moments m;
    for (uint16_t x : v) m.mean += x;
    m.mean /= double(v.size());
    for (uint16_t x : v) m.variance += (x - m.mean) * (x - m.mean);
    m.variance /= double(v.size() - 1);
    return m;
}

}  // namespace

TEST(SensorCapture, TheCameraEquationInPhotons) {
    // Constant radiance L₀ in every band: μe = t · A · π·T/(1 + 4N²(1 + m)²) · QE · Σ λ/(hc) · Δλ · L₀
    // (EMVA 1288 and ISETCam's form), A the pixel's whole area: the QE includes the fill factor.
    const Grid grid{400, 700, 10};
    SpectralCube cube(3, 2, grid);
    std::fill(cube.data.begin(), cube.data.end(), 0.02f);
    SensorSpec s = testSensor();
    const ExpectedElectrons e = expectedElectrons(cube, s);
    double photonsPerWatt = 0.0;
    for (double nm : grid.wavelengths()) photonsPerWatt += nm * 1e-9 / (6.62607015e-34 * 299792458.0) * 10.0;
    const double want = 0.01 * 25e-12 * std::numbers::pi * 0.9 / (1 + 4 * 2.8 * 2.8) * 0.5 * photonsPerWatt *
                        double(0.02f);
    ASSERT_EQ(e.electrons.size(), 6u);
    for (double v : e.electrons) EXPECT_NEAR(v / want, 1.0, 1e-12);
    EXPECT_EQ(e.exposure_s, 0.01);
    // A photodiode's own QE is multiplied by the fill factor (0.8); a magnification of 0.5 makes the
    // working f-number 4.2.
    s.qeIncludesFillFactor = false;
    s.magnification = 0.5;
    const ExpectedElectrons near = expectedElectrons(cube, s);
    const double wantNear = want * 0.8 * (1 + 4 * 2.8 * 2.8) / (1 + 4 * 4.2 * 4.2);
    for (double v : near.electrons) EXPECT_NEAR(v / wantNear, 1.0, 1e-12);
}

TEST(SensorCapture, CosineFourthFalloffAndTheCfa) {
    const Grid grid{500, 600, 50};
    SpectralCube cube(4, 4, grid);
    std::fill(cube.data.begin(), cube.data.end(), 1.0f);
    SensorSpec s = testSensor(3);
    const ExpectedElectrons flat = expectedElectrons(cube, s);
    s.cos4 = true;
    s.focalLength_mm = 0.01;  // 10 µm: pixel (0, 0)'s centre is 7.07 µm off axis
    const ExpectedElectrons falloff = expectedElectrons(cube, s);
    const double d2 = 2 * 7.5e-3 * 7.5e-3, c2 = 1.0 / (1.0 + d2 / (0.01 * 0.01));
    EXPECT_NEAR(falloff.electrons[0] / flat.electrons[0], c2 * c2, 1e-12);
    // Focused at magnification m, the image lies f(1 + m) behind the lens: tan θ = r / (f(1 + m))
    // (issue 48: at m = 0.05 the old r / f differed by up to 111 DN).
    s.magnification = 0.05;
    const ExpectedElectrons near = expectedElectrons(cube, s);
    s.cos4 = false;
    const ExpectedElectrons nearFlat = expectedElectrons(cube, s);
    const double c2m = 1.0 / (1.0 + d2 / (0.0105 * 0.0105));
    EXPECT_NEAR(near.electrons[0] / nearFlat.electrons[0], c2m * c2m, 1e-12);
    // RGGB-like tile {{0, 1}, {1, 2}}: channel 1's QE is half of channel 0's, channel 2's a third.
    EXPECT_EQ(flat.channel[0], 0);
    EXPECT_EQ(flat.channel[1], 1);
    EXPECT_EQ(flat.channel[4], 1);
    EXPECT_EQ(flat.channel[5], 2);
    EXPECT_NEAR(flat.electrons[1] / flat.electrons[0], 0.5, 1e-12);
    EXPECT_NEAR(flat.electrons[5] / flat.electrons[0], 1.0 / 3.0, 1e-12);
}

TEST(SensorCapture, AutoExposureFillsTheChosenFractionOfTheFullWell) {
    const Grid grid{500, 600, 50};
    SpectralCube cube(10, 10, grid);
    for (size_t i = 0; i < cube.data.size(); ++i) cube.data[i] = float(i % 100) / 100.0f;
    SensorSpec s = testSensor();
    s.exposure_s.reset();
    s.fullWell_e = 10000;
    const ExpectedElectrons e = expectedElectrons(cube, s);
    EXPECT_TRUE(e.autoExposed);
    std::vector<double> sorted = e.electrons;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_NEAR(sorted[98], 7000.0, 1e-6);  // the 99th of 100: the nearest-rank 99th percentile
}

TEST(SensorCapture, WithoutNoiseTheRawIsTheRoundedMeanPlusBlackClippedToTheAdc) {
    SensorSpec s = testSensor();
    s.gain_dn_per_e = 0.37;
    s.blackLevel_dn = 64;
    s.fullWell_e = 5000;
    s.adcBits = 12;
    const std::vector<double> mu{0.0, 1.2, 100.0, 4999.0, 6000.0, 1e6};
    const std::vector<uint16_t> raw = digitize(mu, 6, s, CaptureNoise{false});
    EXPECT_EQ(raw[0], 64);
    EXPECT_EQ(raw[1], 64);                                         // 0.444 rounds to 0
    EXPECT_EQ(raw[2], 64 + 37);
    EXPECT_EQ(raw[3], 64 + int(std::nearbyint(0.37 * 4999)));      // 1850
    EXPECT_EQ(raw[4], 64 + int(std::nearbyint(0.37 * 5000)));      // the full well
    s.gain_dn_per_e = 1.0;
    const std::vector<uint16_t> saturated = digitize(mu, 6, s, CaptureNoise{true, 3, 0});
    EXPECT_EQ(saturated[5], 4095);  // 5000 + 64 > 2^12 − 1: never a code above the ADC's range
}

TEST(SensorCapture, AFlatFieldOf1000ElectronsHasPoissonMeanAndVariance) {
    // K = 1 and no read noise: DN = the electron count. n = 10⁶: 5σ bounds on mean and variance.
    SensorSpec s = testSensor();
    const size_t n = 1000000;
    const std::vector<double> mu(n, 1000.0);
    const Moments m = moments(digitize(mu, 1000, s, CaptureNoise{true, 11, 0}));
    EXPECT_NEAR(m.mean, 1000.0, 5.0 * std::sqrt(1000.0 / n));
    EXPECT_NEAR(m.variance, 1000.0, 5.0 * std::sqrt((1000.0 + 2.0 * 1000.0 * 1000.0) / n));
}

TEST(SensorCapture, PhotonTransferSlopeIsKAndInterceptIsReadNoisePlusQuantization) {
    // EMVA 1288: σ²_DN = K·(μ_DN − black) + K²σ_r² + 1/12 for a linear sensor.
    SensorSpec s = testSensor();
    s.gain_dn_per_e = 0.25;
    s.readNoise_e = 3.0;
    s.blackLevel_dn = 100;
    const size_t n = 1000000;
    std::vector<double> x, y;
    for (double mu : {0.0, 25.0, 50.0, 100.0, 200.0, 400.0}) {
        const Moments m = moments(digitize(std::vector<double>(n, mu), 1000, s, CaptureNoise{true, 5, uint64_t(mu)}));
        x.push_back(m.mean - 100.0);
        y.push_back(m.variance);
    }
    const double mx = std::accumulate(x.begin(), x.end(), 0.0) / x.size(), my = std::accumulate(y.begin(), y.end(), 0.0) / y.size();
    double sxy = 0.0, sxx = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
    }
    const double slope = sxy / sxx, intercept = my - slope * mx;
    std::printf("photon transfer: slope %.5f (K = 0.25), intercept %.4f (K²σr² + 1/12 = %.4f)\n", slope, intercept,
                0.25 * 0.25 * 9.0 + 1.0 / 12.0);
    EXPECT_NEAR(slope, 0.25, 0.005);
    EXPECT_NEAR(intercept, 0.25 * 0.25 * 9.0 + 1.0 / 12.0, 0.05);
}

// DSNU as EMVA 1288 defines it (issue 48, item 4): the spatial σ of the dark signal, an offset added
// after the shot noise that may be negative. Its estimator — the spatial variance of the dark image
// averaged over L frames, less the temporal variance over L — gives back dsnu_e, and the mean dark
// level stays at the black level. (Drawn inside the Poisson mean and clamped at 0, as it was, a
// σ of 2 e⁻ measured about 0.58σ, and the black level rose by σ/√(2π).)
TEST(SensorCapture, DsnuIsMeasuredAsEmva1288EstimatesItAndLeavesTheBlackLevel) {
    const Grid grid{500, 600, 50};
    const int w = 256, h = 256, frames = 16;
    SpectralCube dark(w, h, grid);  // all zero: no light
    SensorSpec s = testSensor();
    s.dsnu_e = 2.0;
    s.readNoise_e = 1.0;
    s.blackLevel_dn = 100;
    s.darkCurrent_e_per_s = 0.0;
    const ExpectedElectrons e = expectedElectrons(dark, s);
    const size_t n = size_t(w) * size_t(h);
    std::vector<double> sum(n, 0.0), sumSquares(n, 0.0);
    for (int f = 0; f < frames; ++f) {
        const std::vector<uint16_t> raw = digitize(e, s, CaptureNoise{true, 9, uint64_t(f)});
        for (size_t i = 0; i < n; ++i) {
            sum[i] += raw[i];
            sumSquares[i] += double(raw[i]) * raw[i];
        }
    }
    double mean = 0.0, temporal = 0.0;
    for (size_t i = 0; i < n; ++i) {
        mean += sum[i] / frames;
        temporal += (sumSquares[i] - sum[i] * sum[i] / frames) / (frames - 1);
    }
    mean /= double(n);
    temporal /= double(n);
    double spatial = 0.0;
    for (size_t i = 0; i < n; ++i) spatial += (sum[i] / frames - mean) * (sum[i] / frames - mean);
    spatial /= double(n - 1);
    const double dsnu = std::sqrt(spatial - temporal / frames) / s.gain_dn_per_e;
    std::printf("DSNU measured %.4f e- (dsnu_e 2), dark mean %.4f DN (black 100), temporal variance %.4f DN²\n", dsnu,
                mean, temporal);
    EXPECT_NEAR(dsnu, 2.0, 0.04);             // 2 %: the estimate's spread over 65 536 pixels is 0.3 %
    EXPECT_NEAR(mean, 100.0, 0.05);           // the offsets' mean, 0 ± 2/256
    EXPECT_NEAR(temporal, 1.0 + 1.0 / 12.0, 0.03);  // read noise and quantization only
}

TEST(SensorCapture, FramesDifferOnlyInTemporalNoise) {
    // Two frames of one sensor (same fixed pattern, other temporal seeds): each carries the PRNU;
    // their difference does not.
    SensorSpec s = testSensor();
    s.prnu = 0.05;
    const size_t n = 200000;
    std::vector<double> gain(n), mu(n);
    for (size_t i = 0; i < n; ++i) {
        gain[i] = prnuGain(s, i);
        mu[i] = 2000.0 * gain[i];
    }
    const std::vector<uint16_t> a = digitize(mu, 1000, s, CaptureNoise{true, 1, 0});
    const std::vector<uint16_t> b = digitize(mu, 1000, s, CaptureNoise{true, 2, 0});
    const std::vector<uint16_t> a2 = digitize(mu, 1000, s, CaptureNoise{true, 1, 0});
    EXPECT_EQ(a, a2);
    EXPECT_NE(a, b);
    auto correlation = [&](auto value) {
        double mv = 0.0, mg = 0.0;
        for (size_t i = 0; i < n; ++i) {
            mv += value(i);
            mg += gain[i];
        }
        mv /= n;
        mg /= n;
        double c = 0.0, vv = 0.0, vg = 0.0;
        for (size_t i = 0; i < n; ++i) {
            c += (value(i) - mv) * (gain[i] - mg);
            vv += (value(i) - mv) * (value(i) - mv);
            vg += (gain[i] - mg) * (gain[i] - mg);
        }
        return c / std::sqrt(vv * vg);
    };
    EXPECT_GT(correlation([&](size_t i) { return double(a[i]); }), 0.9);
    EXPECT_LT(std::fabs(correlation([&](size_t i) { return double(a[i]) - double(b[i]); })), 5.0 / std::sqrt(double(n)));
    // And the PRNU map has the σ the sensor file asks for.
    double m2 = 0.0;
    for (double g : gain) m2 += (g - 1.0) * (g - 1.0);
    EXPECT_NEAR(std::sqrt(m2 / n), 0.05, 0.05 * 5.0 / std::sqrt(2.0 * n));
}

TEST(SensorCapture, AnyThreadCountGivesTheSameNumbers) {
    const Grid grid{500, 600, 50};
    SpectralCube cube(300, 200, grid);
    for (size_t i = 0; i < cube.data.size(); ++i) cube.data[i] = float(i % 997) / 997.0f;
    SensorSpec s = testSensor(3);
    s.prnu = 0.01;
    s.dsnu_e = 1.0;
    s.readNoise_e = 2.0;
    s.fullWell_e = 20000;
    s.exposure_s.reset();
    const ExpectedElectrons one = expectedElectrons(cube, s, std::nullopt, true, 1);
    for (int threads : {2, 3, 7}) {
        const ExpectedElectrons many = expectedElectrons(cube, s, std::nullopt, true, threads);
        EXPECT_EQ(many.electrons, one.electrons) << threads;
        EXPECT_EQ(many.darkOffset, one.darkOffset) << threads;
        EXPECT_EQ(digitize(many, s, CaptureNoise{true, 5, 1, threads}), digitize(one, s, CaptureNoise{true, 5, 1, 1}))
            << threads;
    }
}

// The sensor's own numbers (issue 51, class 2): a cube value that is not finite radiance ≥ 0 is
// named at the cube with its pixel and band; a channel whose QE data lie wholly outside the cube's
// grid is named at the sensor's table instead of capturing black.
TEST(SensorCapture, BadRadianceIsNamedAtTheCubeAndAQeOutsideTheGridAtTheSensor) {
    const Grid grid{400, 700, 100};
    SpectralCube cube(3, 2, grid);
    std::fill(cube.data.begin(), cube.data.end(), 0.01f);
    EXPECT_NO_THROW(requireRadiance(cube, Where{"cube.exr"}));
    cube.data[size_t(1 * 3 + 2) * 4 + 1] = NAN;  // pixel (2, 1), 500 nm
    try {
        requireRadiance(cube, Where{"cube.exr"});
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.where().file, "cube.exr");
        EXPECT_NE(e.message().find("pixel (2, 1) holds nan at 500 nm"), std::string::npos) << e.message();
    }
    cube.data[size_t(1 * 3 + 2) * 4 + 1] = -1.0f;
    EXPECT_THROW(requireRadiance(cube, Where{"cube.exr"}), Error);

    std::fill(cube.data.begin(), cube.data.end(), 0.01f);
    SensorSpec s = testSensor();
    s.file = "nir.json";
    Spectrum nir;
    nir.wavelengths_nm = {800, 900, 1000};
    nir.values = {0.2, 0.4, 0.2};
    s.quantumEfficiency = {nir};
    try {
        expectedElectrons(cube, s, 0.01, false);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.where().key, "quantum_efficiency.table");
        EXPECT_NE(e.message().find("channel c0's data (800 … 1000 nm) lie wholly outside the cube's grid (400 … 700 nm)"),
                  std::string::npos)
            << e.message();
    }
}

// A sensor with a lens (issue 48, item 1) sees the optical image: a flat field keeps its electrons
// away from the frame's edges, and the lens file's mistakes name their key.
TEST(SensorCapture, ALensBlursButKeepsAFlatFieldsElectrons) {
    const Grid grid{400, 700, 10};
    SpectralCube cube(64, 64, grid);
    std::fill(cube.data.begin(), cube.data.end(), 0.02f);
    for (int b = 0; b < grid.bands(); ++b) cube.pixel(24, 24)[b] = 1.0f;  // a point, to be spread
    SensorSpec s = testSensor();
    const ExpectedElectrons sharp = expectedElectrons(cube, s);
    s.lens = LensSpec{};
    s.lens->defocus_um = 30.0;
    const ExpectedElectrons blurred = expectedElectrons(cube, s);
    EXPECT_NEAR(blurred.electrons[size_t(50) * 64 + 50] / sharp.electrons[size_t(50) * 64 + 50], 1.0, 1e-6);
    EXPECT_LT(blurred.electrons[size_t(24) * 64 + 24], 0.5 * sharp.electrons[size_t(24) * 64 + 24]);
    // Within the kernel's reach of the point (11 pixels) and farther than it from the frame's edge.
    double a = 0.0, b = 0.0;
    for (int y = 12; y < 37; ++y)
        for (int x = 12; x < 37; ++x) a += sharp.electrons[size_t(y) * 64 + x], b += blurred.electrons[size_t(y) * 64 + x];
    EXPECT_NEAR(b / a, 1.0, 1e-5);  // the point's light is near it, not lost
}
