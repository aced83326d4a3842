// Numerical behaviour at the extremes (docs/numerics.md): grids from one band to 881 bands and from
// 200 to 2500 nm, light scales over 24 decades, float16 output, needle lobes, grazing angles,
// degenerate geometry, empty scenes, a camera inside an object, fluorescence at the edge of
// its overlap with the light, and scenes moved far from the world origin, scaled from micrometres
// to megametres or lit by point lights lying on a surface. Each test prints what it measured (the
// numbers docs/numerics.md quotes) and checks the GPU path against the double-precision CPU
// reference, or both against an analytic answer where there is one.
#include "io/spectral_exr.h"
#include "reference/cpu_renderer.h"
#include "render/camera_matrices.h"
#include "render/spectral_pass.h"
#include "scene/local_frame.h"
#include "scene/shapes.h"
#include "spectral/library.h"
#include "support/capture_warnings.h"
#include "support/cubes.h"
#include "support/gpu.h"
#include "support/interior_comparison.h"
#include "support/scene_builders.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <unistd.h>
#include <vector>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// --- Measuring --------------------------------------------------------------------------------

size_t nonFinite(const SpectralCube& c) {
    return size_t(std::count_if(c.data.begin(), c.data.end(), [](float v) { return !std::isfinite(v); }));
}

size_t negative(const SpectralCube& c) {
    return size_t(std::count_if(c.data.begin(), c.data.end(), [](float v) { return v < 0.0f; }));
}

struct Rendered {
    SpectralCube gpu;
    ReferenceImage ref;
    SpectralPassPlan plan;
};

// The scene through both renderers, failing the test on any validation error.
Rendered renderBoth(const Scene& s, const SceneOnGrid& g, const SpectralPassOptions& opts = {}) {
    const uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g, opts);
    Rendered r{pass.render(), {}, pass.plan()};
    ReferenceOptions ro;
    ro.ssaa = opts.ssaa;
    r.ref = renderReference(s, g, ro);
    EXPECT_NO_VALIDATION_ERRORS(before);
    return r;
}

// Prints one line: what, interior pixels, worst relative error and where.
void report(const std::string& what, const Rendered& r, const InteriorComparison& m) {
    std::printf("  [numerics] %-40s %4d bands %3d layers %2d passes: %5d interior px, max rel err %.3g (px %d,%d band %d)\n",
                what.c_str(), r.plan.bands, r.plan.layers, r.plan.passes, m.pixels, m.maxRelative, m.worstX, m.worstY,
                m.worstBand);
    ::testing::Test::RecordProperty("max_relative_error_" + what, std::to_string(m.maxRelative));
}

// --- Scenes -----------------------------------------------------------------------------------

// A smooth, daylight-shaped SPD over 300–800 nm (not a library file: tests stay independent of
// the data).
Spectrum daylightLike() {
    std::vector<double> nm, v;
    for (double l = 300; l <= 800; l += 5) {
        nm.push_back(l);
        v.push_back(60 + 40 * std::sin((l - 300) / 70.0) + 30 * std::exp(-0.5 * std::pow((l - 460) / 25, 2)));
    }
    return sampledSpectrum(nm, v, "daylight-like");
}

// A glossy sphere on a floor under an ambient, a directional and a point light: every term of
// the shading (diffuse, specular, the three light kinds) on a curved and a flat surface.
Scene sphereOnFloor(const Grid& grid, int px, double lightScale = 1.0) {
    Scene s = emptyScene(grid, perspectiveCamera({0, 1.2, 4}, {0, 0, 0}, {0, 1, 0}, 35, px, px));
    s.materials.push_back(glossy(gaussianSpectrum(520, 60, 0.7, 200, 2500, 1), constantSpectrum(0.05), 40, "green"));
    s.materials.push_back(lambertian(0.5, "floor"));
    s.meshes.push_back(sphere({0, 0, 0}, 0.8, 48, 24, 0));
    s.meshes.push_back(quad({0, -0.8, 0}, {0, 1, 0}, 6, 6, 1));
    s.lights.push_back(ambientLight(daylightLike(), 0.002 * lightScale));
    s.lights.push_back(directionalLight({-0.4, -1, -0.5}, daylightLike(), 0.01 * lightScale));
    s.lights.push_back(pointLight({1.5, 2, 2}, daylightLike(), 0.3 * lightScale));
    return s;
}


// A folder of its own for files a test writes, removed afterwards.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path = std::filesystem::temp_directory_path() /
               ("metamer-numerics-" + std::to_string(::getpid()) + "-" + info->name());
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
};

}  // namespace

// --- Grids ------------------------------------------------------------------------------------

TEST(Numerics, GridsFromHalfNanometreToSingleBandMatchReference) {
    struct Case {
        Grid grid;
        int bands, layers, passes, px;
    };
    const Case cases[] = {
        {Grid{300, 740, 0.5}, 881, 221, 28, 24},  // the finest step over the default range
        {Grid{300, 740, 1}, 441, 111, 14, 24},
        {Grid{555, 555, 1}, 1, 1, 1, 32},  // one band: one layer with three unused components
        {Grid{555, 555, 0.5}, 1, 1, 1, 16},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.grid.str());
        Scene s = sphereOnFloor(c.grid, c.px);
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(r.plan.bands, c.bands);
        EXPECT_EQ(r.plan.layers, c.layers);
        EXPECT_EQ(r.plan.passes, c.passes);
        ASSERT_EQ(r.gpu.bands(), c.bands);
        ASSERT_EQ(r.gpu.data.size(), size_t(c.px) * c.px * c.bands);
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        report("grid " + c.grid.str(), r, m);
        EXPECT_GE(m.pixels, c.px * c.px / 5);  // a sphere and its shadow: edges and shadow boundaries are left out
        EXPECT_LE(m.maxRelative, 1e-4);
    }
}

// --- Wavelength range ---------------------------------------------------------------------------

TEST(Numerics, FullRangeGridsWithTheEqualEnergyIlluminant) {
    SpectrumLibrary lib;
    const Spectrum& e = lib.get("illuminants/E", Where{});
    ASSERT_LE(e.wavelengths_nm.front(), 200.0);
    ASSERT_GE(e.wavelengths_nm.back(), 2500.0);
    for (Grid grid : {Grid{200, 2500, 50}, Grid{1000, 2500, 10}}) {
        SCOPED_TRACE(grid.str());
        Scene s = emptyScene(grid, perspectiveCamera({0, 1.2, 4}, {0, 0, 0}, {0, 1, 0}, 35, 24, 24));
        s.materials.push_back(glossy(constantSpectrum(0.6), constantSpectrum(0.3), 20, "grey"));
        s.materials.push_back(lambertian(0.2, "floor"));
        s.meshes.push_back(sphere({0, 0, 0}, 0.8, 48, 24, 0));
        s.meshes.push_back(quad({0, -0.8, 0}, {0, 1, 0}, 6, 6, 1));
        s.lights.push_back(directionalLight({-0.4, -1, -0.5}, e, 0.01));
        s.lights.push_back(pointLight({1.5, 2, 2}, e, 0.3));
        CaptureWarnings warnings;
        SceneOnGrid g = onGrid(s);
        EXPECT_TRUE(CaptureWarnings::lines().empty()) << CaptureWarnings::lines().front();
        Rendered r = renderBoth(s, g);
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        report("E on " + grid.str(), r, m);
        EXPECT_GE(m.pixels, 100);
        EXPECT_LE(m.maxRelative, 1e-4);
    }
}

TEST(Numerics, LightThatMissesPartOfTheRangeWarnsAndIsExactlyZeroThere) {
    SpectrumLibrary lib;
    const Spectrum& d65 = lib.get("illuminants/D65", Where{});
    const double lo = d65.wavelengths_nm.front(), hi = d65.wavelengths_nm.back();
    const Grid grid{200, 2500, 50};
    Scene s = emptyScene(grid, orthographicCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 1.0, 16, 16));
    s.materials.push_back(glossy(constantSpectrum(0.6), constantSpectrum(0.3), 5, "grey"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
    s.lights.push_back(directionalLight({-0.2, -0.1, -1}, d65, 0.01, "lights.0"));
    s.lights.push_back(ambientLight(d65, 0.001, "lights.1"));

    CaptureWarnings warnings;
    SceneOnGrid g = onGrid(s);
    // Two lights with the same data range: one grouped warning naming the spectrum and the range.
    ASSERT_EQ(CaptureWarnings::lines().size(), 1u);
    EXPECT_NE(CaptureWarnings::lines()[0].find("illuminants/D65"), std::string::npos) << CaptureWarnings::lines()[0];
    EXPECT_NE(CaptureWarnings::lines()[0].find("bands outside the data are 0"), std::string::npos);

    Rendered r = renderBoth(s, g);
    InteriorComparison m = compareInterior(r.gpu, r.ref);
    report("D65 on " + grid.str(), r, m);
    EXPECT_LE(m.maxRelative, 1e-4);
    // Bands whose interval [λ − Δλ/2, λ + Δλ/2] misses the data entirely hold exactly 0, on both
    // renderers and in every pixel; bands with data are lit.
    int uncovered = 0;
    for (int b = 0; b < grid.bands(); ++b) {
        const double l = grid.wavelength(b);
        const bool outside = l + 0.5 * grid.step_nm <= lo || l - 0.5 * grid.step_nm >= hi;
        uncovered += outside;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                if (outside) {
                    ASSERT_EQ(r.gpu.at(x, y, b), 0.0f) << l << " nm";
                    ASSERT_EQ(r.ref.cube.at(x, y, b), 0.0f) << l << " nm";
                } else if (l >= lo && l <= hi) {
                    ASSERT_GT(r.gpu.at(x, y, b), 0.0f) << l << " nm";
                }
            }
    }
    std::printf("  [numerics] D65 (%g–%g nm) on %s: %d of %d bands exactly 0\n", lo, hi, grid.str().c_str(), uncovered,
                grid.bands());
    EXPECT_EQ(uncovered, 47 - 11);  // 300–750 nm lit, 800 nm partly (its interval reaches 780 nm)

    // The strict policy refuses the same scene; a grid the light misses entirely is always refused.
    EXPECT_THROW(resampleScene(s, grid, CoveragePolicy::Error), Error);
    Scene far = s;
    far.grid = Grid{1000, 2500, 10};
    try {
        onGrid(far);
        ADD_FAILURE() << "a light entirely outside the grid must be an input error";
    } catch (const Error& err) {
        EXPECT_EQ(err.code(), ExitCode::BadInput);
    }
}

// --- Light scale and float16 output -------------------------------------------------------------

TEST(Numerics, LightScalesFromOneEMinus12To1E12AreLinearAndFinite) {
    const Grid grid{380, 720, 10};  // 35 bands: two passes, the second partly filled
    Scene unit = sphereOnFloor(grid, 24);
    // A fluorescent floor adds the coupling Σ a·E·λ·Δλ, the one place a light's whole spectrum is
    // summed before the shader sees it.
    unit.materials[1] = fluorescent(constantSpectrum(0.4), gaussianSpectrum(420, 20, 0.5),
                                    gaussianSpectrum(520, 25), 0.8, "floor");
    Rendered base = renderBoth(unit, onGrid(unit));
    const float baseMax = *std::max_element(base.gpu.data.begin(), base.gpu.data.end());
    TempDir tmp;
    for (double scale : {1e-12, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e12}) {
        SCOPED_TRACE(scale);
        Scene s = sphereOnFloor(grid, 24, scale);
        s.materials[1] = unit.materials[1];
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_EQ(nonFinite(r.ref.cube), 0u);
        EXPECT_EQ(negative(r.gpu), 0u);
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        // Linearity: the GPU cube at this scale over scale × the GPU cube at scale 1, on every
        // value that is not black (the ratio is exact up to float rounding of E and the products).
        double worstRatio = 0.0;
        for (size_t i = 0; i < r.gpu.data.size(); ++i)
            if (base.gpu.data[i] > 1e-4f * baseMax)
                worstRatio = std::max(worstRatio, std::fabs(r.gpu.data[i] / (scale * base.gpu.data[i]) - 1.0));
        // float16: beyond 65504 clamped and counted; the rest rounded to 11 bits, or to the
        // subnormal step 2⁻²⁴ below 2⁻¹⁴, and to 0 at or below 2⁻²⁵.
        ExrWriteOptions half;
        half.half = true;
        half.compression = "none";
        const auto file = tmp.path / "half.exr";
        ExrWriteReport rep = writeSpectralExr(file, r.gpu, half);
        SpectralCube back = readSpectralExr(file);
        ASSERT_EQ(back.data.size(), r.gpu.data.size());
        size_t over = 0, flushed = 0, subnormal = 0;
        double worstHalf = 0.0, worstSubnormalAbs = 0.0;
        for (size_t i = 0; i < back.data.size(); ++i) {
            const float v = r.gpu.data[i], h = back.data[i];
            if (v > 65504.0f) {
                ++over;
                ASSERT_EQ(h, 65504.0f);
            } else if (v >= std::ldexp(1.0f, -14)) {
                worstHalf = std::max(worstHalf, std::fabs(double(h) - v) / v);
            } else if (v > 0.0f) {
                worstSubnormalAbs = std::max(worstSubnormalAbs, std::fabs(double(h) - v));
                flushed += h == 0.0f;
                subnormal += h != 0.0f;
                if (v <= std::ldexp(1.0f, -25)) ASSERT_EQ(h, 0.0f) << v;
            }
        }
        EXPECT_EQ(rep.clampedToHalfMax, over);
        EXPECT_EQ(rep.nonFinite, 0u);
        EXPECT_LE(worstHalf, std::ldexp(1.0, -11));
        EXPECT_LE(worstSubnormalAbs, std::ldexp(1.0, -25));
        std::printf("  [numerics] scale %-6g max rel err %.3g, linearity %.3g, peak %.3g; half: %zu clamped, "
                    "%zu subnormal, %zu flushed to 0 of %zu\n",
                    scale, m.maxRelative, worstRatio, double(*std::max_element(r.gpu.data.begin(), r.gpu.data.end())),
                    over, subnormal, flushed, r.gpu.data.size());
        EXPECT_LE(m.maxRelative, 1e-4);
        EXPECT_LE(worstRatio, 1e-5);
    }
}

TEST(Numerics, LightScalesAtTheEdgesOfFloat32) {
    // Beyond the range of interest: where float32 itself runs out. Radiance near 3e37 renders
    // (fluorescence included: its coupling is scaled so it does not overflow first); a light
    // beyond the largest float32 is refused by the GPU path; radiance below the smallest normal
    // float32 (1.2e-38) flushes to 0 on the GPU, while the reference writes subnormals.
    const Grid grid{380, 720, 10};
    auto scene = [&](double scale) {
        Scene s = sphereOnFloor(grid, 16, scale);
        s.materials[1] = fluorescent(constantSpectrum(0.4), gaussianSpectrum(420, 20, 0.5),
                                     gaussianSpectrum(520, 25), 0.8, "floor");
        return s;
    };
    for (double scale : {1e-36, 1e-30, 1e30, 1e36}) {
        SCOPED_TRACE(scale);
        Scene s = scene(scale);
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_EQ(nonFinite(r.ref.cube), 0u);
        EXPECT_EQ(negative(r.gpu), 0u);
        size_t flushed = 0;
        for (size_t i = 0; i < r.gpu.data.size(); ++i) flushed += r.gpu.data[i] == 0.0f && r.ref.cube.data[i] != 0.0f;
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        std::printf("  [numerics] scale %-6g max rel err %.3g, %zu values 0 on the GPU only (peak %.3g)\n", scale,
                    m.maxRelative, flushed, double(*std::max_element(r.ref.cube.data.begin(), r.ref.cube.data.end())));
        if (scale >= 1e-30) {
            EXPECT_EQ(flushed, 0u);
            EXPECT_LE(m.maxRelative, 1e-4);
        }
    }
    Scene tooBright = scene(1e38);  // the point light's 0.3 × 1e38 × ~100 W·sr⁻¹·nm⁻¹
    SceneOnGrid g = onGrid(tooBright);
    try {
        SpectralPass pass(gpu(), tooBright, g);
        ADD_FAILURE() << "a light beyond float32 must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("float32"), std::string::npos) << e.what();
    }
}

// --- Gloss --------------------------------------------------------------------------------------

// A mirror-like quad seen straight on (orthographic) under a point light 1 m above its centre:
// n·h = cos(θ/2) with θ the light's angle from the normal, so the lobe is a disc around the
// centre whose radius shrinks as 1/√N. The view is scaled to show the lobe over ~10 pixels.
TEST(Numerics, GlossFromZeroToOneMillionStaysFiniteAndMatches) {
    for (double gloss : {0.0, 1.0, 1e2, 1e3, 1e4, 1e5, 1e6}) {
        SCOPED_TRACE(gloss);
        const double width = gloss > 0 ? std::min(2.0, 12.0 * std::sqrt(8.0 / gloss)) : 2.0;  // metres
        Scene s = emptyScene(Grid{400, 700, 20}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, width, 32, 32));
        s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(1.0), gloss, "mirror"));
        s.meshes.push_back(quad({0.013 * width, 0.007 * width, 0}, {0, 0, 1}, 4 * width, 4 * width));
        s.lights.push_back(pointLight({0, 0, 1}, daylightLike(), 1.0));
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_EQ(negative(r.gpu), 0u);
        EXPECT_EQ(nonFinite(r.ref.cube), 0u);
        CompareRule needle;
        needle.floor = 0.0;
        needle.skipBelow = 1e-3;
        InteriorComparison m = compareInterior(r.gpu, r.ref, needle);
        report("gloss " + fmt::format("{:g}", gloss), r, m);
        EXPECT_GE(m.pixels, 500);
        EXPECT_LE(m.maxRelative, 1e-4);
    }
}

TEST(Numerics, GlossZeroIsAConstantLobeOfOneOverPi) {
    // ρs = 1, ρd = 0: L = E·cos θ/π for every view, even where n·h = 0 (x⁰ = 1).
    for (double thetaDeg : {0.0, 45.0, 89.9}) {
        SCOPED_TRACE(thetaDeg);
        const double theta = thetaDeg * kDeg;
        Scene s = emptyScene(Grid{400, 700, 50}, perspectiveCamera({0, -3, 1}, {0, 0, 0}, {0, 0, 1}, 40, 16, 16));
        s.materials.push_back(glossy(constantSpectrum(0.0), constantSpectrum(1.0), 0.0, "flat lobe"));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 40, 40));
        s.lights.push_back(directionalLight({std::sin(theta), 0, -std::cos(theta)}, daylightLike(), 1.0));
        SceneOnGrid g = onGrid(s);
        Rendered r = renderBoth(s, g);
        double worst = 0.0;
        for (int y = 10; y < 16; ++y)  // the lower rows see the quad
            for (int x = 0; x < 16; ++x)
                for (int b = 0; b < r.gpu.bands(); ++b) {
                    const double expected = g.lights[0][b] * std::cos(theta) / kPi;
                    worst = std::max(worst, std::fabs(r.gpu.at(x, y, b) - expected) / expected);
                }
        std::printf("  [numerics] gloss 0 lit at %g°: max rel err vs E·cosθ/π %.3g\n", thetaDeg, worst);
        EXPECT_LE(worst, 1e-5);
    }
}

// --- Grazing angles -----------------------------------------------------------------------------

TEST(Numerics, QuadSeenAndLitAtGrazingAngles) {
    const double a = 89.9 * kDeg;  // from the normal
    // The quad lies in z = 0, long along y so that seen at 89.9° it still fills the view: 20 m
    // foreshortened by cos 89.9° = 1.7e-3 is 3.5 cm, the view is 1 cm.
    auto make = [&](bool perspective) {
        const glm::dvec3 eye = 20.0 * glm::dvec3(0, -std::sin(a), std::cos(a));
        Camera cam = perspective ? perspectiveCamera(eye, {0, 0, 0}, {0, 0, 1}, 0.03, 24, 24)
                                 : orthographicCamera(eye, {0, 0, 0}, {0, 0, 1}, 0.01, 24, 24);
        Scene s = emptyScene(Grid{400, 700, 10}, cam);
        s.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.5), 50, "paint"));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 1, 20));
        // Lit at 89.9° from the mirror direction (n·h = 1), from the side, and by a point light
        // 1 cm above the surface.
        s.lights.push_back(directionalLight({0, std::sin(a), -std::cos(a)}, daylightLike(), 1.0));
        s.lights.push_back(directionalLight({std::sin(a), 0, -std::cos(a)}, daylightLike(), 1.0));
        s.lights.push_back(pointLight({0.3, 0.5, 0.01}, daylightLike(), 0.01));
        return s;
    };
    for (bool perspective : {false, true}) {
        Scene s = make(perspective);
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_EQ(negative(r.gpu), 0u);
        EXPECT_EQ(nonFinite(r.ref.cube), 0u);
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        report(perspective ? "grazing 89.9°, perspective" : "grazing 89.9°, orthographic", r, m);
        EXPECT_GE(m.pixels, 22 * 22);
        EXPECT_LE(m.maxRelative, 1e-4);
        // The point light on its own: in the pixel the two directional lights dominate it
        // (its irradiance is ~10⁻² of theirs), which hides its error in the sum.
        s.lights.erase(s.lights.begin(), s.lights.begin() + 2);
        r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        m = compareInterior(r.gpu, r.ref);
        report(perspective ? "grazing, the point light alone, perspective" : "grazing, the point light alone, ortho", r, m);
        EXPECT_GE(m.pixels, 22 * 22);
        EXPECT_LE(m.maxRelative, 1e-4);
    }
}

TEST(Numerics, LightExactlyOppositeTheEyeHasNoHalfVector) {
    // The eye looks along -z at a quad facing it, whose vertex normals point away (-z), towards a
    // light that travels along +z: the shading normal faces the light (n·w = 1) and w + v is
    // exactly the zero vector. There is no half vector; the lobe is 0 (as in the reference), not
    // normalize(0) = NaN. The same happens near the silhouette of a smooth mesh lit from behind.
    Scene s = emptyScene(Grid{400, 700, 50}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 2.0, 16, 16));
    s.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.5), 30, "paint"));
    Mesh m = quad({0, 0, 0}, {0, 0, 1}, 4, 4);
    m.normals.assign(4, glm::dvec3(0, 0, -1));
    s.meshes.push_back(m);
    s.lights.push_back(directionalLight({0, 0, 1}, daylightLike(), 1.0));
    SceneOnGrid g = onGrid(s);
    Rendered r = renderBoth(s, g);
    EXPECT_EQ(nonFinite(r.gpu), 0u);
    EXPECT_EQ(nonFinite(r.ref.cube), 0u);
    InteriorComparison m2 = compareInterior(r.gpu, r.ref);
    report("w + v = 0 (no half vector)", r, m2);
    EXPECT_LE(m2.maxRelative, 1e-4);
    for (int b = 0; b < r.gpu.bands(); ++b) {
        const double diffuseOnly = 0.5 * g.lights[0][b] / kPi;
        EXPECT_NEAR(r.gpu.at(8, 8, b), diffuseOnly, 1e-6 * diffuseOnly);
    }
}

// --- Degenerate geometry ------------------------------------------------------------------------

TEST(Numerics, DegenerateTrianglesRenderNothingAndHarmNothing) {
    // In front of a lit quad: triangles with a repeated vertex, all three vertices equal, three
    // collinear vertices (exactly, in binary) and a sliver 1e-12 m wide.
    Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 32, 32));
    s.materials.push_back(glossy(constantSpectrum(0.6), constantSpectrum(0.2), 30, "wall"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 3, 3, 0, glm::dvec3(0), "wall"));
    s.lights.push_back(pointLight({0.5, 0.5, 2}, daylightLike(), 1.0));
    s.lights.push_back(directionalLight({0, 0, -1}, daylightLike(), 0.01));
    const Scene clean = s;

    Mesh bad;
    bad.name = "degenerates";
    bad.positions = {{-0.5, -0.5, 1}, {0.5, 0.5, 1}, {0.25, -0.25, 1}, {0.75, -0.75, 1}, {1.25, -1.25, 1},
                     {-1, 0.25, 1}, {1, 0.25, 1}, {0, 0.25 + 1e-12, 1}};
    bad.indices = {0, 0, 1,  // repeated vertex
                   2, 2, 2,  // one point
                   2, 3, 4,  // collinear, exactly
                   0, 1, 1,  // a segment traversed back
                   5, 6, 7};  // a sliver 1e-12 m high and 2 m long
    bad.normals = smoothNormals(bad.positions, bad.indices);
    bad.material = 0;
    s.meshes.push_back(bad);

    Rendered withBad = renderBoth(s, onGrid(s));
    Rendered without = renderBoth(clean, onGrid(clean));
    EXPECT_EQ(nonFinite(withBad.gpu), 0u);
    EXPECT_EQ(nonFinite(withBad.ref.cube), 0u);
    // Nothing of the degenerate mesh is seen: the images equal the clean scene's, value for value
    // (the sliver's height is far below a pixel's 4 mm at the wall).
    size_t gpuDiffer = 0, refDiffer = 0;
    for (size_t i = 0; i < withBad.gpu.data.size(); ++i) {
        gpuDiffer += withBad.gpu.data[i] != without.gpu.data[i];
        refDiffer += withBad.ref.cube.data[i] != without.ref.cube.data[i];
    }
    InteriorComparison m = compareInterior(withBad.gpu, withBad.ref);
    report("degenerate triangles + quad", withBad, m);
    std::printf("  [numerics] degenerate triangles: %zu GPU and %zu reference values differ from the clean scene\n",
                gpuDiffer, refDiffer);
    EXPECT_EQ(gpuDiffer, 0u);
    EXPECT_EQ(refDiffer, 0u);
    EXPECT_GE(m.pixels, 400);
    EXPECT_LE(m.maxRelative, 1e-4);
}

TEST(Numerics, ZeroLengthMissingAndCancellingNormalsFallBackToTheFaceNormal) {
    // docs/physics.md: if the vertex normals cancel, the shading normal is the face normal. The
    // loaders never produce such meshes (glTF rejects zero-length normals, shapes compute theirs),
    // but a Mesh built in code can: both renderers must shade it as a flat face, not as NaN.
    auto scene = [](Mesh m) {
        Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0.3, 0.2, 3}, {0, 0, 0}, {0, 1, 0}, 40, 24, 24));
        s.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.3), 20, "paint"));
        m.material = 0;
        s.meshes.push_back(std::move(m));
        s.lights.push_back(pointLight({0.5, 1, 2}, daylightLike(), 1.0));
        s.lights.push_back(directionalLight({0.2, -0.3, -1}, daylightLike(), 0.01));
        return s;
    };
    const Mesh flat = quad({0, 0, 0}, {0, 0, 1}, 3, 3);
    Rendered expected = [&] {
        Scene s = scene(flat);
        return renderBoth(s, onGrid(s));
    }();

    Mesh zero = flat;
    zero.normals.assign(4, glm::dvec3(0.0));
    Mesh missing = flat;
    missing.normals.clear();
    Mesh cancelling = flat;  // opposite normals on the two ends of the shared diagonal
    cancelling.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, -1}, {0, 0, 1}};
    struct Case {
        const char* what;
        Mesh mesh;
    };
    // The quad's own error (1.0e-4 on lavapipe) sits on its diagonal, where a point light and a
    // highlight make the radiance vary fastest (docs/numerics.md, "The error floor").
    const InteriorComparison unitNormals = compareInterior(expected.gpu, expected.ref);
    report("unit normals (the same quad)", expected, unitNormals);
    EXPECT_LE(unitNormals.maxRelative, 2e-4);
    for (const Case& c : {Case{"zero-length normals", zero}, Case{"no normals", missing}}) {
        SCOPED_TRACE(c.what);
        Scene s = scene(c.mesh);
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_EQ(nonFinite(r.ref.cube), 0u);
        // Shaded exactly as the quad with its unit normals, on both renderers.
        EXPECT_EQ(r.gpu.data, expected.gpu.data);
        EXPECT_EQ(r.ref.cube.data, expected.ref.cube.data);
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        report(c.what, r, m);
        EXPECT_LE(m.maxRelative, 2e-4);
    }
    {
        // Where the interpolated normal passes through zero the face normal takes over; on either
        // side it flips between +z and -z, so a pixel whose centre lies within rounding of that
        // line may be lit on one renderer and dark on the other: only finiteness is asserted,
        // the agreement is printed.
        Scene s = scene(cancelling);
        Rendered r = renderBoth(s, onGrid(s));
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_EQ(nonFinite(r.ref.cube), 0u);
        InteriorComparison m = compareInterior(r.gpu, r.ref);
        report("cancelling normals", r, m);
    }
}

// --- Empty scenes -------------------------------------------------------------------------------

TEST(Numerics, EmptyScenesAreExactlyBlackOnBothRenderers) {
    const Grid grid{300, 740, 5};  // three passes
    const Camera cam = perspectiveCamera({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 40, 16, 16);
    Scene nothing = emptyScene(grid, cam);
    Scene lightsOnly = nothing;
    lightsOnly.lights.push_back(directionalLight({0, 0, -1}, daylightLike(), 1.0));
    lightsOnly.lights.push_back(ambientLight(daylightLike(), 1.0));
    Scene objectsOnly = nothing;
    objectsOnly.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.5), 10, "grey"));
    objectsOnly.meshes.push_back(sphere({0, 0, 0}, 1, 16, 8, 0));
    Scene emptyMesh = lightsOnly;  // a mesh without triangles
    emptyMesh.materials.push_back(lambertian(0.5));
    emptyMesh.meshes.push_back(Mesh{});
    for (const Scene* s : {&nothing, &lightsOnly, &objectsOnly, &emptyMesh}) {
        Rendered r = renderBoth(*s, onGrid(*s));
        ASSERT_EQ(r.gpu.data.size(), size_t(16 * 16 * 89));
        size_t nonzero = 0;
        for (size_t i = 0; i < r.gpu.data.size(); ++i)
            nonzero += (r.gpu.data[i] != 0.0f) + (r.ref.cube.data[i] != 0.0f);
        EXPECT_EQ(nonzero, 0u);
    }
}

// --- Camera inside an object ----------------------------------------------------------------------

TEST(Numerics, CameraInsideASphereSeesItsInside) {
    // The camera at the centre of a sphere: every ray hits a back face, shaded as its front
    // (two-sided). The GPU's near plane is 1e-5 of the far distance here (1e-5 m), far nearer
    // than the 1 m wall.
    Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 70, 32, 32));
    s.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.2), 20, "inside"));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 64, 32, 0));
    s.lights.push_back(pointLight({0.2, 0.3, 0.1}, daylightLike(), 1.0));
    s.lights.push_back(ambientLight(daylightLike(), 0.001));
    const LocalFrame frame = localFrameFor(s, s.camera);
    const double near_m = cameraMatrices(s.camera, s, frame).nearPlane * frame.unit_m();
    Rendered r = renderBoth(s, onGrid(s));
    EXPECT_EQ(nonFinite(r.gpu), 0u);
    EXPECT_EQ(negative(r.gpu), 0u);
    size_t dark = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) dark += r.gpu.at(x, y, 15) == 0.0f;
    EXPECT_EQ(dark, 0u) << "every pixel sees the lit inside";
    InteriorComparison m = compareInterior(r.gpu, r.ref);
    report(fmt::format("inside a sphere (near {:.3g} m)", near_m), r, m);
    EXPECT_LE(near_m, 1e-4);
    EXPECT_GE(m.pixels, 500);
    EXPECT_LE(m.maxRelative, 1e-4);
}

TEST(Numerics, NearPlaneClipsWhatIsNearerThanItOnTheGpuOnly) {
    // The documented difference (docs/physics.md, "Near plane"): in a scene 100 m deep the near
    // plane is 1e-5 of the far distance, about 1 mm; a wall 0.1 mm in front of the camera is
    // clipped by the GPU, which sees the far wall through it, while the reference sees it.
    Scene s = emptyScene(Grid{400, 700, 50}, perspectiveCamera({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, 16, 16));
    s.materials.push_back(lambertian(0.8, "near"));
    s.materials.push_back(lambertian(0.2, "far"));
    s.meshes.push_back(quad({0, 0, -1e-4}, {0, 0, 1}, 1, 1, 0));
    s.meshes.push_back(quad({0, 0, -100}, {0, 0, 1}, 500, 500, 1));
    s.lights.push_back(ambientLight(daylightLike(), 1.0));
    SceneOnGrid g = onGrid(s);
    const LocalFrame frame = localFrameFor(s, s.camera);
    const CameraMatrices cm = cameraMatrices(s.camera, s, frame);
    const double near_m = cm.nearPlane * frame.unit_m(), far_m = cm.farPlane * frame.unit_m();
    Rendered r = renderBoth(s, g);
    const double nearRadiance = 0.8 * g.lights[0][3] / kPi, farRadiance = 0.2 * g.lights[0][3] / kPi;
    std::printf("  [numerics] near plane %.3g m, far %.3g m: wall at 1e-4 m — reference %.4g (the wall), GPU %.4g\n",
                near_m, far_m, r.ref.cube.at(8, 8, 3), r.gpu.at(8, 8, 3));
    EXPECT_GT(near_m, 1e-4);
    EXPECT_NEAR(r.ref.cube.at(8, 8, 3), nearRadiance, 1e-6 * nearRadiance);
    EXPECT_NEAR(r.gpu.at(8, 8, 3), farRadiance, 1e-5 * farRadiance);
}

// --- Fluorescence at the edge of overlap ----------------------------------------------------------

TEST(Numerics, FluorescenceFromASingleOverlappingBandAndFromNone) {
    // 5 nm grid. The excitation ends inside band 505 ([502.5, 507.5] nm); the light starts either
    // inside band 510 (no band holds both: no emission at all) or inside band 505 (exactly one
    // band does: the emission is Φ/π·a·E·λ·Δλ of that band times ê/λ).
    const Grid grid{400, 700, 5};
    const double phi = 0.9;
    CaptureWarnings quiet;  // the boxes cover part of the grid, as intended
    auto scene = [&](double lightStart) {
        Scene s = emptyScene(grid, orthographicCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 1.0, 8, 8));
        s.materials.push_back(fluorescent(constantSpectrum(0.0), boxSpectrum(450, 507, 0.8, 0.1),
                                          gaussianSpectrum(600, 20), phi, "dye"));
        s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4));
        s.lights.push_back(directionalLight({0, 0, -1}, boxSpectrum(lightStart, 650, 2.0, 0.1), 1.0));
        return s;
    };
    {
        Scene s = scene(508.0);
        SceneOnGrid g = onGrid(s);
        int both = 0;
        for (int b = 0; b < grid.bands(); ++b) both += g.materials[0].excitation[b] * g.lights[0][b] != 0.0;
        ASSERT_EQ(both, 0);
        ASSERT_GT(g.materials[0].excitation[(505 - 400) / 5], 0.0);
        ASSERT_GT(g.lights[0][(510 - 400) / 5], 0.0);
        Rendered r = renderBoth(s, g);
        size_t nonzero = 0;
        for (size_t i = 0; i < r.gpu.data.size(); ++i)
            nonzero += (r.gpu.data[i] != 0.0f) + (r.ref.cube.data[i] != 0.0f);
        EXPECT_EQ(nonzero, 0u) << "adjacent bands, no overlap: no fluorescence";
    }
    {
        Scene s = scene(507.0);
        SceneOnGrid g = onGrid(s);
        const int k = (505 - 400) / 5;
        int both = 0;
        for (int b = 0; b < grid.bands(); ++b) both += g.materials[0].excitation[b] * g.lights[0][b] != 0.0;
        ASSERT_EQ(both, 1);
        const double coupling = phi / kPi * g.materials[0].excitation[k] * g.lights[0][k] * 505.0 * grid.step_nm;
        Rendered r = renderBoth(s, g);
        double worst = 0.0;
        for (int b = 0; b < grid.bands(); ++b) {
            const double expected = coupling * g.materials[0].emission[b] / g.wavelengths_nm[b];
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x) {
                    if (expected == 0.0) {
                        ASSERT_EQ(r.gpu.at(x, y, b), 0.0f);
                        continue;
                    }
                    worst = std::max(worst, std::fabs(r.gpu.at(x, y, b) - expected) / expected);
                    worst = std::max(worst, std::fabs(r.ref.cube.at(x, y, b) - expected) / expected);
                }
        }
        std::printf("  [numerics] fluorescence from one overlapping band (a·E = %.3g at 505 nm): max rel err %.3g\n",
                    g.materials[0].excitation[k] * g.lights[0][k], worst);
        EXPECT_GT(r.gpu.at(4, 4, (600 - 400) / 5), 0.0f);
        EXPECT_LE(worst, 1e-5);
    }
}

// --- Scale and position -------------------------------------------------------------------------
// docs/numerics.md, "Scale and position": both renderers compute in the scene's local frame
// (scene/local_frame.h), so a scene renders the same wherever it is and at whatever scale.

namespace {

// The scene moved by t (m): every vertex, the camera, the point lights.
Scene translated(Scene s, glm::dvec3 t) {
    for (Mesh& m : s.meshes)
        for (glm::dvec3& p : m.positions) p += t;
    s.camera.position += t;
    s.camera.target += t;
    for (Light& l : s.lights) l.position += t;
    return s;
}

// The scene scaled by k about the world origin, its point lights k² brighter so that every
// radiance stays what it was (E = I·cos θ/d²).
Scene scaled(Scene s, double k) {
    for (Mesh& m : s.meshes)
        for (glm::dvec3& p : m.positions) p *= k;
    s.camera.position *= k;
    s.camera.target *= k;
    s.camera.height_m *= k;
    for (Light& l : s.lights)
        if (l.type == Light::Type::Point) {
            l.position *= k;
            l.scale *= k * k;
        }
    return s;
}

// The point-lit quad's known answer: a Lambertian plane z = 0 (normal +z) of reflectance ρ under a
// point light of intensity I, seen through the centre of pixel (x, y) of `cam`:
// L = ρ·I·cos θ/(π d²) where the pixel's ray meets the plane. Computed here in double from
// docs/physics.md ("Camera", "Point lights"), not by either renderer.
double pointLitPlane(const Camera& cam, glm::dvec3 light, double rho, double intensity, int x, int y) {
    const glm::dvec3 f = glm::normalize(cam.target - cam.position), r = glm::normalize(glm::cross(f, cam.up)),
                     u = glm::cross(r, f);
    const double aspect = double(cam.width) / cam.height;
    const double nx = 2.0 * (x + 0.5) / cam.width - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / cam.height;
    glm::dvec3 origin = cam.position, dir = f;
    if (cam.projection == Camera::Projection::Perspective) {
        const double t = std::tan(0.5 * cam.fov_y_deg * kDeg);
        dir = glm::normalize(f + nx * t * aspect * r + ny * t * u);
    } else {
        origin += 0.5 * cam.height_m * (nx * aspect * r + ny * u);
    }
    const glm::dvec3 p = origin - (origin.z / dir.z) * dir;
    const glm::dvec3 toLight = light - p;
    const double d2 = glm::dot(toLight, toLight);
    return rho * intensity * (toLight.z / std::sqrt(d2)) / (kPi * d2);
}

// A white Lambertian quad (ρ = 0.5, 2 m × 2 m in z = 0) under a point light of 1 W·sr⁻¹·nm⁻¹,
// every coordinate a dyadic fraction so that moving it by whole metres is exact. Perspective:
// seen head-on (a flat scene with no depth span, the case that went black at micrometres);
// orthographic: seen obliquely.
const glm::dvec3 kQuadLight{0.375, 0.25, 0.625};
Scene pointLitQuad(bool perspective) {
    Camera cam = perspective ? perspectiveCamera({0, 0, 2.5}, {0, 0, 0}, {0, 1, 0}, 40, 24, 24)
                             : orthographicCamera({0.5, -1.0, 2.0}, {0, 0, 0}, {0, 1, 0}, 1.25, 24, 24);
    Scene s = emptyScene(Grid{400, 700, 100}, cam);
    s.materials.push_back(lambertian(0.5, "white"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 2, 2));
    s.lights.push_back(pointLight(kQuadLight, constantSpectrum(1.0), 1.0, "lights.0"));
    return s;
}

struct AgainstKnownAnswer {
    double gpu = 0.0, cpu = 0.0;  // worst relative error over interior pixels and bands
    int pixels = 0;
};

// Both cubes against pointLitPlane on the base scene's camera (the answer does not move with the
// scene), on the reference's interior pixels.
AgainstKnownAnswer againstPointLitPlane(const Rendered& r, const Camera& base) {
    AgainstKnownAnswer a;
    const ReferenceImage& ref = r.ref;
    const int W = ref.cube.width, H = ref.cube.height;
    for (int y = 1; y + 1 < H; ++y)
        for (int x = 1; x + 1 < W; ++x) {
            bool interior = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) interior = interior && ref.objectId[size_t(y + dy) * W + x + dx] == 0;
            if (!interior) continue;
            ++a.pixels;
            const double expected = pointLitPlane(base, kQuadLight, 0.5, 1.0, x, y);
            for (int b = 0; b < ref.cube.bands(); ++b) {
                a.gpu = std::max(a.gpu, std::fabs(r.gpu.at(x, y, b) / expected - 1.0));
                a.cpu = std::max(a.cpu, std::fabs(ref.cube.at(x, y, b) / expected - 1.0));
                if (!std::isfinite(r.gpu.at(x, y, b))) a.gpu = INFINITY;
            }
        }
    return a;
}

// Cube `c` against cube `base` on the interior pixels of `mask` (the reference of either):
// relative error as compareInterior counts it.
InteriorComparison compareCubes(const SpectralCube& c, const SpectralCube& base, const ReferenceImage& mask) {
    ReferenceImage asReference = mask;
    asReference.cube = base;
    return compareInterior(c, asReference);
}

// The double-precision reference cube before rounding to float: the pixels' radiance in double,
// for comparisons finer than float32's 6e-8.
std::vector<double> referenceInDouble(const Scene& s, const SceneOnGrid& g) {
    const ReferenceRenderer renderer(s, g);
    const int W = s.camera.width, H = s.camera.height, B = renderer.bands();
    std::vector<double> out(size_t(W) * H * B);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) renderer.pixel(x, y, &out[(size_t(y) * W + x) * B]);
    return out;
}

double worstRelative(const std::vector<double>& a, const std::vector<double>& base) {
    double peak = 0.0, worst = 0.0;
    for (double v : base) peak = std::max(peak, std::fabs(v));
    for (size_t i = 0; i < a.size(); ++i)
        worst = std::max(worst, std::fabs(a[i] - base[i]) / std::max(std::fabs(base[i]), 1e-4 * peak));
    return worst;
}

// A glossy sphere on a floor under every kind of light, with shadows: geometry, point and
// directional lights, the shadow maps and the environment (a sky and a ground).
Scene litSphereOnFloor() {
    Scene s = sphereOnFloor(Grid{400, 700, 50}, 24);
    s.lights.push_back(hemisphereLight({0, 1, 0}, daylightLike(), 0.001, "sky"));
    s.lights.push_back(hemisphereLight({0, -1, 0}, daylightLike(), 0.0003, "ground"));
    for (Light& l : s.lights) l.shadows = true;
    return s;
}

}  // namespace

TEST(Numerics, PointLitLambertianQuadIsRhoICosThetaOverPiDSquared) {
    for (bool perspective : {true, false}) {
        SCOPED_TRACE(perspective ? "perspective" : "orthographic");
        const Scene s = pointLitQuad(perspective);
        const Rendered r = renderBoth(s, onGrid(s));
        const AgainstKnownAnswer a = againstPointLitPlane(r, s.camera);
        std::printf("  [numerics] point-lit quad, %s: %d px; against rho*I*cos/(pi d^2): GPU %.3g, reference %.3g\n",
                    perspective ? "perspective, head-on" : "orthographic, oblique", a.pixels, a.gpu, a.cpu);
        EXPECT_GE(a.pixels, 20 * 20 / (perspective ? 1 : 3));
        EXPECT_LE(a.gpu, 1e-5);
        EXPECT_LE(a.cpu, 1e-6);  // float32 rounding of the cube
    }
}

TEST(Numerics, ScenesFarFromTheWorldOriginRenderAsAtIt) {
    // The same scene, camera with it, moved 10³, 10⁵ and 10⁷ m (and a non-dyadic 1.2 × 10⁴ m):
    // every position is made relative to the frame's origin in double before it is rounded to
    // float, so the GPU's error depends on distances within the scene, not from the world origin.
    const glm::dvec3 direction(1.0, -0.75, 0.5);
    struct Case {
        double distance;
        glm::dvec3 t;
    };
    const Case cases[] = {{1e3, 1e3 * direction}, {1e5, 1e5 * direction}, {1e7, 1e7 * direction},
                          {1.2e4, {12345.678, -9876.54321, 4321.0987}}};
    for (bool perspective : {true, false}) {
        const Scene base = pointLitQuad(perspective);
        const Rendered r0 = renderBoth(base, onGrid(base));
        const std::vector<double> ref0 = referenceInDouble(base, onGrid(base));
        for (const Case& c : cases) {
            SCOPED_TRACE(c.distance);
            const Scene s = translated(base, c.t);
            const Rendered r = renderBoth(s, onGrid(s));
            const InteriorComparison gpu = compareCubes(r.gpu, r0.gpu, r0.ref);
            const double cpu = worstRelative(referenceInDouble(s, onGrid(s)), ref0);
            const AgainstKnownAnswer a = againstPointLitPlane(r, base.camera);
            std::printf("  [numerics] point-lit quad (%s) moved %.3g m: GPU vs unmoved %.3g, reference vs unmoved %.3g "
                        "(in double); against the known answer GPU %.3g\n",
                        perspective ? "perspective" : "orthographic", glm::length(c.t), gpu.maxRelative, cpu, a.gpu);
            EXPECT_EQ(nonFinite(r.gpu), 0u);
            EXPECT_GE(gpu.pixels, 100);
            EXPECT_LE(gpu.maxRelative, 1e-5);
            EXPECT_LE(cpu, 1e-9);
            EXPECT_LE(a.gpu, 1e-5);
        }
    }
    // Every kind of light, shadows and the environment. At 10⁷ m the sphere's vertices (not dyadic)
    // are themselves rounded to 0.93 nm when moved (the spacing of doubles there is 1.9 nm), which
    // bounds what the reference can agree to.
    const Scene base = litSphereOnFloor();
    const Rendered r0 = renderBoth(base, onGrid(base));
    const std::vector<double> ref0 = referenceInDouble(base, onGrid(base));
    for (double distance : {1e3, 1e5, 1e7}) {
        SCOPED_TRACE(distance);
        const Scene s = translated(base, distance * direction);
        const Rendered r = renderBoth(s, onGrid(s));
        const InteriorComparison gpu = compareCubes(r.gpu, r0.gpu, r0.ref);
        const double cpu = worstRelative(referenceInDouble(s, onGrid(s)), ref0);
        std::printf("  [numerics] lit sphere on a floor (shadows, sky and ground) moved %.3g m: GPU vs unmoved %.3g "
                    "(%d px), reference vs unmoved %.3g\n",
                    distance * glm::length(direction), gpu.maxRelative, gpu.pixels, cpu);
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_GE(gpu.pixels, 150);
        EXPECT_LE(gpu.maxRelative, 1e-5);
        EXPECT_LE(cpu, distance < 1e6 ? 1e-9 : 1e-7);
    }
}

TEST(Numerics, ScenesFromMicrometresToMegametresRenderAsAtOneMetre) {
    // The same scenes scaled by 10⁻⁶ … 10⁶ (point lights k² brighter, so the radiance is unchanged).
    // The frame's unit is a power of two near the scene's size, so the GPU computes with numbers
    // of the same magnitude at every scale.
    for (bool perspective : {true, false}) {
        const Scene base = pointLitQuad(perspective);
        const Rendered r0 = renderBoth(base, onGrid(base));
        for (double k : {1e-6, 1e-3, 1e3, 1e6}) {
            SCOPED_TRACE(k);
            const Scene s = scaled(base, k);
            const Rendered r = renderBoth(s, onGrid(s));
            const InteriorComparison gpu = compareCubes(r.gpu, r0.gpu, r0.ref);
            const AgainstKnownAnswer a = againstPointLitPlane(r, base.camera);
            std::printf("  [numerics] point-lit quad (%s) at scale %g: GPU vs 1 m %.3g (%d px); against the known "
                        "answer GPU %.3g, reference %.3g\n",
                        perspective ? "perspective, head-on" : "orthographic", k, gpu.maxRelative, gpu.pixels, a.gpu,
                        a.cpu);
            EXPECT_EQ(nonFinite(r.gpu), 0u);
            EXPECT_GE(gpu.pixels, 100);
            EXPECT_LE(gpu.maxRelative, 1e-5);
            EXPECT_LE(a.gpu, 1e-5);
            EXPECT_LE(a.cpu, 1e-6);
        }
    }
    const Scene base = litSphereOnFloor();
    const Rendered r0 = renderBoth(base, onGrid(base));
    for (double k : {1e-6, 1e6}) {
        SCOPED_TRACE(k);
        const Scene s = scaled(base, k);
        const Rendered r = renderBoth(s, onGrid(s));
        const InteriorComparison gpu = compareCubes(r.gpu, r0.gpu, r0.ref);
        const InteriorComparison cpu = compareCubes(r.ref.cube, r0.ref.cube, r0.ref);
        std::printf("  [numerics] lit sphere on a floor at scale %g: GPU vs 1 m %.3g (%d px), reference vs 1 m %.3g\n", k,
                    gpu.maxRelative, gpu.pixels, cpu.maxRelative);
        EXPECT_EQ(nonFinite(r.gpu), 0u);
        EXPECT_GE(gpu.pixels, 150);
        EXPECT_LE(gpu.maxRelative, 1e-5);
        EXPECT_LE(cpu.maxRelative, 1e-6);
    }
}

TEST(Numerics, ScenesBeyondTheSupportedLengthsAreRefusedByName) {
    // Objects spanning less than 10⁻¹⁵ m or more than 10¹⁵ m, and a camera or a light farther
    // than 2⁶⁰ of the scene's span: an input error naming the key, from either renderer, never a
    // black image.
    const Scene base = pointLitQuad(true);
    for (double k : {1e-17, 1e17}) {
        Scene s = scaled(base, k);
        s.file = "far.json";
        const SceneOnGrid g = onGrid(s);
        expectInputError([&] { SpectralPass pass(gpu(), s, g); }, "far.json", "objects", "Metamer renders scenes from");
        expectInputError([&] { renderReference(s, g); }, "far.json", "objects", "Metamer renders scenes from");
    }
    Scene s = base;
    s.file = "far.json";
    s.camera.position = {0, 0, 1e19};
    expectInputError([&] { renderReference(s, onGrid(s)); }, "far.json", "camera.position", "the camera is 1e+19 m");
    s = base;
    s.file = "far.json";
    s.lights[0].position = {0, 0, -1e19};
    expectInputError([&] { SpectralPass pass(gpu(), s, onGrid(s)); }, "far.json", "lights.0.position", "the light is 1e+19 m");
    // The edges themselves render (2 × 2 m quad → 2.8 m span: scaled to 1.1e-15 and 0.9e15 m).
    for (double k : {4e-16, 3.2e14}) {
        const Scene edge = scaled(base, k);
        const Rendered r = renderBoth(edge, onGrid(edge));
        const AgainstKnownAnswer a = againstPointLitPlane(r, base.camera);
        std::printf("  [numerics] point-lit quad spanning %.3g m: against the known answer GPU %.3g, reference %.3g\n",
                    2.0 * std::sqrt(2.0) * k, a.gpu, a.cpu);
        EXPECT_LE(a.gpu, 1e-5);
    }
}

TEST(Numerics, PointLightsOnASurfaceContributeNothingAndNeverNaN) {
    // An orthographic view of a quad in z = 0, 17 × 17 pixels of exactly 1/16 m, so that pixel
    // centres lie at multiples of 1/16 m: the centre (on the diagonal shared by the quad's two
    // triangles), a corner (a vertex), the middle of a side (an edge) and interior points. Point
    // lights placed exactly there are in the surface's plane: cos θ = 0 for every other point of
    // the quad, and at their own pixel d = 0, which has no direction and contributes nothing
    // (docs/physics.md). So the image equals that of the directional light alone, exactly.
    Scene lit = emptyScene(Grid{400, 700, 50}, orthographicCamera({0, 0, 2}, {0, 0, 0}, {0, 1, 0}, 17.0 / 16.0, 17, 17));
    lit.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.25), 20, "paint"));
    lit.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 1, 1));
    lit.lights.push_back(directionalLight({0.25, -0.5, -1}, daylightLike(), 1.0));
    Scene onSurface = lit;
    const glm::dvec3 atPixelCentres[] = {{0, 0, 0},          {0.5, 0.5, 0},       {-0.5, -0.5, 0}, {0.5, 0, 0},
                                         {0, -0.5, 0},       {0.0625, 0.0625, 0}, {-0.25, 0.3125, 0},
                                         {0.4375, -0.125, 0}, {-0.1875, -0.375, 0}};
    for (const glm::dvec3& p : atPixelCentres) {
        onSurface.lights.push_back(pointLight(p, daylightLike(), 1.0));
        onSurface.lights.back().shadows = false;
    }
    const Rendered alone = renderBoth(lit, onGrid(lit)), with = renderBoth(onSurface, onGrid(onSurface));
    EXPECT_EQ(nonFinite(with.gpu), 0u);
    EXPECT_EQ(negative(with.gpu), 0u);
    EXPECT_EQ(nonFinite(with.ref.cube), 0u);
    double worstGpu = 0.0, worstCpu = 0.0;
    auto worse = [](double& worst, float a, float b) {  // a NaN counts as the worst
        const double d = std::fabs(double(a) - double(b));
        if (!(d <= worst)) worst = std::isnan(d) ? INFINITY : d;
    };
    for (size_t i = 0; i < alone.gpu.data.size(); ++i) {
        worse(worstGpu, with.gpu.data[i], alone.gpu.data[i]);
        worse(worstCpu, with.ref.cube.data[i], alone.ref.cube.data[i]);
    }
    std::printf("  [numerics] %zu point lights on pixel centres of a lit quad: largest |difference| from the "
                "directional light alone GPU %.3g, reference %.3g\n",
                std::size(atPixelCentres), worstGpu, worstCpu);
    EXPECT_EQ(worstGpu, 0.0);
    EXPECT_EQ(worstCpu, 0.0);

    // A light on a vertex of a smooth sphere, and one inside it: no NaN, no Inf, nothing negative.
    Scene sphereScene = emptyScene(Grid{400, 700, 50}, perspectiveCamera({0, 0.5, 3}, {0, 0, 0}, {0, 1, 0}, 40, 24, 24));
    sphereScene.materials.push_back(glossy(constantSpectrum(0.5), constantSpectrum(0.25), 20, "paint"));
    sphereScene.meshes.push_back(sphere({0, 0, 0}, 1.0, 32, 16, 0));
    const glm::dvec3 vertex = sphereScene.meshes[0].positions[sphereScene.meshes[0].positions.size() / 2];
    sphereScene.lights.push_back(pointLight(vertex, daylightLike(), 1.0));
    sphereScene.lights.push_back(pointLight({0, 0, 0}, daylightLike(), 1.0));
    sphereScene.lights.push_back(directionalLight({0, -1, -1}, daylightLike(), 1.0));
    const Rendered r = renderBoth(sphereScene, onGrid(sphereScene));
    EXPECT_EQ(nonFinite(r.gpu), 0u);
    EXPECT_EQ(negative(r.gpu), 0u);
    EXPECT_EQ(nonFinite(r.ref.cube), 0u);
}
