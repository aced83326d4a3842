#include "scene/scene_white.h"

#include "color/cie_xyz.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

double luminanceOf(const std::vector<double>& bands, const ColorMatchingFunctions& cmf) {
    double y = 0.0;
    for (size_t b = 0; b < bands.size(); ++b) y += bands[b] * cmf.y[b] * cmf.grid.step_nm;
    return y;
}

}  // namespace

ReferenceWhite referenceWhite(const Scene& scene, const SceneOnGrid& spectra, const SpectrumLibrary& library) {
    ColorMatchingFunctions cmf = loadCie1931(library, spectra.grid);
    ReferenceWhite w;
    double best = -1.0;
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        if (light.type == Light::Type::Ambient || light.type == Light::Type::Hemisphere) continue;
        std::vector<double> e = spectra.lights[l];
        std::string how = "at normal incidence";
        if (light.type == Light::Type::Point) {
            double d2 = glm::dot(light.position - scene.camera.target, light.position - scene.camera.target);
            if (d2 <= 0.0) continue;
            for (double& v : e) v /= d2;
            how = fmt::format("at the camera target, {:.3g} m away", std::sqrt(d2));
        }
        double y = luminanceOf(e, cmf);
        if (y > best) {
            best = y;
            w.irradiance = e;
            double factor = light.scale;
            if (light.type == Light::Type::Point)
                factor /= glm::dot(light.position - scene.camera.target, light.position - scene.camera.target);
            w.terms = {{light.spectrum.spectrum, factor}};
            w.source = fmt::format("lights.{} ({}, {})", l, light.spectrum.spectrum.source, how);
        }
    }
    // A self-luminous surface is a light too: L_e·Σ A·cos θ/d² over its triangles facing the camera
    // target (each a small source seen at normal incidence).
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& material = scene.materials[m];
        if (!material.emitter) continue;
        double factor = 0.0, nearest = INFINITY;
        for (const Mesh& mesh : scene.meshes) {
            if (mesh.material != m) continue;
            for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
                const glm::dvec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                                 c = mesh.positions[mesh.indices[t + 2]];
                const glm::dvec3 areaNormal = 0.5 * glm::cross(b - a, c - a);  // area × the front's normal
                const glm::dvec3 toTarget = scene.camera.target - (a + b + c) / 3.0;
                const double d2 = glm::dot(toTarget, toTarget);
                if (!(d2 > 0.0)) continue;
                factor += std::max(0.0, glm::dot(areaNormal, toTarget)) / (d2 * std::sqrt(d2));
                nearest = std::min(nearest, std::sqrt(d2));
            }
        }
        const std::vector<double>& radiance = spectra.materials[m].emitted;
        std::vector<double> e(radiance.size());
        for (size_t b = 0; b < e.size(); ++b) e[b] = radiance[b] * factor;
        const double y = luminanceOf(e, cmf);
        if (y > best) {
            best = y;
            w.irradiance = e;
            w.terms = {{material.emitter->spectrum.spectrum, material.emitter->scale * factor}};
            w.source = fmt::format("materials.{} (its emitted radiance {}, at the camera target, {:.3g} m away)",
                                   material.name, material.emitter->spectrum.spectrum.source, nearest);
        }
    }
    if (best <= 0.0) {
        // Only ambient and hemisphere light (or none that the observer sees): white is what they
        // give a surface facing each hemisphere's middle (irradiance π·L).
        w.irradiance.assign(spectra.grid.bands(), 0.0);
        w.terms.clear();
        for (size_t l = 0; l < scene.lights.size(); ++l) {
            const Light& light = scene.lights[l];
            const double f = light.type == Light::Type::Ambient ? 1.0 : light.type == Light::Type::Hemisphere ? M_PI : 0.0;
            if (f == 0.0) continue;
            for (size_t b = 0; b < w.irradiance.size(); ++b) w.irradiance[b] += f * spectra.lights[l][b];
            w.terms.emplace_back(light.spectrum.spectrum, f * light.scale);
        }
        w.source = "the ambient and hemisphere lights";
        if (luminanceOf(w.irradiance, cmf) <= 0.0) {
            w.irradiance.assign(spectra.grid.bands(), 1.0);
            w.terms = {{Spectrum::makeConstant(1.0), 1.0}};
            w.source = "equal-energy white (the scene has no visible light)";
            warn(Where{scene.file.string(), "lights"},
                 "no light the CIE 1931 observer can see; exposure and adaptation use an equal-energy white");
        }
    }
    w.radiance = w.irradiance;
    for (double& v : w.radiance) v /= M_PI;
    return w;
}

}  // namespace metamer
