#include "color/tonemap.h"
#include "color/detector_registry.h"

#include "color/astm_e308.h"
#include "color/cie_xyz.h"
#include "color/lab.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

glm::dvec3 firstThreeResponses(const Detector& d, const std::vector<double>& radiance) {
    glm::dvec3 r(0.0);
    for (int c = 0; c < 3 && c < int(d.weights.size()); ++c)
        for (size_t b = 0; b < radiance.size(); ++b) r[c] += d.weights[c][b] * radiance[b];
    return r;
}

}  // namespace

std::vector<double> DisplayChannels::of(const std::vector<double>& bands, double step_nm) const {
    switch (kind) {
        case Kind::Bands: return bands;
        case Kind::Projected: {
            std::vector<double> out(bands.size(), 0.0);
            for (const auto& e : basis) {
                double c = 0;
                for (size_t b = 0; b < bands.size(); ++b) c += e[b] * bands[b] * step_nm;
                for (size_t b = 0; b < bands.size(); ++b) out[b] += c * e[b];
            }
            return out;
        }
        case Kind::Reduced: {
            std::vector<double> out(lightAnalysis.size(), 0.0);
            for (size_t c = 0; c < lightAnalysis.size(); ++c)
                for (size_t b = 0; b < bands.size(); ++b) out[c] += lightAnalysis[c][b] * bands[b];
            return out;
        }
    }
    return bands;
}

TonemapPlan makeTonemapPlan(const TonemapSettings& settings, const Grid& grid, const ReferenceWhite& white,
                            const SpectrumLibrary& library, const DisplayChannels& channels) {
    TonemapPlan p;
    p.settings = settings;
    p.grid = grid;
    p.display = parseDisplay(settings.display, settings.bits, Where{"", "--display"});
    p.white = white;
    p.representation = channels.mode;
    const bool projected = channels.kind == DisplayChannels::Kind::Projected;
    if (channels.kind == DisplayChannels::Kind::Reduced) {
        if (settings.detector != "cie1931")
            failInput(Where{"", "--detector"}, "the {} mode keeps no spectra: only the CIE 1931 observer can see it, "
                      "not {}", channels.mode, settings.detector);
        if (settings.integration == Integration::AstmE308)
            failInput(Where{"", "--integration"}, "the {} mode keeps no spectra to weight: ASTM E308 needs a spectral "
                      "mode (full or linear:K)", channels.mode);
        const int c = channels.toXyz.empty() ? 0 : int(channels.toXyz[0].size());
        p.grid = Grid{0, double(c - 1), 1};  // the renderers' grid of channel indices
        p.white.irradiance = channels.of(white.irradiance, grid.step_nm);
        p.white.radiance = channels.of(white.radiance, grid.step_nm);
        p.detector.name = "cie1931";
        p.detector.kind = DetectorKind::Observer;
        p.detector.channels = {"X", "Y", "Z"};
        p.detector.weights = channels.toXyz;
        p.detector.units = "W·sr⁻¹·m⁻² (radiometric CIE 1931 tristimulus, no 683), via the " + channels.mode + " mode";
        p.detector.source = channels.description;
        p.detector.grid = p.grid;
    } else {
        const bool astm = settings.integration == Integration::AstmE308;
        p.detector = makeDetector(settings.detector, library, grid, astm ? Integration::Riemann : settings.integration,
                                  Where{"", "--detector"});
        if (astm) applyAstmE308(p.detector, library, p.white, Where{"", "--integration"});
        if (projected) {
            // Peercy's pixels are projections onto the basis, and a detector is linear: responses of
            // the projected radiance are those of projected weights, so the GPU pass can read the
            // unprojected target. The white is white under the projected light.
            for (auto& w : p.detector.weights) w = channels.of(w, grid.step_nm);
            p.white.irradiance = channels.of(white.irradiance, grid.step_nm);
            p.white.radiance = channels.of(white.radiance, grid.step_nm);
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
            p.camera = characterizeCamera(p.detector, p.white.irradiance, library, grid, settings.integration);
            // A fit that went NaN (a light the camera barely sees: a narrow line) is no fit.
            bool finite = std::isfinite(p.camera->rmsDeltaE2000) && std::isfinite(p.camera->maxDeltaE2000);
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) finite = finite && std::isfinite(p.camera->rawToXyz[i][j]);
            if (!finite)
                failInput(Where{"", "--detector"},
                          "camera {} cannot be characterized under the reference white {}: the ColorChecker fit is "
                          "not finite (rms ΔE2000 {}); the light has too little power where the camera's channels "
                          "see", p.detector.name, p.white.source, p.camera->rmsDeltaE2000);
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
            p.film = makeFilm(p.detector.name.substr(p.detector.name.find(':') + 1), library, grid,
                              settings.integration, p.white.radiance);
            if (projected)
                for (auto& w : p.film->layers.weights) w = channels.of(w, grid.step_nm);
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
