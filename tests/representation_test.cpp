// Representation modes on the paper's Figure 3 case (scenes/metamers.json): what each mode can
// and cannot predict about a metameric pair, checked against tests/data/representations (made by
// spectra/generate_quadrature.py with colour-science, independent of the engine).
#include "represent/representation.h"
#include "color/delta_e.h"
#include "color/lab.h"
#include "color/tonemap.h"
#include "reference/cpu_renderer.h"
#include "render/render_setup.h"
#include "render/tonemap_pass.h"
#include "scene/scene_json.h"
#include "support/gpu.h"

#include <fstream>
#include <map>
#include <sstream>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static SpectrumLibrary lib;
    return lib;
}

// ΔE2000 between the two patches of scenes/metamers.json (left: base, right: metamer), each
// pixel's XYZ relative to the plan's white (Y = 100), from the CPU reference and CPU tonemap.
struct PairResult {
    double deltaE;
    DisplayImage image;
};

PairResult pairDeltaE(const std::string& mode, const std::string& illuminant, bool gpu = false) {
    Scene scene = loadScene(fs::path(METAMER_SOURCE_DIR) / "scenes" / "metamers.json", library(),
                            {"lights.0.spectrum=illuminants/" + illuminant});
    SceneOnGrid spectra = resampleScene(scene, scene.grid);
    Representation rep = makeRepresentation(parseMode(mode, Where{}), scene.grid, library(), &spectra);
    SceneOnGrid rendered = represent(spectra, rep, scene);
    TonemapPlan plan = makeScenePlan(TonemapSettings{}, scene, spectra, library(), &rep);
    DisplayImage d;
    if (gpu) {
        SpectralPassOptions po;
        po.sampled = true;
        SpectralPass pass(test::gpu(), scene, rendered, po);
        pass.draw();
        TonemapPass tonemap(test::gpu(), pass, plan);
        d = tonemap.render();
    } else {
        d = tonemapReference(plan, renderReference(scene, rendered).cube);
    }
    auto xyzAt = [&](int x, int y) {
        size_t i = size_t(y) * d.width + x;
        return glm::dvec3(d.xyz[3 * i], d.xyz[3 * i + 1], d.xyz[3 * i + 2]);
    };
    glm::dvec3 white = plan.sourceWhiteXyz * 100.0;
    int y = d.height / 2;
    double de = deltaE2000(xyzToLab(xyzAt(d.width / 4, y), white), xyzToLab(xyzAt(3 * d.width / 4, y), white));
    return {de, d};
}

// tests/data/representations/representation_modes_delta_e.csv: mode,illuminant → ΔE00.
double expected(const std::string& mode, const std::string& illuminant) {
    std::ifstream in(fs::path(METAMER_TEST_DATA_DIR) / "representations" / "representation_modes_delta_e.csv");
    std::string line;
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::string m, i, de;
        std::getline(ss, m, ',');
        std::getline(ss, i, ',');
        std::getline(ss, de, ',');
        if (m == mode && i == illuminant) return std::stod(de);
    }
    ADD_FAILURE() << "no row " << mode << "," << illuminant;
    return 0;
}

}  // namespace

TEST(Representation, ModeNamesParseAndBadOnesNameTheFlag) {
    EXPECT_EQ(parseMode("full", Where{}).name(), "full");
    EXPECT_EQ(parseMode("rgb", Where{}).name(), "rgb");
    EXPECT_EQ(parseMode("ac1c2", Where{}).name(), "ac1c2:4");
    EXPECT_EQ(parseMode("ac1c2:8", Where{}).name(), "ac1c2:8");
    EXPECT_EQ(parseMode("linear:6", Where{}).name(), "linear:6");
    for (const char* bad : {"rbg", "ac1c2:2", "ac1c2:9", "ac1c2:x", "linear", "linear:0", "linear:13"}) {
        try {
            parseMode(bad, Where{"", "--mode"});
            ADD_FAILURE() << bad << " parsed";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput);
            EXPECT_NE(std::string(e.what()).find("--mode"), std::string::npos) << e.what();
        }
    }
}

TEST(Representation, FullSpectralMatchesUnderD65AndNotUnderA) {
    double d65 = pairDeltaE("full", "D65").deltaE, a = pairDeltaE("full", "A").deltaE;
    EXPECT_LT(d65, 0.1);
    EXPECT_GT(a, 3.0);
    EXPECT_NEAR(d65, expected("spectral_380_780_5", "D65"), 0.01);
    EXPECT_NEAR(a, expected("spectral_380_780_5", "A"), 0.05);
}

TEST(Representation, RgbCannotSeparateThePairUnderAnyLight) {
    for (const char* light : {"D65", "A", "FL2", "FL11"}) {
        SCOPED_TRACE(light);
        EXPECT_LT(pairDeltaE("rgb", light).deltaE, 0.05);
    }
    EXPECT_NEAR(pairDeltaE("rgb", "A").deltaE, expected("rgb", "A"), 0.01);
}

TEST(Representation, FourSampleAc1c2MissesUnderBothLightsAndEightSamplesApproachTheTruth) {
    // The oracle takes point values of the spectra at the sample wavelengths; the engine reads
    // them by linear interpolation between 5 nm band centres, hence the tolerance.
    double d65 = pairDeltaE("ac1c2:4", "D65").deltaE, a = pairDeltaE("ac1c2:4", "A").deltaE;
    EXPECT_GT(d65, 1.0);
    EXPECT_GT(a, 3.0);
    EXPECT_NEAR(d65, expected("ac1c2_4", "D65"), 0.5);
    EXPECT_NEAR(a, expected("ac1c2_4", "A"), 0.5);
    double a8 = pairDeltaE("ac1c2:8", "A").deltaE;
    EXPECT_NEAR(a8, expected("ac1c2_8", "A"), 0.5);
    EXPECT_NEAR(a8, pairDeltaE("full", "A").deltaE, 1.0);
}

TEST(Representation, RgbIsExactUnderD65ForEveryReflectance) {
    // Under D65 a reflectance's RGB times the light's RGB gives back its exact XYZ: the whole image
    // equals the full-spectral one (the chart of the metamers scene, and its background).
    DisplayImage rgb = pairDeltaE("rgb", "D65").image, full = pairDeltaE("full", "D65").image;
    ASSERT_EQ(rgb.xyz.size(), full.xyz.size());
    double worst = 0;
    for (size_t i = 0; i < rgb.xyz.size(); ++i)
        worst = std::max(worst, std::fabs(double(rgb.xyz[i]) - full.xyz[i]) / std::max(1.0, double(full.xyz[i])));
    EXPECT_LT(worst, 2e-3);  // the 1 nm RGB weights against 5 nm bands
}

TEST(Representation, GpuRendersModesLikeTheReference) {
    for (const char* mode : {"rgb", "ac1c2:4"}) {
        SCOPED_TRACE(mode);
        uint32_t before = test::gpu().validationErrors();
        PairResult g = pairDeltaE(mode, "A", true), c = pairDeltaE(mode, "A");
        EXPECT_NEAR(g.deltaE, c.deltaE, 1e-3);
        int worst = 0;
        for (size_t i = 0; i < g.image.counts.size(); ++i)
            worst = std::max(worst, std::abs(int(g.image.counts[i]) - int(c.image.counts[i])));
        EXPECT_LE(worst, 1);
        EXPECT_NO_VALIDATION_ERRORS(before);
    }
}

TEST(Representation, NonSpectralModesServeOnlyTheCie1931Observer) {
    Scene scene = loadScene(fs::path(METAMER_SOURCE_DIR) / "scenes" / "metamers.json", library());
    SceneOnGrid spectra = resampleScene(scene, scene.grid);
    Representation rep = makeRepresentation(parseMode("rgb", Where{}), scene.grid, library());
    TonemapSettings s;
    s.detector = "camera:nikon_d5100";
    EXPECT_THROW(makeScenePlan(s, scene, spectra, library(), &rep), Error);
}

TEST(Representation, LinearIsExactForSpectraInsideItsBasis) {
    // metamers.json holds one light and reflected spectra spanning 3 dimensions (the grey card's is
    // the light's own shape): linear:3 represents every pixel exactly.
    PairResult lin = pairDeltaE("linear:3", "A"), full = pairDeltaE("full", "A");
    EXPECT_NEAR(lin.deltaE, full.deltaE, 1e-4);
    double worst = 0;
    for (size_t i = 0; i < lin.image.xyz.size(); ++i)
        worst = std::max(worst, std::fabs(double(lin.image.xyz[i]) - full.image.xyz[i]) /
                                    std::max(1.0, double(full.image.xyz[i])));
    EXPECT_LT(worst, 1e-5);
}

TEST(Representation, LinearErrorFallsWithMoreBasisFunctions) {
    // The 24-patch chart under A spans 24 dimensions; fewer basis functions must cost accuracy,
    // and the error must fall as K grows.
    Scene scene = loadScene(fs::path(METAMER_SOURCE_DIR) / "scenes" / "colorchecker.json", library(),
                            {"camera.width=60", "camera.height=40", "lights.0.spectrum=illuminants/A"});
    SceneOnGrid spectra = resampleScene(scene, scene.grid);
    auto render = [&](const std::string& mode) {
        Representation rep = makeRepresentation(parseMode(mode, Where{}), scene.grid, library(), &spectra);
        SceneOnGrid rendered = represent(spectra, rep, scene);
        TonemapPlan plan = makeScenePlan(TonemapSettings{}, scene, spectra, library(), &rep);
        return std::make_pair(tonemapReference(plan, renderReference(scene, rendered).cube), plan);
    };
    auto [full, plan] = render("full");
    glm::dvec3 white = plan.sourceWhiteXyz * 100.0;
    auto worstDeltaE = [&](const DisplayImage& d) {
        double worst = 0;
        for (size_t i = 0; i + 2 < d.xyz.size(); i += 3) {
            glm::dvec3 a(d.xyz[i], d.xyz[i + 1], d.xyz[i + 2]), b(full.xyz[i], full.xyz[i + 1], full.xyz[i + 2]);
            worst = std::max(worst, deltaE2000(xyzToLab(a, white), xyzToLab(b, white)));
        }
        return worst;
    };
    double e2 = worstDeltaE(render("linear:2").first), e4 = worstDeltaE(render("linear:4").first),
           e8 = worstDeltaE(render("linear:8").first);
    std::printf("  colorchecker under A, worst ΔE2000 against full: linear:2 %.3g, linear:4 %.3g, linear:8 %.3g\n", e2,
                e4, e8);
    EXPECT_GT(e2, 1.0);
    EXPECT_LT(e8, e4);
    EXPECT_LT(e4, e2);
}
