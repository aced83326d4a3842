// A colour reversal (slide) film as a detector: exposure of three silver-halide layers, their
// characteristic curves, the dyes they leave, and the slide projected with a tungsten lamp and
// seen by the CIE 1931 observer. The bottom row of Johnson & Fairchild's Figure 5.
//
// It is a parametric MODEL, not measured data: no film maker publishes its sensitivities and dye
// densities as open data. Shapes, positions and tone-scale numbers follow published typical
// figures of E-6 slide films (spectra/README.md, "Film", cites them); the formulas are in
// docs/color.md, "Detectors".
//
//   H_i    = Σ_b layers.weights[i][b] · L_b                      exposure of layer i (blue, green, red)
//   x_i    = log10(H_i / exposureOfWhite_i)                      0 for the reference white
//   D_i    = filmCurveDensity(curves[i], x_i)                    dye amount (peak density units)
//   D(λ_b) = Σ_i D_i · dyeDensity[i][b] + baseDensity[b]         yellow, magenta, cyan + base
//   XYZ_c  = Σ_b projection[c][b] · 10^(−D(λ_b)) / projectedWhiteY
//
// Reversal film: more light, less dye. The clear film (D_i = dMin) projects to Y = 1.
#pragma once

#include "color/detector.h"
#include "spectral/library.h"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace metamer {

// The characteristic curve D(x) of one layer, x = log10(H / H_white). A straight line of slope
// −gamma through (logH0, (dMin + dMax)/2), joined to the floor dMin and the ceiling dMax by smooth
// toe and shoulder of width `toe` (density units):
//   R = dMax − dMin,   γ' = gamma / tanh(R / (4·toe)),   u = γ'·(logH0 − x) + R/2
//   D = dMin + toe · [sp(u / toe) − sp((u − R) / toe)],  sp(z) = ln(1 + e^z)
// Smooth, strictly decreasing in x, dMin < D < dMax; D(logH0) = (dMin + dMax)/2 with slope −gamma
// there exactly. x → −∞ (no light) gives dMax, x → +∞ gives dMin.
struct FilmCurve {
    double dMin = 0.0, dMax = 0.0, logH0 = 0.0, gamma = 1.0;
    double toe = 0.2;
};

// D(x); x = −∞ (zero or negative exposure) gives dMax.
double filmCurveDensity(const FilmCurve& curve, double logRelativeExposure);

struct FilmModel {
    std::string name;                             // "reversal"
    Detector layers;                              // kind Film: "blue","green","red" sensitivities × quadrature
    FilmCurve curves[3];                          // blue → yellow dye, green → magenta, red → cyan
    std::vector<std::vector<double>> dyeDensity;  // [3][band]: yellow, magenta, cyan at unit amount (peak 1)
    std::vector<double> baseDensity;              // [band]: support + stain, exposure-independent
    std::vector<std::vector<double>> projection;  // [3][band]: lamp(λ)·cmf_c(λ)·quadrature weight (CIE 1931)
    // The layer exposures the film renders as its white point (x = 0 in every layer): the
    // exposures of the balance illuminant's white, scaled so that the green layer's equals the
    // reference white's (a "metered" exposure). Under the balance illuminant these are the
    // reference white's own exposures; under another light the white's exposures differ from
    // them, and the slide shows the colour cast a real film does (films do not adapt).
    glm::dvec3 exposureOfWhite{0.0};
    double projectedWhiteY = 0.0;   // Σ projection[1]·10^(−D_clear): the clear film (dMin + base), → Y = 1
    double openGateY = 0.0;         // Σ projection[1]: the lamp with no film, on the same scale
    std::string balanceIlluminant;  // library name of the light the film is balanced for
    std::string lamp;               // library name of the projection lamp's spectrum
};

// Loads spectra/film/<name>.json and its tables onto `grid`. `referenceWhiteRadianceOnGrid` is
// the radiance of the scene's reference white (a perfect diffuser under the reference light),
// per band, which sets the exposure. Input errors (naming the file and key): unknown film, a
// malformed description, a grid on which the white exposes a layer not at all, or on which the
// projected film has no luminance (no visible bands).
FilmModel makeFilm(const std::string& name, const SpectrumLibrary& library, const Grid& grid,
                   Integration integration, const std::vector<double>& referenceWhiteRadianceOnGrid,
                   const Where& where = {});

// Only the layers' detector (what makeDetector("film:<name>") returns).
Detector makeFilmLayers(const std::string& name, const SpectrumLibrary& library, const Grid& grid,
                        Integration integration, const Where& where);

// Names of the films in the library (spectra/film/*.json), sorted.
std::vector<std::string> filmNames(const SpectrumLibrary& library);

// The steps of the chain, in double, for one radiance spectrum on the model's grid:
glm::dvec3 filmExposures(const FilmModel& film, const double* radianceBands);  // H_i
glm::dvec3 filmDensitiesFromExposures(const FilmModel& film, const glm::dvec3& exposures);  // D_i
glm::dvec3 filmXyzFromDensities(const FilmModel& film, const glm::dvec3& densities);  // relative XYZ
// The whole chain: exposures → layer densities → D(λ) → transmittance → projected XYZ
// (relative, clear film Y = 1).
glm::dvec3 filmXyz(const FilmModel& film, const double* radianceBands);

}  // namespace metamer
