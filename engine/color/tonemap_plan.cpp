#include "color/tonemap.h"

#include "color/astm_e308.h"
#include "color/cie_xyz.h"
#include "color/lab.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

double luminanceOf(const std::vector<double>& bands, const ColorMatchingFunctions& cmf) {
    double y = 0.0;
    for (size_t b = 0; b < bands.size(); ++b) y += bands[b] * cmf.y[b] * cmf.grid.step_nm;
    return y;
}

glm::dvec3 firstThreeResponses(const Detector& d, const std::vector<double>& radiance) {
    glm::dvec3 r(0.0);
    for (int c = 0; c < 3 && c < int(d.weights.size()); ++c)
        for (size_t b = 0; b < radiance.size(); ++b) r[c] += d.weights[c][b] * radiance[b];
    return r;
}

}  // namespace

ReferenceWhite referenceWhite(const Scene& scene, const SceneOnGrid& spectra, const SpectrumLibrary& library) {
    ColorMatchingFunctions cmf = loadCie1931(library, spectra.grid);
    ReferenceWhite w;
    double best = -1.0;
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        if (light.type == Light::Type::Ambient) continue;
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
    if (best <= 0.0) {
        // Only ambient light (or none that the observer sees): white is what the ambient gives.
        w.irradiance.assign(spectra.grid.bands(), 0.0);
        w.terms.clear();
        for (size_t l = 0; l < scene.lights.size(); ++l)
            if (scene.lights[l].type == Light::Type::Ambient) {
                for (size_t b = 0; b < w.irradiance.size(); ++b) w.irradiance[b] += spectra.lights[l][b];
                w.terms.emplace_back(scene.lights[l].spectrum.spectrum, scene.lights[l].scale);
            }
        w.source = "the ambient light";
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

TonemapPlan makeTonemapPlan(const TonemapSettings& settings, const Scene& scene, const SceneOnGrid& spectra,
                            const SpectrumLibrary& library, const Representation* representation) {
    TonemapPlan p;
    p.settings = settings;
    p.grid = spectra.grid;
    p.display = parseDisplay(settings.display, settings.bits, Where{"", "--display"});
    p.white = referenceWhite(scene, spectra, library);
    if (representation && !representation->mode.spectral()) {
        const Representation& r = *representation;
        if (settings.detector != "cie1931")
            failInput(Where{"", "--detector"}, "the {} mode keeps no spectra: only the CIE 1931 observer can see it, "
                      "not {}", r.mode.name(), settings.detector);
        if (settings.integration == Integration::AstmE308)
            failInput(Where{"", "--integration"}, "the {} mode keeps no spectra to weight: ASTM E308 needs a spectral "
                      "mode (full or linear:K)", r.mode.name());
        p.representation = r.mode.name();
        p.grid = r.renderGrid();
        p.white.irradiance = lightChannels(r, p.white.irradiance);
        p.white.radiance = lightChannels(r, p.white.radiance);
        p.detector.name = "cie1931";
        p.detector.kind = DetectorKind::Observer;
        p.detector.channels = {"X", "Y", "Z"};
        p.detector.weights = r.toXyz;
        p.detector.units = "W·sr⁻¹·m⁻² (radiometric CIE 1931 tristimulus, no 683), via the " + r.mode.name() + " mode";
        p.detector.source = r.description;
        p.detector.grid = p.grid;
    } else {
        const bool astm = settings.integration == Integration::AstmE308;
        p.detector = makeDetector(settings.detector, library, spectra.grid, astm ? Integration::Riemann : settings.integration,
                                  Where{"", "--detector"});
        if (astm) applyAstmE308(p.detector, library, p.white, Where{"", "--integration"});
        if (representation && representation->mode.kind == ModeKind::Linear) {
            // Peercy's pixels are projections onto the basis, and a detector is linear: responses of
            // the projected radiance are those of projected weights, so the GPU pass can read the
            // unprojected target. The white is white under the projected light.
            p.representation = representation->mode.name();
            for (auto& w : p.detector.weights) w = project(*representation, w);
            p.white.irradiance = lightChannels(*representation, p.white.irradiance);
            p.white.radiance = lightChannels(*representation, p.white.radiance);
        }
    }

    glm::dvec3 rawWhite = firstThreeResponses(p.detector, p.white.radiance);
    switch (p.detector.kind) {
        case DetectorKind::Observer:
            if (!(rawWhite.y > 0.0))
                failInput(Where{"", "--detector"}, "the reference white {} has no luminance for {}", p.white.source,
                          p.detector.name);
            p.responseToXyz = glm::dmat3(1.0 / rawWhite.y);
            break;
        case DetectorKind::Camera: {
            p.camera = characterizeCamera(p.detector, p.white.irradiance, library, spectra.grid, settings.integration);
            glm::dmat3 balance(0.0);
            for (int c = 0; c < 3; ++c) {
                if (!(rawWhite[c] > 0.0))
                    failInput(Where{"", "--detector"}, "camera {} channel {} sees nothing of the reference white {}",
                              p.detector.name, p.detector.channels[c], p.white.source);
                balance[c][c] = 1.0 / rawWhite[c];
            }
            p.responseToXyz = p.camera->rawToXyz * balance;
            break;
        }
        case DetectorKind::Film:
            p.film = makeFilm(p.detector.name.substr(p.detector.name.find(':') + 1), library, spectra.grid,
                              settings.integration, p.white.radiance);
            if (representation && representation->mode.kind == ModeKind::Linear)
                for (auto& w : p.film->layers.weights) w = project(*representation, w);
            p.mode = TonemapMode::Film;
            break;
        case DetectorKind::Custom: p.mode = TonemapMode::ResponsesOnly; break;
    }

    if (p.mode == TonemapMode::Linear) {
        p.sourceWhiteXyz = p.responseToXyz * rawWhite;
    } else if (p.mode == TonemapMode::Film) {
        // The viewer adapts to the projected clear film (the brightest white on the screen).
        const FilmModel& f = *p.film;
        glm::dvec3 clear(0.0);
        for (size_t b = 0; b < f.baseDensity.size(); ++b) {
            double density = f.baseDensity[b];
            for (int i = 0; i < 3; ++i) density += f.curves[i].dMin * f.dyeDensity[i][b];
            double t = std::pow(10.0, -density);
            for (int c = 0; c < 3; ++c) clear[c] += f.projection[c][b] * t;
        }
        p.sourceWhiteXyz = clear / f.projectedWhiteY;
    }
    if (p.mode != TonemapMode::ResponsesOnly) {
        glm::dvec3 src = p.sourceWhiteXyz / p.sourceWhiteXyz.y;
        p.adaptation = adaptationMatrix(settings.adaptation, src, p.display.whiteXyz / p.display.whiteXyz.y);
    }

    if (settings.absolute) {
        if (p.detector.name != "cie1931")
            failInput(Where{"", "--absolute"}, "absolute XYZ (cd/m²) is defined for the CIE 1931 observer only, not {}",
                      p.detector.name);
        p.xyzOutputScale = 683.0 * rawWhite.y;
        p.xyzUnits = "absolute, cd/m² (683 lm/W × CIE 1931 Y)";
    } else {
        p.xyzOutputScale = 100.0;
        p.xyzUnits = fmt::format("relative: a perfect white diffuser under {} has Y = 100", p.white.source);
    }
    p.description = fmt::format("{}detector {} ({} integration), white {}, adaptation {}, display {} {}-bit",
                                p.representation == "full" ? "" : "mode " + p.representation + ", ", p.detector.name,
                                integrationName(settings.integration),
                                p.white.source, adaptationName(settings.adaptation), p.display.name, p.display.bits);
    return p;
}

glm::dvec3 relativeXyz(const TonemapPlan& plan, const float* radiance, double* responses) {
    const auto& w = plan.detector.weights;
    size_t bands = plan.grid.bands();
    for (size_t c = 0; c < w.size(); ++c) {
        double r = 0.0;
        for (size_t b = 0; b < bands; ++b) r += w[c][b] * radiance[b];
        responses[c] = r;
    }
    switch (plan.mode) {
        case TonemapMode::Linear: return plan.responseToXyz * glm::dvec3(responses[0], responses[1], responses[2]);
        case TonemapMode::Film: {
            std::vector<double> l(radiance, radiance + bands);
            return filmXyz(*plan.film, l.data());
        }
        case TonemapMode::ResponsesOnly: break;
    }
    return glm::dvec3(0.0);
}

}  // namespace metamer
