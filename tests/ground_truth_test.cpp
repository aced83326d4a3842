// The ground truth beside the cube (render/ground_truth.h, docs/io.md "Ground truth"): on every
// bundled scene, on both renderers, radiance = reflectance × illumination band by band wherever the
// mask is 0; the GPU's maps against the CPU reference's; a white quad's maps written down by hand;
// `metamer render --write` as a user runs it.
#include "io/exr_file.h"
#include "io/image_file.h"
#include "io/png_file.h"
#include "io/spectral_image.h"
#include "reference/cpu_renderer.h"
#include "render/ground_truth.h"
#include "render/spectral_pass.h"
#include "scene/scene_json.h"
#include "spectral/library.h"
#include "support/bundled_scenes.h"
#include "support/cli.h"
#include "support/gpu.h"
#include "support/interior_comparison.h"
#include "support/scene_builders.h"
#include "support/temp_folder.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

using namespace metamer;
using namespace metamer::test;
namespace fs = std::filesystem;

namespace {

const SpectrumLibrary& library() {
    static SpectrumLibrary lib;
    return lib;
}

// Every bundled scene and the dataset sweep's base scene.
std::vector<fs::path> scenesToHold() {
    std::vector<fs::path> scenes = bundledScenes();
    scenes.push_back(fs::path(METAMER_SOURCE_DIR) / "scenes" / "dataset" / "scene.json");
    return scenes;
}

struct Maps {
    std::vector<float> radiance, reflectance, illumination;
};

Maps gpuMaps(const Scene& scene, const SceneOnGrid& spectra) {
    Maps m;
    for (SurfaceQuantity q : {SurfaceQuantity::Radiance, SurfaceQuantity::Reflectance, SurfaceQuantity::Illumination}) {
        SpectralPassOptions po;
        po.quantity = q;
        std::vector<float> cube = SpectralPass(gpu(), scene, spectra, po).render().data;
        (q == SurfaceQuantity::Radiance ? m.radiance : q == SurfaceQuantity::Reflectance ? m.reflectance : m.illumination) =
            std::move(cube);
    }
    return m;
}

Maps cpuMaps(ReferenceRenderer& reference) {
    Maps m;
    for (SurfaceQuantity q : {SurfaceQuantity::Radiance, SurfaceQuantity::Reflectance, SurfaceQuantity::Illumination}) {
        reference.setQuantity(q);
        std::vector<float> cube = reference.render().cube.data;
        (q == SurfaceQuantity::Radiance ? m.radiance : q == SurfaceQuantity::Reflectance ? m.reflectance : m.illumination) =
            std::move(cube);
    }
    return m;
}

// The worst departure from radiance = reflectance × illumination over the mask's clean pixels:
// for a material without a specular lobe per value, relative to max(|L|, ρ·I) (float rounding of
// the two sums), and for one with a lobe (below kSpecularShare of the pixel) the pixel's
// Σ|L − ρI| / ΣL.
struct Exactness {
    double lambertian = 0, glossy = 0;
    size_t lambertianPixels = 0, glossyPixels = 0, masked = 0;
};

Exactness exactness(const Scene& scene, const Maps& m, const GeometryMaps& g, int bands) {
    Exactness e;
    const size_t pixels = g.mask.size();
    for (size_t i = 0; i < pixels; ++i) {
        const float* L = &m.radiance[i * size_t(bands)];
        const float* R = &m.reflectance[i * size_t(bands)];
        const float* I = &m.illumination[i * size_t(bands)];
        if (g.mask[i] != 0) {
            ++e.masked;
            if (g.mask[i] & kTruthBackground)  // the maps are 0 where no surface is seen
                for (int b = 0; b < bands; ++b) EXPECT_EQ(R[b], 0.0f) << "background pixel " << i;
            continue;
        }
        if (scene.materials[size_t(g.material[i])].hasSpecular()) {
            double diff = 0, sum = 0;
            for (int b = 0; b < bands; ++b) {
                diff += std::fabs(double(L[b]) - double(R[b]) * I[b]);
                sum += L[b];
            }
            ++e.glossyPixels;
            if (sum > 0) e.glossy = std::max(e.glossy, diff / sum);
        } else {
            ++e.lambertianPixels;
            for (int b = 0; b < bands; ++b) {
                const double product = double(R[b]) * I[b];
                const double scale = std::max(std::fabs(double(L[b])), std::fabs(product));
                if (scale > 0) e.lambertian = std::max(e.lambertian, std::fabs(double(L[b]) - product) / scale);
            }
        }
    }
    return e;
}

}  // namespace

// The test: every bundled scene (and the dataset's), both renderers, one case per scene.
// The GPU sums the lights in float for both the radiance and the illumination, so the two round
// differently: 1e-5 (measured up to 2.3e-7); the reference 1e-6 (its doubles rounded to float).
class GroundTruthOnBundledScene : public ::testing::TestWithParam<fs::path> {};

TEST_P(GroundTruthOnBundledScene, RadianceIsReflectanceTimesIlluminationWhereTheMaskIsClear) {
    const fs::path file = GetParam();
    const Scene scene = loadScene(file, library(), {"camera.width=48", "camera.height=36"});
    const SceneOnGrid spectra = onGrid(scene);
    ReferenceRenderer reference(scene, spectra);
    const GeometryMaps g = reference.geometryMaps();
    const uint32_t before = gpu().validationErrors();
    const Exactness onGpu = exactness(scene, gpuMaps(scene, spectra), g, spectra.grid.bands());
    EXPECT_NO_VALIDATION_ERRORS(before);
    const Exactness onCpu = exactness(scene, cpuMaps(reference), g, spectra.grid.bands());
    std::printf("  %s: clean %zu Lambertian + %zu glossy px (%zu masked); Lambertian GPU %.2g, CPU %.2g; glossy "
                "GPU %.2g, CPU %.2g\n",
                file.string().c_str(), onGpu.lambertianPixels, onGpu.glossyPixels, onGpu.masked, onGpu.lambertian,
                onCpu.lambertian, onGpu.glossy, onCpu.glossy);
    ::testing::Test::RecordProperty("lambertian_gpu", std::to_string(onGpu.lambertian));
    ::testing::Test::RecordProperty("lambertian_cpu", std::to_string(onCpu.lambertian));
    EXPECT_GT(onGpu.lambertianPixels + onGpu.glossyPixels, 100u);
    EXPECT_LE(onGpu.lambertian, 1e-5);
    EXPECT_LE(onCpu.lambertian, 1e-6);
    EXPECT_LE(onGpu.glossy, kSpecularShare * 1.001 + 1e-5);
    EXPECT_LE(onCpu.glossy, kSpecularShare * 1.001);
}

INSTANTIATE_TEST_SUITE_P(GroundTruth, GroundTruthOnBundledScene, ::testing::ValuesIn(scenesToHold()),
                         [](const ::testing::TestParamInfo<fs::path>& info) {
                             std::string name = info.param.parent_path().filename() == "dataset"
                                                    ? "dataset"
                                                    : info.param.stem().string();
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

// Per-pixel |Σ_b gpu − Σ_b cpu| / Σ_b cpu over pixels whose 3×3 neighbourhood sees one object, sorted.
std::vector<double> bandSumDifferences(const SpectralCube& gpuCube, const ReferenceImage& cpu) {
    std::vector<double> out;
    const int W = cpu.cube.width, H = cpu.cube.height;
    for (int y = 1; y + 1 < H; ++y)
        for (int x = 1; x + 1 < W; ++x) {
            const int32_t id = cpu.objectId[size_t(y) * W + x];
            bool interior = id >= 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) interior = interior && cpu.objectId[size_t(y + dy) * W + x + dx] == id;
            if (!interior) continue;
            double g = 0, c = 0;
            for (int b = 0; b < cpu.cube.bands(); ++b) {
                g += gpuCube.at(x, y, b);
                c += cpu.cube.at(x, y, b);
            }
            if (c > 0) out.push_back(std::fabs(g - c) / c);
        }
    std::sort(out.begin(), out.end());
    return out;
}

// The GPU's maps against the reference's, by the radiance's own rules: per band 1e-4 of the band's
// largest value away from edges and shadow boundaries (gpu_vs_reference_test.cpp); a textured
// scene 1e-4 of the peak (textures_test.cpp: sharp texel edges); interreflection 1.5 % in the
// median pixel and 5 % in the 95th percentile (interreflection_test.cpp: each renderer solves it
// its own way); coloured shadows 1e-2 (transparency_test.cpp: the transmittance maps' interpolation).
TEST(GroundTruth, TheGpuMapsMatchTheReference) {
    for (const char* name : {"spheres.json", "textured.json", "filters.json", "cornell-box.json", "imaging-systems.json",
                             "fluorescent.json"}) {
        SCOPED_TRACE(name);
        const Scene scene =
            loadScene(fs::path(METAMER_SOURCE_DIR) / "scenes" / name, library(), {"camera.width=64", "camera.height=48"});
        const SceneOnGrid spectra = onGrid(scene);
        ReferenceRenderer referenceRenderer(scene, spectra);  // one solve of the interreflection for both maps
        for (SurfaceQuantity q : {SurfaceQuantity::Reflectance, SurfaceQuantity::Illumination}) {
            SpectralPassOptions po;
            po.quantity = q;
            const uint32_t before = gpu().validationErrors();
            const SpectralCube onGpu = SpectralPass(gpu(), scene, spectra, po).render();
            EXPECT_NO_VALIDATION_ERRORS(before);
            referenceRenderer.setQuantity(q);
            const ReferenceImage reference = referenceRenderer.render();
            if (scene.interreflection && q == SurfaceQuantity::Illumination) {
                const std::vector<double> d = bandSumDifferences(onGpu, reference);
                ASSERT_GT(d.size(), 500u);
                const double median = d[d.size() / 2], p95 = d[d.size() * 95 / 100];
                std::printf("  %s %s: %zu interior pixels, median %.4f, p95 %.4f\n", name, surfaceQuantityName(q),
                            d.size(), median, p95);
                EXPECT_LT(median, 0.015);
                EXPECT_LT(p95, 0.05);
                continue;
            }
            const InteriorComparison c = compareInterior(onGpu, reference);
            double peak = 0;
            for (float v : reference.cube.data) peak = std::max(peak, double(v));
            std::printf("  %s %s: %d interior pixels, max relative error %.3g, %.3g of the peak\n", name,
                        surfaceQuantityName(q), c.pixels, c.maxRelative, c.maxAbsolute / peak);
            EXPECT_GE(c.pixels, 200);
            if (scene.hasTextures())
                EXPECT_LE(c.maxAbsolute / peak, 1e-4) << surfaceQuantityName(q);
            else if (scene.hasTransparency() && q == SurfaceQuantity::Illumination)
                EXPECT_LE(c.maxRelative, 1e-2);  // coloured shadows' transmittance maps (transparency_test.cpp)
            else
                EXPECT_LE(c.maxRelative, 1e-4) << surfaceQuantityName(q);
        }
    }
}

// A white quad (ρd = 0.8) facing the camera 2 m away, lit by a directional light at 60° from its
// normal with irradiance E⊥ = 3 W·m⁻²·nm⁻¹ normal to the beam, and an ambient light of 0.5:
// illumination = (3·cos 60° + 0.5)/π, reflectance 0.8, depth 2 m, normal (0, 0, 1), ids 0 and 0.
TEST(GroundTruth, AWhiteQuadUnderKnownLightsHasTheMapsWrittenDownByHand) {
    const Grid grid{400, 700, 10};
    Scene scene = emptyScene(grid, orthographicCamera({0, 0, 2}, {0, 0, 0}, {0, 1, 0}, 1.0, 16, 16));
    scene.materials.push_back(lambertian(0.8, "white"));
    scene.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 4.0, 4.0, 0, {0, 1, 0}, "wall"));
    const double theta = 60.0 * M_PI / 180.0;
    scene.lights.push_back(ambientLight(constantSpectrum(0.5)));
    scene.lights.push_back(directionalLight({std::sin(theta), 0, -std::cos(theta)}, constantSpectrum(3.0)));
    const SceneOnGrid spectra = onGrid(scene);
    const double expected = (3.0 * std::cos(theta) + 0.5) / M_PI;
    ReferenceRenderer reference(scene, spectra);
    const Maps onGpu = gpuMaps(scene, spectra), onCpu = cpuMaps(reference);
    for (const Maps* m : {&onGpu, &onCpu})
        for (size_t i = 0; i < m->illumination.size(); ++i) {
            ASSERT_NEAR(m->illumination[i], expected, 2e-6 * expected) << (m == &onGpu ? "GPU" : "CPU") << " value " << i;
            ASSERT_NEAR(m->reflectance[i], 0.8, 1e-7);
            ASSERT_NEAR(m->radiance[i], 0.8 * expected, 2e-6 * expected);
        }
    const GeometryMaps g = ReferenceRenderer(scene, spectra).geometryMaps();
    for (size_t i = 0; i < g.mask.size(); ++i) {
        EXPECT_EQ(g.mask[i], 0) << i;
        EXPECT_EQ(g.object[i], 0);
        EXPECT_EQ(g.material[i], 0);
        EXPECT_NEAR(g.depth_m[i], 2.0, 1e-6);
        EXPECT_NEAR(g.normal[3 * i + 2], 1.0, 1e-7);
        EXPECT_NEAR(g.normal[3 * i], 0.0, 1e-7);
    }
}

// The mask says why, one reason at a time: a fluorescent, a glossy, a self-luminous quad, one
// behind a filter, the background and the edges between them.
TEST(GroundTruth, TheMaskNamesEachReason) {
    const Grid grid{400, 700, 10};
    Scene scene = emptyScene(grid, orthographicCamera({0, 0, 2}, {0, 0, 0}, {0, 1, 0}, 2.0, 40, 40));
    scene.materials.push_back(lambertian(0.5, "matte"));
    scene.materials.push_back(fluorescent(constantSpectrum(0.2), gaussianSpectrum(450, 20), gaussianSpectrum(550, 20), 0.5));
    scene.materials.push_back(glossy(constantSpectrum(0.2), constantSpectrum(0.5), 10.0));
    scene.materials.push_back(emitting(lambertian(0.5, "lamp"), constantSpectrum(1.0)));
    scene.materials.push_back(filterSheet(constantSpectrum(0.5)));
    // Four quads in the image's quadrants (a gap of background between them), a filter over the
    // bottom-right one.
    scene.meshes.push_back(quad({-0.5, 0.5, 0}, {0, 0, 1}, 0.8, 0.8, 1, {0, 1, 0}, "fluorescent"));
    scene.meshes.push_back(quad({0.5, 0.5, 0}, {0, 0, 1}, 0.8, 0.8, 2, {0, 1, 0}, "glossy"));
    scene.meshes.push_back(quad({-0.5, -0.5, 0}, {0, 0, 1}, 0.8, 0.8, 3, {0, 1, 0}, "lamp"));
    scene.meshes.push_back(quad({0.5, -0.5, 0}, {0, 0, 1}, 0.8, 0.8, 0, {0, 1, 0}, "matte"));
    scene.meshes.push_back(quad({0.5, -0.5, 0.5}, {0, 0, 1}, 0.4, 0.4, 4, {0, 1, 0}, "filter"));
    scene.lights.push_back(directionalLight({0, 0, -1}, constantSpectrum(1.0)));
    const SceneOnGrid spectra = onGrid(scene);
    ReferenceRenderer reference(scene, spectra);
    reference.setQuantity(SurfaceQuantity::Illumination);  // the mask is the radiance's, whatever the maps are
    const GeometryMaps g = reference.geometryMaps();
    auto at = [&](int x, int y) { return g.mask[size_t(y) * 40 + size_t(x)]; };
    EXPECT_EQ(at(10, 10), kTruthFluorescent);
    EXPECT_EQ(at(30, 10), kTruthSpecular);  // the light straight down the view: the lobe's peak
    EXPECT_EQ(at(10, 30), kTruthEmitter);
    EXPECT_EQ(at(30, 30), kTruthTransparent);
    EXPECT_EQ(at(23, 30), 0);  // the matte quad beside its filter
    EXPECT_EQ(at(20, 20), kTruthBackground);
    EXPECT_EQ(at(2, 10), kTruthFluorescent | kTruthEdge);  // its neighbour at x = 1 sees the background
    EXPECT_EQ(g.object[size_t(30) * 40 + 30], 3);  // the matte quad, seen through the filter
    EXPECT_EQ(g.object[size_t(20) * 40 + 20], -1);
}

class GroundTruthCli : public TempFolderTest {};

// As a user runs it: every map written beside the cube, named by the scene's stem, each file
// saying what it holds; the legend names the objects; the reflectance reads back as reflectance.
TEST_F(GroundTruthCli, WriteNamesEveryMapAndEachFileSaysWhatItHolds) {
    const fs::path scene = fs::path(METAMER_SOURCE_DIR) / "scenes" / "colorchecker.json";
    const CliRun run = runMetamer(fmt::format(
        "render '{}' --out '{}' --set camera.width=48 --set camera.height=32 --grid 400:700:10 "
        "--write cube,reflectance,illumination,ids,depth,normal --format exr,hdf5",
        scene.string(), dir.string()));
    ASSERT_EQ(run.code, 0) << run.output;
    for (const char* f : {"colorchecker.exr", "colorchecker.h5", "colorchecker.reflectance.exr",
                          "colorchecker.reflectance.h5", "colorchecker.illumination.exr", "colorchecker.illumination.h5",
                          "colorchecker.ids.exr", "colorchecker.ids.json", "colorchecker.depth.exr",
                          "colorchecker.normal.exr", "colorchecker.mask.png"})
        EXPECT_TRUE(fs::exists(dir / f)) << f << "\n" << run.output;
    EXPECT_EQ(namesIn(), (std::vector<std::string>{"colorchecker.depth.exr", "colorchecker.exr", "colorchecker.h5",
                                                 "colorchecker.ids.exr", "colorchecker.ids.json",
                                                 "colorchecker.illumination.exr", "colorchecker.illumination.h5",
                                                 "colorchecker.mask.png", "colorchecker.normal.exr",
                                                 "colorchecker.reflectance.exr", "colorchecker.reflectance.h5"}));
    const SpectralImage reflectance = readSpectralImage(dir / "colorchecker.reflectance.exr");
    EXPECT_EQ(reflectance.component, SpectralComponent::Reflective);
    EXPECT_EQ(readSpectralImage(dir / "colorchecker.reflectance.h5").component, SpectralComponent::Reflective);
    const SpectralImage radiance = readSpectralImage(dir / "colorchecker.exr");
    const SpectralImage illumination = readSpectralImage(dir / "colorchecker.illumination.exr");
    ASSERT_EQ(radiance.cube.data.size(), reflectance.cube.data.size());
    std::ifstream legendFile(dir / "colorchecker.ids.json");
    const nlohmann::json legend = nlohmann::json::parse(legendFile);
    EXPECT_EQ(legend["background"], -1);
    ASSERT_FALSE(legend["objects"].empty());
    ASSERT_FALSE(legend["materials"].empty());
    const std::vector<float> ids = readExrChannels(dir / "colorchecker.ids.exr", {"object", "material"}, Where{"ids"});
    ASSERT_EQ(ids.size(), size_t(2 * 48 * 32));
    // Every id is in the legend, and the centre pixel sees a patch whose material is a ColorChecker's.
    for (size_t i = 0; i < ids.size(); i += 2) {
        ASSERT_GE(ids[i], -1.0f);
        ASSERT_LT(ids[i], float(legend["objects"].size()));
        if (ids[i] >= 0) EXPECT_EQ(ids[i + 1], float(legend["objects"][size_t(ids[i])]["material"].get<int>()));
    }
    // radiance = reflectance × illumination where the mask is clear: the files keep the identity.
    const std::vector<float> mask = readPng(dir / "colorchecker.mask.png", Where{"mask"}).pixels;
    size_t clean = 0;
    const int bands = radiance.cube.bands();
    for (size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] != 0) continue;
        ++clean;
        for (int b = 0; b < bands; ++b) {
            const size_t v = i * size_t(bands) + size_t(b);
            const double product = double(reflectance.cube.data[v]) * illumination.cube.data[v];
            EXPECT_NEAR(radiance.cube.data[v], product, 1e-5 * std::max(1e-30, product)) << "pixel " << i << " band " << b;
        }
    }
    EXPECT_GT(clean, mask.size() / 3);
    EXPECT_NE(run.output.find("ground-truth mask"), std::string::npos) << run.output;
}

TEST_F(GroundTruthCli, AWrongOutputNameListsTheMaps) {
    const CliRun run = runMetamer(fmt::format("render '{}/scenes/colorchecker.json' --out '{}' --write reflectanse",
                                              METAMER_SOURCE_DIR, dir.string()));
    EXPECT_NE(run.code, 0);
    EXPECT_NE(run.output.find("--write"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("did you mean 'reflectance'"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("illumination"), std::string::npos) << run.output;
    EXPECT_TRUE(namesIn().empty());
}
