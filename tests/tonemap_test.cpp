// The display path end to end: the GPU tonemap pass against its CPU reference, the exposure rule,
// and a rendered ColorChecker against colour-science (tests/reference/make_colorchecker_table.py).
#include "color/tonemap.h"
#include "color/cie_xyz.h"
#include "color/delta_e.h"
#include "color/lab.h"
#include "reference/cpu_renderer.h"
#include "render/render_setup.h"
#include "render/tonemap_pass.h"
#include "scene/scene_json.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

using namespace metamer;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static SpectrumLibrary lib;
    return lib;
}

Scene bundled(const std::string& name, std::vector<std::string> overrides = {}) {
    return loadScene(fs::path(METAMER_SOURCE_DIR) / "scenes" / (name + ".json"), library(), overrides);
}

struct Config {
    std::string detector, adaptation, display;
    int bits;
};

std::string describe(const Config& c) {
    return c.detector + " / " + c.adaptation + " / " + c.display + " " + std::to_string(c.bits) + "-bit";
}

TonemapSettings settingsFor(const Config& c) {
    TonemapSettings s;
    s.detector = c.detector;
    s.adaptation = parseAdaptation(c.adaptation, Where{});
    s.display = c.display;
    s.bits = c.bits;
    return s;
}

double relativeDifference(float a, float b, float scale) { return std::fabs(a - b) / std::max(std::fabs(b), scale); }

}  // namespace

TEST(Tonemap, GpuPassMatchesCpuReferenceWithinOneCount) {
    Scene scene = bundled("imaging-systems", {"camera.width=96", "camera.height=72"});
    SceneOnGrid spectra = onGrid(scene);
    const std::vector<Config> configs = {
        {"cie1931", "bradford", "srgb", 8},      {"cie1964", "cat16", "crt", 16},
        {"camera:nikon_d5100", "cat02", "srgb", 8}, {"camera:sigma_sd_merrill", "none", "crt", 8},
        {"film:reversal", "bradford", "srgb", 16}, {"cie1931", "vonkries", "crt", 16},
    };
    uint32_t before = gpu().validationErrors();
    SpectralPassOptions po;
    po.sampled = true;
    SpectralPass pass(gpu(), scene, spectra, po);
    pass.draw();
    SpectralCube cube;
    pass.readback(cube);
    for (const Config& c : configs) {
        SCOPED_TRACE(describe(c));
        TonemapPlan plan = makeScenePlan(settingsFor(c), scene, spectra, library());
        TonemapPass tonemap(gpu(), pass, plan);
        DisplayImage g = tonemap.render();
        DisplayImage r = tonemapReference(plan, cube);
        ASSERT_EQ(g.counts.size(), r.counts.size());
        int worstCount = 0;
        size_t differing = 0;
        for (size_t i = 0; i < g.counts.size(); ++i) {
            int d = std::abs(int(g.counts[i]) - int(r.counts[i]));
            worstCount = std::max(worstCount, d);
            differing += d != 0;
        }
        double worstXyz = 0, worstResponse = 0;
        float yMax = 0, rMax = 0;
        for (float v : r.xyz) yMax = std::max(yMax, std::fabs(v));
        for (float v : r.responses) rMax = std::max(rMax, std::fabs(v));
        for (size_t i = 0; i < g.xyz.size(); ++i)
            worstXyz = std::max(worstXyz, relativeDifference(g.xyz[i], r.xyz[i], 1e-3f * yMax));
        for (size_t i = 0; i < g.responses.size(); ++i)
            worstResponse = std::max(worstResponse, relativeDifference(g.responses[i], r.responses[i], 1e-3f * rMax));
        std::printf("  %s: max count difference %d (%zu of %zu values differ), XYZ rel %.2g, responses rel %.2g, "
                    "clipped %zu/%zu\n",
                    describe(c).c_str(), worstCount, differing, g.counts.size(), worstXyz, worstResponse,
                    g.clippedPixels, r.clippedPixels);
        EXPECT_LE(worstCount, 1);
        EXPECT_LE(worstXyz, 1e-4);
        EXPECT_LE(worstResponse, 1e-4);
    }
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(Tonemap, SupersampledTargetIsFilteredBeforeTheDisplayPath) {
    Scene scene = bundled("imaging-systems", {"camera.width=40", "camera.height=30"});
    SceneOnGrid spectra = onGrid(scene);
    SpectralPassOptions po;
    po.sampled = true;
    po.ssaa = 2;
    SpectralPass pass(gpu(), scene, spectra, po);
    pass.draw();
    SpectralCube cube;
    pass.readback(cube);  // box-filtered to 40×30
    TonemapPlan plan = makeScenePlan(TonemapSettings{}, scene, spectra, library());
    TonemapPass tonemap(gpu(), pass, plan);
    DisplayImage g = tonemap.render(), r = tonemapReference(plan, cube);
    ASSERT_EQ(g.width, 40);
    int worst = 0;
    for (size_t i = 0; i < g.counts.size(); ++i) worst = std::max(worst, std::abs(int(g.counts[i]) - int(r.counts[i])));
    EXPECT_LE(worst, 1);
}

TEST(Tonemap, PerfectWhiteUnderTheReferenceLightHasY100) {
    // A white Lambertian quad facing a directional light: its radiance is E/π, the reference
    // white itself, so relative Y = 100 and absolute Y = 683·Σ (E/π)·ȳ·Δλ.
    Scene s = emptyScene(Grid{380, 780, 5}, orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, 4, 4));
    s.materials.push_back(lambertian(1.0));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 10, 10));
    s.lights.push_back(directionalLight({0, 0, -1}, gaussianSpectrum(560, 90, 1.0, 300, 800, 5), 0.7));
    s.lights.push_back(ambientLight(constantSpectrum(0.001)));  // dim: does not define the white
    SceneOnGrid g = onGrid(s);
    ReferenceImage img = renderReference(s, g);
    TonemapSettings relative;
    TonemapPlan plan = makeScenePlan(relative, s, g, library());
    EXPECT_NE(plan.white.source.find("lights.0"), std::string::npos) << plan.white.source;
    DisplayImage d = tonemapReference(plan, img.cube);
    TonemapSettings absolute;
    absolute.absolute = true;
    TonemapPlan planAbs = makeScenePlan(absolute, s, g, library());
    DisplayImage a = tonemapReference(planAbs, img.cube);
    // Without the ambient light the white is exact.
    s.lights.pop_back();
    SceneOnGrid g2 = onGrid(s);
    ReferenceImage img2 = renderReference(s, g2);
    TonemapPlan p2 = makeScenePlan(relative, s, g2, library());
    DisplayImage d2 = tonemapReference(p2, img2.cube);
    EXPECT_NEAR(d2.xyz[1], 100.0, 1e-4);
    TonemapPlan p2abs = makeScenePlan(absolute, s, g2, library());
    DisplayImage a2 = tonemapReference(p2abs, img2.cube);
    ColorMatchingFunctions cmf = loadCie1931(library(), s.grid);
    double y = 0;
    for (int b = 0; b < s.grid.bands(); ++b) y += g2.lights[0][b] / M_PI * cmf.y[b] * s.grid.step_nm;
    EXPECT_NEAR(a2.xyz[1], 683.0 * y, 1e-4 * 683.0 * y);
    // With the ambient light, the white is still the directional light: Y slightly above 100.
    EXPECT_GT(d.xyz[1], 100.0);
    EXPECT_LT(d.xyz[1], 100.5);
    EXPECT_GT(a.xyz[1], a2.xyz[1]);
}

TEST(Tonemap, RenderedColorCheckerMatchesColourScience) {
    // tests/data/color/colorchecker_reference.csv: colour-science on the grid 300:740:5 with our
    // band averaging and Riemann sums; XYZ relative to the perfect diffuser (Y = 100), L*a*b*,
    // and sRGB counts after Bradford adaptation to D65.
    std::ifstream in(fs::path(METAMER_TEST_DATA_DIR) / "color" / "colorchecker_reference.csv");
    ASSERT_TRUE(in) << "missing tests/data/color/colorchecker_reference.csv";
    std::string line;
    std::getline(in, line);  // header
    struct Row {
        glm::dvec3 xyz, lab, rgb8;
    };
    std::map<std::string, std::map<std::string, Row>> table;  // illuminant → patch → row
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::string illuminant, patch, field;
        std::getline(ss, illuminant, ',');
        std::getline(ss, patch, ',');
        double v[9];
        for (double& x : v) {
            std::getline(ss, field, ',');
            x = std::stod(field);
        }
        table[illuminant][patch] = Row{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
    }
    ASSERT_EQ(table.size(), 3u);
    for (const auto& [illuminant, patches] : table) {
        SCOPED_TRACE(illuminant);
        Scene scene = bundled("colorchecker", {"grid.start_nm=300", "grid.end_nm=740",
                                               "lights.0.spectrum=illuminants/" + illuminant, "camera.width=150",
                                               "camera.height=100"});
        SceneOnGrid spectra = onGrid(scene);
        ReferenceImage img = renderReference(scene, spectra);
        TonemapPlan plan = makeScenePlan(TonemapSettings{}, scene, spectra, library());
        DisplayImage d = tonemapReference(plan, img.cube);
        glm::dvec3 white = plan.sourceWhiteXyz * 100.0;
        int checked = 0;
        double worst = 0;
        for (int y = 1; y + 1 < img.cube.height; ++y)
            for (int x = 1; x + 1 < img.cube.width; ++x) {
                int32_t id = img.objectId[size_t(y) * img.cube.width + x];
                if (id < 0) continue;
                const std::string& name = scene.materials[scene.meshes[id].material].name;
                auto it = patches.find(name);
                if (it == patches.end()) continue;
                size_t i = size_t(y) * img.cube.width + x;
                glm::dvec3 xyz(d.xyz[3 * i], d.xyz[3 * i + 1], d.xyz[3 * i + 2]);
                double de = deltaE2000(xyzToLab(xyz, white), it->second.lab);
                worst = std::max(worst, de);
                ASSERT_LE(de, 0.01) << name << " at " << x << "," << y;
                for (int c = 0; c < 3; ++c)
                    ASSERT_LE(std::fabs(d.counts[3 * i + c] - it->second.rgb8[c]), 1.0) << name << " channel " << c;
                ++checked;
            }
        std::printf("  %s: %d patch pixels, worst ΔE2000 %.2g\n", illuminant.c_str(), checked, worst);
        EXPECT_GT(checked, 24 * 20);
    }
}
