// The golden suite must catch regressions and let float rounding through (the regression-suite
// issue, item 5): the GPU render of a golden scene passes its golden; the same render with one
// band off by 0.5%, with one light's falloff changed, or with a detector shifted by 1 nm fails.
#include "color/tonemap.h"
#include "compare/compare.h"
#include "compare/tolerance.h"
#include "render/render_setup.h"
#include "render/tonemap_pass.h"
#include "scene/scene_json.h"
#include "spectral/csv.h"
#include "support/gpu.h"

#include <filesystem>
#include <fstream>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

const fs::path kRoot = METAMER_SOURCE_DIR;
const fs::path kGolden = kRoot / "tests" / "golden";

const SpectrumLibrary& library() {
    static SpectrumLibrary lib;
    return lib;
}

struct Golden {
    ImageData reference;
    Tolerance tolerance;
    CompareOptions options;
};

Golden loadGolden(const std::string& name, const std::string& file, const std::string& stem) {
    Golden g;
    g.reference = readComparable(kGolden / name / file);
    g.tolerance = readTolerance(kGolden / name / (file + ".tolerance.json"));
    applyTolerance(g.tolerance, g.options);
    g.options.mask = readMask(kGolden / name / (stem + ".edges.png"), g.reference.width, g.reference.height);
    return g;
}

Verdict judgeAgainst(const Golden& g, const ImageData& test) {
    return judge(compareImages(test, g.reference, g.options), g.tolerance);
}

SpectralCube renderGpu(const Scene& scene) {
    uint32_t before = test::gpu().validationErrors();
    SceneOnGrid spectra = resampleScene(scene, scene.grid);
    SpectralPass pass(test::gpu(), scene, spectra);
    SpectralCube cube = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    return cube;
}

// The GPU responses of a detector for a scene, as an image comparable with a golden responses EXR.
ImageData gpuResponses(const Scene& scene, const std::string& detector) {
    SceneOnGrid spectra = resampleScene(scene, scene.grid);
    SpectralPassOptions po;
    po.sampled = true;
    SpectralPass pass(test::gpu(), scene, spectra, po);
    pass.draw();
    TonemapSettings settings;
    settings.detector = detector;
    TonemapPlan plan = makeScenePlan(settings, scene, spectra, library());
    TonemapPass tonemap(test::gpu(), pass, plan);
    DisplayImage image = tonemap.render();
    ImageData d;
    d.width = image.width;
    d.height = image.height;
    d.channels = plan.detector.channels;
    d.data = image.responses;
    return d;
}

}  // namespace

TEST(GoldenSuite, PassesTheGpuRenderAndCatchesAPerturbedBand) {
    Golden g = loadGolden("glossy", "glossy.exr", "glossy");
    Scene scene = loadScene(kGolden / "scenes" / "glossy.json", library());
    SpectralCube cube = renderGpu(scene);
    Verdict ok = judgeAgainst(g, fromCube(cube));
    EXPECT_TRUE(ok.pass) << ok.failures.front();

    // One band 0.5% too bright everywhere.
    int band = cube.bands() / 2;
    for (int y = 0; y < cube.height; ++y)
        for (int x = 0; x < cube.width; ++x) cube.at(x, y, band) *= 1.005f;
    Verdict bad = judgeAgainst(g, fromCube(cube));
    EXPECT_FALSE(bad.pass) << "a 0.5% error in one band passed the golden";
}

TEST(GoldenSuite, CatchesAChangedLightFalloff) {
    // The point light 1% farther from everything: irradiance I·cosθ/d² drops by about 2%, as a
    // falloff bug (say d^2.02) would make it.
    Golden g = loadGolden("glossy", "glossy.exr", "glossy");
    Scene scene = loadScene(kGolden / "scenes" / "glossy.json", library());
    for (Light& l : scene.lights)
        if (l.type == Light::Type::Point) l.scale /= 1.0201;
    Verdict bad = judgeAgainst(g, fromCube(renderGpu(scene)));
    EXPECT_FALSE(bad.pass) << "a 2% change of a point light's irradiance passed the golden";
}

TEST(GoldenSuite, CatchesADetectorShiftedByOneNanometre) {
    // The golden "camera" holds the Nikon D5100 responses; a user detector with the same
    // sensitivities 1 nm longer must not pass for it, while the unshifted data must.
    std::string stem = "imaging-systems";
    Golden g = loadGolden("camera", stem + ".camera-nikon_d5100.exr", stem);
    std::vector<std::string> overrides = {"camera.width=64", "camera.height=48"};
    Scene scene = loadScene(kRoot / "scenes" / "imaging-systems.json", library(), overrides);

    SpectralTable t = readSpectralTable(library().root() / "cameras" / "nikon_d5100.csv", 3);
    fs::path dir = fs::temp_directory_path() / "metamer-golden-shift";
    fs::create_directories(dir);
    auto writeDetector = [&](const fs::path& path, double shift) {
        std::ofstream f(path);
        f << "wavelength_nm";
        for (std::string n : t.columnNames) {  // the camera detector names its channels R, G, B
            for (char& ch : n) ch = char(std::toupper(static_cast<unsigned char>(ch)));
            f << "," << n;
        }
        f << "\n";
        for (size_t i = 0; i < t.wavelengths_nm.size(); ++i) {
            f << t.wavelengths_nm[i] + shift;
            for (const auto& c : t.columns) f << "," << c[i];
            f << "\n";
        }
    };
    writeDetector(dir / "same.csv", 0.0);
    writeDetector(dir / "shifted.csv", 1.0);
    Verdict same = judgeAgainst(g, gpuResponses(scene, "csv:" + (dir / "same.csv").string()));
    EXPECT_TRUE(same.pass) << same.failures.front();
    Verdict shifted = judgeAgainst(g, gpuResponses(scene, "csv:" + (dir / "shifted.csv").string()));
    EXPECT_FALSE(shifted.pass) << "a 1 nm shift of the camera's sensitivities passed the golden";
}
