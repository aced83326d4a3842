// Colorimetric characterization of a camera: the white balance and the 3×3 matrix that take its
// raw RGB to CIE 1931 XYZ, fitted on the 24 ColorChecker patches under the scene's reference
// white, as a camera maker's (or a colour scientist's) linear characterization does. A camera is
// not colorimetric (its sensitivities are not a linear mix of the CMFs), so the fit leaves errors;
// those errors are the camera's "view" of the scene that Johnson & Fairchild's Figure 5 shows.
// docs/color.md, "Detectors".
#pragma once

#include "color/detector.h"
#include "spectral/library.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace metamer {

enum class CameraFit {
    // minimize Σ‖M·b_p − XYZ_p‖² subject to M·(1,1,1) = XYZ_white: the white (and every grey the
    // camera sees as neutral) maps exactly to the white point. The default.
    WhitePreserving,
    // plain linear least squares over the 24 patches, no constraint (a slightly lower rms error,
    // but the white lands off the white point by the residual).
    LeastSquares,
};

struct CameraCharacterization {
    glm::dvec3 whiteBalance{1.0};  // gains g_c = 1 / raw_c(reference white): the white's balanced raw is (1,1,1)
    glm::dmat3 rawToXyz{1.0};      // balanced raw → XYZ (relative: the reference white has Y = 1)
    glm::dvec3 whiteXyz{0.0};      // CIE 1931 XYZ of the reference white (a perfect diffuser), Y = 1
    CameraFit fit = CameraFit::WhitePreserving;
    double rmsDeltaE2000 = 0.0;    // over the 24 patches, CIELAB relative to whiteXyz
    double maxDeltaE2000 = 0.0;
    std::vector<double> patchDeltaE2000;  // per patch, in colorCheckerPatchNames() order
    std::vector<glm::dvec3> patchBalancedRaw;  // b_p: each patch's white-balanced raw (the white's is 1, 1, 1)
    std::vector<glm::dvec3> patchXyz;          // its CIE 1931 XYZ under the reference white (the white's Y = 1)
};

// The 24 ColorChecker Classic patches in chart order (row by row from dark skin to black), as
// library names without the folder ("dark_skin" ... "black_2"; spectra/colorchecker/).
const std::vector<std::string>& colorCheckerPatchNames();

// Characterizes `camera` (3 channels, on `grid`) for a scene whose reference white is the
// illuminant `illuminantOnGrid` (spectral power per band; its scale does not matter). The patch
// reflectances come from the library's colorchecker/ folder, resampled onto `grid`; the
// colorimetry is CIE 1931 with the same `integration`. Input errors: a camera channel that sees
// nothing of the illuminant, an illuminant with no visible power.
CameraCharacterization characterizeCamera(const Detector& camera, const std::vector<double>& illuminantOnGrid,
                                          const SpectrumLibrary& library, const Grid& grid,
                                          Integration integration, CameraFit fit = CameraFit::WhitePreserving);

// Balanced raw → relative XYZ: rawToXyz · (whiteBalance ∘ raw).
glm::dvec3 cameraRawToXyz(const CameraCharacterization& c, const glm::dvec3& raw);

// The whole linear map raw → relative XYZ, rawToXyz · diag(whiteBalance), for a GPU matrix.
glm::dmat3 cameraResponseToXyz(const CameraCharacterization& c);

}  // namespace metamer
