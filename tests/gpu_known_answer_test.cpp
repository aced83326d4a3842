// Known answers through the GPU spectral pass: radiances you can write down.
#include "render/spectral_pass.h"
#include "scene/scene_on_grid.h"
#include "support/gpu.h"

#include <glm/gtc/constants.hpp>

#include <cmath>

using namespace metamer;

namespace {

SceneSpectrum constantSpectrum(double v, SpectrumKind kind) {
    return SceneSpectrum{Spectrum::makeConstant(v), kind, Where{"test", "spectrum"}};
}

SceneSpectrum gaussianLight(double peak_nm, double sigma_nm, double height) {
    Spectrum s;
    for (double w = 200; w <= 1000; w += 1.0) {
        s.wavelengths_nm.push_back(w);
        s.values.push_back(height * std::exp(-0.5 * std::pow((w - peak_nm) / sigma_nm, 2)) + 0.1 * height);
    }
    s.source = "gaussian";
    return SceneSpectrum{s, SpectrumKind::Light, Where{"test", "light"}};
}

Mesh quad(glm::dvec3 center, glm::dvec3 normal, double size, uint32_t material) {
    glm::dvec3 n = glm::normalize(normal);
    glm::dvec3 a = std::fabs(n.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    glm::dvec3 u = glm::normalize(glm::cross(a, n)), v = glm::cross(n, u);
    Mesh m;
    double h = size / 2;
    m.positions = {center - h * u - h * v, center + h * u - h * v, center + h * u + h * v, center - h * u + h * v};
    m.normals.assign(4, n);
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    m.name = "quad";
    return m;
}

Scene whiteQuadScene(glm::dvec3 quadNormal) {
    Scene s;
    s.grid = Grid{380, 780, 5};
    s.camera.projection = Camera::Projection::Orthographic;
    s.camera.position = {0, 0, 5};
    s.camera.target = {0, 0, 0};
    s.camera.height_m = 1.0;
    s.camera.width = s.camera.height = 16;
    Material white;
    white.name = "white";
    white.diffuse = constantSpectrum(1.0, SpectrumKind::Reflectance);
    white.specular = constantSpectrum(0.0, SpectrumKind::Reflectance);
    s.materials.push_back(white);
    s.meshes.push_back(quad({0, 0, 0}, quadNormal, 10.0, 0));
    return s;
}

}  // namespace

TEST(GpuKnownAnswer, WhiteLambertianQuadUnderDirectionalLightIsEOverPi) {
    uint32_t before = test::gpu().validationErrors();
    Scene s = whiteQuadScene({0, 0, 1});
    Light l;
    l.type = Light::Type::Directional;
    l.direction = {0, 0, -1};  // travelling towards the quad, which faces +z
    l.spectrum = gaussianLight(550, 40, 2.0);
    l.scale = 0.5;
    s.lights.push_back(l);
    SceneOnGrid g = resampleScene(s, s.grid);
    SpectralPass pass(test::gpu(), s, g);
    SpectralCube cube = pass.render();
    ASSERT_EQ(cube.bands(), 81);
    for (int y = 0; y < cube.height; ++y)
        for (int x = 0; x < cube.width; ++x)
            for (int b = 0; b < cube.bands(); ++b) {
                double expected = g.lights[0][b] / glm::pi<double>();
                ASSERT_NEAR(cube.at(x, y, b), expected, 1e-6 * expected) << x << "," << y << " band " << b;
            }
    EXPECT_NO_VALIDATION_ERRORS(before);
}
