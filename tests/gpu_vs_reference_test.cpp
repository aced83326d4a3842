// The GPU spectral pass against the CPU reference (double precision, independent code) on small
// scenes covering every feature: per band, max relative error ≤ 1e-4 on pixels away from edges.
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"
#include "scene/shapes.h"
#include "support/gpu.h"
#include "support/interior_comparison.h"
#include "support/scene_builders.h"

#include <algorithm>
#include <cmath>

using namespace metamer;
using namespace metamer::test;

namespace {

void expectGpuMatchesReference(const Scene& scene, int minInteriorPixels, const SpectralPassOptions& opts = {}) {
    uint32_t before = gpu().validationErrors();
    SceneOnGrid g = onGrid(scene);
    SpectralPass pass(gpu(), scene, g, opts);
    SpectralCube cube = pass.render();
    ReferenceOptions ro;
    ro.ssaa = opts.ssaa;
    ReferenceImage ref = renderReference(scene, g, ro);
    ASSERT_EQ(cube.data.size(), ref.cube.data.size());
    InteriorComparison c = compareInterior(cube, ref);
    ::testing::Test::RecordProperty("max_relative_error", std::to_string(c.maxRelative));
    std::printf("  %s: %d interior pixels, %d bands, max relative error %.3g (pixel %d,%d band %d)\n",
                pass.plan().describe().c_str(), c.pixels, cube.bands(), c.maxRelative, c.worstX, c.worstY,
                c.worstBand);
    EXPECT_GE(c.pixels, minInteriorPixels);
    EXPECT_LE(c.maxRelative, 1e-4) << "at pixel " << c.worstX << "," << c.worstY << " band " << c.worstBand
                                   << ": gpu " << cube.at(c.worstX, c.worstY, c.worstBand) << " cpu "
                                   << ref.cube.at(c.worstX, c.worstY, c.worstBand);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

Spectrum daylightLike() {
    // A smooth, D-illuminant-shaped test SPD over 300–800 nm (not a library file: tests stay
    // independent of the data).
    std::vector<double> nm, v;
    for (double l = 300; l <= 800; l += 5) {
        nm.push_back(l);
        v.push_back(60 + 40 * std::sin((l - 300) / 70.0) + 30 * std::exp(-0.5 * std::pow((l - 460) / 25, 2)));
    }
    return sampledSpectrum(nm, v, "daylight-like");
}

Spectrum tungstenLike() {
    std::vector<double> nm, v;
    for (double l = 300; l <= 800; l += 5) {
        nm.push_back(l);
        v.push_back(10 + 0.0004 * (l - 300) * (l - 300));
    }
    return sampledSpectrum(nm, v, "tungsten-like");
}

}  // namespace

TEST(GpuVsReference, GlossySpheresUnderThreeLights) {
    Scene s = emptyScene(Grid{300, 740, 5}, perspectiveCamera({0, 1.5, 6}, {0, 0, 0}, {0, 1, 0}, 35, 96, 96));
    s.materials.push_back(lambertian(gaussianSpectrum(600, 60, 0.8, 300, 800, 5), "red"));
    s.materials.push_back(glossy(gaussianSpectrum(450, 40, 0.6, 300, 800, 5), constantSpectrum(0.04), 60, "plastic"));
    s.materials.push_back(glossy(constantSpectrum(0.02), gaussianSpectrum(650, 120, 0.95, 300, 800, 5), 400, "metal"));
    s.materials.push_back(lambertian(0.5, "floor"));
    s.meshes.push_back(sphere({-1.3, 0, 0}, 0.6, 64, 32, 0));
    s.meshes.push_back(sphere({0, 0, 0}, 0.6, 64, 32, 1));
    s.meshes.push_back(sphere({1.3, 0, 0}, 0.6, 64, 32, 2));
    s.meshes.push_back(quad({0, -0.6, 0}, {0, 1, 0}, 8, 8, 3));
    s.lights.push_back(ambientLight(daylightLike(), 0.002));
    s.lights.push_back(directionalLight({-0.3, -1, -0.6}, daylightLike(), 0.01));
    s.lights.push_back(pointLight({2, 3, 2}, tungstenLike(), 0.5));
    expectGpuMatchesReference(s, 1500);
}

TEST(GpuVsReference, FluorescentObjectsUnderUvAndVisibleLight) {
    Scene s = emptyScene(Grid{300, 740, 5}, perspectiveCamera({0, 2, 5}, {0, 0, 0}, {0, 1, 0}, 40, 80, 64));
    s.materials.push_back(fluorescent(constantSpectrum(0.5), boxSpectrum(300, 400, 0.4, 10),
                                      gaussianSpectrum(440, 20, 1.0), 0.9, "brightener"));
    s.materials.push_back(fluorescent(gaussianSpectrum(650, 50, 0.4, 300, 800, 5), gaussianSpectrum(530, 30, 0.5),
                                      gaussianSpectrum(590, 20, 1.0), 0.7, "orange dye"));
    s.materials.push_back(lambertian(0.8, "white"));
    s.meshes.push_back(sphere({-1, 0, 0}, 0.7, 48, 24, 0));
    s.meshes.push_back(sphere({1, 0, 0}, 0.7, 48, 24, 1));
    s.meshes.push_back(quad({0, -0.7, 0}, {0, 1, 0}, 6, 6, 2));
    s.lights.push_back(directionalLight({0.2, -1, -0.5}, gaussianSpectrum(365, 8, 100, 300, 800, 1), 0.02));
    s.lights.push_back(pointLight({-1, 2, 2}, daylightLike(), 0.3));
    s.lights.push_back(ambientLight(daylightLike(), 0.001));
    expectGpuMatchesReference(s, 1000);
}

TEST(GpuVsReference, OrthographicChartOfPatches) {
    Scene s = emptyScene(Grid{380, 780, 10}, orthographicCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 4.4, 96, 64));
    for (int i = 0; i < 24; ++i) {
        s.materials.push_back(lambertian(gaussianSpectrum(400 + 15 * i, 30 + 3 * i, 0.05 + 0.035 * i, 300, 800, 5),
                                         "patch" + std::to_string(i)));
        double x = -2.5 + (i % 6), y = 1.5 - (i / 6);
        s.meshes.push_back(quad({x * 1.0, y * 1.0, 0}, {0, 0, 1}, 0.9, 0.9, uint32_t(i)));
    }
    s.lights.push_back(directionalLight({0, 0, -1}, daylightLike(), 0.01));
    expectGpuMatchesReference(s, 2000);
}

TEST(GpuVsReference, SixteenLightsOnGlossyMetal) {
    Scene s = emptyScene(Grid{400, 700, 2}, perspectiveCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 64, 64));
    s.materials.push_back(glossy(constantSpectrum(0.1), gaussianSpectrum(600, 100, 0.9, 300, 800, 5), 30, "copperish"));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 64, 32, 0));
    for (int i = 0; i < 16; ++i) {
        double a = 2 * M_PI * i / 16;
        s.lights.push_back(pointLight({3 * std::cos(a), 2 * std::sin(a), 2 + 0.1 * i},
                                      gaussianSpectrum(400 + 20 * i, 30, 10, 300, 800, 2), 0.5,
                                      "light" + std::to_string(i)));
    }
    expectGpuMatchesReference(s, 1500);
}

// 128 lights, the most a scene may have, of every kind: beyond the first 4 of a kind the shader
// loops instead of unrolling (spectral.frag, UNROLLED_LIGHTS), which must not change the sum.
TEST(GpuVsReference, TheMostLightsASceneMayHaveOfEveryKind) {
    Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 40, 40));
    s.materials.push_back(glossy(constantSpectrum(0.3), constantSpectrum(0.2), 20, "glossy"));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 48, 24, 0));
    for (int i = 0; i < 128; ++i) {
        const double a = 2 * M_PI * i / 128;
        const Spectrum e = gaussianSpectrum(400 + 2 * i, 40, 1, 300, 800, 5);
        if (i % 16 == 0)
            s.lights.push_back(ambientLight(e, 0.001, "ambient" + std::to_string(i)));
        else if (i % 2)
            s.lights.push_back(directionalLight({std::cos(a), std::sin(a), -1}, e, 0.01));
        else
            s.lights.push_back(pointLight({3 * std::cos(a), 3 * std::sin(a), 3}, e, 0.1, "point" + std::to_string(i)));
        s.lights.back().shadows = i < 12;  // a few shadowing lights of each kind (they go first in the shader)
    }
    expectGpuMatchesReference(s, 700);
}

TEST(GpuVsReference, FineGridOfManyPasses) {
    // 0.5 nm over 400–700 nm: 601 bands, 151 layers, 19 passes of up to 8 attachments.
    Scene s = emptyScene(Grid{400, 700, 0.5}, perspectiveCamera({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 40, 32, 32));
    s.materials.push_back(glossy(gaussianSpectrum(500, 50, 0.7), constantSpectrum(0.05), 20, "green"));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 48, 24, 0));
    s.lights.push_back(directionalLight({-1, -1, -1}, daylightLike(), 0.01));
    expectGpuMatchesReference(s, 400);
}

TEST(GpuVsReference, SupersampledEdgesMatchReferenceSupersampling) {
    Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 48, 48));
    s.materials.push_back(lambertian(0.7));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 64, 32, 0));
    s.lights.push_back(directionalLight({0, -1, -1}, daylightLike(), 0.01));
    SpectralPassOptions o;
    o.ssaa = 2;
    expectGpuMatchesReference(s, 500, o);
}

TEST(GpuVsReference, CopyReadbackEqualsMappedReadback) {
    Scene s = emptyScene(Grid{300, 740, 5}, perspectiveCamera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30, 40, 30));
    s.materials.push_back(glossy(gaussianSpectrum(500, 50, 0.7), constantSpectrum(0.05), 20, "green"));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 32, 16, 0));
    s.lights.push_back(pointLight({1, 2, 3}, daylightLike(), 1.0));
    SceneOnGrid g = onGrid(s);
    SpectralPassOptions copy, map;
    copy.readback = Readback::Copy;
    map.readback = Readback::Auto;
    SpectralPass a(gpu(), s, g, copy), b(gpu(), s, g, map);
    EXPECT_FALSE(a.plan().mappedReadback);
    SpectralCube ca = a.render(), cb = b.render();
    EXPECT_EQ(ca.data, cb.data);
}

TEST(GpuVsReference, ClosedMeshesSeenFromOutsideAndFromInside) {
    // A closed sphere (scene/shapes.h: Mesh::closed) is drawn with its back faces culled while the
    // camera sees it whole from outside; from inside, its inner side is what shows, so culling
    // must be off. Both against the reference, which has no such notion.
    Scene s = emptyScene(Grid{400, 700, 10}, perspectiveCamera({0, 0.5, 6}, {0, 0, 0}, {0, 1, 0}, 40, 64, 64));
    s.materials.push_back(glossy(gaussianSpectrum(550, 60, 0.6), constantSpectrum(0.04), 40, "plastic"));
    s.materials.push_back(lambertian(0.5, "floor"));
    Mesh ball = makeSphere({0, 0, 0}, 1.0, 48);
    ASSERT_TRUE(ball.closed);
    s.meshes.push_back(ball);
    s.meshes.push_back(quad({0, -1, 0}, {0, 1, 0}, 8, 8, 1));
    s.lights.push_back(ambientLight(daylightLike(), 0.002));
    s.lights.push_back(directionalLight({-0.3, -1, -0.6}, daylightLike(), 0.01));
    // Culling is under test, not the shadow maps' texels; inside, the walls the light meets are lit.
    for (Light& l : s.lights) l.shadows = false;
    expectGpuMatchesReference(s, 500);
    s.camera = perspectiveCamera({0, 0, 0.2}, {0, 0, -1}, {0, 1, 0}, 60, 64, 64);  // inside
    expectGpuMatchesReference(s, 2500);
}
