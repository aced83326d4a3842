// Issue 13's known answer, through both renderers: tabulated inputs rendered on their own grid come
// out exactly as tabulated. A head-on white-lit Lambertian quad of reflectance ρ under a
// directional light of irradiance E has radiance ρ(λᵢ)·E(λᵢ)/π in every band, the first and the
// last included, when λᵢ are the data's own wavelengths — whatever kinks the data have.
// (The rule: spectral/resampling.h; its unit tests: spectral/resampling_test.cpp; colour-science
// on the ColorChecker: tests/python/check_colorimetry_standards.py.)
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

using namespace metamer;
using namespace metamer::test;

namespace {

// Values with a kink at every sample, drawn at random, every `step` nm over [start, end].
Spectrum kinked(double start, double end, double step, double lo, double hi, unsigned seed, const char* name) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    std::vector<double> nm, v;
    for (int i = 0; start + i * step <= end + 1e-9; ++i) {
        nm.push_back(start + i * step);
        v.push_back(u(rng));
    }
    return sampledSpectrum(nm, v, name);
}

// Distance in units of the float's last place.
double ulps(float actual, double expected) {
    const float e = float(expected);
    return std::fabs(double(actual) - double(e)) / double(std::nextafter(e, INFINITY) - e);
}

}  // namespace

TEST(Sampling, TabulatedInputsOnTheirOwnGridComeOutExactly) {
    for (double step : {1.0, 5.0, 10.0}) {
        SCOPED_TRACE(fmt::format("{} nm data on 300:740:{}", step, step));
        const Spectrum rho = kinked(300, 740, step, 0.05, 0.95, 1, "ρ");
        const Spectrum e = kinked(300, 740, step, 0.2, 1.8, 2, "E");
        Scene s = emptyScene(Grid{300, 740, step}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, 8, 8));
        s.materials.push_back(lambertian(rho));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4));
        s.lights.push_back(directionalLight({0, 0, -1}, e, 1.0));
        const SceneOnGrid g = onGrid(s);
        // The spectra on the grid are the tabulated values, bit for bit.
        ASSERT_EQ(g.grid.bands(), int(rho.values.size()));
        for (int b = 0; b < g.grid.bands(); ++b) {
            ASSERT_EQ(g.materials[0].diffuse[size_t(b)], rho.values[size_t(b)]) << b;
            ASSERT_EQ(g.lights[0][size_t(b)], e.values[size_t(b)]) << b;
        }
        const ReferenceImage ref = renderReference(s, g);
        uint32_t before = gpu().validationErrors();
        SpectralPass pass(gpu(), s, g);
        const SpectralCube cube = pass.render();
        EXPECT_NO_VALIDATION_ERRORS(before);
        double worstCpu = 0, worstGpu = 0;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                for (int b = 0; b < g.grid.bands(); ++b) {
                    const double expected = rho.values[size_t(b)] * e.values[size_t(b)] / std::numbers::pi;
                    worstCpu = std::max(worstCpu, ulps(ref.cube.at(x, y, b), expected));
                    worstGpu = std::max(worstGpu, ulps(cube.at(x, y, b), expected));
                }
        std::printf("  %g nm: %d bands, CPU within %.1f ulp, GPU within %.1f ulp of float(ρ·E/π)\n", step,
                    g.grid.bands(), worstCpu, worstGpu);
        EXPECT_LE(worstCpu, 0.0);  // the reference rounds the double result once
        EXPECT_LE(worstGpu, 3.0);  // ρ, E, 1/π to float, two products
    }
}

TEST(Sampling, BandMeanResamplingStillAveragesTheSameData) {
    // A scene can ask for band means (grid.resample = band-mean): on the data's own 5 nm grid the
    // band of a kinked spectrum is then (v₋ + 6v + v₊)/8 instead of v.
    const Spectrum rho = kinked(300, 740, 5, 0.05, 0.95, 1, "ρ");
    Grid grid{300, 740, 5};
    grid.resampling = Resampling::BandMean;
    Scene s = emptyScene(grid, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, 4, 4));
    s.materials.push_back(lambertian(rho));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4));
    s.lights.push_back(directionalLight({0, 0, -1}, constantSpectrum(1.0), 1.0));
    const SceneOnGrid g = onGrid(s);
    const auto& v = rho.values;
    for (size_t b = 1; b + 1 < v.size(); ++b)
        ASSERT_NEAR(g.materials[0].diffuse[b], (v[b - 1] + 6 * v[b] + v[b + 1]) / 8, 1e-15) << b;
}
