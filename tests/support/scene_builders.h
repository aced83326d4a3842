// Helpers to build small scenes in code for tests: spectra (constant, sampled, Gaussian),
// materials, lights, cameras, quads and spheres. Header-only; shared by the CPU reference tests
// and the GPU tests, so both render exactly the same scenes.
#pragma once

#include "scene/scene.h"
#include "scene/scene_on_grid.h"

#include <glm/glm.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace metamer::test {

// --- Spectra -----------------------------------------------------------------------------------

inline Spectrum constantSpectrum(double value) { return Spectrum::makeConstant(value); }

inline Spectrum sampledSpectrum(std::vector<double> nm, std::vector<double> values,
                                std::string source = "inline") {
    Spectrum s;
    s.wavelengths_nm = std::move(nm);
    s.values = std::move(values);
    s.source = std::move(source);
    s.validate(Where{"", s.source, 0});
    return s;
}

// peak·exp(-(λ-centre)²/(2σ²)) sampled every step_nm over [lo, hi].
inline Spectrum gaussianSpectrum(double centre_nm, double sigma_nm, double peak = 1.0,
                                 double lo_nm = 300.0, double hi_nm = 800.0, double step_nm = 1.0) {
    std::vector<double> nm, v;
    const int n = static_cast<int>(std::llround((hi_nm - lo_nm) / step_nm));
    for (int i = 0; i <= n; ++i) {
        const double l = lo_nm + i * step_nm;
        nm.push_back(l);
        v.push_back(peak * std::exp(-0.5 * (l - centre_nm) * (l - centre_nm) / (sigma_nm * sigma_nm)));
    }
    return sampledSpectrum(std::move(nm), std::move(v), "gaussian");
}

// `value` on [lo, hi] and 0 elsewhere, with edges `ramp_nm` wide (data must increase strictly).
inline Spectrum boxSpectrum(double lo_nm, double hi_nm, double value, double ramp_nm = 1e-3) {
    return sampledSpectrum({lo_nm - ramp_nm, lo_nm, hi_nm, hi_nm + ramp_nm}, {0.0, value, value, 0.0},
                           "box");
}

inline SceneSpectrum sceneSpectrum(Spectrum s, SpectrumKind kind, std::string key = "") {
    return SceneSpectrum{std::move(s), kind, Where{"", std::move(key), 0}};
}

// --- Materials ---------------------------------------------------------------------------------

inline Material lambertian(Spectrum diffuse, std::string name = "lambertian") {
    Material m;
    m.name = name;
    m.diffuse = sceneSpectrum(std::move(diffuse), SpectrumKind::Reflectance, "materials." + name + ".diffuse");
    m.specular = sceneSpectrum(constantSpectrum(0.0), SpectrumKind::Reflectance,
                               "materials." + name + ".specular");
    return m;
}

inline Material lambertian(double rho, std::string name = "lambertian") {
    return lambertian(constantSpectrum(rho), std::move(name));
}

// A Lambertian surface that also emits radiance L_e(λ) × scale from its front (scene/scene.h, Material::Emitter).
inline Material emitting(Material m, Spectrum radiance, double scale = 1.0) {
    Material::Emitter e;
    e.spectrum = sceneSpectrum(std::move(radiance), SpectrumKind::Light, "materials." + m.name + ".emitted_radiance.spectrum");
    e.scale = scale;
    e.where = Where{"test", "materials." + m.name + ".emitted_radiance"};
    m.emitter = std::move(e);
    return m;
}

// A thin sheet that transmits T(λ) per crossing and reflects nothing (scene/scene.h).
inline Material filterSheet(Spectrum transmittance, std::string name = "filter") {
    Material m = lambertian(0.0, name);
    m.transmittance = sceneSpectrum(std::move(transmittance), SpectrumKind::Transmittance, "materials." + name + ".transmittance");
    return m;
}

// A plane-parallel dielectric slab of index n, thickness d (m) and glass absorbance a(λ) per metre.
inline Material slabMaterial(RefractiveIndex n, double thickness_m, std::optional<Spectrum> absorbance = std::nullopt,
                             std::string name = "glass") {
    Material m = lambertian(0.0, name);
    Material::Slab slab;
    slab.ior = std::move(n);
    slab.iorSource = "test";
    slab.thickness_m = thickness_m;
    if (absorbance) slab.absorbance = sceneSpectrum(*absorbance, SpectrumKind::Absorbance, "materials." + name + ".slab.absorbance");
    m.slab = std::move(slab);
    return m;
}
inline RefractiveIndex constantIndex(double n) {
    RefractiveIndex r;
    r.constant = n;
    return r;
}

// An absorbing medium of decadic absorbance a(λ) per metre (to fill a closed mesh).
inline Material absorbingMedium(Spectrum absorbancePerMetre, std::string name = "medium") {
    Material m = lambertian(0.0, name);
    m.absorbance = sceneSpectrum(std::move(absorbancePerMetre), SpectrumKind::Absorbance, "materials." + name + ".absorbance");
    return m;
}

inline Material glossy(Spectrum diffuse, Spectrum specular, double gloss, std::string name = "glossy") {
    Material m = lambertian(std::move(diffuse), name);
    m.specular = sceneSpectrum(std::move(specular), SpectrumKind::Reflectance,
                               "materials." + name + ".specular");
    m.gloss = gloss;
    return m;
}

// A fluorescent material: excitation (absorptance) and emission shape, as in the scene file.
inline Material fluorescent(Spectrum diffuse, Spectrum excitation, Spectrum emission,
                            double quantumYield, std::string name = "fluorescent") {
    Material m = lambertian(std::move(diffuse), name);
    Fluorescence f;
    f.excitation = sceneSpectrum(std::move(excitation), SpectrumKind::Excitation,
                                 "materials." + name + ".fluorescence.excitation");
    f.emission = sceneSpectrum(std::move(emission), SpectrumKind::Emission,
                               "materials." + name + ".fluorescence.emission");
    f.quantum_yield = quantumYield;
    m.fluorescence = std::move(f);
    return m;
}

// A fluorescent material given by a Donaldson matrix D(λin, λout) in nm⁻¹, times `scale`, as a
// scene's "fluorescence": {"matrix": ..., "scale": ...}.
inline Material donaldsonMaterial(Spectrum diffuse, BispectralMatrix d, double scale = 1.0,
                                  std::string name = "donaldson") {
    Material m = lambertian(std::move(diffuse), name);
    Fluorescence f;
    f.matrix = SceneMatrix{std::move(d), scale, Where{"", "materials." + name + ".fluorescence.matrix", 0}};
    m.fluorescence = std::move(f);
    return m;
}

// --- Lights ------------------------------------------------------------------------------------
// spectrum × scale: ambient and directional, irradiance in W·m⁻²·nm⁻¹; point, intensity in
// W·sr⁻¹·nm⁻¹.

inline Light ambientLight(Spectrum s, double scale = 1.0, std::string name = "ambient") {
    Light l;
    l.type = Light::Type::Ambient;
    l.spectrum = sceneSpectrum(std::move(s), SpectrumKind::Light, name);
    l.scale = scale;
    l.name = std::move(name);
    return l;
}

// `travel`: the direction the light travels (towards the scene); normalized here.
inline Light directionalLight(glm::dvec3 travel, Spectrum s, double scale = 1.0,
                              std::string name = "directional") {
    Light l = ambientLight(std::move(s), scale, std::move(name));
    l.type = Light::Type::Directional;
    l.direction = glm::normalize(travel);
    return l;
}

inline Light pointLight(glm::dvec3 position, Spectrum s, double scale = 1.0,
                        std::string name = "point") {
    Light l = ambientLight(std::move(s), scale, std::move(name));
    l.type = Light::Type::Point;
    l.position = position;
    return l;
}

// A uniform hemisphere of radiance L = spectrum × scale (W·sr⁻¹·m⁻²·nm⁻¹) from every direction ω
// with ω·up > 0: a sky, or with up pointing down a ground.
inline Light hemisphereLight(glm::dvec3 up, Spectrum s, double scale = 1.0, std::string name = "hemisphere") {
    Light l = ambientLight(std::move(s), scale, std::move(name));
    l.type = Light::Type::Hemisphere;
    l.up = glm::normalize(up);
    return l;
}

// --- Cameras -----------------------------------------------------------------------------------

inline Camera orthographicCamera(glm::dvec3 position, glm::dvec3 target, glm::dvec3 up,
                                 double height_m, int width, int height) {
    Camera c;
    c.projection = Camera::Projection::Orthographic;
    c.position = position;
    c.target = target;
    c.up = up;
    c.height_m = height_m;
    c.width = width;
    c.height = height;
    return c;
}

inline Camera perspectiveCamera(glm::dvec3 position, glm::dvec3 target, glm::dvec3 up,
                                double fov_y_deg, int width, int height) {
    Camera c = orthographicCamera(position, target, up, 2.0, width, height);
    c.projection = Camera::Projection::Perspective;
    c.fov_y_deg = fov_y_deg;
    return c;
}

// --- Geometry ----------------------------------------------------------------------------------

// The default in-plane "up" of a quad with normal n: world +y, or world -z when n is (nearly)
// vertical.
inline glm::dvec3 defaultQuadUp(glm::dvec3 normal) {
    normal = glm::normalize(normal);
    return std::abs(normal.y) > 0.999 ? glm::dvec3(0, 0, -1) : glm::dvec3(0, 1, 0);
}

// A flat rectangle: `width` along r = normalize(cross(up, n)), `height` along u = cross(n, r)
// (the projection of `up` onto the plane), two triangles counter-clockwise seen from n, vertex
// normals = n. Corners, in order: centre ∓ r·w/2 ∓ u·h/2 (bottom-left, bottom-right, top-right,
// top-left as seen from the normal side with `up` up).
inline Mesh quad(glm::dvec3 centre, glm::dvec3 normal, double width, double height,
                 uint32_t material = 0, glm::dvec3 up = glm::dvec3(0.0), std::string name = "quad") {
    const glm::dvec3 n = glm::normalize(normal);
    if (up == glm::dvec3(0.0)) up = defaultQuadUp(n);
    const glm::dvec3 r = glm::normalize(glm::cross(up, n));
    const glm::dvec3 u = glm::cross(n, r);
    const glm::dvec3 hr = 0.5 * width * r, hu = 0.5 * height * u;
    Mesh m;
    m.positions = {centre - hr - hu, centre + hr - hu, centre + hr + hu, centre - hr + hu};
    m.normals.assign(4, n);
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    m.name = std::move(name);
    return m;
}

// The inside of the unit cube [0, 1]³: six unit quads facing in, all of `material` (a closed
// room: the interreflection tests' furnaces).
inline std::vector<Mesh> insideOfUnitCube(uint32_t material = 0) {
    std::vector<Mesh> walls;
    for (const glm::dvec3 n : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0),
                               glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)})
        walls.push_back(quad(glm::dvec3(0.5) - 0.5 * n, n, 1.0, 1.0, material));
    return walls;
}

// A UV sphere: `segments` around the axis (+y), `rings` from pole to pole; smooth normals.
// 2·segments·(rings − 1) triangles (e.g. 128×64 → 16 128).
inline Mesh sphere(glm::dvec3 centre, double radius, int segments, int rings, uint32_t material = 0,
                   std::string name = "sphere") {
    Mesh m;
    m.material = material;
    m.name = std::move(name);
    const double pi = std::numbers::pi;
    // Rows of vertices from the north pole (row 0) to the south pole (row `rings`), with a seam
    // column duplicated so every row has segments + 1 vertices.
    for (int j = 0; j <= rings; ++j) {
        const double theta = pi * j / rings;
        for (int i = 0; i <= segments; ++i) {
            const double phi = 2.0 * pi * i / segments;
            const glm::dvec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                               -std::sin(theta) * std::sin(phi));
            m.positions.push_back(centre + radius * n);
            m.normals.push_back(n);
        }
    }
    auto at = [segments](int j, int i) { return static_cast<uint32_t>(j * (segments + 1) + i); };
    for (int j = 0; j < rings; ++j) {
        for (int i = 0; i < segments; ++i) {
            const uint32_t a = at(j, i), b = at(j + 1, i), c = at(j + 1, i + 1), d = at(j, i + 1);
            // Counter-clockwise seen from outside; the pole rows have one degenerate half each,
            // which is dropped.
            if (j != 0) m.indices.insert(m.indices.end(), {a, b, d});
            if (j != rings - 1) m.indices.insert(m.indices.end(), {b, c, d});
        }
    }
    return m;
}

// --- Scenes ------------------------------------------------------------------------------------

inline Scene emptyScene(const Grid& grid, const Camera& camera) {
    Scene s;
    s.file = "test-scene";
    s.grid = grid;
    s.camera = camera;
    return s;
}

// The scene's spectra on its own grid, with the default coverage policy.
inline SceneOnGrid onGrid(const Scene& scene) { return resampleScene(scene, scene.grid); }

}  // namespace metamer::test
