// The display path that never writes the bands (render/display_frame.h) against the cube path: on
// every bundled scene, for every kind of detector (observers, cameras, film, a csv detector of 8
// channels), adaptation, display and representation mode, the response pass's responses and XYZ
// equal the integral of the band passes' cube (color/tonemap_reference, double precision) within
// 1e-5 relative, and its display counts are within 1 of the cube path's tonemap pass. Both paths
// rasterize the same triangles with the same depth, so every pixel is compared, edges included.
#include "color/tonemap.h"
#include "io/image_reader.h"
#include "render/display_frame.h"
#include "render/render_job.h"
#include "render/render_setup.h"
#include "render/tonemap_pass.h"
#include "represent/representation.h"
#include "scene/shapes.h"
#include "support/gpu.h"
#include "support/scene_builders.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

using namespace metamer;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

// Relative error against max(|reference|, floor × the channel's largest |reference|): a channel
// that is almost black at a pixel (the blue of a red sphere) is not held to 1e-5 of almost
// nothing. The floor is 1e-3 of the channel's range.
struct Worst {
    double relative = 0;
    size_t pixel = 0;
    int channel = -1;
};

Worst worstRelative(const std::vector<float>& got, const std::vector<float>& want, int channels, double floor = 1e-3) {
    Worst w;
    if (got.size() != want.size()) return {INFINITY, 0, -1};
    std::vector<double> range(size_t(channels), 0.0);
    for (size_t i = 0; i < want.size(); ++i)
        range[i % channels] = std::max(range[i % channels], double(std::fabs(want[i])));
    for (size_t i = 0; i < want.size(); ++i) {
        const int c = int(i % channels);
        const double rel = std::fabs(double(got[i]) - want[i]) / std::max(double(std::fabs(want[i])), floor * range[c] + 1e-300);
        if (!(rel <= w.relative)) w = {std::isnan(rel) ? INFINITY : rel, i / channels, c};
    }
    return w;
}

int worstCount(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b) {
    if (a.size() != b.size()) return 1 << 20;
    int worst = 0;
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    return worst;
}

// Eight Gaussian channels over 380–780 nm, one of them with a negative lobe (a colour-matching
// function's shape), to fill both response layers.
fs::path eightChannelDetector() {
    // One file per process: two tests of this file run at once under CTest, and one rewriting
    // the table while the other reads it made the reader see it empty.
    const fs::path path =
        fs::temp_directory_path() / ("metamer_response_pass_eight_" + std::to_string(::getpid()) + ".csv");
    std::ofstream f(path);
    f << "wavelength_nm";
    for (int c = 0; c < 8; ++c) f << ",c" << c;
    f << "\n";
    for (int nm = 300; nm <= 830; nm += 5) {
        f << nm;
        for (int c = 0; c < 8; ++c) {
            const double mu = 400 + 50 * c, x = (nm - mu) / 25.0;
            double v = std::exp(-0.5 * x * x);
            if (c == 5) v -= 0.3 * std::exp(-0.5 * ((nm - 450) / 20.0) * ((nm - 450) / 20.0));
            f << "," << v;
        }
        f << "\n";
    }
    return path;
}

struct Case {
    std::string scene, detector = "cie1931", adaptation = "bradford", display = "srgb", mode = "full";
    int bits = 8, ssaa = 1;
    std::vector<std::string> overrides = {};  // --set on top of the size
};

std::string describe(const Case& c) {
    return fmt::format("{} / {} / {} / {} {}-bit / mode {} / ssaa {}", c.scene, c.detector, c.adaptation, c.display,
                       c.bits, c.mode, c.ssaa);
}

struct Figures {
    double responses = 0, xyz = 0;  // worst relative error against the cube's integral
    int countsVsPass = 0, countsVsReference = 0;
};

// The cube path: every band, read back; its tonemap pass, and the integral in double.
struct CubePath {
    DisplayImage viaPass, integral;
};
CubePath cubePath(const LoadedScene& loaded, const TonemapPlan& plan, int ssaa) {
    SpectralPassOptions po;
    po.ssaa = ssaa;
    po.sampled = true;
    SpectralPass bands(gpu(), loaded.scene, loaded.rendered, po);
    bands.draw();
    TonemapPass bandTonemap(gpu(), bands, plan);
    CubePath out;
    out.viaPass = bandTonemap.render();
    SpectralCube cube;
    bands.readback(cube);
    out.integral = tonemapReference(plan, cube);
    return out;
}

// The response pass (DisplayFrame) against the cube path on a loaded scene, for `job`'s display.
Figures compareLoaded(const RenderJob& job, const LoadedScene& loaded, int ssaa) {
    const TonemapPlan plan = makeJobTonemapPlan(job, loaded, tonemapSettings(job, loaded.scene, nullptr));

    const auto [viaPass, integral] = cubePath(loaded, plan, ssaa);

    // The response pass.
    SpectralPassOptions ro;
    ro.ssaa = ssaa;
    DisplayFrame frame(gpu(), loaded.scene, loaded.rendered, plan, ro);
    EXPECT_TRUE(frame.passPlan().responses);
    EXPECT_EQ(frame.passPlan().bands, int(plan.detector.weights.size()));
    const DisplayImage viaResponses = frame.render();

    Figures f;
    const Worst r = worstRelative(viaResponses.responses, integral.responses, viaResponses.channels);
    f.responses = r.relative;
    EXPECT_LE(r.relative, 1e-5) << "responses: pixel " << r.pixel << " channel " << r.channel;
    if (plan.mode != TonemapMode::ResponsesOnly) {
        const Worst x = worstRelative(viaResponses.xyz, integral.xyz, 3);
        f.xyz = x.relative;
        // 2e-5: a camera's characterization matrix amplifies the float rounding of its responses,
        // which on spheres.json includes the hemisphere lights' lobe lookup (measured 1.2e-5).
        EXPECT_LE(x.relative, 2e-5) << "XYZ: pixel " << x.pixel << " channel " << x.channel;
        f.countsVsPass = worstCount(viaResponses.counts, viaPass.counts);
        f.countsVsReference = worstCount(viaResponses.counts, integral.counts);
        EXPECT_LE(f.countsVsPass, 1);
        EXPECT_LE(f.countsVsReference, 1);
    }
    return f;
}

Figures compareCase(const Case& c) {
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / (c.scene + ".json");
    job.overrides = {"camera.width=80", "camera.height=64"};
    job.overrides.insert(job.overrides.end(), c.overrides.begin(), c.overrides.end());
    job.mode = c.mode;
    job.ssaa = c.ssaa;
    job.detector = c.detector;
    job.adaptation = c.adaptation;
    job.display = c.display;
    job.bits = c.bits;
    const std::unique_ptr<LoadedScene> loaded = loadJobScene(job);
    return compareLoaded(job, *loaded, c.ssaa);
}

// A built scene as loadJobScene would hold it, in full spectral mode.
std::unique_ptr<LoadedScene> loadedFrom(Scene scene) {
    auto l = std::make_unique<LoadedScene>();
    l->scene = std::move(scene);
    l->grid = l->scene.grid;
    l->spectra = resampleScene(l->scene, l->grid);
    l->representation = makeRepresentation(parseMode("full", Where{}), l->grid, l->library, &l->spectra);
    l->rendered = represent(l->spectra, l->representation, l->scene);
    return l;
}

const char* kScenes[] = {"spheres", "colorchecker", "textured", "metamers", "fluorescent", "fluorescent-matrix",
                         "imaging-systems", "mesh", "paints"};

}  // namespace

TEST(ResponsePass, EqualsTheCubePathOnEveryBundledSceneAndDetector) {
    const uint32_t before = gpu().validationErrors();
    const std::string csv = "csv:" + eightChannelDetector().string();
    Figures worst;
    for (const char* scene : kScenes)
        for (const std::string& detector :
             {std::string("cie1931"), std::string("cie1964"), std::string("camera:nikon_d5100"),
              std::string("camera:sigma_sd_merrill"), std::string("film:reversal"), csv}) {
            Case c{scene, detector};
            SCOPED_TRACE(describe(c));
            const Figures f = compareCase(c);
            worst.responses = std::max(worst.responses, f.responses);
            worst.xyz = std::max(worst.xyz, f.xyz);
            worst.countsVsPass = std::max(worst.countsVsPass, f.countsVsPass);
            worst.countsVsReference = std::max(worst.countsVsReference, f.countsVsReference);
        }
    std::printf("response pass vs cube path, 9 scenes × 6 detectors: worst relative error responses %.2e, XYZ %.2e; "
                "worst count difference %d (tonemap pass), %d (CPU tonemap)\n",
                worst.responses, worst.xyz, worst.countsVsPass, worst.countsVsReference);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(ResponsePass, EqualsTheCubePathInEveryModeAdaptationAndDisplay) {
    const uint32_t before = gpu().validationErrors();
    const std::vector<Case> cases = {
        {"metamers", "cie1931", "bradford", "srgb", "rgb"},
        {"fluorescent", "cie1931", "bradford", "srgb", "ac1c2"},
        {"textured", "cie1931", "bradford", "srgb", "ac1c2:8"},
        {"colorchecker", "cie1931", "bradford", "srgb", "linear:6"},
        {"textured", "cie1964", "cat16", "crt", "linear:4", 16},
        {"spheres", "camera:canon_eos_5d_mark_ii", "cat02", "crt", "full", 16},
        {"imaging-systems", "film:reversal", "vonkries", "srgb", "full", 16},
        {"metamers", "cie1931", "none", "crt", "full", 8},
        {"spheres", "cie1931", "bradford", "srgb", "full", 8, 2},
        {"textured", "camera:nikon_d5100", "bradford", "srgb", "full", 8, 3},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(describe(c));
        compareCase(c);
    }
    EXPECT_NO_VALIDATION_ERRORS(before);
}

// A custom detector's quick-look PNG (CIE 1931 → sRGB, auto exposure) comes from a response pass
// of the CIE 1931 observer when no cube is written, and from the cube otherwise: the same counts
// within 1 (the 99th-percentile exposure of float32 XYZ summed two ways).
TEST(ResponsePass, QuickLookOfACustomDetectorWithoutTheBands) {
    const uint32_t before = gpu().validationErrors();
    const fs::path dir = fs::temp_directory_path() / "metamer_response_pass_quicklook";
    fs::remove_all(dir);
    for (const char* scene : {"spheres", "textured"}) {
        SCOPED_TRACE(scene);
        RenderJob job;
        job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / (std::string(scene) + ".json");
        job.overrides = {"camera.width=96", "camera.height=80"};
        job.detector = "csv:" + eightChannelDetector().string();
        job.validation = true;
        job.outDir = dir / "responses";
        job.write = {"png", "responses"};
        const RenderJobResult viaResponses = runRenderJob(job);
        EXPECT_TRUE(viaResponses.responsePass);
        EXPECT_EQ(viaResponses.validationErrors, 0u);
        job.outDir = dir / "cube";
        job.write = {"cube", "png"};
        const RenderJobResult viaCube = runRenderJob(job);
        EXPECT_FALSE(viaCube.responsePass);
        const RasterImage a = readRasterImage(dir / "responses" / (std::string(scene) + ".png"), Where{});
        const RasterImage b = readRasterImage(dir / "cube" / (std::string(scene) + ".png"), Where{});
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        float worst = 0;
        size_t lit = 0;
        for (size_t i = 0; i < a.pixels.size(); ++i) {
            worst = std::max(worst, std::fabs(a.pixels[i] - b.pixels[i]));
            lit += a.pixels[i] > 0;
        }
        EXPECT_LE(worst, 1.0f);
        EXPECT_GT(lit, a.pixels.size() / 4);  // an image, not a black frame
        EXPECT_NE(a.attribute("ImageDescription").find("quick-look"), std::string::npos);
    }
    EXPECT_NO_VALIDATION_ERRORS(before);
}

TEST(ResponsePass, RefusesMoreChannelsThanTheTonemapPassCarriesAndHasNoCube) {
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "spheres.json";
    job.overrides = {"camera.width=16", "camera.height=16"};
    const std::unique_ptr<LoadedScene> loaded = loadJobScene(job);
    TonemapPlan plan = makeJobTonemapPlan(job, *loaded, tonemapSettings(job, loaded->scene, nullptr));
    DisplayFrame frame(gpu(), loaded->scene, loaded->rendered, plan);
    SpectralPassOptions po;
    po.sampled = true;
    po.responseWeights = plan.detector.weights;
    SpectralPass pass(gpu(), loaded->scene, loaded->rendered, po);
    SpectralCube cube;
    EXPECT_THROW(pass.readback(cube), Error);
    plan.detector.weights.assign(9, plan.detector.weights[0]);
    try {
        DisplayFrame nine(gpu(), loaded->scene, loaded->rendered, plan);
        ADD_FAILURE() << "nine channels were accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where().key, "--detector");
        EXPECT_NE(std::string(e.what()).find("at most 8"), std::string::npos) << e.what();
    }
}

// Seen through sheets, media and a slab, radiance is τ(λ)·L(λ) (+ the slab's reflection): the
// response pass keeps its sums per band and applies τ inside them (interface.h,
// GpuResponseBlock::spectra). filters.json as shipped (gels, a dye cuvette, a glass block, a tilted
// window reflecting the sky; coloured shadows of a shadowing light), and with its window made a
// sheet (no slab: one set of channels): every kind of detector, ssaa and another display, within
// the bounds of the opaque scenes.
TEST(ResponsePass, SeenThroughSheetsMediaAndASlabEqualsTheCubePath) {
    const uint32_t before = gpu().validationErrors();
    const std::string csv = "csv:" + eightChannelDetector().string();
    const std::vector<std::string> sheet = {R"(materials.window={"transmittance": "filters/green_gel"})"};
    Figures worst;
    for (const std::vector<std::string>& overrides : {std::vector<std::string>{}, sheet})
        for (const std::string& detector : {std::string("cie1931"), std::string("camera:nikon_d5100"),
                                            std::string("film:reversal"), csv}) {
            Case c{"filters", detector};
            c.overrides = overrides;
            SCOPED_TRACE(describe(c) + (overrides.empty() ? "" : " / window a sheet"));
            const Figures f = compareCase(c);
            worst.responses = std::max(worst.responses, f.responses);
            worst.xyz = std::max(worst.xyz, f.xyz);
            worst.countsVsPass = std::max(worst.countsVsPass, f.countsVsPass);
        }
    Case ssaa{"filters", "cie1964", "cat16", "crt", "full", 16, 2};
    SCOPED_TRACE(describe(ssaa));
    compareCase(ssaa);
    std::printf("response pass vs cube path through sheets, media and a slab: worst relative error responses %.2e, "
                "XYZ %.2e; worst count difference %d\n",
                worst.responses, worst.xyz, worst.countsVsPass);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

// Two slabs add their reflections in depth order, which the response pass's sums do not carry:
// filters.json with its amber gel made a slab as well draws bands for its display image, and its
// responses and counts are those of the cube path exactly (the same band passes and tonemap pass).
TEST(ResponsePass, ASceneWithTwoSlabsDrawsBandsForItsDisplayImage) {
    const uint32_t before = gpu().validationErrors();
    RenderJob job;
    job.scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "filters.json";
    job.overrides = {"camera.width=80", "camera.height=64",
                     R"(materials.amber_gel={"slab": {"ior": 1.5, "thickness": 0.002}})"};
    const std::unique_ptr<LoadedScene> loaded = loadJobScene(job);
    EXPECT_FALSE(loaded->scene.transparencyInResponses());
    const TonemapPlan plan = makeJobTonemapPlan(job, *loaded, tonemapSettings(job, loaded->scene, nullptr));
    const auto [viaPass, integral] = cubePath(*loaded, plan, 1);

    DisplayFrame frame(gpu(), loaded->scene, loaded->rendered, plan, SpectralPassOptions{});
    EXPECT_FALSE(frame.passPlan().responses);
    EXPECT_EQ(frame.passPlan().bands, loaded->rendered.grid.bands());
    const DisplayImage viaFrame = frame.render();
    EXPECT_EQ(viaFrame.responses, viaPass.responses);
    EXPECT_EQ(viaFrame.counts, viaPass.counts);
    EXPECT_LE(worstRelative(viaFrame.responses, integral.responses, viaFrame.channels).relative, 1e-5);
    EXPECT_LE(worstCount(viaFrame.counts, integral.counts), 1);
    EXPECT_NO_VALIDATION_ERRORS(before);
}

// Every term the response pass takes through filters at once, in a built scene: a glossy ball (the
// specular records), a rank-one fluorescent paint seen through a gel and lying in the gel's
// coloured shadow (its coupling from the filtered light, its emission × τ of the camera), a dye box
// and drop, a tilted tinted window reflecting a sky (a hemisphere light: the lobe tables and the
// slab reflection pass, and a second piece of the gel in front of part of it: its reflection × τ
// of what lies in front; an unused slab material before it, so that its channels are not the
// first slab's), a shadowing directional light and a shadowing point light (Fresnel per band in
// the point light's coloured shadow through the window), perspective; on 300–730 nm, where CIE
// 1931 sees nothing below 360 nm (the sums skip those band layers: SPEC_RESPONSE_FIRST_LAYER).
TEST(ResponsePass, ThroughFiltersEveryTermEqualsTheCubePath) {
    const uint32_t before = gpu().validationErrors();
    Scene s = emptyScene(Grid{300, 730, 5}, perspectiveCamera({0.3, 0.2, 3}, {0, 0, 0}, {0, 1, 0}, 35.0, 96, 72));
    s.materials.push_back(lambertian(0.8, "wall"));
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4, 4, 0));
    s.lights.push_back(ambientLight(gaussianSpectrum(550, 90, 2.0, 300, 800, 1), 1.0));
    s.lights.push_back(directionalLight({0.3, -0.4, -1}, gaussianSpectrum(600, 120, 1.0, 300, 800, 1), 2.0));
    s.lights.back().shadows = true;
    s.lights.push_back(pointLight({-0.6, 0.8, 1.5}, gaussianSpectrum(470, 60, 1.0, 300, 800, 1), 3.0));
    s.lights.back().shadows = true;
    s.lights.push_back(hemisphereLight({0, 1, 0}, gaussianSpectrum(480, 150, 0.5, 300, 800, 1), 1.0));
    auto add = [&](Material m) {
        s.materials.push_back(std::move(m));
        return uint32_t(s.materials.size() - 1);
    };
    const uint32_t ball = add(glossy(constantSpectrum(0.4), constantSpectrum(0.3), 40, "ball"));
    s.meshes.push_back(sphere({0.3, -0.2, 0.25}, 0.25, 48, 24, ball));
    const uint32_t paint = add(fluorescent(constantSpectrum(0.3), gaussianSpectrum(450, 25, 0.6, 300, 800, 1),
                                           gaussianSpectrum(560, 30, 1.0, 300, 800, 1), 0.8, "paint"));
    s.meshes.push_back(quad({-0.5, -0.4, 0.01}, {0, 0, 1}, 0.6, 0.5, paint));
    const uint32_t gel = add(filterSheet(gaussianSpectrum(520, 80, 0.9, 300, 800, 1), "gel"));
    s.meshes.push_back(quad({-0.45, -0.3, 0.5}, {0.1, 0, 1}, 0.5, 0.4, gel));
    const uint32_t dye = add(absorbingMedium(gaussianSpectrum(520, 40, 15.0, 300, 800, 1), "dye"));
    Mesh box = makeBox({-0.4, 0.3, 0.4}, {0.3, 0.4, 0.2});
    box.material = dye;
    s.meshes.push_back(std::move(box));
    Mesh drop = makeSphere({0.1, -0.5, 0.6}, 0.15, 48);
    drop.material = dye;
    s.meshes.push_back(std::move(drop));
    add(slabMaterial(constantIndex(1.8), 0.01, std::nullopt, "unused glass"));  // unused: the window's channels come after it
    const uint32_t window = add(slabMaterial(nbk7(), 0.006, gaussianSpectrum(520, 40, 30.0, 300, 800, 1), "window"));
    s.meshes.push_back(quad({0.6, 0.3, 0.8}, {-0.5, 0.2, 1}, 0.6, 0.5, window));
    s.meshes.push_back(quad({0.75, 0.4, 1.2}, {0, 0, 1}, 0.3, 0.3, gel));  // in front of part of the window
    const std::unique_ptr<LoadedScene> loaded = loadedFrom(std::move(s));
    ASSERT_TRUE(loaded->scene.transparencyInResponses());
    Figures worst;
    for (const char* detector : {"cie1931", "camera:nikon_d5100"}) {
        SCOPED_TRACE(detector);
        RenderJob job;
        job.detector = detector;
        const Figures f = compareLoaded(job, *loaded, 1);
        worst.responses = std::max(worst.responses, f.responses);
        worst.xyz = std::max(worst.xyz, f.xyz);
    }
    std::printf("response pass vs cube path, every term through filters: worst relative error responses %.2e, XYZ %.2e\n",
                worst.responses, worst.xyz);
    EXPECT_NO_VALIDATION_ERRORS(before);
}
