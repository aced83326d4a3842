// Transparent objects (docs/physics.md, "Transparent objects"): known answers for thin filters and
// absorbing media, through the GPU transmission pass and the CPU reference each on its own, and
// the two against each other. Every radiance here can be written down: a white Lambertian wall
// under an ambient irradiance E has radiance L₀ = E/π, and what lies in front of it multiplies L₀
// band by band.
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"
#include "scene/shapes.h"
#include "support/gpu.h"
#include "support/interior_comparison.h"
#include "support/scene_builders.h"

#include <cmath>
#include <cstring>
#include <numbers>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kPx = 33;  // odd: the middle pixel's ray passes through the axis

// A white wall at z = 0 under an ambient light, radiance L₀(λ) = E(λ)/π (L0 below); an orthographic
// camera looking down −z at a 1 m square of it (pixel (x, y) sees (xw(x), yw(y))).
Scene litWall(const Grid& grid = Grid{400, 700, 10}, int px = kPx) {
    Scene s = emptyScene(grid, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, px, px));
    s.materials.push_back(lambertian(1.0, "wall"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
    s.lights.push_back(ambientLight(gaussianSpectrum(550, 90, 2.0, 300, 800, 1), kPi));
    return s;
}
// The wall's radiance, W·sr⁻¹·m⁻²·nm⁻¹: ρE/π with ρ = 1 and E the ambient irradiance.
double L0(const SceneOnGrid& g, int b) { return g.lights[0][size_t(b)] / kPi; }
double xw(int x, int px = kPx) { return ((x + 0.5) / px - 0.5); }
double yw(int y, int px = kPx) { return (0.5 - (y + 0.5) / px); }

// A smooth transmittance with structure across the grid.
Spectrum gelTransmittance() {
    std::vector<double> nm, v;
    for (double l = 300; l <= 800; l += 5) {
        nm.push_back(l);
        v.push_back(0.05 + 0.9 / (1.0 + std::exp(-(l - 560) / 15)));  // a long-pass (orange) gel
    }
    return sampledSpectrum(nm, v, "long-pass gel");
}
Spectrum dyeAbsorbance(double scale) {  // m⁻¹: a band around 520 nm
    return gaussianSpectrum(520, 40, scale, 300, 800, 1);
}

uint32_t addMaterial(Scene& s, Material m) {
    s.materials.push_back(std::move(m));
    return uint32_t(s.materials.size() - 1);
}
void addBox(Scene& s, glm::dvec3 centre, glm::dvec3 size, uint32_t material) {
    Mesh b = makeBox(centre, size);
    b.material = material;
    b.name = "box";
    s.meshes.push_back(std::move(b));
}

SpectralCube gpuRender(const Scene& s, const SceneOnGrid& g) {
    const uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g);
    SpectralCube c = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    return c;
}
SpectralCube cpuRender(const Scene& s, const SceneOnGrid& g) { return renderReference(s, g).cube; }
// The reference's pixel in double, before the cube rounds it to float.
std::vector<double> cpuPixel(const Scene& s, const SceneOnGrid& g, int x, int y) {
    ReferenceRenderer r(s, g);
    std::vector<double> radiance(size_t(r.bands()));
    r.pixel(x, y, radiance.data());
    return radiance;
}

// Both renderers' pixel (x, y) against expected(b), relative `tolerance` (GPU: float).
template <typename Expected>
void expectPixel(const Scene& s, int x, int y, Expected expected, double gpuTolerance, const char* what) {
    const SceneOnGrid g = onGrid(s);
    const SpectralCube gc = gpuRender(s, g);
    const std::vector<double> cc = cpuPixel(s, g, x, y);
    for (int b = 0; b < gc.bands(); ++b) {
        const double e = expected(g, b);
        EXPECT_NEAR(cc[size_t(b)], e, 1e-10 * e + 1e-30) << what << ": cpu, band " << b;
        EXPECT_NEAR(gc.at(x, y, b), e, gpuTolerance * e + 1e-30) << what << ": gpu, band " << b;
    }
}

}  // namespace

TEST(Transparency, WallBehindAFilterIsTTimesL0) {
    Scene s = litWall();
    const uint32_t gel = addMaterial(s, filterSheet(gelTransmittance(), "gel"));
    s.meshes.push_back(quad({0, 0, 0.5}, {0, 0, 1}, 0.5, 0.5, gel));
    const SceneOnGrid g = onGrid(s);
    const SpectralCube gc = gpuRender(s, g), cc = cpuRender(s, g);
    for (int y = 0; y < kPx; ++y)
        for (int x = 0; x < kPx; ++x) {
            const bool covered = std::fabs(xw(x)) < 0.25 && std::fabs(yw(y)) < 0.25;
            for (int b = 0; b < gc.bands(); ++b) {
                const double e = L0(g, b) * (covered ? g.materials[gel].transmittance[b] : 1.0);
                ASSERT_NEAR(cc.at(x, y, b), e, 1e-7 * e) << x << "," << y << " band " << b;
                ASSERT_NEAR(gc.at(x, y, b), e, 1e-6 * e) << x << "," << y << " band " << b;
            }
        }
}

TEST(Transparency, AFilterBehindTheWallIsHidden) {
    Scene s = litWall();
    const uint32_t gel = addMaterial(s, filterSheet(constantSpectrum(0.3), "gel"));
    s.meshes.push_back(quad({0, 0, -0.5}, {0, 0, 1}, 2, 2, gel));
    expectPixel(s, kPx / 2, kPx / 2, [](const SceneOnGrid& g, int b) { return L0(g, b); }, 1e-6, "hidden filter");
}

// Multiplication commutes; in float it is exact up to the rounding of each product: the two
// orders agree to 1 ulp.
TEST(Transparency, TwoFiltersGiveTheSameImageInEitherDrawOrder) {
    Scene s = litWall();
    const uint32_t a = addMaterial(s, filterSheet(gelTransmittance(), "gel"));
    const uint32_t b = addMaterial(s, filterSheet(gaussianSpectrum(480, 60, 0.9, 300, 800, 1), "blue"));
    Scene reversed = s;
    s.meshes.push_back(quad({0.1, 0, 0.3}, {0, 0, 1}, 0.5, 0.5, a));
    s.meshes.push_back(quad({-0.1, 0, 0.6}, {0, 0, 1}, 0.5, 0.5, b));
    reversed.meshes.push_back(s.meshes[2]);
    reversed.meshes.push_back(s.meshes[1]);
    const SceneOnGrid g = onGrid(s);
    const SpectralCube one = gpuRender(s, g), other = gpuRender(reversed, onGrid(reversed));
    int overlapped = 0;
    for (int y = 0; y < kPx; ++y)
        for (int x = 0; x < kPx; ++x) {
            const bool both = std::fabs(xw(x)) < 0.15 && std::fabs(yw(y)) < 0.25;
            overlapped += both;
            for (int k = 0; k < one.bands(); ++k) {
                const float u = one.at(x, y, k), v = other.at(x, y, k);
                ASSERT_LE(std::fabs(u - v), std::nextafter(std::fabs(u), INFINITY) - std::fabs(u)) << x << "," << y;
                if (both) {
                    const double e = L0(g, k) * g.materials[a].transmittance[k] * g.materials[b].transmittance[k];
                    ASSERT_NEAR(u, e, 1e-6 * e);
                }
            }
        }
    EXPECT_GT(overlapped, 50);
}

// Beer–Lambert: a box of depth d seen face-on transmits 10^(−a·d); dyes add ε·c per cm.
TEST(Transparency, DyeCubeFaceOnIsTenToMinusEpsilonCD) {
    Scene s = litWall();
    Material dye = lambertian(0.0, "dye");
    Material::Dye d;
    d.absorptivity = sceneSpectrum(gaussianSpectrum(520, 40, 3000.0, 300, 800, 1), SpectrumKind::Absorbance);
    d.concentration = 2e-4;  // mol/L: a peak absorbance of 0.6 per cm
    dye.dyes.push_back(d);
    const uint32_t m = addMaterial(s, dye);
    const double depth = 0.01;  // a 1 cm cuvette
    addBox(s, {0, 0, 0.3}, {0.4, 0.4, depth}, m);
    expectPixel(
        s, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            const double eps = 3000.0 * std::exp(-0.5 * std::pow((g.wavelengths_nm[b] - 520) / 40, 2));
            return L0(g, b) * std::pow(10.0, -eps * 2e-4 * (depth * 100.0));
        },
        2e-5, "dye cube");
}

// A sphere seen through its centre: the path is its diameter (the UV sphere has a vertex on the
// axis at both ends).
TEST(Transparency, SphereThroughItsCentreHasPathTwoR) {
    Scene s = litWall();
    const uint32_t m = addMaterial(s, absorbingMedium(dyeAbsorbance(5.0)));
    const double r = 0.2;
    Mesh ball = makeSphere({0, 0, 0.5}, r, 64);
    ball.material = m;
    s.meshes.push_back(ball);
    expectPixel(
        s, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) { return L0(g, b) * std::pow(10.0, -g.materials[m].absorbance[b] * 2 * r); },
        2e-5, "sphere");
}

// Doubling the concentration squares the transmittance; two media overlapping along a ray multiply.
TEST(Transparency, DoubledConcentrationSquaresAndOverlappingMediaMultiply) {
    auto transmittance = [](const Scene& s, int b) {
        const SceneOnGrid g = onGrid(s);
        const SpectralCube c = gpuRender(s, g);
        return std::make_pair(c.at(kPx / 2, kPx / 2, b) / L0(g, b), cpuPixel(s, g, kPx / 2, kPx / 2)[size_t(b)] / L0(g, b));
    };
    Scene one = litWall(), two = litWall(), both = litWall();
    addBox(one, {0, 0, 0.3}, {0.3, 0.3, 0.1}, addMaterial(one, absorbingMedium(dyeAbsorbance(4.0))));
    addBox(two, {0, 0, 0.3}, {0.3, 0.3, 0.1}, addMaterial(two, absorbingMedium(dyeAbsorbance(8.0))));
    // Two boxes of the first medium overlapping in depth: 0.1 m each, 0.15 m of ray in either.
    const uint32_t m = addMaterial(both, absorbingMedium(dyeAbsorbance(4.0)));
    addBox(both, {0, 0, 0.3}, {0.3, 0.3, 0.1}, m);
    addBox(both, {0, 0, 0.25}, {0.3, 0.3, 0.1}, m);
    for (int b : {0, 10, 12, 20, 30}) {
        const auto [g1, c1] = transmittance(one, b);
        const auto [g2, c2] = transmittance(two, b);
        const auto [g3, c3] = transmittance(both, b);
        EXPECT_NEAR(c2, c1 * c1, 1e-12) << "band " << b;
        EXPECT_NEAR(g2, g1 * g1, 2e-6) << "band " << b;
        EXPECT_NEAR(c3, c1 * c1, 1e-12) << "band " << b;
        EXPECT_NEAR(g3, g1 * g1, 2e-6) << "band " << b;
    }
}

// An opaque surface inside a medium ends the path there: a wall through the middle of a box.
TEST(Transparency, OpaqueSurfaceInsideAMediumEndsThePath) {
    Scene s = litWall();
    const uint32_t m = addMaterial(s, absorbingMedium(dyeAbsorbance(6.0)));
    addBox(s, {0, 0, 0.0}, {0.4, 0.4, 0.2}, m);  // the wall at z = 0 cuts it in half: 0.1 m in front
    expectPixel(
        s, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) { return L0(g, b) * std::pow(10.0, -g.materials[m].absorbance[b] * 0.1); },
        2e-5, "wall inside the medium");
}

// A perspective camera inside a medium: the path runs from the eye to the wall.
TEST(Transparency, CameraInsideAMedium) {
    Scene s = litWall();
    s.camera = perspectiveCamera({0, 0, 0.5}, {0, 0, 0}, {0, 1, 0}, 40.0, kPx, kPx);
    const uint32_t m = addMaterial(s, absorbingMedium(dyeAbsorbance(2.0)));
    addBox(s, {0, 0, 0.5}, {3, 3, 1.4}, m);  // from z = −0.2 to 1.2, around the camera
    expectPixel(
        s, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            const double path = 0.5;  // the middle pixel's ray runs along the axis (kPx is odd)
            return L0(g, b) * std::pow(10.0, -g.materials[m].absorbance[b] * path);
        },
        2e-5, "camera inside");
}

// Coloured shadows: a light through a filter is filtered. A directional light at 45° (travelling
// +x, −z) casts a filter's shadow beside the filter as the camera sees it, so the wall there is
// lit by E·T: L = ρ·(E_ambient + E·cos45°·T)/π, band by band, within the shadow map's rules (the
// interior of the coloured shadow; its edge within a texel of the transmittance map).
Scene colouredShadowScene(const Material& caster, bool box) {
    Scene s = litWall();
    s.lights.push_back(directionalLight({1, 0, -1}, gaussianSpectrum(600, 100, 1.5, 300, 800, 1), 1.0));
    s.lights.back().shadows = true;
    const uint32_t m = addMaterial(s, caster);
    // Centred 0.3 m up and 0.3 m to the left of x = 0: its shadow falls around the wall's centre.
    if (box)
        addBox(s, {-0.3, 0, 0.3}, {0.3, 0.3, 0.05}, m);
    else
        s.meshes.push_back(quad({-0.3, 0, 0.3}, {0, 0, 1}, 0.3, 0.3, m));
    return s;
}

double litByBoth(const SceneOnGrid& g, int b, double tau) {
    return (g.lights[0][size_t(b)] + g.lights[1][size_t(b)] * std::sqrt(0.5) * tau) / kPi;
}

TEST(Transparency, AFiltersColouredShadowIsTTimesTheLight) {
    const Scene s = colouredShadowScene(filterSheet(gelTransmittance(), "gel"), false);
    for (int x : {kPx / 2 - 2, kPx / 2, kPx / 2 + 2})  // inside the shadow, clear of the filter's own image
        expectPixel(
            s, x, kPx / 2,
            [](const SceneOnGrid& g, int b) { return litByBoth(g, b, g.materials[1].transmittance[size_t(b)]); },
            2e-6, "coloured shadow");
    // Outside it, the light is whole.
    expectPixel(s, kPx - 3, kPx / 2, [](const SceneOnGrid& g, int b) { return litByBoth(g, b, 1.0); }, 2e-6, "lit");
}

TEST(Transparency, AMediumsShadowIsBeerLambertAlongTheLight) {
    const Scene s = colouredShadowScene(absorbingMedium(dyeAbsorbance(6.0)), true);
    // The light crosses the 5 cm slab's top and bottom at 45°: a path of 0.05·√2 m.
    expectPixel(
        s, kPx / 2, kPx / 2,
        [](const SceneOnGrid& g, int b) {
            return litByBoth(g, b, std::pow(10.0, -g.materials[1].absorbance[size_t(b)] * 0.05 * std::sqrt(2.0)));
        },
        2e-5, "medium's shadow");
}

// Fluorescence is excited by the light that arrives: a filter that passes the excitation band
// half as well halves the fluorescence in its shadow, while reflection follows T band by band.
// A fluorescent wall (material 0) under a violet-blue light at 45° that casts the shadow of a
// yellow gel (material 1: T = 0.1 below ~470 nm, 0.9 above) over the wall's centre.
Scene fluorescentWallBehindAYellowGel(Material paint) {
    Scene s = emptyScene(Grid{360, 700, 10}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, kPx, kPx));
    s.materials.push_back(std::move(paint));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
    s.lights.push_back(directionalLight({1, 0, -1}, gaussianSpectrum(450, 80, 1.0, 300, 800, 1), 2.0));
    s.lights.back().shadows = true;
    std::vector<double> nm, v;
    for (double l = 300; l <= 800; l += 2) {
        nm.push_back(l);
        v.push_back(0.1 + 0.8 / (1.0 + std::exp(-(l - 470) / 8)));
    }
    const uint32_t gel = addMaterial(s, filterSheet(sampledSpectrum(nm, v, "yellow"), "yellow"));
    s.meshes.push_back(quad({-0.3, 0, 0.3}, {0, 0, 1}, 0.3, 0.3, gel));
    return s;
}

TEST(Transparency, FluorescenceInAColouredShadowIsExcitedByTheFilteredLight) {
    const Spectrum excitation = gaussianSpectrum(420, 25, 0.6, 300, 800, 1);
    const Spectrum emission = gaussianSpectrum(560, 30, 1.0, 300, 800, 1);
    const Scene s = fluorescentWallBehindAYellowGel(fluorescent(constantSpectrum(0.3), excitation, emission, 0.8, "paint"));
    expectPixel(
        s, kPx / 2, kPx / 2,
        [](const SceneOnGrid& g, int b) {
            const MaterialOnGrid& m = g.materials[0];
            const std::vector<double>& E = g.lights[0];
            const std::vector<double>& T = g.materials[1].transmittance;
            const double cosI = std::sqrt(0.5), step = g.grid.step_nm;
            double absorbed = 0.0;  // Σ a·E·T·λ·Δλ
            for (size_t i = 0; i < E.size(); ++i) absorbed += m.excitation[i] * E[i] * T[i] * g.wavelengths_nm[i] * step;
            const double reflected = m.diffuse[size_t(b)] * E[size_t(b)] * T[size_t(b)] * cosI / kPi;
            const double emitted = cosI * m.quantum_yield / kPi * m.emission[size_t(b)] / g.wavelengths_nm[size_t(b)] * absorbed;
            return reflected + emitted;
        },
        2e-5, "fluorescence in a coloured shadow");
}

// The same with a Donaldson matrix in the scene (every fluorescent material then emits from
// per-light spectra): in the coloured shadow the emission is (1/π)·Σᵢ D(λᵢ, λo)·E(λᵢ)·T(λᵢ)·Δλ,
// a matrix–vector product per fragment on the GPU.
TEST(Transparency, DonaldsonFluorescenceInAColouredShadowIsExcitedByTheFilteredLight) {
    BispectralMatrix d;  // one fluorophore: excited around 420 nm, emitting around 560 nm
    for (double l = 300; l <= 800; l += 5) {
        d.in_nm.push_back(l);
        d.out_nm.push_back(l);
    }
    const size_t n = d.in_nm.size();
    d.values.assign(n * n, 0.0);
    for (size_t i = 0; i < n; ++i)
        for (size_t o = 0; o < n; ++o)
            d.values[i * n + o] = 0.6 * std::exp(-0.5 * std::pow((d.in_nm[i] - 420) / 25, 2)) * 0.01 *
                                  std::exp(-0.5 * std::pow((d.out_nm[o] - 560) / 30, 2));
    d.source = "test";
    const Scene s = fluorescentWallBehindAYellowGel(donaldsonMaterial(constantSpectrum(0.3), d, 1.0, "paint"));
    expectPixel(
        s, kPx / 2, kPx / 2,
        [](const SceneOnGrid& g, int b) {
            const MaterialOnGrid& m = g.materials[0];
            const std::vector<double>& E = g.lights[0];
            const std::vector<double>& T = g.materials[1].transmittance;
            const double cosI = std::sqrt(0.5), step = g.grid.step_nm;
            const size_t bands = E.size(), o = size_t(b);
            double emitted = 0.0;
            for (size_t i = 0; i < bands; ++i) emitted += m.donaldson[i * bands + o] * E[i] * T[i] * step / kPi;
            return m.diffuse[o] * E[o] * T[o] * cosI / kPi + cosI * emitted;
        },
        2e-5, "Donaldson fluorescence in a coloured shadow");
}

// Slabs (docs/physics.md, "Transparent objects"): the closed forms written out here, independently of
// spectral/dielectric.cpp. A white wall lit by a directional light that casts no shadow (so the
// slab does not filter its light) and nothing a slab could reflect (no ambient, no hemisphere).
struct SlabAnswer {
    double t = 0.0, r = 0.0;
};
SlabAnswer slabClosedForm(double n, double cosI, double absorbanceTimesThickness) {
    const double sinT2 = (1.0 - cosI * cosI) / (n * n), cosT = std::sqrt(1.0 - sinT2);
    const double tau = std::pow(10.0, -absorbanceTimesThickness / cosT);
    const double rs = std::pow((cosI - n * cosT) / (cosI + n * cosT), 2), rp = std::pow((cosT - n * cosI) / (cosT + n * cosI), 2);
    SlabAnswer a;
    for (double r : {rs, rp}) {
        a.t += 0.5 * (1 - r) * (1 - r) * tau / (1 - r * r * tau * tau);
        a.r += 0.5 * (r + (1 - r) * (1 - r) * r * tau * tau / (1 - r * r * tau * tau));
    }
    return a;
}
double nbk7Sellmeier(double nm) {  // Schott N-BK7
    const double l2 = (nm * 1e-3) * (nm * 1e-3);
    return std::sqrt(1 + 1.03961212 * l2 / (l2 - 0.00600069867) + 0.231792344 * l2 / (l2 - 0.0200179144) +
                     1.01046945 * l2 / (l2 - 103.560653));
}
Scene slabScene(Material glass, double tiltDeg) {
    Scene s = emptyScene(Grid{400, 700, 10}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, kPx, kPx));
    s.materials.push_back(lambertian(1.0, "wall"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
    s.lights.push_back(directionalLight({0, 0, -1}, gaussianSpectrum(550, 90, 2.0, 300, 800, 1), kPi));
    s.lights.back().shadows = false;
    const uint32_t m = addMaterial(s, std::move(glass));
    const double a = tiltDeg * kPi / 180;
    s.meshes.push_back(quad({0, 0, 0.5}, {std::sin(a), 0, std::cos(a)}, 0.6, 0.6, m));
    return s;
}

TEST(Transparency, SlabsTransmitTheClosedFormsAtZeroAndSixtyDegrees) {
    // n = 1.5 face-on: T = 0.9230769; with an internal transmittance of 0.5, T = 0.4609844.
    EXPECT_NEAR(slabClosedForm(1.5, 1.0, 0.0).t, 0.9230769, 5e-8);
    EXPECT_NEAR(slabClosedForm(1.5, 1.0, std::log10(2.0)).t, 0.4609844, 5e-8);
    struct Case {
        const char* what;
        RefractiveIndex n;
        double tilt, a, d;  // degrees; decadic absorbance per metre; thickness, m
    };
    const Case cases[] = {{"n = 1.5, 0°", constantIndex(1.5), 0.0, 0.0, 0.004},
                          {"n = 1.5, 0°, τ = 0.5", constantIndex(1.5), 0.0, std::log10(2.0) / 0.01, 0.01},
                          {"n = 1.5, 60°", constantIndex(1.5), 60.0, 0.0, 0.004},
                          {"N-BK7, 0°", nbk7(), 0.0, 0.0, 0.004},
                          {"N-BK7, 60°, absorbing", nbk7(), 60.0, 20.0, 0.01}};
    for (const Case& c : cases) {
        const Scene s = slabScene(slabMaterial(c.n, c.d, c.a > 0 ? std::optional<Spectrum>(constantSpectrum(c.a)) : std::nullopt), c.tilt);
        const bool bk7 = c.n.kind == RefractiveIndex::Kind::Sellmeier;
        expectPixel(
            s, kPx / 2, kPx / 2,
            [&](const SceneOnGrid& g, int b) {
                const double n = bk7 ? nbk7Sellmeier(g.wavelengths_nm[size_t(b)]) : 1.5;
                return g.lights[0][size_t(b)] / kPi * slabClosedForm(n, std::cos(c.tilt * kPi / 180), c.a * c.d).t;
            },
            2e-6, c.what);
    }
}

// A glass with a reflection in front of a tinted glass in front of a coloured wall, under a sky
// (a hemisphere light whose up points at the camera, which each face-on slab mirrors):
// L = E₁ + T₁·(E₂ + T₂·L_wall), E = R·L_sky, L_wall = ρ·L_sky — band by band, in either draw order.
TEST(Transparency, ReflectingSlabsCompositeFarthestFirst) {
    Scene s = emptyScene(Grid{400, 700, 10}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, kPx, kPx));
    s.materials.push_back(lambertian(gaussianSpectrum(620, 60, 0.8, 300, 800, 1), "red wall"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
    s.lights.push_back(hemisphereLight({0, 0, 1}, gaussianSpectrum(500, 120, 1.0, 300, 800, 1), 1.0));
    const uint32_t front = addMaterial(s, slabMaterial(nbk7(), 0.006, std::nullopt, "window"));
    const uint32_t back = addMaterial(s, slabMaterial(constantIndex(1.7), 0.01, dyeAbsorbance(40.0), "tinted"));
    Scene reversed = s;
    s.meshes.push_back(quad({0, 0, 0.6}, {0, 0, 1}, 0.6, 0.6, front));
    s.meshes.push_back(quad({0, 0, 0.3}, {0, 0, 1}, 0.6, 0.6, back));
    reversed.meshes.push_back(s.meshes[2]);
    reversed.meshes.push_back(s.meshes[1]);
    auto expected = [&](const SceneOnGrid& g, int b) {
        const double sky = g.lights[0][size_t(b)], wall = g.materials[0].diffuse[size_t(b)] * sky;
        const SlabAnswer one = slabClosedForm(nbk7Sellmeier(g.wavelengths_nm[size_t(b)]), 1.0, 0.0);
        const SlabAnswer two = slabClosedForm(1.7, 1.0, g.materials[back].slabAbsorbance[size_t(b)] * 0.01);
        return one.r * sky + one.t * (two.r * sky + two.t * wall);
    };
    expectPixel(s, kPx / 2, kPx / 2, expected, 2e-6, "glass, tinted glass, wall");
    expectPixel(reversed, kPx / 2, kPx / 2, expected, 2e-6, "the same drawn in the other order");
    // The case exactly: a glass with its reflection in front of a gel (E₂ = 0).
    Scene gel = s;
    gel.materials[back] = filterSheet(gelTransmittance(), "gel");
    expectPixel(
        gel, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            const double sky = g.lights[0][size_t(b)], wall = g.materials[0].diffuse[size_t(b)] * sky;
            const SlabAnswer one = slabClosedForm(nbk7Sellmeier(g.wavelengths_nm[size_t(b)]), 1.0, 0.0);
            return one.r * sky + one.t * (0.0 + g.materials[back].transmittance[size_t(b)] * wall);
        },
        2e-6, "glass, gel, wall");
    // A gel in front of the glass filters the glass's reflection too: L = T·(E₁ + T₁·L_wall) — the
    // channel pass puts the gel in front of the nearest slab, the slab's second draw multiplies by it.
    Scene gelInFront = gel;
    gelInFront.meshes[1].material = back;   // the gel, nearer
    gelInFront.meshes[2].material = front;  // the glass, farther
    expectPixel(
        gelInFront, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            const double sky = g.lights[0][size_t(b)], wall = g.materials[0].diffuse[size_t(b)] * sky;
            const SlabAnswer one = slabClosedForm(nbk7Sellmeier(g.wavelengths_nm[size_t(b)]), 1.0, 0.0);
            return g.materials[back].transmittance[size_t(b)] * (one.r * sky + one.t * wall);
        },
        2e-6, "gel, glass, wall");
    // A glass inside a dye box (z 0.2 … 0.8, the glass at 0.5): the medium's path splits at it, 0.3 m
    // in front multiplying the glass's reflection and all 0.6 m the wall: L = τ₀.₃·(E₁ + T₁·τ₀.₃·L_wall).
    Scene straddle = s;
    straddle.meshes.resize(1);
    const uint32_t dye = addMaterial(straddle, absorbingMedium(dyeAbsorbance(2.0), "dye"));
    addBox(straddle, {0, 0, 0.5}, {0.8, 0.8, 0.6}, dye);
    straddle.meshes.push_back(quad({0, 0, 0.5}, {0, 0, 1}, 0.6, 0.6, front));
    expectPixel(
        straddle, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            const double sky = g.lights[0][size_t(b)], wall = g.materials[0].diffuse[size_t(b)] * sky;
            const SlabAnswer one = slabClosedForm(nbk7Sellmeier(g.wavelengths_nm[size_t(b)]), 1.0, 0.0);
            const double half = std::pow(10.0, -g.materials[dye].absorbance[size_t(b)] * 0.3);
            return half * (one.r * sky + one.t * half * wall);
        },
        2e-5, "dye, glass inside it, dye, wall");
    // Beside the slabs the sky lights the wall alone.
    expectPixel(s, 1, kPx / 2, [&](const SceneOnGrid& g, int b) { return g.materials[0].diffuse[size_t(b)] * g.lights[0][size_t(b)]; },
                2e-6, "the wall beside the slabs");
}

// GPU against the reference on a scene of everything at once, perspective, with shadows and a
// glossy object seen through a filter, media and a reflecting slab.
TEST(Transparency, GpuMatchesReferenceOnFiltersAndMedia) {
    Scene s = litWall(Grid{380, 730, 5}, 96);
    s.camera = perspectiveCamera({0.3, 0.2, 3}, {0, 0, 0}, {0, 1, 0}, 35.0, 96, 72);
    s.lights.push_back(directionalLight({0.3, -0.4, -1}, gaussianSpectrum(600, 120, 1.0, 300, 800, 1), 2.0));
    s.lights.back().shadows = true;
    const uint32_t ball = addMaterial(s, glossy(constantSpectrum(0.4), constantSpectrum(0.3), 40, "ball"));
    s.meshes.push_back(sphere({0.3, -0.2, 0.25}, 0.25, 48, 24, ball));
    const uint32_t gel = addMaterial(s, filterSheet(gelTransmittance(), "gel"));
    s.meshes.push_back(quad({0.2, -0.1, 0.9}, {0.1, 0, 1}, 0.5, 0.6, gel));
    const uint32_t dye = addMaterial(s, absorbingMedium(dyeAbsorbance(15.0), "dye"));
    addBox(s, {-0.4, 0.2, 0.4}, {0.3, 0.5, 0.2}, dye);
    Mesh drop = makeSphere({-0.1, -0.5, 0.6}, 0.15, 48);
    drop.material = dye;
    s.meshes.push_back(drop);
    // A tilted window of N-BK7 with a tint, over the wall's right side: it reflects the ambient
    // light, transmits by Fresnel at its angle, and colours the directional light's shadow.
    const uint32_t window = addMaterial(s, slabMaterial(nbk7(), 0.006, dyeAbsorbance(30.0), "window"));
    s.meshes.push_back(quad({0.75, 0.35, 0.7}, {-0.5, 0.2, 1}, 0.5, 0.4, window));
    const SceneOnGrid g = onGrid(s);
    const SpectralCube gc = gpuRender(s, g);
    // The transparent objects' silhouettes are edges too (ReferenceImage::crossings, which
    // renderReference's interior test uses): there the path through a tessellated surface changes
    // fast with the ray, and the rasterizer's snapped vertices (1/256 px on lavapipe) move it.
    const ReferenceImage ref = renderReference(s, g);
    // The coloured shadows are compared on their own: the pixels whose light came through a
    // transparent object, found as those whose crossings change when the light casts no shadow.
    Scene unshadowed = s;
    unshadowed.lights.back().shadows = false;
    const ReferenceImage plain = renderReference(unshadowed, g);
    ReferenceImage direct = ref, coloured = ref;
    for (size_t i = 0; i < ref.objectId.size(); ++i) {
        const bool inColouredShadow = ref.crossings[i] != plain.crossings[i];
        (inColouredShadow ? direct : coloured).objectId[i] = kMixedId;  // left out of that comparison
    }
    const InteriorComparison c = compareInterior(gc, direct), cs = compareInterior(gc, coloured);
    std::printf("  lit directly or seen through filters and media: %d interior pixels, max relative error %.3g (pixel "
                "%d,%d band %d)\n",
                c.pixels, c.maxRelative, c.worstX, c.worstY, c.worstBand);
    std::printf("  in coloured shadows: %d interior pixels, max relative error %.3g (pixel %d,%d band %d)\n", cs.pixels,
                cs.maxRelative, cs.worstX, cs.worstY, cs.worstBand);
    EXPECT_GE(c.pixels, 2500);
    EXPECT_LE(c.maxRelative, 1e-4);
    // The transmittance maps are 256² over the light's view of the scene: across a medium's side,
    // where the path grows by ~1.7 optical depths per texel here, their interpolation misses the
    // kinks by a few 10⁻³ (docs/physics.md, "Transparent objects", coloured shadows; measured 5e-3).
    EXPECT_GE(cs.pixels, 300);
    EXPECT_LE(cs.maxRelative, 1e-2);
}

// Issue 50: ten thousand sheets, stacked 10 µm apart, multiply as Tⁿ — seen through from the camera
// (the channel pass: one draw each, n summed at the pixel) and in their coloured shadow (the
// transmittance map's channel: n interpolated, then 2^(n·log2 T) per band). Each sheet passes
// gel(λ)^(1/2500), so the stack passes gel⁴ (down to 6·10⁻⁶ at the gel's foot). A directional
// light at 45° (travelling +x, −z) throws the stack's shadow 0.3 m to its right.
TEST(Transparency, TenThousandSheetsMultiplyAsTToTheN) {
    Scene s = litWall();
    s.lights.push_back(directionalLight({1, 0, -1}, gaussianSpectrum(600, 100, 1.5, 300, 800, 1), 1.0));
    s.lights.back().shadows = true;
    std::vector<double> nm, v;
    for (double l = 300; l <= 800; l += 5) {
        nm.push_back(l);
        v.push_back(std::pow(0.05 + 0.9 / (1.0 + std::exp(-(l - 560) / 15)), 1.0 / 2500.0));
    }
    const uint32_t m = addMaterial(s, filterSheet(sampledSpectrum(nm, v, "a 2500th of a gel"), "thin gel"));
    constexpr int kSheets = 10000;
    for (int i = 0; i < kSheets; ++i) s.meshes.push_back(quad({-0.3, 0, 0.3 + 1e-5 * i}, {0, 0, 1}, 0.3, 0.3, m));
    auto stack = [&](const SceneOnGrid& g, int b) { return std::pow(g.materials[m].transmittance[size_t(b)], kSheets); };
    // The pixel under the stack (x = −0.3 m): the wall is lit whole there and seen through every sheet.
    const int under = int((0.5 - 0.3) * kPx);
    expectPixel(
        s, under, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            return stack(g, b) * (g.lights[0][size_t(b)] + g.lights[1][size_t(b)] * std::sqrt(0.5)) / kPi;
        },
        1e-5, "seen through the stack");
    // The middle pixel: in the stack's coloured shadow, not behind it.
    expectPixel(
        s, kPx / 2, kPx / 2,
        [&](const SceneOnGrid& g, int b) {
            return (g.lights[0][size_t(b)] + g.lights[1][size_t(b)] * std::sqrt(0.5) * stack(g, b)) / kPi;
        },
        1e-5, "in the stack's coloured shadow");
}
