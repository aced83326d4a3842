// reference/lobe_table.h and lobe_integrals.h: the oracles against each other, the table against
// them on a sample and at the closed forms, its symmetries, the early-out, the disk cache. The
// certification over 10⁴ random and 10³ grazing configurations per gloss is
// tests/lobe_certification_test.cpp.
#include "reference/hemisphere_lobe.h"
#include "reference/lobe_integrals.h"
#include "reference/lobe_table.h"

#include "support/lobe_oracles.h"
#include "support/temp_folder.h"

#include "lobe_lookup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <random>
#include <vector>

using namespace metamer;
using glm::dvec3;

namespace {

constexpr double kPi = std::numbers::pi;

// v = n = u: I = 2π·∫₀^{π/2} cos(θ/2)^N·cos θ·sin θ dθ; with c = cos(θ/2), sin θ dθ = −4c dc and
// cos θ = 2c² − 1: I = 8π·[2c^(N+4)/(N+4) − c^(N+2)/(N+2)] from 1/√2 to 1.
double normalView(double N) {
    const double c = 1.0 / std::sqrt(2.0);
    return 8.0 * kPi * (2.0 / (N + 4.0) * (1.0 - std::pow(c, N + 4.0)) - 1.0 / (N + 2.0) * (1.0 - std::pow(c, N + 2.0)));
}

using Configuration = test::LobeConfiguration;

// Every third view grazing (n·v < 0.03), every second hemisphere's boundary near the lobe.
std::vector<Configuration> configurations(int count, double gloss, unsigned seed) {
    test::LobeConfigurations random(seed);
    std::vector<Configuration> out;
    for (int i = 0; i < count; ++i) out.push_back(random.next(gloss, i % 3 == 0 ? 0.03 : 1.0, i % 2 == 0));
    return out;
}

}  // namespace

TEST(LobeOracles, RingAndLuneQuadraturesAgree) {
    // Two quadratures with nothing in common but the integrand: the ring oracle exact on each
    // ring of half vectors, the lune oracle adaptive over directions.
    for (double N : {1.0, 60.0, 10000.0}) {
        double worst = 0.0;
        for (const Configuration& c : configurations(24, N, 3)) {
            const double unoccluded = test::ringOracle(c.n, c.v, c.u, N, false);
            const double ring = test::ringOracle(c.n, c.v, c.u, N), lune = test::luneOracle(c.n, c.v, c.u, N);
            worst = std::max(worst, std::fabs(ring - lune) / unoccluded);
        }
        std::printf("N = %g: ring vs lune oracle, max difference %.2e of the unoccluded lobe\n", N, worst);
        EXPECT_LT(worst, 1e-9) << "N = " << N;
    }
}

TEST(LobeOracles, ClosedForms) {
    const dvec3 z(0, 0, 1);
    for (double N : {0.5, 1.0, 60.0, 10000.0}) {
        EXPECT_NEAR(test::ringOracle(z, z, z, N) / normalView(N), 1.0, 1e-10) << N;
        EXPECT_NEAR(test::luneOracle(z, z, z, N) / normalView(N), 1.0, 1e-9) << N;
        EXPECT_NEAR(test::ringOracle(z, z, z, N, false) / normalView(N), 1.0, 1e-10) << N;
    }
    // N = 0: the hemisphere's irradiance factor, by both.
    const dvec3 n(0, 0, 1), v = glm::normalize(dvec3(0.3, 0, 1));
    for (double c : {-0.5, 0.0, 0.3, 1.0}) {
        const dvec3 u(std::sqrt(1 - c * c), 0, c);
        EXPECT_DOUBLE_EQ(test::ringOracle(n, v, u, 0.0), kPi * (1 + c) / 2);
        EXPECT_DOUBLE_EQ(hemisphereLobe(nullptr, n, v, u).x, kPi * (1 + c) / 2);
    }
}

TEST(LobeTable, NormalViewMatchesTheClosedForm) {
    // v = n = u: the table's corner (x1 = 1, x2 = 1) against the closed form, to 10⁻⁶.
    const dvec3 z(0, 0, 1);
    for (double N : {1.0, 60.0, 10000.0}) {
        const auto table = lobeTableFor(N);
        const glm::dvec2 lobe = lobeIntegrals(*table, z, z, z);
        EXPECT_NEAR(lobe.x / normalView(N), 1.0, 1e-6) << "N = " << N;
        EXPECT_NEAR(lobe.y / normalView(N), 1.0, 1e-6) << "N = " << N;
    }
}

TEST(LobeTable, AgreesWithTheOraclesOnASample) {
    // 300 configurations per gloss (the certification does 11 000): within 10⁻⁴ of the unoccluded
    // lobe, and the unoccluded lobe itself within 10⁻⁵.
    for (double N : {1.0, 60.0, 10000.0}) {
        const auto table = lobeTableFor(N);
        double worst = 0.0, worstUnoccluded = 0.0;
        for (const Configuration& c : configurations(300, N, 11)) {
            const double unoccluded = test::ringOracle(c.n, c.v, c.u, N, false, 1e-10);
            const glm::dvec2 lobe = lobeIntegrals(*table, c.n, c.v, c.u);
            worst = std::max(worst, std::fabs(lobe.x - test::ringOracle(c.n, c.v, c.u, N, true, 1e-10)) / unoccluded);
            worstUnoccluded = std::max(worstUnoccluded, std::fabs(lobe.y / unoccluded - 1.0));
        }
        std::printf("N = %g: table vs ring oracle, max %.2e of the unoccluded lobe; unoccluded lobe max %.2e\n", N,
                    worst, worstUnoccluded);
        EXPECT_LT(worst, 1e-4) << "N = " << N;
        EXPECT_LT(worstUnoccluded, 1e-5) << "N = " << N;
    }
}

TEST(LobeTable, OppositeHemispheresAddUpToTheUnoccludedLobe) {
    // A sky and a ground looked up separately (not paired): the table is built so that
    // f(π − β_w, −x2) = 1 − f(β_w, x2), which the lookup keeps to float rounding.
    const auto table = lobeTableFor(60.0);
    for (const Configuration& c : configurations(500, 60.0, 5)) {
        const glm::dvec2 sky = lobeIntegrals(*table, c.n, c.v, c.u), ground = lobeIntegrals(*table, c.n, c.v, -c.u);
        EXPECT_NEAR(sky.x + ground.x, sky.y, 1e-6 * sky.y);
    }
}

TEST(LobeTable, TheEarlyOutConeHoldsTheWholeLobe) {
    // Where the hemisphere's boundary lies outside the interval's cone about the mirror direction,
    // the lookup answers 0 or the whole lobe without reading the table: the exact value is within
    // 10⁻⁷ of that (the cone's tail). The cone is narrow only for glossy lobes (at N = 60 its half
    // angle is about 80°), so two glossy ones.
    for (double N : {200.0, 10000.0}) {
        const auto table = lobeTableFor(N);
        int decided = 0;
        for (const Configuration& c : configurations(400, N, 9)) {
            const double nv = glm::dot(c.n, c.v), k = LOBE_X1_WARP * std::sqrt(N + 1.0);
            const double x1 = std::log1p(k * std::asin(nv)) / std::log1p(k * 0.5 * kPi);
            const int interval = std::clamp(int(std::floor(x1 * (LOBE_MOMENT_NODES - 1))), 0, LOBE_MOMENT_NODES - 2);
            const double ur = glm::dot(c.u, 2.0 * nv * c.n - c.v);
            if (!(std::fabs(ur) > std::bit_cast<float>(table->data[LOBE_CONES_OFFSET + interval].x))) continue;
            ++decided;
            const glm::dvec2 lobe = lobeIntegrals(*table, c.n, c.v, c.u);
            EXPECT_EQ(lobe.x, ur > 0.0 ? lobe.y : 0.0);
            const double exact = test::ringOracle(c.n, c.v, c.u, N, true, 1e-10);
            const double whole = test::ringOracle(c.n, c.v, c.u, N, false, 1e-10);
            EXPECT_NEAR(exact, ur > 0.0 ? whole : 0.0, 1e-7 * whole) << "N = " << N;
        }
        std::printf("N = %g: %d of 400 configurations decided by the cone\n", N, decided);
        EXPECT_GT(decided, 20);
    }
}

TEST(LobeTable, AViewBelowTheTangentPlaneIsTakenAtTheHorizon) {
    // Interpolated normals turn away from the eye at silhouettes: n·v < 0 is looked up as the
    // view's projection onto the tangent plane (continuous at n·v = 0).
    const auto table = lobeTableFor(60.0);
    const dvec3 n(0, 0, 1), u = glm::normalize(dvec3(-0.2, 0.1, 1));
    const glm::dvec2 below = lobeIntegrals(*table, n, glm::normalize(dvec3(1, 0, -0.05)), u);
    const glm::dvec2 horizon = lobeIntegrals(*table, n, dvec3(1, 0, 0), u);
    EXPECT_NEAR(below.x, horizon.x, 1e-12);
    EXPECT_NEAR(below.y, horizon.y, 1e-12);
    const glm::dvec2 above = lobeIntegrals(*table, n, glm::normalize(dvec3(1, 0, 1e-7)), u);
    EXPECT_NEAR(above.x, horizon.x, 1e-5 * horizon.y);
}

TEST(LobeIntegrals, MomentsOfTheNormalView) {
    // At v = n the lobe is symmetric about n: no centroid offset, equal spreads, and its mass is
    // the closed form.
    const LobeMoments m = lobeMoments(0.5 * kPi, 60.0, 1e-7);
    EXPECT_NEAR(m.unoccluded / normalView(60.0), 1.0, 1e-10);
    EXPECT_NEAR(m.gamma, 0.0, 1e-12);
    EXPECT_NEAR(m.sigma1, m.sigma2, 1e-10);
    EXPECT_LT(m.coneHalfAngle, 0.5 * kPi);
}

class LobeTableCache : public test::TempFolderTest {};

TEST_F(LobeTableCache, RoundTripAndDamagedFilesAreIgnored) {
    // A table of made-up values (the file format, not the numbers, is under test).
    LobeTable t;
    t.gloss = 42.5;
    t.data.resize(LOBE_TABLE_UVEC4);
    auto bits = [](float a, float b, float c, float d) {
        return glm::uvec4(std::bit_cast<uint32_t>(a), std::bit_cast<uint32_t>(b), std::bit_cast<uint32_t>(c),
                          std::bit_cast<uint32_t>(d));
    };
    // Moments (γ, σ1, σ2, ln I) and cones (sine, two slopes) as floats in their ranges, any bits after.
    for (size_t i = 0; i < t.data.size(); ++i)
        t.data[i] = i < LOBE_CONES_OFFSET    ? bits(float(i) * 1e-3f, 0.5f, 0.25f, -1.0f)
                    : i < LOBE_VALUES_OFFSET ? bits(0.5f, 0.01f, -0.01f, 0.0f)
                                             : glm::uvec4(uint32_t(i), 0xffffffffu, 0x7fc00000u, 1u);
    const auto file = dir / lobeCacheFileName(t.gloss);
    writeLobeTable(file, t);
    const auto back = readLobeTable(file, t.gloss);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->data, t.data);
    EXPECT_FALSE(readLobeTable(file, 42.25)) << "another gloss's header";
    EXPECT_FALSE(readLobeTable(dir / "missing.bin", t.gloss));
    EXPECT_FALSE(readLobeTable(dir, t.gloss)) << "a folder";
    // Truncated, a flipped version byte, a NaN inside: each ignored.
    auto damaged = [&](auto edit) {
        std::string bytes;
        {
            std::ifstream in(file, std::ios::binary);
            bytes.assign(std::istreambuf_iterator<char>(in), {});
        }
        edit(bytes);
        const auto copy = dir / "damaged.bin";
        std::ofstream(copy, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return readLobeTable(copy, t.gloss);
    };
    EXPECT_FALSE(damaged([](std::string& b) { b.resize(b.size() - 16); }));
    EXPECT_FALSE(damaged([](std::string& b) { b[8] ^= 1; }));
    EXPECT_FALSE(damaged([](std::string& b) { b[b.size() / 2] ^= 0x10; })) << "a bit flipped among the values";
    EXPECT_FALSE(damaged([&](std::string& b) {  // a NaN among the moments
        const float nan = std::nanf("");
        std::memcpy(&b[b.size() - (LOBE_TABLE_UVEC4 - 3) * sizeof(glm::uvec4)], &nan, 4);
    }));
    EXPECT_TRUE(damaged([](std::string&) {}));
    // Absurd but finite values under a valid checksum (issue 51, class 7): a spread of 10³⁰ rad, a
    // cone's sine of 7, ln I_unoccluded of 10⁴ — each not a table this program makes: ignored.
    for (const glm::uvec4 entry : {bits(0.1f, 1e30f, 0.25f, -1.0f), bits(0.1f, 0.5f, 0.25f, 1e4f)}) {
        LobeTable absurd = t;
        absurd.data[7] = entry;
        writeLobeTable(dir / "absurd.bin", absurd);
        EXPECT_FALSE(readLobeTable(dir / "absurd.bin", t.gloss));
    }
    LobeTable absurd = t;
    absurd.data[LOBE_CONES_OFFSET + 3] = bits(7.0f, 0.01f, -0.01f, 0.0f);
    writeLobeTable(dir / "absurd.bin", absurd);
    EXPECT_FALSE(readLobeTable(dir / "absurd.bin", t.gloss));
}

TEST_F(LobeTableCache, TablesAreReadFromTheFolderTheVariableNames) {
    // A file placed in the folder METAMER_LOBE_CACHE names is what lobeTableFor returns (made-up
    // values, so it cannot have been built), and it is kept for the process.
    const char* old = std::getenv("METAMER_LOBE_CACHE");
    const std::string saved = old ? old : "";
    setenv("METAMER_LOBE_CACHE", dir.c_str(), 1);
    EXPECT_EQ(lobeCacheFolder(), dir);
    LobeTable t;
    t.gloss = 3.25;
    t.data.assign(LOBE_TABLE_UVEC4, glm::uvec4(0x3e800000u));  // 0.25f
    writeLobeTable(dir / lobeCacheFileName(t.gloss), t);
    const auto read = lobeTableFor(t.gloss);
    EXPECT_EQ(read->data, t.data);
    EXPECT_EQ(lobeTableFor(t.gloss), read) << "kept for the process";
    old ? setenv("METAMER_LOBE_CACHE", saved.c_str(), 1) : unsetenv("METAMER_LOBE_CACHE");
}
