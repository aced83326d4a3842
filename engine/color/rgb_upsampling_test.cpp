// RGB → spectrum up-sampling (color/rgb_upsampling.h): the model, the colour it is fitted to,
// the solver, the table and its round trip. The figures quoted in docs/upsampling.md are printed
// by the tests marked "prints". The end-to-end check against colour-science is
// tests/python/check_upsampling_colour.py.
#include "color/rgb_upsampling.h"
#include "spectral/resampling.h"

#include "color/delta_e.h"
#include "color/lab.h"
#include "color/srgb.h"
#include "spectral/csv.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <unistd.h>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}

const RgbUpsampler& upsampler() { return RgbUpsampler::srgb(library()); }

// The RGB mode's reflectance weights as spectra/generate_quadrature.py wrote them (an independent
// computation of the colour the fit matches): linear sRGB = Σ w(λ)·ρ(λ), 1 nm, 360–830 nm.
struct Weights {
    std::vector<double> nm;
    std::vector<glm::dvec3> w;
};
const Weights& csvWeights() {
    static const Weights weights = [] {
        SpectralTable t = readSpectralTable(library().root() / "quadrature/rgb_weights.csv", 3);
        Weights out;
        out.nm = t.wavelengths_nm;
        for (size_t i = 0; i < t.wavelengths_nm.size(); ++i)
            out.w.emplace_back(t.columns[0][i], t.columns[1][i], t.columns[2][i]);
        return out;
    }();
    return weights;
}

template <typename F>
glm::dvec3 rgbOfFunction(F rho) {
    const Weights& w = csvWeights();
    glm::dvec3 rgb(0.0);
    for (size_t i = 0; i < w.nm.size(); ++i) rgb += w.w[i] * rho(w.nm[i]);
    return rgb;
}

glm::dvec3 rgbOfCoefficients(const RgbUpsampler::Coefficients& c) {
    return rgbOfFunction([&](double nm) { return RgbUpsampler::reflectance(c, nm); });
}

// ΔE2000 between a colour (clamped as the up-sampler clamps it) and its up-sampled spectrum under
// D65: through the table alone (lookup) or the polished fit.
double roundTripDeltaE(const RgbUpsampler& up, const glm::dvec3& linear, bool polished) {
    const auto c = polished ? up.fit(linear) : up.lookup(linear);
    return deltaE2000(up.labOf(c), RgbUpsampler::labOfLinearRgb(RgbUpsampler::clampLinearRgb(linear)));
}

struct Stats {
    double median = 0, p95 = 0, max = 0;
    glm::dvec3 worst{0.0};
};
Stats statistics(std::vector<std::pair<double, glm::dvec3>> v) {
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    Stats s;
    s.median = v[v.size() / 2].first;
    s.p95 = v[std::min(v.size() - 1, v.size() * 95 / 100)].first;
    s.max = v.back().first;
    s.worst = v.back().second;
    return s;
}

// CIELAB of a reflectance under a light, relative to the light's white (1 nm, 360–830 nm, the
// CIE 1931 observer).
template <typename F>
glm::dvec3 labUnder(const Spectrum& light, F rho) {
    static const SpectralTable cmf = readSpectralTable(library().root() / "observers/cie1931_2deg.csv", 3);
    glm::dvec3 xyz(0.0), white(0.0);
    for (size_t i = 0; i < cmf.wavelengths_nm.size(); ++i) {
        const double nm = cmf.wavelengths_nm[i];
        const glm::dvec3 w = light.at(nm) * glm::dvec3(cmf.columns[0][i], cmf.columns[1][i], cmf.columns[2][i]);
        xyz += w * rho(nm);
        white += w;
    }
    return xyzToLab(xyz, white);
}

const char* const kPatches[24] = {"dark_skin",    "light_skin",    "blue_sky",     "foliage",    "blue_flower",
                                  "bluish_green", "orange",        "purplish_blue", "moderate_red", "purple",
                                  "yellow_green", "orange_yellow", "blue",         "green",      "red",
                                  "yellow",       "magenta",       "cyan",         "white_9_5",  "neutral_8",
                                  "neutral_6_5",  "neutral_5",     "neutral_3_5",  "black_2"};

}  // namespace

// --- The model ----------------------------------------------------------------------------------

TEST(RgbUpsampling, SigmoidKnownValuesAndBounds) {
    EXPECT_EQ(RgbUpsampler::sigmoid(0.0), 0.5);
    EXPECT_NEAR(RgbUpsampler::sigmoid(1.0), 0.5 + 0.5 / std::sqrt(2.0), 1e-15);
    EXPECT_NEAR(RgbUpsampler::sigmoid(-3.0), 0.5 - 1.5 / std::sqrt(10.0), 1e-15);
    double previous = 0.0;
    for (double x = -1e6; x <= 1e6; x = x < 0 ? x / 1.5 + 1e-3 : x * 1.5 + 1e-3) {
        const double s = RgbUpsampler::sigmoid(x);
        ASSERT_GE(s, previous) << x;  // monotonic
        ASSERT_NEAR(s + RgbUpsampler::sigmoid(-x), 1.0, 1e-15) << x;  // odd about ½
        previous = s;
    }
    EXPECT_GT(RgbUpsampler::sigmoid(-1e6), 0.0);  // never 0 or 1 at moderate x
    EXPECT_LT(RgbUpsampler::sigmoid(1e6), 1.0);
    EXPECT_EQ(RgbUpsampler::sigmoid(1e300), 1.0);
    EXPECT_EQ(RgbUpsampler::sigmoid(-1e300), 0.0);
    EXPECT_EQ(RgbUpsampler::sigmoid(std::numeric_limits<double>::infinity()), 1.0);
}

TEST(RgbUpsampling, BlackAndWhiteCoefficientsAreExactInDoubleAndFloat) {
    for (double nm : {300.0, 360.0, 555.0, 830.0, 2500.0}) {
        EXPECT_EQ(RgbUpsampler::reflectance(RgbUpsampler::kBlack, nm), 0.0);
        EXPECT_EQ(RgbUpsampler::reflectance(RgbUpsampler::kWhite, nm), 1.0);
    }
    // The same formula in single precision, as a shader would evaluate it.
    for (float c2 : {static_cast<float>(RgbUpsampler::kBlack.c2), static_cast<float>(RgbUpsampler::kWhite.c2)}) {
        const float s = 0.5f + c2 / (2.0f * std::sqrt(1.0f + c2 * c2));
        EXPECT_EQ(s, c2 > 0 ? 1.0f : 0.0f);
    }
    const RgbUpsampler& up = upsampler();
    EXPECT_EQ(up.linearRgbOf(RgbUpsampler::kBlack), glm::dvec3(0.0));
    EXPECT_EQ(up.linearRgbOf(RgbUpsampler::kWhite), glm::dvec3(1.0));
}

TEST(RgbUpsampling, ReflectanceHoldsItsEndValuesOutsideTheFitRange) {
    const RgbUpsampler::Coefficients c{-2e-4, 0.21, -52.0};
    EXPECT_EQ(RgbUpsampler::reflectance(c, 200.0), RgbUpsampler::reflectance(c, 360.0));
    EXPECT_EQ(RgbUpsampler::reflectance(c, 2500.0), RgbUpsampler::reflectance(c, 830.0));
    const double q = (c.c0 * 500.0 + c.c1) * 500.0 + c.c2;
    EXPECT_NEAR(RgbUpsampler::reflectance(c, 500.0), 0.5 + q / (2.0 * std::sqrt(1.0 + q * q)), 1e-15);
}

// --- The colour the fit matches -----------------------------------------------------------------

TEST(RgbUpsampling, ColourWeightsAgreeWithTheRgbModesTable) {
    // linearRgbOf uses weights computed here from D65 and the CIE 1931 table; rgb_weights.csv was
    // written by spectra/generate_quadrature.py from colour-science's copy of the same tables.
    const RgbUpsampler& up = upsampler();
    const RgbUpsampler::Coefficients cases[] = {
        {0, 0, 0}, {0, 0, 1.3}, {-2e-4, 0.21, -52.0}, {3.1e-4, -0.33, 80.0}, {1e-3, -1.1, 290.0}, {0, 0.02, -11.0}};
    for (const auto& c : cases) {
        const glm::dvec3 mine = up.linearRgbOf(c), csv = rgbOfCoefficients(c);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(mine[k], csv[k], 2e-9) << c.c0 << " " << c.c1 << " " << c.c2;
    }
    // A constant reflectance g is the grey (g, g, g).
    const glm::dvec3 half = up.linearRgbOf({0, 0, 0});
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(half[k], 0.5, 1e-14);
    EXPECT_NEAR(RgbUpsampler::labOfLinearRgb(glm::dvec3(1.0)).x, 100.0, 1e-12);
    EXPECT_NEAR(RgbUpsampler::labOfLinearRgb(glm::dvec3(1.0)).y, 0.0, 1e-9);
    EXPECT_NEAR(RgbUpsampler::labOfLinearRgb(glm::dvec3(1.0)).z, 0.0, 1e-9);
}

// --- The solver ---------------------------------------------------------------------------------

TEST(RgbUpsampling, GreysSolveToFlatSpectra) {
    const RgbUpsampler& up = upsampler();
    for (double g : {1e-4, 0.01, 0.18, 0.5, 0.9, 0.999}) {
        const auto s = up.solve(glm::dvec3(g));
        EXPECT_LT(s.residual, RgbUpsampler::kResidualTolerance);
        // Flat: c0 = c1 = 0 (to the solver's tolerance), and S(c2) = g.
        EXPECT_NEAR(s.coefficients.c0 * 470.0 * 470.0, 0.0, 1e-6) << g;
        EXPECT_NEAR((2 * s.coefficients.c0 * 595.0 + s.coefficients.c1) * 470.0, 0.0, 1e-6) << g;
        for (double nm = 360; nm <= 830; nm += 10)
            EXPECT_NEAR(RgbUpsampler::reflectance(s.coefficients, nm), g, 1e-6 * std::max(g, 0.01)) << g << " " << nm;
        // The table gives flat spectra too (the grey axis is a table edge, x = y = 1), but its
        // level is interpolated in c2, not in ρ, so only fit()'s polish makes it exact.
        for (bool polished : {false, true}) {
            const auto f = polished ? up.fit(glm::dvec3(g)) : up.lookup(glm::dvec3(g));
            double lo = 1, hi = 0;
            for (double nm = 360; nm <= 830; nm += 1) {
                lo = std::min(lo, RgbUpsampler::reflectance(f, nm));
                hi = std::max(hi, RgbUpsampler::reflectance(f, nm));
            }
            EXPECT_LT(hi - lo, 1e-6 * std::max(g, 0.01)) << g;
            if (polished) {
                // ΔE*ab ≤ 1e-4 is a relative error of ~5e-6 in Y above the CIELAB knee, and
                // 1e-4/903 absolute below it.
                EXPECT_NEAR(0.5 * (hi + lo), g, std::max(1e-5 * g, 2e-7)) << g;
            } else {
                // The table interpolates c2 linearly between z samples while ρ = S(c2) is not
                // linear in it: the level is off by up to a few % at dark greys (printed).
                const double d = deltaE2000(up.labOf(f), RgbUpsampler::labOfLinearRgb(glm::dvec3(g)));
                std::printf("grey %.4f: lookup level %.6f, ΔE00 %.3f\n", g, 0.5 * (hi + lo), d);
                EXPECT_LT(d, 0.3) << g;
            }
        }
    }
}

TEST(RgbUpsampling, SolverReachesEveryCornerOfTheGamut) {
    // The sRGB cube's corners and edge midpoints; the primaries and secondaries are the most
    // saturated colours a texture can hold. ΔE*ab ≤ 1e-6 means the model reproduces them exactly.
    const RgbUpsampler& up = upsampler();
    for (int r = 0; r <= 2; ++r)
        for (int g = 0; g <= 2; ++g)
            for (int b = 0; b <= 2; ++b) {
                const glm::dvec3 c(r / 2.0, g / 2.0, b / 2.0);
                const auto s = up.solve(c, up.fit(c));
                EXPECT_LE(s.residual, RgbUpsampler::kResidualTolerance) << c.x << " " << c.y << " " << c.z;
                EXPECT_LT(deltaE2000(up.labOf(s.coefficients), RgbUpsampler::labOfLinearRgb(c)), 1e-5);
                // and from a cold start (zero coefficients, a flat 0.5)
                const auto cold = up.solve(c);
                EXPECT_LE(cold.residual, RgbUpsampler::kResidualTolerance) << c.x << " " << c.y << " " << c.z;
            }
}

TEST(RgbUpsampling, ClampingRule) {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(RgbUpsampler::clampLinearRgb({0.2, 0.5, 0.7}), glm::dvec3(0.2, 0.5, 0.7));
    EXPECT_EQ(RgbUpsampler::clampLinearRgb({-0.1, 0.5, nan}), glm::dvec3(0.0, 0.5, 0.0));
    EXPECT_EQ(RgbUpsampler::clampLinearRgb({2.0, 1.0, 0.5}), glm::dvec3(1.0, 0.5, 0.25));  // hue kept
    EXPECT_EQ(RgbUpsampler::clampLinearRgb({inf, 3.0, -1.0}), glm::dvec3(1.0, 0.0, 0.0));
    EXPECT_EQ(RgbUpsampler::clampLinearRgb({inf, inf, 1.0}), glm::dvec3(1.0, 1.0, 0.0));
    const RgbUpsampler& up = upsampler();
    const auto a = up.fit({2.0, 1.0, 0.5}), b = up.fit({1.0, 0.5, 0.25});
    EXPECT_EQ(a.c0, b.c0);
    EXPECT_EQ(a.c2, b.c2);
    const auto w = up.fit({5.0, 5.0, 5.0});
    EXPECT_EQ(RgbUpsampler::reflectance(w, 555.0), 1.0);
    const auto k = up.fit({-1.0, nan, 0.0});
    EXPECT_EQ(RgbUpsampler::reflectance(k, 555.0), 0.0);
    // Encoded input: decoded first.
    const glm::dvec3 e(0.8, 0.3, 0.05);
    const auto fe = up.fitEncoded(e), fl = up.fit({srgbDecode(0.8), srgbDecode(0.3), srgbDecode(0.05)});
    EXPECT_EQ(fe.c0, fl.c0);
    EXPECT_EQ(fe.c1, fl.c1);
    EXPECT_EQ(fe.c2, fl.c2);
}

// --- The table ----------------------------------------------------------------------------------

TEST(RgbUpsampling, TableIsTheOneBuiltWithTheProject) {
    const RgbUpsampler& up = upsampler();
    EXPECT_EQ(up.resolution(), RgbUpsampler::kDefaultResolution);
    EXPECT_NE(up.source(), "built in memory") << "the build's table was not found or did not match";
    EXPECT_EQ(&up, &RgbUpsampler::srgb(library()));  // made once
    std::printf("table: %s, resolution %d\n", up.source().c_str(), up.resolution());
}

TEST(RgbUpsampling, EveryTableSpectrumIsBoundedAndEveryNodeMatchesItsColour) {
    // S∘quadratic is monotonic on each side of the quadratic's vertex, so the extremes of ρ over
    // 360–830 nm are at the ends or at the vertex: checking those three bounds every spectrum.
    const RgbUpsampler& up = upsampler();
    const int res = up.resolution();
    long open = 0, nodes = 0;
    double worst = 0.0;
    for (int l = 0; l < 3; ++l)
        for (int zi = 0; zi < res; ++zi)
            for (int yi = 0; yi < res; ++yi)
                for (int xi = 0; xi < res; ++xi) {
                    const auto c = up.node(l, xi, yi, zi);
                    ASSERT_TRUE(std::isfinite(c.c0) && std::isfinite(c.c1) && std::isfinite(c.c2));
                    double lo = std::min(RgbUpsampler::reflectance(c, 360), RgbUpsampler::reflectance(c, 830));
                    double hi = std::max(RgbUpsampler::reflectance(c, 360), RgbUpsampler::reflectance(c, 830));
                    if (c.c0 != 0.0) {
                        const double v = RgbUpsampler::reflectance(c, -c.c1 / (2 * c.c0));
                        lo = std::min(lo, v), hi = std::max(hi, v);
                    }
                    ASSERT_GE(lo, 0.0);
                    ASSERT_LE(hi, 1.0);
                    if (zi == 0) {
                        ASSERT_EQ(hi, 0.0);  // the black layer is exactly black
                    } else {
                        ASSERT_GT(lo, 0.0);
                        ASSERT_LT(hi, 1.0);
                        ++open;
                    }
                    ++nodes;
                    // The colour of every 7th node (the full check takes seconds).
                    if ((xi + 3 * yi + 5 * zi + l) % 7 == 0) {
                        const glm::dvec3 target = up.nodeColor(l, xi, yi, zi);
                        const double d = glm::length(up.labOf(c) - RgbUpsampler::labOfLinearRgb(target));
                        worst = std::max(worst, d);
                    }
                }
    // Conversion to nm coefficients and back costs a little precision: ΔE*ab 1e-6 at a node
    // becomes a few 1e-6 here.
    EXPECT_LT(worst, 1e-4);
    EXPECT_EQ(open, nodes - 3L * res * res);
    std::printf("nodes: %ld, spectra strictly inside (0, 1): %ld; largest node ΔE*ab %.2e\n", nodes, open, worst);
}

TEST(RgbUpsampling, SpectraAreUnimodalAndTheFitIsContinuous) {
    // Smoothness: a sigmoid of a quadratic rises and falls at most once, so its 1 nm samples have
    // at most one interior extremum; and nearby colours give nearby spectra (no jumps between
    // solution branches, in the table or in the polished fit).
    const RgbUpsampler& up = upsampler();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double largestJump = 0.0;
    for (int n = 0; n < 2000; ++n) {
        const glm::dvec3 c(u(rng), u(rng), u(rng));
        const auto f = up.fit(c);
        int turns = 0;
        double prevDiff = 0.0;
        for (double nm = 361; nm <= 830; nm += 1) {
            const double d = RgbUpsampler::reflectance(f, nm) - RgbUpsampler::reflectance(f, nm - 1);
            if (d != 0.0 && prevDiff != 0.0 && (d > 0) != (prevDiff > 0)) ++turns;
            if (d != 0.0) prevDiff = d;
        }
        ASSERT_LE(turns, 1) << c.x << " " << c.y << " " << c.z;
        // Continuity: a step of 1e-7 in every channel moves ρ by about that much (a jump between
        // solution branches would move it by a large amount). Across the l = argmax switch too.
        const glm::dvec3 d = n % 2 ? glm::dvec3(1e-7) : glm::dvec3(1e-7, -1e-7, 0.0);
        const auto g = up.fit(glm::clamp(c + d, 0.0, 1.0));
        const auto fl = up.lookup(c), gl = up.lookup(glm::clamp(c + d, 0.0, 1.0));
        for (double nm = 360; nm <= 830; nm += 5) {
            largestJump = std::max(largestJump, std::abs(RgbUpsampler::reflectance(f, nm) - RgbUpsampler::reflectance(g, nm)));
            largestJump = std::max(largestJump, std::abs(RgbUpsampler::reflectance(fl, nm) - RgbUpsampler::reflectance(gl, nm)));
        }
    }
    // Ties between channels, where the table switches from one largest channel to another.
    for (double t : {0.1, 0.5, 0.9}) {
        const auto a = up.lookup({t, t + 1e-9, 0.3 * t}), b = up.lookup({t + 1e-9, t, 0.3 * t});
        for (double nm = 360; nm <= 830; nm += 5)
            largestJump = std::max(largestJump, std::abs(RgbUpsampler::reflectance(a, nm) - RgbUpsampler::reflectance(b, nm)));
    }
    EXPECT_LT(largestJump, 1e-3);
    std::printf("largest change of ρ for a 1e-7 step of the colour: %.2e\n", largestJump);
}

TEST(RgbUpsampling, BuildIsDeterministicAndFilesRoundTrip) {
    RgbUpsampler::BuildStats one, two;
    const RgbUpsampler a = RgbUpsampler::build(library(), 8, 1, &one);
    const RgbUpsampler b = RgbUpsampler::build(library(), 8, 2, &two);
    EXPECT_EQ(one.unconverged, 0);
    EXPECT_LE(one.maxResidual, RgbUpsampler::kResidualTolerance);
    EXPECT_EQ(one.iterations, two.iterations);
    for (int l = 0; l < 3; ++l)
        for (int z = 0; z < 8; ++z)
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x) {
                    ASSERT_EQ(a.node(l, x, y, z).c0, b.node(l, x, y, z).c0);
                    ASSERT_EQ(a.node(l, x, y, z).c2, b.node(l, x, y, z).c2);
                }
    EXPECT_EQ(a.zSamples().front(), 0.0);
    EXPECT_EQ(a.zSamples().back(), 1.0);
    EXPECT_GT(a.zSamples()[1], 0.0);

    const fs::path dir = fs::temp_directory_path() / ("metamer_rgb_table_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / "t.bin";
    a.write(file);
    RgbUpsampler c(library());
    ASSERT_TRUE(c.read(file));
    EXPECT_EQ(c.resolution(), 8);
    EXPECT_EQ(c.source(), file.string());
    const glm::dvec3 probe(0.3, 0.6, 0.1);
    EXPECT_EQ(c.fit(probe).c1, a.fit(probe).c1);

    // Rejected: missing, truncated, trailing bytes, another format or other colour weights.
    RgbUpsampler d(library());
    EXPECT_FALSE(d.read(dir / "missing.bin"));
    const auto size = fs::file_size(file);
    fs::copy_file(file, dir / "cut.bin");
    fs::resize_file(dir / "cut.bin", size - 8);
    EXPECT_FALSE(d.read(dir / "cut.bin"));
    fs::copy_file(file, dir / "long.bin");
    std::ofstream(dir / "long.bin", std::ios::app | std::ios::binary) << "x";
    EXPECT_FALSE(d.read(dir / "long.bin"));
    for (size_t byte : {0u, 8u, 16u}) {  // magic, version, fingerprint
        fs::copy_file(file, dir / "bad.bin", fs::copy_options::overwrite_existing);
        std::fstream f(dir / "bad.bin", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(byte));
        f.put('\x7f');
        f.close();
        EXPECT_FALSE(d.read(dir / "bad.bin")) << byte;
    }
    EXPECT_EQ(d.resolution(), 0);
    EXPECT_THROW(d.fit(probe), Error);
    fs::remove_all(dir);
}

// --- Round trip ---------------------------------------------------------------------------------

TEST(RgbUpsampling, RoundTripOverTheColorChecker) {
    // Each patch's linear sRGB under D65 (the RGB mode's weights, white → 1) is up-sampled; the
    // spectrum's colour under D65 is compared with the patch's. Patches outside the sRGB gamut
    // (a negative channel) are clamped first, so their error is the clamp's, reported apart.
    const RgbUpsampler& up = upsampler();
    std::vector<std::pair<double, glm::dvec3>> lookups, fits, metamerA, metamerF;
    double spectralWorst = 0.0;
    const Spectrum& illuminantA = library().get("illuminants/A", Where{});
    const Spectrum& fl11 = library().get("illuminants/FL11", Where{});
    std::printf("%-14s %-28s %12s %10s %8s %7s %7s\n", "patch", "linear sRGB", "ΔE00 lookup", "ΔE00 fit", "max|Δρ|",
                "A", "FL11");
    for (const char* name : kPatches) {
        const Spectrum& s = library().get(std::string("colorchecker/") + name, Where{});
        const glm::dvec3 rgb = rgbOfFunction([&](double nm) { return s.at(nm); });
        const bool outside = rgb.x < 0 || rgb.y < 0 || rgb.z < 0 || rgb.x > 1 || rgb.y > 1 || rgb.z > 1;
        const glm::dvec3 lab = RgbUpsampler::labOfLinearRgb(rgb);
        const double dl = deltaE2000(up.labOf(up.lookup(rgb)), lab);
        const auto f = up.fit(rgb);
        const double df = deltaE2000(up.labOf(f), lab);
        // How far the smooth metamer is from the measured reflectance (not a fit error), and what
        // that does under other lights: ΔE00 between the two under A and FL11.
        double dr = 0.0;
        for (double nm = 400; nm <= 700; nm += 5) dr = std::max(dr, std::abs(RgbUpsampler::reflectance(f, nm) - s.at(nm)));
        const double underA = deltaE2000(labUnder(illuminantA, [&](double nm) { return s.at(nm); }),
                                         labUnder(illuminantA, [&](double nm) { return RgbUpsampler::reflectance(f, nm); }));
        const double underF = deltaE2000(labUnder(fl11, [&](double nm) { return s.at(nm); }),
                                         labUnder(fl11, [&](double nm) { return RgbUpsampler::reflectance(f, nm); }));
        std::printf("%-14s (%7.4f, %7.4f, %7.4f)%s %12.4f %10.2e %8.3f %7.3f %7.3f\n", name, rgb.x, rgb.y, rgb.z,
                    outside ? "*" : " ", dl, df, dr, underA, underF);
        if (!outside) metamerA.emplace_back(underA, rgb), metamerF.emplace_back(underF, rgb);
        if (!outside) {
            lookups.emplace_back(dl, rgb);
            fits.emplace_back(df, rgb);
            EXPECT_LT(df, 1e-3) << name;
        } else {
            // Clamped: the error is that of the clamp (cyan's red is −0.03).
            EXPECT_LT(df, 5.0) << name;
        }
        spectralWorst = std::max(spectralWorst, dr);
    }
    const Stats l = statistics(lookups), f = statistics(fits);
    std::printf("ColorChecker, %zu in-gamut patches: ΔE00 lookup median %.4f, 95th %.4f, max %.4f; "
                "fit median %.1e, max %.1e\n", lookups.size(), l.median, l.p95, l.max, f.median, f.max);
    const Stats ma = statistics(metamerA), mf = statistics(metamerF);
    std::printf("measured vs up-sampled, in-gamut patches: ΔE00 under A median %.2f, max %.2f; under FL11 median "
                "%.2f, max %.2f\n", ma.median, ma.max, mf.median, mf.max);
    EXPECT_GE(lookups.size(), 22u);
    EXPECT_LT(l.max, 0.2);
    EXPECT_GT(ma.max, 0.5);  // a metamer under D65 only
    // The measured reflectances are not smooth metamers: they differ from the up-sampled ones.
    EXPECT_GT(spectralWorst, 0.2);
}

TEST(RgbUpsampling, RoundTripOverTheGamut) {
    // A lattice of 8-bit encoded values (what PNG/JPEG textures hold), random linear colours, and
    // the cube's faces (one channel 0 or 1: the gamut boundary, where the table is least accurate).
    const RgbUpsampler& up = upsampler();
    std::vector<glm::dvec3> lattice, random, faces;
    const int n = 52;  // every 5th 8-bit code value
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) lattice.push_back(RgbUpsampler::decodeSrgb(glm::dvec3(i, j, k) * (5.0 / 255.0)));
    std::mt19937 rng(2019);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int m = 0; m < 20000; ++m) {
        random.emplace_back(u(rng), u(rng), u(rng));
        glm::dvec3 face(u(rng), u(rng), u(rng));
        face[m % 3] = (m / 3) % 2 ? 1.0 : 0.0;
        faces.push_back(face);
    }
    Stats latticeStats[2];
    for (const auto& [name, set] : {std::pair{"8-bit lattice (52³, encoded)", &lattice},
                                    std::pair{"random linear (20000)", &random},
                                    std::pair{"cube faces (20000)", &faces}}) {
        for (bool polished : {false, true}) {
            std::vector<std::pair<double, glm::dvec3>> errs;
            const auto t0 = std::chrono::steady_clock::now();
            for (const glm::dvec3& c : *set) errs.emplace_back(roundTripDeltaE(up, c, polished), c);
            const double us = 1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
                              static_cast<double>(set->size());
            const Stats s = statistics(errs);
            std::printf("%-30s %-6s ΔE00 median %.2e, 95th %.2e, max %.2e at linear (%.4f, %.4f, %.4f); "
                        "%.2f µs/colour with its colour\n",
                        name, polished ? "fit" : "lookup", s.median, s.p95, s.max, s.worst.x, s.worst.y, s.worst.z, us);
            if (set == &lattice) latticeStats[polished] = s;
            EXPECT_LT(s.max, polished ? 1e-3 : 1.0) << name;
        }
    }
    EXPECT_LT(latticeStats[0].median, 0.03);
    EXPECT_LT(latticeStats[0].p95, 0.15);
    EXPECT_LT(latticeStats[1].p95, 1e-4);
}

TEST(RgbUpsampling, NearBlackAndNearWhite) {
    // The darkest non-zero 8-bit codes, and colours just below white. The table alone is worst
    // next to white (the white node's coefficients run to +∞ and dominate the interpolation);
    // fit() polishes that away.
    const RgbUpsampler& up = upsampler();
    double worstLookup = 0.0;
    for (const glm::dvec3& e : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1), glm::dvec3(1, 1, 1),
                                glm::dvec3(2, 1, 0), glm::dvec3(254, 255, 255), glm::dvec3(255, 254, 255),
                                glm::dvec3(255, 255, 254), glm::dvec3(254, 254, 254), glm::dvec3(255, 250, 240)}) {
        const glm::dvec3 lin = RgbUpsampler::decodeSrgb(e / 255.0);
        const glm::dvec3 lab = RgbUpsampler::labOfLinearRgb(lin);
        const double dl = deltaE2000(up.labOf(up.lookup(lin)), lab);
        RgbUpsampler::FitReport report;
        const auto f = up.fit(lin, &report);
        const double df = deltaE2000(up.labOf(f), lab);
        EXPECT_LT(df, 1e-3) << e.x << " " << e.y << " " << e.z;
        EXPECT_LE(report.residual, RgbUpsampler::kFitTolerance);
        worstLookup = std::max(worstLookup, dl);
        std::printf("8-bit (%3.0f, %3.0f, %3.0f): ΔE00 lookup %.2e, fit %.2e (%d iterations), ρ(555 nm) %.6f\n", e.x,
                    e.y, e.z, dl, df, report.iterations, RgbUpsampler::reflectance(f, 555.0));
    }
    EXPECT_LT(worstLookup, 1.0);
    // Tiny linear values below the first z sample still give a spectrum darker than that sample.
    const double z1 = up.zSamples()[1];
    EXPECT_LT(up.linearRgbOf(up.lookup(glm::dvec3(0.5 * z1, 0.25 * z1, 0.0))).x, z1);
}

// --- Bands on a render grid ---------------------------------------------------------------------

namespace {

// The exact band mean of S(c1·λ + c2) (c0 = 0): ∫S(x)dx = (x + √(1 + x²))/2, written without
// cancellation for x < 0.
double exactLinearMean(double c1, double c2, double a, double b) {
    auto F = [](double x) { return x >= 0 ? 0.5 * (x + std::sqrt(1 + x * x)) : 0.5 / (std::sqrt(1 + x * x) - x); };
    return (F(c1 * b + c2) - F(c1 * a + c2)) / (c1 * (b - a));
}

}  // namespace

TEST(RgbUpsampling, BandsAreTheModelAtTheBandCentres) {
    // The default rule: the model is known everywhere, so a band holds ρ(λi), bit for bit.
    const RgbUpsampler::Coefficients cs[] = {{-2e-4, 0.21, -52.0}, {0.0, 1e4, -1e4 * 555.0}, {2.4e-3, -2.6, 700.0}};
    for (Resampling rule : {Resampling::Interpolate, Resampling::Sprague})
        for (const Grid& g : {Grid{300, 740, 5}, Grid{200, 2500, 50}, Grid{380.25, 780.25, 0.5}})
            for (const auto& c : cs) {
                Grid grid = g;
                grid.resampling = rule;
                const std::vector<double> b = RgbUpsampler::bands(c, grid);
                for (int i = 0; i < grid.bands(); ++i)
                    ASSERT_EQ(b[size_t(i)], RgbUpsampler::reflectance(c, grid.wavelength(i))) << grid.str() << " " << i;
            }
}

TEST(RgbUpsampling, BandMeanBandsAreBandAveragesOfTheModel) {
    Grid grids[] = {Grid{300, 740, 5}, Grid{360, 830, 1}, Grid{200, 2500, 50}, Grid{380, 780, 0.5}};
    for (Grid& g : grids) g.resampling = Resampling::BandMean;
    // Smooth spectra against a fine midpoint rule (0.01 and 0.005 nm, Richardson-extrapolated:
    // error O(h⁴), below 1e-12 here).
    const RgbUpsampler::Coefficients smooth[] = {{-2e-4, 0.21, -52.0}, {3.1e-4, -0.33, 80.0}, {2.4e-3, -2.6, 700.0}};
    auto midpoint = [](const RgbUpsampler::Coefficients& c, double lo, double width, int m) {
        double sum = 0.0;
        for (int k = 0; k < m; ++k) sum += RgbUpsampler::reflectance(c, lo + (k + 0.5) * width / m);
        return sum / m;
    };
    for (const Grid& grid : grids)
        for (const auto& c : smooth) {
            const std::vector<double> b = RgbUpsampler::bands(c, grid);
            ASSERT_EQ(static_cast<int>(b.size()), grid.bands());
            for (int i = 0; i < grid.bands(); ++i) {
                const double lo = grid.wavelength(i) - 0.5 * grid.step_nm;
                const int m = static_cast<int>(std::lround(grid.step_nm / 0.01));
                const double exact = (4.0 * midpoint(c, lo, grid.step_nm, 2 * m) - midpoint(c, lo, grid.step_nm, m)) / 3.0;
                ASSERT_NEAR(b[static_cast<size_t>(i)], exact, 1e-9) << grid.str() << " band " << i;
            }
        }
    // Steep ones, like the table's at the gamut boundary (transitions down to 1e-4 nm wide),
    // against the closed form for a linear argument.
    for (const Grid& grid : grids)
        for (double slope : {0.5, 10.0, 1e3, 1e4, -1e4})
            for (double centre : {452.3, 555.0, 612.71}) {
                const RgbUpsampler::Coefficients c{0.0, slope, -slope * centre};
                const std::vector<double> b = RgbUpsampler::bands(c, grid);
                for (int i = 0; i < grid.bands(); ++i) {
                    const double lo = grid.wavelength(i) - 0.5 * grid.step_nm, hi = lo + grid.step_nm;
                    // Outside 360–830 nm ρ holds its end values.
                    double expect = 0.0;
                    const double a1 = std::max(lo, 360.0), b1 = std::min(hi, 830.0);
                    if (b1 > a1) expect += exactLinearMean(slope, c.c2, a1, b1) * (b1 - a1);
                    if (lo < 360.0) expect += RgbUpsampler::reflectance(c, 360.0) * (std::min(hi, 360.0) - lo);
                    if (hi > 830.0) expect += RgbUpsampler::reflectance(c, 830.0) * (hi - std::max(lo, 830.0));
                    ASSERT_NEAR(b[static_cast<size_t>(i)], expect / grid.step_nm, 1e-8)
                        << grid.str() << " band " << i << " slope " << slope << " centre " << centre;
                }
            }
    // Black and white stay exact on any grid, under either rule.
    const RgbUpsampler& up = upsampler();
    for (Grid g : {grids[0], Grid{300, 740, 5}}) {
        for (double v : up.bands(glm::dvec3(0.0), g)) EXPECT_EQ(v, 0.0);
        for (double v : up.bands(glm::dvec3(1.0), g)) EXPECT_EQ(v, 1.0);
    }
}

TEST(RgbUpsampling, ColourOnARenderGrid) {
    // What the renderer sees: the model at the band centres, D65 and the observer resampled onto
    // the grid by the same rule (docs/physics.md "Resampling"). The fit is made at 1 nm, so a 5 nm
    // or 10 nm grid adds its own small quadrature error; printed, and bounded.
    const RgbUpsampler& up = upsampler();
    const Spectrum& d65 = library().get("illuminants/D65", Where{});
    SpectralTable cmf = readSpectralTable(library().root() / "observers/cie1931_2deg.csv", 3);
    for (const Grid& grid : {Grid{360, 830, 1}, Grid{380, 780, 5}, Grid{380, 780, 10}}) {
        const std::vector<double> e = resample(d65, grid);
        std::vector<double> cm[3];
        for (int k = 0; k < 3; ++k) {
            Spectrum s;
            s.wavelengths_nm = cmf.wavelengths_nm;
            s.values = cmf.columns[static_cast<size_t>(k)];
            cm[k] = resample(s, grid);
        }
        auto xyzOf = [&](const std::vector<double>& rho) {
            glm::dvec3 xyz(0.0);
            for (size_t i = 0; i < rho.size(); ++i) xyz += rho[i] * e[i] * glm::dvec3(cm[0][i], cm[1][i], cm[2][i]);
            return xyz;
        };
        const glm::dvec3 white = xyzOf(std::vector<double>(e.size(), 1.0));
        std::vector<std::pair<double, glm::dvec3>> errs;
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int m = 0; m < 3000; ++m) {
            const glm::dvec3 lin(u(rng), u(rng), u(rng));
            const glm::dvec3 xyz = xyzOf(up.bands(lin, grid));
            // Relative to the grid's own white, so only the spectrum's shape is compared.
            const glm::dvec3 lab = xyzToLab(xyz / white.y, white / white.y);
            errs.emplace_back(deltaE2000(lab, RgbUpsampler::labOfLinearRgb(lin)), lin);
        }
        const Stats s = statistics(errs);
        std::printf("grid %-12s ΔE00 median %.4f, 95th %.4f, max %.4f\n", grid.str().c_str(), s.median, s.p95, s.max);
        EXPECT_LT(s.max, 2.0) << grid.str();
    }
}

TEST(RgbUpsampling, FloatEvaluationOfTableCoefficients) {
    // A shader evaluates c0·λ² + c1·λ + c2 in single precision; with nm coefficients the terms
    // cancel, so measure how far ρ moves over the table (printed; docs/upsampling.md).
    const RgbUpsampler& up = upsampler();
    const int res = up.resolution();
    double worst = 0.0;
    for (int l = 0; l < 3; ++l)
        for (int zi = 1; zi < res; zi += 3)
            for (int yi = 0; yi < res; yi += 3)
                for (int xi = 0; xi < res; xi += 3) {
                    const auto c = up.node(l, xi, yi, zi);
                    const float c0 = static_cast<float>(c.c0), c1 = static_cast<float>(c.c1),
                                c2 = static_cast<float>(c.c2);
                    for (float nm = 380.0f; nm <= 780.0f; nm += 10.0f) {
                        const float x = (c0 * nm + c1) * nm + c2;
                        const float s = 0.5f + x / (2.0f * std::sqrt(1.0f + x * x));
                        worst = std::max(worst, std::abs(double(s) - RgbUpsampler::reflectance(c, nm)));
                    }
                }
    std::printf("largest |ρ_float − ρ_double| over the table: %.2e\n", worst);
    EXPECT_LT(worst, 0.05);
}

TEST(RgbUpsampling, Speed) {
    // Printed, not asserted (docs/upsampling.md): per colour, on the 8-bit lattice.
    const RgbUpsampler& up = upsampler();
    std::vector<glm::dvec3> colours;
    for (int i = 0; i < 256; i += 15)
        for (int j = 0; j < 256; j += 15)
            for (int k = 0; k < 256; k += 15) colours.push_back(RgbUpsampler::decodeSrgb(glm::dvec3(i, j, k) / 255.0));
    double sink = 0.0;
    auto time = [&](const char* what, auto&& f) {
        const auto t0 = std::chrono::steady_clock::now();
        for (const glm::dvec3& c : colours) sink += f(c);
        const double us = 1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
                          static_cast<double>(colours.size());
        std::printf("%-32s %8.2f µs per colour\n", what, us);
    };
    time("lookup", [&](const glm::dvec3& c) { return up.lookup(c).c2; });
    time("fit (lookup + polish)", [&](const glm::dvec3& c) { return up.fit(c).c2; });
    time("solve from a flat start", [&](const glm::dvec3& c) { return up.solve(c).coefficients.c2; });
    const RgbUpsampler::Coefficients probe = up.fit({0.6, 0.3, 0.1});
    time("bands on 300:740:5 (89 bands)", [&](const glm::dvec3&) { return RgbUpsampler::bands(probe, Grid{300, 740, 5})[3]; });
    time("bands of a fit, 300:740:5", [&](const glm::dvec3& c) { return up.bands(c, Grid{300, 740, 5})[3]; });
    EXPECT_TRUE(std::isfinite(sink));
}
