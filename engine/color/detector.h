// Detectors: what turns a spectral radiance into a few channel responses. A human observer (the
// CIE colour-matching functions), a digital camera (its RGB sensitivities), the three layers of a
// colour film, or any sensitivity table the user supplies. Johnson & Fairchild (1999, Figure 5)
// render one scene as seen by a human, a camera and a slide film; this is the first step of each.
//
// A detector is linear in the radiance: response_c = Σ_b weights[c][b] · L_b, where the weights
// already hold the sensitivity resampled onto the grid times the quadrature weight of each band.
// Everything after that (white balance, characterization, film tone scale) lives elsewhere
// (camera_characterization.h, film.h); which detector a name means, color/detector_registry.h.
// docs/color.md, "Detectors".
#pragma once

#include "core/error.h"
#include "spectral/grid.h"
#include "spectral/library.h"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace metamer {

// How a band sum approximates ∫ s(λ) L(λ) dλ (docs/color.md, "Integration").
//   Riemann:   Σ s(λb) L_b Δλ, the sensitivities sampled at the band centres from their tables:
//              CIE 15:2004's summation, what colour-science's sd_to_XYZ(method="Integration")
//              computes on the same grid. The default.
//   Trapezoid: the same with the first and last band weighted Δλ/2: the band values integrated as
//              point samples from the first centre to the last (exact for a linear integrand).
//   AstmE308:  ASTM E308-15 tristimulus weighting factors (computed per ASTM E2022-11, as
//              colour-science's sd_to_XYZ(method="ASTM E308")) for the CIE observers, applied to
//              the radiance as a reflectance factor under the reference white (color/astm_e308.h).
//              Made by makeTonemapPlan, which knows the white; makeDetector refuses it.
// A one-band grid has weight Δλ (there is no interval between centres to integrate).
enum class Integration { Riemann, Trapezoid, AstmE308 };

// "riemann" / "trapezoid" / "astm-e308"; anything else is an input error at `where`.
Integration parseIntegration(const std::string& name, const Where& where);
const char* integrationName(Integration integration);

// The quadrature weight of each band, in nm.
std::vector<double> quadratureWeights(const Grid& grid, Integration integration);

enum class DetectorKind { Observer, Camera, Film, Custom };

struct Detector {
    std::string name;                          // the spec it was made from: "cie1931", "camera:nikon_d5100", ...
    DetectorKind kind = DetectorKind::Custom;
    std::vector<std::string> channels;         // "X","Y","Z" / "R","G","B" / "blue","green","red" / CSV header
    std::vector<std::vector<double>> weights;  // [channel][band]: sensitivity(band) × quadrature weight (nm)
    std::string units;                         // of a response, for logs and file metadata
    std::string source;                        // where the sensitivities came from (file or library name)
    Grid grid;                                 // the grid the weights are on
    Integration integration = Integration::Riemann;
};

// A CIE observer as a detector (X, Y, Z; zero outside its data): `libraryName` is its table in
// the library ("observers/cie1931_2deg"), `spec` the name it goes by ("cie1931"). The detectors
// a user names are made by color/detector_registry.h; this is the one the display path itself
// needs (film projection, camera characterization, quick looks).
Detector observerDetector(const std::string& spec, const std::string& libraryName, const SpectrumLibrary& library,
                          const Grid& grid, Integration integration);

// response_c = Σ_b weights[c][b] · bands[b], for `bands` on detector.grid (grid.bands() values).
std::vector<double> detectorResponse(const Detector& detector, const double* bands);
// The same for a 3-channel detector (a runtime error otherwise), from double or float radiance.
glm::dvec3 detectorResponse3(const Detector& detector, const double* bands);
glm::dvec3 detectorResponse3(const Detector& detector, const float* bands);

}  // namespace metamer
