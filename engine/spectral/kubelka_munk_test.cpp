#include "spectral/kubelka_munk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace metamer;

namespace {

// Kubelka's closed form as textbooks write it, with a = 1 + K/S, b = √(a² − 1): an independent
// expression of what kubelkaMunkOverSubstrate computes in another form.
double textbookOverSubstrate(double K, double S, double X, double Rg) {
    const double a = 1.0 + K / S, b = std::sqrt(a * a - 1.0), coth = 1.0 / std::tanh(b * S * X);
    return (1.0 - Rg * (a - b * coth)) / (a - Rg + b * coth);
}

// The layer as a pile of n thin sublayers, each one's R and T from the differential equations to
// first order (R = S·dx, T = 1 − (K + S)·dx), combined by the adding rule: converges to the layer.
KubelkaMunkLayer byAddingThinSublayers(double K, double S, double X, int n) {
    const double dx = X / n;
    double r = S * dx, t = 1.0 - (K + S) * dx;
    const double r1 = r, t1 = t;
    for (int i = 1; i < n; ++i) {  // add one sublayer beneath: symmetric layers
        const double d = 1.0 - r * r1;
        const double rn = r + t * t * r1 / d, tn = t * t1 / d;
        r = rn;
        t = tn;
    }
    return {r, t};
}

}  // namespace

TEST(KubelkaMunk, TheIssuesKnownAnswers) {
    // From the numpy and scipy oracles of tests/python/check_kubelka_munk.py (issue 28).
    EXPECT_NEAR(kubelkaMunkInfinite(0.1, 1.0), 0.6417424, 5e-8);
    EXPECT_NEAR(kubelkaMunkLayer(1, 10, 0.1).reflectance, 0.4610336, 5e-8);
    EXPECT_NEAR(kubelkaMunkLayer(1, 10, 0.1).transmittance, 0.4452842, 5e-8);
    EXPECT_NEAR(kubelkaMunkOverSubstrate(1, 10, 0.1, 0.8), 0.7123473, 5e-8);
    EXPECT_NEAR(saundersonMeasured(kubelkaMunkInfinite(0.1, 1.0), 0.04, 0.6), 0.4407273, 5e-8);
}

TEST(KubelkaMunk, ClosedFormEqualsTheTextbookFormAndTheAddingOfThinSublayers) {
    for (double K : {0.01, 1.0, 30.0})
        for (double S : {0.1, 10.0, 200.0})
            for (double X : {1e-3, 0.1, 2.0})
                for (double Rg : {0.0, 0.3, 0.8, 1.0}) {
                    const double r = kubelkaMunkOverSubstrate(K, S, X, Rg);
                    EXPECT_NEAR(r, textbookOverSubstrate(K, S, X, Rg), 1e-12) << K << " " << S << " " << X << " " << Rg;
                }
    const KubelkaMunkLayer exact = kubelkaMunkLayer(1.0, 10.0, 0.1), added = byAddingThinSublayers(1.0, 10.0, 0.1, 1 << 16);
    EXPECT_NEAR(added.reflectance, exact.reflectance, 1e-4);
    EXPECT_NEAR(added.transmittance, exact.transmittance, 1e-4);
}

TEST(KubelkaMunk, ThinAndThickLimits) {
    for (double Rg : {0.0, 0.2, 0.9}) {
        EXPECT_NEAR(kubelkaMunkOverSubstrate(2.0, 50.0, 1e-12, Rg), Rg, 1e-9);
        EXPECT_EQ(kubelkaMunkOverSubstrate(2.0, 50.0, 0.0, Rg), Rg);
        EXPECT_NEAR(kubelkaMunkOverSubstrate(2.0, 50.0, 10.0, Rg), kubelkaMunkInfinite(2.0, 50.0), 1e-12);
        EXPECT_EQ(kubelkaMunkOverSubstrate(2.0, 50.0, INFINITY, Rg), kubelkaMunkInfinite(2.0, 50.0));
    }
}

TEST(KubelkaMunk, NoNaNAtTheExtremes) {
    // A clear layer, a pure absorber, a pure scatterer, enormous and tiny products.
    EXPECT_EQ(kubelkaMunkLayer(0, 0, 1).reflectance, 0.0);
    EXPECT_EQ(kubelkaMunkLayer(0, 0, 1).transmittance, 1.0);
    EXPECT_NEAR(kubelkaMunkLayer(3, 0, 0.5).transmittance, std::exp(-1.5), 1e-15);
    EXPECT_EQ(kubelkaMunkLayer(3, 0, 0.5).reflectance, 0.0);
    EXPECT_NEAR(kubelkaMunkLayer(0, 4, 0.5).reflectance, 2.0 / 3.0, 1e-15);  // SX/(1 + SX)
    EXPECT_NEAR(kubelkaMunkLayer(0, 4, 0.5).transmittance, 1.0 / 3.0, 1e-15);
    EXPECT_EQ(kubelkaMunkInfinite(1.0, 0.0), 0.0);
    EXPECT_EQ(kubelkaMunkInfinite(0.0, 1.0), 1.0);
    for (double K : {0.0, 1e-300, 1e-8, 1.0, 1e8, 1e300})
        for (double S : {0.0, 1e-300, 1e-8, 1.0, 1e8, 1e300})
            for (double X : {0.0, 1e-300, 1e-6, 1.0, 1e6, 1e300, double(INFINITY)})
                for (double Rg : {0.0, 0.5, 1.0}) {
                    const double r = kubelkaMunkOverSubstrate(K, S, X, Rg);
                    ASSERT_TRUE(std::isfinite(r) && r >= 0.0 && r <= 1.0 + 1e-12)
                        << "K " << K << " S " << S << " X " << X << " Rg " << Rg << ": " << r;
                }
    // Large K/S: R∞ ≈ S/(2K), no cancellation.
    EXPECT_NEAR(kubelkaMunkInfinite(1e8, 1.0) / 5e-9, 1.0, 1e-7);
}

TEST(KubelkaMunk, StacksApplyBottomUpAndOneLayerSplitInTwoIsTheSameLayer) {
    const std::vector<KubelkaMunkFilm> split{{1.0, 10.0, 0.04}, {1.0, 10.0, 0.06}};
    EXPECT_NEAR(kubelkaMunkStack(split, 0.8), kubelkaMunkOverSubstrate(1, 10, 0.1, 0.8), 1e-14);
    const std::vector<KubelkaMunkFilm> twoPaints{{5.0, 1.0, 0.2}, {0.1, 30.0, 0.02}};
    EXPECT_NEAR(kubelkaMunkStack(twoPaints, 0.5),
                kubelkaMunkOverSubstrate(0.1, 30.0, 0.02, kubelkaMunkOverSubstrate(5.0, 1.0, 0.2, 0.5)), 1e-15);
    EXPECT_NE(kubelkaMunkStack(twoPaints, 0.5),
              kubelkaMunkOverSubstrate(5.0, 1.0, 0.2, kubelkaMunkOverSubstrate(0.1, 30.0, 0.02, 0.5)));
}

TEST(KubelkaMunk, MixAddsEachPigmentsConcentrationTimesItsConstantsToTheFilmsOwn) {
    const std::vector<KubelkaMunkPigment> whiteAndBlack{{0.1, 2.0, 3000.0}, {0.002, 50000.0, 400.0}};
    const KubelkaMunkCoefficients bare = kubelkaMunkMix(whiteAndBlack);
    EXPECT_NEAR(bare.K, 0.1 * 2.0 + 0.002 * 50000.0, 1e-12);  // 100.2
    EXPECT_NEAR(bare.S, 0.1 * 3000.0 + 0.002 * 400.0, 1e-12);  // 300.8
    const KubelkaMunkCoefficients inBinder = kubelkaMunkMix(whiteAndBlack, {5.0, 7.0});
    EXPECT_NEAR(inBinder.K, 105.2, 1e-12);
    EXPECT_NEAR(inBinder.S, 307.8, 1e-12);
    // Not normalized: doubling every concentration doubles K and S, and keeps K/S (and R∞).
    const std::vector<KubelkaMunkPigment> twice{{0.2, 2.0, 3000.0}, {0.004, 50000.0, 400.0}};
    const KubelkaMunkCoefficients doubled = kubelkaMunkMix(twice);
    EXPECT_NEAR(doubled.K, 2.0 * bare.K, 1e-12);
    EXPECT_NEAR(kubelkaMunkInfinite(doubled.K, doubled.S), kubelkaMunkInfinite(bare.K, bare.S), 1e-15);
    const KubelkaMunkCoefficients none = kubelkaMunkMix({}, {5.0, 7.0});
    EXPECT_EQ(none.K, 5.0);
    EXPECT_EQ(none.S, 7.0);
}

TEST(KubelkaMunk, SaundersonRoundTripsAndKOverSInverts) {
    for (double R : {0.0, 0.05, 0.5, 0.95})
        EXPECT_NEAR(saundersonInverse(saundersonMeasured(R, 0.04, 0.6), 0.04, 0.6), R, 1e-15);
    EXPECT_NEAR(saundersonMeasured(0.3, 0.04, 0.6) - saundersonBody(0.3, 0.04, 0.6), 0.04, 1e-16);
    for (double q : {1e-4, 0.1, 3.0, 100.0}) EXPECT_NEAR(kOverSFromInfinite(kubelkaMunkInfinite(q, 1.0)) / q, 1.0, 1e-10);
}

TEST(KubelkaMunk, DiffuseFresnelReflectanceByIntegration) {
    EXPECT_NEAR(saundersonK1(1.5), 0.04, 1e-16);
    EXPECT_NEAR(internalDiffuseReflectance(1.5), 0.59635, 5e-6);
    EXPECT_NEAR(externalDiffuseReflectance(1.5), 0.09178, 5e-6);
    EXPECT_EQ(internalDiffuseReflectance(1.0), 0.0);
    EXPECT_NEAR(externalDiffuseReflectance(1.0), 0.0, 1e-15);
    for (double n : {1.2, 1.33, 1.5, 1.7, 2.4}) {
        // Stokes' reciprocity for diffuse light: 1 − r_i = (1 − r_e)/n².
        EXPECT_NEAR(1.0 - internalDiffuseReflectance(n), (1.0 - externalDiffuseReflectance(n)) / (n * n), 1e-12) << n;
    }
}
