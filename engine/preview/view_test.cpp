// The preview's view on the GPU (headless: the view needs no window): the probe against the
// colour-science oracle of the metameric pair and against the tonemap pass, camera moves against
// the same camera written in the scene, settings changes and reloads.
#include "color/lab.h"
#include "color/delta_e.h"
#include "preview/camera_control.h"
#include "preview/view.h"
#include "support/gpu.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace metamer;
using namespace metamer::preview;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

RenderJob metamersJob(std::vector<std::string> overrides = {}) {
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "metamers.json";
    job.overrides = std::move(overrides);
    return job;
}

// tests/data/representations/representation_modes_delta_e.csv (colour-science): ΔE00 of the pair.
double oracle(const std::string& mode, const std::string& illuminant) {
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

double pairDeltaE(View& v) {
    ProbeReadout base = v.probe(v.width() / 4, v.height() / 2), metamer = v.probe(3 * v.width() / 4, v.height() / 2);
    return deltaE2000(base.lab, metamer.lab);
}

}  // namespace

TEST(PreviewView, ProbeSeesTheMetamericPairAsColourScienceDoes) {
    uint32_t before = gpu().validationErrors();
    View v(gpu(), metamersJob());
    v.render();
    EXPECT_NEAR(pairDeltaE(v), oracle("spectral_380_780_5", "D65"), 0.01);
    v.update(metamersJob({"lights.0.spectrum=illuminants/A"}));
    v.render();
    EXPECT_NEAR(pairDeltaE(v), oracle("spectral_380_780_5", "A"), 0.01);
    // RGB predicts a match under A as well (the probe reads the mode's channels).
    RenderJob rgb = metamersJob({"lights.0.spectrum=illuminants/A"});
    rgb.mode = "rgb";
    v.update(rgb);
    v.render();
    ProbeReadout p = v.probe(10, 10);
    EXPECT_TRUE(p.wavelengths_nm.empty());
    EXPECT_EQ(p.channelNames, (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_NEAR(pairDeltaE(v), oracle("rgb", "A"), 0.01);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(PreviewView, ProbeMatchesTheCubeAndTheTonemapPass) {
    uint32_t before = gpu().validationErrors();
    View v(gpu(), metamersJob({"lights.0.spectrum=illuminants/A"}));
    v.render();
    const SpectralCube& cube = v.cube();
    const DisplayImage& img = v.image();
    for (glm::ivec2 px : {glm::ivec2(64, 64), glm::ivec2(192, 64), glm::ivec2(3, 5)}) {
        SCOPED_TRACE(testing::Message() << px.x << "," << px.y);
        ProbeReadout p = v.probe(px.x, px.y);
        ASSERT_EQ(p.values.size(), size_t(cube.bands()));
        // The probe draws its pixel alone (a 1×1 tile): the same surface point, rounded differently.
        float peak = 0;
        for (int b = 0; b < cube.bands(); ++b) peak = std::max(peak, std::fabs(cube.at(px.x, px.y, b)));
        ASSERT_GT(peak, 0.0f);
        for (int b = 0; b < cube.bands(); ++b)
            EXPECT_NEAR(p.values[b], cube.at(px.x, px.y, b), 1e-5 * std::max(peak, std::fabs(cube.at(px.x, px.y, b))));
        EXPECT_DOUBLE_EQ(p.wavelengths_nm.front(), 380.0);
        // The probe's XYZ (double, from its own bands) against the whole cube's pixel's.
        size_t i = size_t(px.y) * img.width + px.x;
        std::vector<double> responses(v.plan().detector.weights.size());
        const glm::dvec3 whole = relativeXyz(v.plan(), cube.pixel(px.x, px.y), responses.data()) * 100.0;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.xyz[c], whole[c], 1e-5 * std::max(1.0, whole[c]));
        EXPECT_EQ(p.counts, glm::ivec3(img.counts[3 * i], img.counts[3 * i + 1], img.counts[3 * i + 2]));
        EXPECT_NEAR(p.whiteXyz.y, 100.0, 1e-9);
        glm::dvec3 back = labToXyz(p.lab, p.whiteXyz);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], p.xyz[c], 1e-9);
    }
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(PreviewView, AMovedCameraRendersAsTheSameCameraWrittenInTheScene) {
    uint32_t before = gpu().validationErrors();
    // The spheres: perspective, specular, two lights; a small image keeps it quick.
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "spheres.json";
    job.overrides = {"camera.width=96", "camera.height=64"};
    View moved(gpu(), job);
    Camera c = zoom(pan(orbit(moved.scene().camera, 0.4, 0.15), 7.0, -3.0), 0.8);
    moved.setCamera(c);
    moved.render();
    RenderJob written = job;
    auto vec = [](const glm::dvec3& v) { return fmt::format("[{:.17g},{:.17g},{:.17g}]", v.x, v.y, v.z); };
    written.overrides.push_back("camera.position=" + vec(c.position));
    written.overrides.push_back("camera.target=" + vec(c.target));
    View file(gpu(), written);
    file.render();
    ASSERT_EQ(moved.image().counts.size(), file.image().counts.size());
    int worst = 0;
    for (size_t i = 0; i < moved.image().counts.size(); ++i)
        worst = std::max(worst, std::abs(int(moved.image().counts[i]) - int(file.image().counts[i])));
    EXPECT_LE(worst, 1);
    // And it did move: the file's own camera sees something else.
    View still(gpu(), job);
    still.render();
    EXPECT_NE(still.image().counts, moved.image().counts);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(PreviewView, DisplayChangesKeepTheSpectralPassAndBadSettingsKeepTheView) {
    uint32_t before = gpu().validationErrors();
    View v(gpu(), metamersJob());
    v.render();
    std::vector<uint16_t> d65 = v.image().counts;
    RenderJob crt = metamersJob();
    crt.display = "crt";
    v.update(crt);
    EXPECT_EQ(v.plan().settings.display, "crt");
    v.render();
    EXPECT_NE(v.image().counts, d65);
    // An unknown detector is an input error naming the flag; the view keeps its settings.
    RenderJob bad = crt;
    bad.detector = "camera:nonesuch";
    try {
        v.update(bad);
        ADD_FAILURE() << "accepted an unknown detector";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
    }
    EXPECT_EQ(v.plan().settings.display, "crt");
    EXPECT_FALSE(v.job().detector.has_value());
    v.render();
    EXPECT_EQ(v.image().width, 256);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(PreviewView, ReloadReadsTheChangedFileAndKeepsTheCamera) {
    uint32_t before = gpu().validationErrors();
    fs::path dir = fs::temp_directory_path() / ("metamer_reload_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::path scene = dir / "pair.json";
    std::ifstream src(fs::path(METAMER_SOURCE_DIR) / "scenes" / "metamers.json");
    std::stringstream text;
    text << src.rdbuf();
    std::string d65 = text.str();
    std::ofstream(scene) << d65;
    RenderJob job;
    job.scene = scene;
    View v(gpu(), job);
    Camera panned = pan(v.scene().camera, 40.0, 0.0);
    v.setCamera(panned);
    v.render();
    // The file now says illuminant A.
    std::string a = d65;
    const std::string light = "\"spectrum\": \"illuminants/D65\"";
    ASSERT_NE(a.find(light), std::string::npos);
    a.replace(a.find(light), light.size(), "\"spectrum\": \"illuminants/A\"");
    std::ofstream(scene) << a;
    v.reload();
    v.render();
    EXPECT_EQ(v.scene().lights[0].spectrum.spectrum.source, "illuminants/A");
    // The panned view is kept: the reloaded view equals a fresh view of the new file moved the same way.
    View fresh(gpu(), job);
    fresh.setCamera(panned);
    fresh.render();
    EXPECT_EQ(v.image().counts, fresh.image().counts);
    // A broken file is refused and the view keeps the last good scene.
    std::ofstream(scene) << "{ not json";
    EXPECT_THROW(v.reload(), Error);
    EXPECT_EQ(v.scene().lights[0].spectrum.spectrum.source, "illuminants/A");
    fs::remove_all(dir);
    EXPECT_NO_VALIDATION_ERRORS(before);
}
