// Textures and normal maps (docs/physics.md, "Textures"): known answers on the GPU and the CPU
// reference, and the GPU against the reference on a textured, bump-mapped, fluorescent scene.
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"
#include "represent/representation.h"
#include "scene/gltf_material.h"
#include "scene/gltf_mesh.h"
#include "scene/scene_json.h"
#include "scene/texture.h"
#include "support/capture_warnings.h"
#include "support/gpu.h"
#include "support/interior_comparison.h"
#include "support/scene_builders.h"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>

using namespace metamer;
using namespace metamer::test;

namespace {

constexpr double kPi = std::numbers::pi;

// A quad from the builder with texture coordinates: the image upright on it (u along "right",
// v down), tangent "right", w = +1 (cross(n, right) = up, towards decreasing v).
Mesh texturedQuad(glm::dvec3 centre, glm::dvec3 normal, double w, double h, uint32_t material,
                  glm::dvec3 up = glm::dvec3(0.0), double repeat = 1.0) {
    Mesh m = quad(centre, normal, w, h, material, up);
    m.uvs = {{0, repeat}, {repeat, repeat}, {repeat, 0}, {0, 0}};
    glm::dvec3 right = glm::normalize(m.positions[1] - m.positions[0]);
    m.tangents.assign(4, glm::dvec4(right, 1.0));
    return m;
}

// The builder's UV sphere (rows pole to pole, a duplicated seam) with u = i/segments,
// v = j/rings and tangents along increasing u.
Mesh texturedSphere(glm::dvec3 centre, double radius, int segments, int rings, uint32_t material) {
    Mesh m = sphere(centre, radius, segments, rings, material);
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i <= segments; ++i) {
            double phi = 2.0 * kPi * i / segments;
            m.uvs.push_back({double(i) / segments, double(j) / rings});
            // ∂p/∂φ ∝ (−sin φ, 0, −cos φ); increasing v runs south, so the bitangent (up the
            // image, north) is −∂p/∂θ and w follows from cross(n, t).
            glm::dvec3 t(-std::sin(phi), 0.0, -std::cos(phi));
            glm::dvec3 n = m.normals[m.uvs.size() - 1];
            glm::dvec3 north = glm::dvec3(0, 1, 0) - n * n.y;
            double w = glm::dot(glm::cross(n, t), north) >= 0.0 ? 1.0 : -1.0;
            m.tangents.push_back(glm::dvec4(t, w));
        }
    return m;
}

Texture spectralTexture(int w, int h, std::vector<double> nm, std::function<double(int, int, double)> value) {
    Texture t;
    t.kind = Texture::Kind::Spectral;
    t.file = "test-texture.exr";
    t.where = Where{"test-scene", "materials.textured.textures.diffuse"};
    t.width = w;
    t.height = h;
    t.wavelengths_nm = nm;
    t.channels = int(nm.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (double l : nm) t.texels.push_back(float(value(x, y, l)));
    return t;
}

Texture normalTexture(int w, int h, std::function<glm::dvec3(int, int)> n) {
    Texture t;
    t.kind = Texture::Kind::Normal;
    t.file = "test-normals.png";
    t.width = w;
    t.height = h;
    t.channels = 3;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 v = glm::normalize(n(x, y));
            for (int c = 0; c < 3; ++c) t.texels.push_back(float(v[c]));
        }
    return t;
}

std::vector<double> wavelengths(double lo, double hi, double step) {
    std::vector<double> nm;
    for (double l = lo; l <= hi + 1e-9; l += step) nm.push_back(l);
    return nm;
}

Camera topDown(int px) { return orthographicCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0, px, px); }
Spectrum flatLight() { return constantSpectrum(2.0); }
Spectrum daylightish() { return gaussianSpectrum(560, 120, 1.5, 300, 800, 1); }

SpectralCube gpuRender(const Scene& s, const SceneOnGrid& g) {
    uint32_t before = gpu().validationErrors();
    SpectralPass pass(gpu(), s, g);
    SpectralCube c = pass.render();
    EXPECT_NO_VALIDATION_ERRORS(before);
    return c;
}

}  // namespace

// A texture whose every texel holds spectrum S on a material with diffuse 1 renders as the
// untextured material with diffuse S: the texture path adds nothing but the lookup.
TEST(Textures, UniformTextureEqualsTheUntexturedMaterial) {
    std::vector<double> nm = wavelengths(380, 780, 20);
    auto s = [](double l) { return 0.2 + 0.6 * std::exp(-0.5 * std::pow((l - 600) / 60, 2)); };
    for (bool gpuPath : {true, false}) {
        Scene plain = emptyScene(Grid{400, 700, 5}, topDown(12));
        std::vector<double> values;
        for (double l : nm) values.push_back(double(float(s(l))));
        plain.materials.push_back(lambertian(sampledSpectrum(nm, values)));
        plain.meshes.push_back(texturedQuad({0, 0, 0}, {0, 0, 1}, 2, 2, 0));
        plain.lights.push_back(directionalLight({0.3, 0.2, -1}, daylightish()));
        Scene textured = plain;
        textured.materials[0] = lambertian(1.0);
        textured.materials[0].textures.diffuse = 0;
        textured.textures.push_back(spectralTexture(5, 3, nm, [&](int, int, double l) { return s(l); }));
        SceneOnGrid gp = onGrid(plain), gt = onGrid(textured);
        SpectralCube a = gpuPath ? gpuRender(plain, gp) : renderReference(plain, gp).cube;
        SpectralCube b = gpuPath ? gpuRender(textured, gt) : renderReference(textured, gt).cube;
        ASSERT_EQ(a.data.size(), b.data.size());
        double worst = 0;
        for (size_t i = 0; i < a.data.size(); ++i)
            worst = std::max(worst, std::fabs(double(a.data[i]) - b.data[i]) / std::max(1e-30, double(std::fabs(a.data[i]))));
        std::printf("  %s: largest relative difference %.3g\n", gpuPath ? "GPU" : "CPU", worst);
        // Float rounding only: bilinear weights of four equal texels sum to 1 within an ulp or two.
        EXPECT_LE(worst, 5e-7) << (gpuPath ? "GPU" : "CPU");
    }
}

// An 8×8 checker of two spectra seen texel for pixel: each pixel is at a texel centre, where
// bilinear filtering returns that texel exactly, so the radiance is ρ(texel)·E/π.
TEST(Textures, CheckerBandValuesAtTexelCentres) {
    const int n = 8;
    std::vector<double> nm = wavelengths(400, 700, 10);
    auto a = [](double l) { return 0.1 + 0.8 * (l - 400) / 300; };
    auto b = [](double l) { return 0.9 - 0.7 * (l - 400) / 300; };
    Scene s = emptyScene(Grid{400, 700, 10}, topDown(n));
    s.materials.push_back(lambertian(1.0));
    s.materials[0].textures.diffuse = 0;
    s.textures.push_back(spectralTexture(n, n, nm, [&](int x, int y, double l) { return (x + y) % 2 ? b(l) : a(l); }));
    s.meshes.push_back(texturedQuad({0, 0, 0}, {0, 0, 1}, 1, 1, 0, {0, 1, 0}));
    s.lights.push_back(directionalLight({0, 0, -1}, flatLight()));
    SceneOnGrid g = onGrid(s);
    // Linear spectra sampled on the grid's own wavelengths resample to themselves in every band
    // the data cover whole (the band average of a straight line is its centre value); the two end
    // bands hold the end value over their outer half, so they are left out.
    SpectralCube cubes[2] = {gpuRender(s, g), renderReference(s, g).cube};
    for (int which = 0; which < 2; ++which)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int k = 1; k + 1 < g.grid.bands(); ++k) {
                    double l = g.wavelengths_nm[k];
                    double expected = ((x + y) % 2 ? b(l) : a(l)) * 2.0 / kPi;
                    ASSERT_NEAR(cubes[which].at(x, y, k), expected, 2e-6 * expected)
                        << (which ? "CPU" : "GPU") << " pixel " << x << "," << y << " band " << l << " nm";
                }
}

// Texture coordinates repeat: a 2×2 texture tiled 4 times across 8 pixels puts every pixel
// centre on a texel centre, texel (x mod 2, y mod 2), across the tile seams too.
TEST(Textures, CoordinatesRepeat) {
    std::vector<double> nm = wavelengths(400, 700, 100);
    Scene s = emptyScene(Grid{400, 700, 100}, topDown(8));
    s.materials.push_back(lambertian(1.0));
    s.materials[0].textures.diffuse = 0;
    s.textures.push_back(spectralTexture(2, 2, nm, [](int x, int y, double) { return 0.2 + 0.2 * x + 0.4 * y; }));
    s.meshes.push_back(texturedQuad({0, 0, 0}, {0, 0, 1}, 1, 1, 0, {0, 1, 0}, 4.0));
    s.lights.push_back(directionalLight({0, 0, -1}, flatLight()));
    SceneOnGrid g = onGrid(s);
    SpectralCube cube = gpuRender(s, g);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            double expected = (0.2 + 0.2 * (x % 2) + 0.4 * (y % 2)) * 2.0 / kPi;
            ASSERT_NEAR(cube.at(x, y, 1), expected, 2e-6) << x << "," << y;
        }
}

// A uniform normal map tilting the normal by α about the tangent frame's y axis: under a light
// along the geometric normal the diffuse radiance falls to ρE·cos α/π (GPU and reference).
TEST(Textures, NormalMapTiltsTheShadingNormal) {
    const double alpha = 35 * kPi / 180;
    Scene s = emptyScene(Grid{500, 600, 50}, topDown(6));
    s.materials.push_back(lambertian(0.5));
    s.materials[0].textures.normal = 0;
    s.textures.push_back(normalTexture(3, 3, [&](int, int) { return glm::dvec3(std::sin(alpha), 0, std::cos(alpha)); }));
    s.meshes.push_back(texturedQuad({0, 0, 0}, {0, 0, 1}, 2, 2, 0, {0, 1, 0}));
    s.lights.push_back(directionalLight({0, 0, -1}, flatLight()));
    SceneOnGrid g = onGrid(s);
    SpectralCube cubes[2] = {gpuRender(s, g), renderReference(s, g).cube};
    double expected = 0.5 * 2.0 * std::cos(alpha) / kPi;
    for (int which = 0; which < 2; ++which)
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 6; ++x) ASSERT_NEAR(cubes[which].at(x, y, 0), expected, 2e-6) << which;
    // A light tilted by α the same way (towards +x, the tangent) meets the mapped normal head-on.
    s.lights[0] = directionalLight({-std::sin(alpha), 0, -std::cos(alpha)}, flatLight());
    g = onGrid(s);
    SpectralCube tilted = gpuRender(s, g);
    EXPECT_NEAR(tilted.at(3, 3, 0), 0.5 * 2.0 / kPi, 2e-6);
}

// Bump maps become normal maps: a height ramp of slope s per texel (interior) gives
// n ∝ (−s, 0, 1); rising towards the top of the image, n ∝ (0, −s, 1)... with y up the image.
TEST(Textures, HeightToNormalsFollowsTheSlope) {
    const int w = 8, h = 8;
    std::vector<float> ramp(w * h), up(w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            ramp[y * w + x] = float(0.1 * x);
            up[y * w + x] = float(0.1 * (h - 1 - y));  // rises up the image
        }
    std::vector<float> n = heightToNormals(ramp, w, h, 2.0);
    const float* c = &n[(3 * w + 3) * 3];
    double len = std::sqrt(0.2 * 0.2 + 1.0);
    EXPECT_NEAR(c[0], -0.2 / len, 1e-6);
    EXPECT_NEAR(c[1], 0.0, 1e-6);
    EXPECT_NEAR(c[2], 1.0 / len, 1e-6);
    n = heightToNormals(up, w, h, 2.0);
    c = &n[(3 * w + 3) * 3];
    EXPECT_NEAR(c[0], 0.0, 1e-6);
    EXPECT_NEAR(c[1], -0.2 / len, 1e-6);  // the surface rises up the image: the normal leans down
    EXPECT_NEAR(c[2], 1.0 / len, 1e-6);
}

// The GPU against the reference on a scene with every texture kind: a sphere with an RGB
// texture (up-sampled) and a bump map, a glossy quad with spectral diffuse and specular textures
// and a normal map, a fluorescent quad, under a point and a directional light. Per band, relative
// error ≤ 1e-4 away from edges (as tests/gpu_vs_reference_test.cpp).
TEST(Textures, GpuMatchesReferenceOnATexturedBumpMappedFluorescentScene) {
    Scene s = emptyScene(Grid{380, 730, 5},
                         perspectiveCamera({0.2, 0.6, 4.0}, {0, 0, 0}, {0, 1, 0}, 40, 96, 72));
    std::vector<double> nm = wavelengths(380, 730, 10);
    // Smooth textures: bilinear interpolation of slowly varying texels, so the float texture
    // coordinates of the rasterizer shift values by far less than the tolerance.
    Texture rgb;
    rgb.kind = Texture::Kind::Rgb;
    rgb.file = "test-rgb.png";
    rgb.width = 16;
    rgb.height = 8;
    rgb.channels = 3;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            rgb.texels.push_back(float(0.2 + 0.6 * x / 15.0));
            rgb.texels.push_back(float(0.3 + 0.4 * y / 7.0));
            rgb.texels.push_back(float(0.5 - 0.3 * x / 15.0));
        }
    s.textures.push_back(rgb);  // 0
    std::vector<float> height(32 * 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) height[y * 32 + x] = float(0.5 + 0.5 * std::sin(2 * kPi * x / 32) * std::cos(2 * kPi * y / 16));
    Texture bump = normalTexture(32, 16, [](int, int) { return glm::dvec3(0, 0, 1); });
    bump.texels = heightToNormals(height, 32, 16, 1.5);
    s.textures.push_back(bump);  // 1
    s.textures.push_back(spectralTexture(6, 6, nm, [](int x, int y, double l) {
        return 0.3 + 0.05 * x + 0.03 * y * std::sin(l / 40.0);
    }));  // 2
    s.textures.push_back(spectralTexture(4, 4, nm, [](int x, int, double l) { return 0.5 + 0.1 * x * (l - 380) / 350; }));  // 3
    s.textures.push_back(normalTexture(8, 8, [](int x, int y) {
        return glm::dvec3(0.15 * std::sin(x * 0.8), 0.12 * std::cos(y * 0.7), 1.0);
    }));  // 4

    Material sphereMat = lambertian(1.0, "sphere");
    sphereMat.textures.diffuse = 0;
    sphereMat.textures.normal = 1;
    Material glossyMat = glossy(constantSpectrum(1.0), constantSpectrum(0.4), 25, "glossy");
    glossyMat.textures.diffuse = 2;
    glossyMat.textures.specular = 3;
    glossyMat.textures.normal = 4;
    s.materials = {sphereMat, glossyMat,
                   fluorescent(constantSpectrum(0.2), gaussianSpectrum(420, 25, 0.8, 300, 800, 1),
                               gaussianSpectrum(520, 30, 1.0, 380, 780, 1), 0.7)};
    s.meshes.push_back(texturedSphere({-0.6, 0.1, 0}, 0.6, 64, 32, 0));
    s.meshes.push_back(texturedQuad({0.7, 0, -0.2}, {-0.3, 0.2, 1}, 1.1, 1.3, 1));
    s.meshes.push_back(texturedQuad({0.0, -0.75, 0.3}, {0, 1, 0.2}, 2.4, 0.8, 2));
    s.lights.push_back(pointLight({1.5, 2.0, 3.0}, daylightish(), 6.0));
    s.lights.push_back(directionalLight({-0.4, -0.5, -1}, gaussianSpectrum(430, 40, 1.0, 300, 800, 1), 0.8));

    uint32_t before = gpu().validationErrors();
    SceneOnGrid g = onGrid(s);
    SpectralPass pass(gpu(), s, g);
    SpectralCube cube = pass.render();
    ReferenceImage ref = renderReference(s, g);
    EXPECT_NO_VALIDATION_ERRORS(before);
    InteriorComparison c = compareInterior(cube, ref);
    std::printf("  %d interior pixels, max relative error %.3g (pixel %d,%d band %d)\n", c.pixels, c.maxRelative,
                c.worstX, c.worstY, c.worstBand);
    EXPECT_GE(c.pixels, 1500);
    EXPECT_LE(c.maxRelative, 1e-4) << "pixel " << c.worstX << "," << c.worstY << " band " << c.worstBand;
}

// In the RGB representation a texture's texels are analysed as the materials' spectra are; the
// render still matches the reference in that mode.
TEST(Textures, RgbModeAnalysesTexelsLikeSpectra) {
    Scene s = emptyScene(Grid{380, 780, 5}, topDown(8));
    std::vector<double> nm = wavelengths(380, 780, 20);
    s.materials.push_back(lambertian(1.0));
    s.materials[0].textures.diffuse = 0;
    s.textures.push_back(spectralTexture(8, 8, nm, [](int x, int y, double l) { return 0.2 + 0.05 * x + 0.02 * y * (l - 380) / 400; }));
    s.meshes.push_back(texturedQuad({0, 0, 0}, {0, 0, 1}, 1, 1, 0, {0, 1, 0}));
    s.lights.push_back(directionalLight({0, 0, -1}, daylightish()));
    SceneOnGrid full = onGrid(s);
    Representation r = makeRepresentation(parseMode("rgb", Where{"", "--mode"}), s.grid, SpectrumLibrary(), &full);
    SceneOnGrid g = represent(full, r, s);
    ASSERT_EQ(g.textures.size(), 1u);
    ASSERT_EQ(g.textures[0].channels, 3);
    SpectralCube cube = gpuRender(s, g);
    ReferenceImage ref = renderReference(s, g);
    for (size_t i = 0; i < cube.data.size(); ++i) ASSERT_NEAR(cube.data[i], ref.cube.data[i], 1e-5 * std::fabs(ref.cube.data[i]) + 1e-9);
}

// linear:K analyses a textured reflectance texel by texel: texels mixing three fixed spectra
// (1, f₂, f₃ with weights that differ from texel to texel) under one light reflect spectra in a
// 3-dimensional space, so linear:3 is exact and the basis has 3 functions, whatever K asks. With
// 24 texels the basis comes from the samples' Gram matrix, with 64 (more than the 31 bands) from
// the bands' second-moment matrix; both must find it. Without the texels in the analysis the basis
// would hold only the light's own shape.
TEST(Textures, LinearModeAnalysesTexturesTexelByTexel) {
    std::vector<double> nm = wavelengths(380, 780, 10);
    auto f2 = [](double l) { return std::exp(-0.5 * std::pow((l - 520) / 40, 2)); };
    auto f3 = [](double l) { return (l - 380) / 400; };
    for (int side : {0, 1}) {
        const int w = side ? 8 : 6, h = side ? 8 : 4;
        Scene s = emptyScene(Grid{400, 700, 10}, topDown(16));
        s.materials.push_back(lambertian(1.0));
        s.materials[0].textures.diffuse = 0;
        s.textures.push_back(spectralTexture(w, h, nm, [&](int x, int y, double l) {
            return 0.1 + 0.02 * x + 0.3 * f2(l) * (y + 1) / h + 0.4 * f3(l) * ((x * 7 + y * 3) % 5) / 4.0;
        }));
        s.meshes.push_back(texturedQuad({0, 0, 0}, {0, 0, 1}, 1, 1, 0, {0, 1, 0}));
        s.lights.push_back(directionalLight({0.2, 0.1, -1}, daylightish()));
        SceneOnGrid g = onGrid(s);
        Representation r = makeRepresentation(parseMode("linear:5", Where{"", "--mode"}), s.grid, SpectrumLibrary(), &g);
        EXPECT_EQ(r.basis.size(), 3u) << w << "x" << h << " texels";
        SpectralCube lin = renderReference(s, represent(g, r, s)).cube;
        projectCube(r, lin.data, lin.bands());
        SpectralCube full = renderReference(s, g).cube;
        double worst = 0, peak = 0;
        for (size_t i = 0; i < full.data.size(); ++i) {
            worst = std::max(worst, double(std::fabs(lin.data[i] - full.data[i])));
            peak = std::max(peak, double(full.data[i]));
        }
        std::printf("  %dx%d texels: linear:3 against full, worst %.3g of the peak radiance\n", w, h, worst / peak);
        EXPECT_GT(peak, 0.0);
        EXPECT_LE(worst, 1e-6 * peak) << w << "x" << h << " texels";
    }
}

// glTF images embedded in the file — in a GLB's buffer views or as data: URIs — are the same
// images as the files beside a .gltf: the panel of scenes/textured.json written both ways
// (tests/data/gltf/make_embedded.py) gives the same bytes and the same texels, and a JPEG
// base colour decodes to the PNG's colours within JPEG's loss.
TEST(Textures, EmbeddedGltfImagesLoadAsTheirFiles) {
    const std::string assets = std::string(METAMER_SOURCE_DIR) + "/scenes/assets/";
    const std::string data = std::string(METAMER_TEST_DATA_DIR) + "/gltf/";
    const Where where{"test-scene", "objects.0.mesh"};
    auto bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
    };
    const GltfModel files = loadGltf(assets + "panel.gltf", where);
    ASSERT_TRUE(files.materials.at(0).baseColorTexture && files.materials[0].normalTexture);
    ASSERT_FALSE(files.materials[0].baseColorTexture->isEmbedded());
    const Texture colour = loadTexture(files.materials[0].baseColorTexture->file, TextureRole::Reflectance,
                                       TextureEncoding::Srgb, 1.0, where);
    const Texture normals =
        loadTexture(files.materials[0].normalTexture->file, TextureRole::Normal, TextureEncoding::Auto, 1.0, where);
    for (const char* name : {"panel-embedded.glb", "panel-datauri.gltf"}) {
        SCOPED_TRACE(name);
        const GltfModel m = loadGltf(data + name, where);
        ASSERT_EQ(m.materials.size(), 2u);
        const GltfMaterial& tiles = m.materials[0];
        ASSERT_TRUE(tiles.baseColorTexture && tiles.normalTexture);
        ASSERT_TRUE(tiles.baseColorTexture->isEmbedded());
        EXPECT_EQ(tiles.baseColorTexture->embedded, bytes(assets + "tiles.png"));
        EXPECT_EQ(tiles.normalTexture->embedded, bytes(assets + "tiles_normal.png"));
        EXPECT_NE(tiles.baseColorTexture->name.find("image 0"), std::string::npos) << tiles.baseColorTexture->name;
        const Texture c = loadTexture(EncodedImage{tiles.baseColorTexture->name, tiles.baseColorTexture->embedded},
                                      TextureRole::Reflectance, TextureEncoding::Srgb, 1.0, where);
        const Texture n = loadTexture(EncodedImage{tiles.normalTexture->name, tiles.normalTexture->embedded},
                                      TextureRole::Normal, TextureEncoding::Auto, 1.0, where);
        EXPECT_EQ(c.kind, Texture::Kind::Rgb);
        EXPECT_EQ(c.width, colour.width);
        EXPECT_EQ(c.texels, colour.texels);
        EXPECT_EQ(n.kind, Texture::Kind::Normal);
        EXPECT_EQ(n.texels, normals.texels);
    }
    const GltfModel jpegModel = loadGltf(data + "panel-jpeg.glb", where);
    const Texture jpeg = loadTexture(EncodedImage{"panel-jpeg.glb image 0", jpegModel.materials.at(0).baseColorTexture->embedded},
                                     TextureRole::Reflectance, TextureEncoding::Srgb, 1.0, where);
    ASSERT_EQ(jpeg.texels.size(), colour.texels.size());
    double sum = 0;
    for (size_t i = 0; i < jpeg.texels.size(); ++i) sum += std::fabs(jpeg.texels[i] - colour.texels[i]);
    const double mean = sum / double(jpeg.texels.size());
    std::printf("  JPEG base colour against the PNG: mean |difference| %.4f (linear reflectance)\n", mean);
    EXPECT_GT(mean, 0.0);
    EXPECT_LT(mean, 0.03);  // quality 95 with chroma subsampling, sharp grout lines
    // A sampler that clamps or mirrors, and a texture transform, are said to be ignored.
    {
        CaptureWarnings warnings;
        std::ifstream in(data + "panel-datauri.gltf");
        std::string text((std::istreambuf_iterator<char>(in)), {});
        const std::string marker = "\"textures\": [";
        ASSERT_NE(text.find(marker), std::string::npos);
        text.replace(text.find(marker), marker.size(), "\"samplers\": [{\"wrapS\": 33071}], " + marker + "{\"source\": 0, \"sampler\": 0}, ");
        const std::string normal = "\"normalTexture\": {";
        ASSERT_NE(text.find(normal), std::string::npos);
        text.insert(text.find(normal) + normal.size(), "\"extensions\": {\"KHR_texture_transform\": {\"scale\": [2, 2]}}, ");
        const auto dir = std::filesystem::temp_directory_path() / ("metamer-wrap-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        std::ofstream(dir / "clamped.gltf") << text;
        const GltfModel clamped = loadGltf(dir / "clamped.gltf", where);
        std::filesystem::remove_all(dir);
        EXPECT_TRUE(clamped.materials.at(0).baseColorTexture);
        EXPECT_TRUE(CaptureWarnings::any("asks for clamp-to-edge wrapping; textures repeat"))
            << ::testing::PrintToString(CaptureWarnings::lines());
        EXPECT_TRUE(CaptureWarnings::any("normalTexture has a KHR_texture_transform, which is not applied"))
            << ::testing::PrintToString(CaptureWarnings::lines());
    }
    // Bytes that are neither PNG nor JPEG are an input error naming the image.
    const std::vector<unsigned char> text = {'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'};
    try {
        loadTexture(EncodedImage{"x.glb image 3", text}, TextureRole::Reflectance, TextureEncoding::Srgb, 1.0, where);
        ADD_FAILURE() << "text accepted as an image";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'x.glb image 3' is neither a PNG nor a JPEG"), std::string::npos) << e.what();
    }
}

// The bundled scene: a spectral EXR texture, an sRGB texture and a normal map from a glTF file's
// own materials, a bump map — loaded as a user would, converted as docs/scene-format.md says,
// and rendered alike by the GPU and the reference.
TEST(Textures, BundledTexturedSceneLoadsGltfMaterialsAndMatchesTheReference) {
    Scene s = loadScene(std::string(METAMER_SOURCE_DIR) + "/scenes/textured.json", SpectrumLibrary(),
                        {"camera.width=128", "camera.height=96"});
    const Material* tiles = nullptr;
    const Material* brass = nullptr;
    for (const Material& m : s.materials) {
        if (m.name == "tiles") tiles = &m;
        if (m.name == "brass") brass = &m;
    }
    ASSERT_TRUE(tiles && brass) << "the glTF file's materials become scene materials by name";
    EXPECT_GE(tiles->textures.diffuse, 0);
    EXPECT_GE(tiles->textures.normal, 0);
    EXPECT_EQ(s.textures[size_t(tiles->textures.diffuse)].kind, Texture::Kind::Rgb);
    EXPECT_NEAR(tiles->gloss, glossFromRoughness(0.6), 1e-9);
    // Metallic brass: no diffuse, specular F0 = its base colour (up-sampled: reflects more red than blue).
    ASSERT_TRUE(brass->diffuse.spectrum.isConstant());
    EXPECT_EQ(*brass->diffuse.spectrum.constant, 0.0);
    EXPECT_GT(brass->specular.spectrum.at(650), brass->specular.spectrum.at(450) + 0.2);
    EXPECT_NEAR(brass->gloss, 2.0 / std::pow(0.49, 2) - 2.0, 1e-9);  // α = 0.7², N = 2/α² − 2

    uint32_t before = gpu().validationErrors();
    SceneOnGrid g = onGrid(s);
    SpectralPass pass(gpu(), s, g);
    SpectralCube cube = pass.render();
    ReferenceImage ref = renderReference(s, g);
    EXPECT_NO_VALIDATION_ERRORS(before);
    double peak = 0;
    for (float v : ref.cube.data) peak = std::max(peak, double(v));
    InteriorComparison c = compareInterior(cube, ref);
    const double worst = c.maxAbsolute / peak;
    const int interior = c.pixels;
    std::printf("  %d interior pixels, largest difference %.3g of the peak radiance\n", interior, worst);
    EXPECT_GE(interior, 4000);
    // The textures here have sharp edges (tile grout, patch borders): a texture coordinate that
    // the rasterizer interpolates in float lands a few 1e-7 of a texel away from the reference's,
    // which at an edge between texels of very different value moves the result by that fraction
    // of the step. Hence a bound relative to the peak rather than per pixel (measured: 1.2e-5).
    EXPECT_LE(worst, 1e-4);
}
