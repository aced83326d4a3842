#include "color/camera_characterization.h"
#include "color/cie_xyz.h"
#include "spectral/resampling.h"

#include "color/delta_e.h"
#include "color/lab.h"

#include <glm/glm.hpp>

#include <cmath>

namespace metamer {

const std::vector<std::string>& colorCheckerPatchNames() {
    static const std::vector<std::string> names = {
        "dark_skin", "light_skin", "blue_sky",  "foliage",   "blue_flower", "bluish_green",
        "orange",    "purplish_blue", "moderate_red", "purple", "yellow_green", "orange_yellow",
        "blue",      "green",     "red",       "yellow",    "magenta",     "cyan",
        "white_9_5", "neutral_8", "neutral_6_5", "neutral_5", "neutral_3_5", "black_2"};
    return names;
}

glm::dvec3 cameraRawToXyz(const CameraCharacterization& c, const glm::dvec3& raw) {
    return c.rawToXyz * (c.whiteBalance * raw);
}

glm::dmat3 cameraResponseToXyz(const CameraCharacterization& c) {
    glm::dmat3 gains(1.0);
    for (int i = 0; i < 3; ++i) gains[i][i] = c.whiteBalance[i];
    return c.rawToXyz * gains;
}

CameraCharacterization characterizeCamera(const Detector& camera, const std::vector<double>& illuminantOnGrid,
                                          const SpectrumLibrary& library, const Grid& grid, Integration integration,
                                          CameraFit fit) {
    const size_t n = static_cast<size_t>(grid.bands());
    if (camera.weights.size() != 3)
        failInput(Where{camera.source}, "detector '{}' has {} channels; characterizing a camera needs 3 (R, G, B)",
                  camera.name, camera.weights.size());
    if (!(camera.grid == grid) || camera.weights[0].size() != n || illuminantOnGrid.size() != n)
        failRuntime("camera '{}' (grid {}) and illuminant ({} bands) are not on the grid {}", camera.name,
                    camera.grid.str(), illuminantOnGrid.size(), grid.str());
    Detector cmf = observerDetector("cie1931", kCie1931Observer, library, grid, integration);

    CameraCharacterization c;
    c.fit = fit;
    // The perfect white (ρ = 1): its raw sets the white balance, its Y the colorimetric scale.
    glm::dvec3 rawWhite = detectorResponse3(camera, illuminantOnGrid.data());
    glm::dvec3 xyzWhite = detectorResponse3(cmf, illuminantOnGrid.data());
    if (!(xyzWhite.y > 0))
        failInput(Where{camera.name}, "the reference white has no luminance (CIE 1931 Y) on the grid {}", grid.str());
    for (int i = 0; i < 3; ++i)
        if (!(rawWhite[i] > 0))
            failInput(Where{camera.name}, "camera channel {} sees nothing of the reference white on the grid {}",
                      camera.channels[i], grid.str());
    c.whiteBalance = 1.0 / rawWhite;
    c.whiteXyz = xyzWhite / xyzWhite.y;

    // Balanced raw b_p and target XYZ_p of each patch.
    const auto& names = colorCheckerPatchNames();
    std::vector<glm::dvec3> raw(names.size()), target(names.size());
    std::vector<double> lit(n);
    for (size_t p = 0; p < names.size(); ++p) {
        std::vector<double> rho = resample(library.get("colorchecker/" + names[p], Where{}), grid);
        for (size_t b = 0; b < n; ++b) lit[b] = rho[b] * illuminantOnGrid[b];
        raw[p] = c.whiteBalance * detectorResponse3(camera, lit.data());
        target[p] = detectorResponse3(cmf, lit.data()) / xyzWhite.y;
    }

    // Normal equations, one row of M at a time: A·m_i = v_i with A = Σ b bᵀ, v_i = Σ b·XYZ_p,i.
    // glm is column-major: A[col][row]; A is symmetric anyway.
    glm::dmat3 a(0.0);
    glm::dvec3 v[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
    for (size_t p = 0; p < raw.size(); ++p) {
        a += glm::outerProduct(raw[p], raw[p]);
        for (int i = 0; i < 3; ++i) v[i] += raw[p] * target[p][i];
    }
    const glm::dmat3 ai = glm::inverse(a);
    const glm::dvec3 ones(1.0);
    glm::dvec3 rows[3];
    for (int i = 0; i < 3; ++i) {
        rows[i] = ai * v[i];
        if (fit == CameraFit::WhitePreserving) {
            // Lagrange: minimize ‖…‖² with m_i·1 = white_i gives m_i = A⁻¹(v_i − μ·1),
            // μ = (1ᵀA⁻¹v_i − white_i) / (1ᵀA⁻¹1).
            double mu = (glm::dot(ones, rows[i]) - c.whiteXyz[i]) / glm::dot(ones, ai * ones);
            rows[i] = ai * (v[i] - mu * ones);
        }
    }
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) c.rawToXyz[col][row] = rows[row][col];

    double sum2 = 0.0;
    for (size_t p = 0; p < raw.size(); ++p) {
        double de = deltaE2000(xyzToLab(c.rawToXyz * raw[p], c.whiteXyz), xyzToLab(target[p], c.whiteXyz));
        c.patchDeltaE2000.push_back(de);
        c.maxDeltaE2000 = std::max(c.maxDeltaE2000, de);
        sum2 += de * de;
    }
    c.rmsDeltaE2000 = std::sqrt(sum2 / static_cast<double>(raw.size()));
    c.patchBalancedRaw = std::move(raw);
    c.patchXyz = std::move(target);
    return c;
}

}  // namespace metamer
