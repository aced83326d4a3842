#include "spectral/dielectric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace metamer;

namespace {

// The slab summed ray by ray (reflections inside, each pass attenuated by τ), for one
// polarization of single-interface reflectance r: an independent path to the closed form.
void slabBySummation(double r, double tau, double& reflectance, double& transmittance) {
    reflectance = r;
    transmittance = 0.0;
    double inside = (1.0 - r) * tau;  // power just before the back face
    for (int bounce = 0; bounce < 400; ++bounce) {
        transmittance += inside * (1.0 - r);
        inside *= r * tau;  // reflected at the back face, back to the front
        reflectance += inside * (1.0 - r);
        inside *= r * tau;  // reflected at the front face, to the back again
    }
}

}  // namespace

TEST(Dielectric, SlabAtNormalIncidenceHasTheTextbookValues) {
    // n = 1.5: R₁ = 0.04, T = (1 − R₁)²/(1 − R₁²) = 0.9230769…; with τ = 0.5, 0.4609844….
    EXPECT_NEAR(fresnelReflectance(1.0, 1.5, 1.0).unpolarized(), 0.04, 1e-15);
    EXPECT_NEAR(slab(1.5, 1.0, 1.0).transmittance, 0.9230769230769231, 1e-15);
    EXPECT_NEAR(slab(1.5, 1.0, 0.5).transmittance, 0.46098439375750304, 1e-15);
    EXPECT_NEAR(slab(1.5, 1.0, 1.0).reflectance, 0.07692307692307693, 1e-15);  // 2R₁/(1 + R₁)
    EXPECT_NEAR(slab(1.5, 1.0, 0.5).reflectance, 0.04921968787515006, 1e-15);
    const SlabReflectanceTransmittance clear = slab(1.5, 1.0, 1.0);
    EXPECT_NEAR(clear.reflectance + clear.transmittance, 1.0, 1e-15);  // nothing absorbed
}

TEST(Dielectric, SlabClosedFormEqualsTheRayByRaySumAtEveryAngle) {
    for (double degrees : {0.0, 30.0, 60.0, 80.0, 89.0}) {
        for (double tau : {1.0, 0.9, 0.5, 0.01}) {
            const double cosI = std::cos(degrees * std::numbers::pi / 180.0);
            const FresnelReflectance f = fresnelReflectance(1.0, 1.5, cosI);
            double rs, ts, rp, tp;
            slabBySummation(f.s, tau, rs, ts);
            slabBySummation(f.p, tau, rp, tp);
            const SlabReflectanceTransmittance s = slab(1.5, cosI, tau);
            EXPECT_NEAR(s.transmittance, 0.5 * (ts + tp), 1e-14) << degrees << "° τ " << tau;
            EXPECT_NEAR(s.reflectance, 0.5 * (rs + rp), 1e-14) << degrees << "° τ " << tau;
        }
    }
}

TEST(Dielectric, FresnelAt60DegreesAndBrewsterAndTotalInternalReflection) {
    // n = 1.5 at 60°: cos θt = √(1 − (sin 60°/1.5)²) = √(2/3); Rs and Rp by hand.
    const double cosT = std::sqrt(2.0 / 3.0);
    const double rs = (0.5 - 1.5 * cosT) / (0.5 + 1.5 * cosT), rp = (cosT - 0.75) / (cosT + 0.75);
    const FresnelReflectance f = fresnelReflectance(1.0, 1.5, 0.5);
    EXPECT_NEAR(f.s, rs * rs, 1e-15);
    EXPECT_NEAR(f.p, rp * rp, 1e-15);
    EXPECT_NEAR(slab(1.5, 0.5, 1.0).transmittance, 0.5 * ((1 - rs * rs) / (1 + rs * rs) + (1 - rp * rp) / (1 + rp * rp)), 1e-15);
    // At Brewster's angle (tan θ = n) p is not reflected at all.
    const double brewster = std::atan(1.5);
    EXPECT_NEAR(fresnelReflectance(1.0, 1.5, std::cos(brewster)).p, 0.0, 1e-30);
    // From glass to air beyond the critical angle (41.8° for n = 1.5): totally reflected.
    const FresnelReflectance tir = fresnelReflectance(1.5, 1.0, std::cos(45.0 * std::numbers::pi / 180.0));
    EXPECT_TRUE(tir.total);
    EXPECT_EQ(tir.unpolarized(), 1.0);
    EXPECT_FALSE(fresnelReflectance(1.5, 1.0, std::cos(40.0 * std::numbers::pi / 180.0)).total);
}

TEST(Dielectric, NBk7BySellmeierHasItsCatalogueIndexAndAbbeNumber) {
    const RefractiveIndex n = nbk7();
    EXPECT_NEAR(n.at(587.5618), 1.5168, 5e-6);
    EXPECT_NEAR(abbeNumber(n), 64.17, 0.01);
    EXPECT_GT(n.at(400.0), n.at(700.0));  // normal dispersion
}

TEST(Dielectric, IndexModelsConstantTableCauchy) {
    RefractiveIndex t;
    t.kind = RefractiveIndex::Kind::Table;
    t.wavelengths_nm = {400, 500, 700};
    t.values = {1.53, 1.52, 1.51};
    EXPECT_DOUBLE_EQ(t.at(450), 1.525);
    EXPECT_DOUBLE_EQ(t.at(300), 1.53);  // constant beyond the data
    EXPECT_DOUBLE_EQ(t.at(800), 1.51);
    RefractiveIndex c;
    c.kind = RefractiveIndex::Kind::Cauchy;
    c.b = {1.5, 0.004, 0.0};  // A, B (µm²)
    EXPECT_NEAR(c.at(500), 1.5 + 0.004 / 0.25, 1e-15);
    EXPECT_EQ(RefractiveIndex{}.at(550), 1.0);
}

TEST(Dielectric, BeerLambertMultipliesAndConcentrationsSquare) {
    // A dye of absorbance 50 per metre through 1 cm: 10^−0.5; doubling the concentration (the
    // absorbance) squares the transmittance; two media in a row multiply.
    const double t = beerLambert(50.0, 0.01);
    EXPECT_NEAR(t, std::pow(10.0, -0.5), 1e-15);
    EXPECT_NEAR(beerLambert(100.0, 0.01), t * t, 1e-15);
    EXPECT_NEAR(beerLambert(50.0, 0.01) * beerLambert(20.0, 0.02), beerLambert(1.0, 0.5 + 0.4), 1e-15);
    // Through a slab at 60° the path is d/cos θt.
    EXPECT_NEAR(slabInternalTransmittance(1.5, 0.5, 50.0, 0.01), beerLambert(50.0, 0.01 / std::sqrt(2.0 / 3.0)), 1e-15);
}
