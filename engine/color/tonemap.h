// The display path as plain data: what the tonemap pass (GPU, render/tonemap_pass) and its CPU
// reference (color/tonemap_reference) both evaluate, per pixel:
//
//   spectral radiance L(λ) ─ detector weights ─► responses r (K channels)
//     ─► relative XYZ (reference white Y = 1): linear (observer, camera: 3×3) or film (nonlinear)
//     ─► chromatic adaptation (3×3, scene white → display white)
//     ─► display model (XYZ → RGB → clip → inverse transfer) ─► digital counts
//
// Everything view-independent — detector weights, camera characterization, film tables, the
// exposure that puts the reference white at Y = 1, the adaptation matrix — is decided here, once,
// in double precision. docs/color.md describes each step. The plan knows no scene: it is made from
// a grid, a reference white (scene/scene_white.h picks a scene's), the detector and display
// choices and, for reduced representations, what the cube's channels are (DisplayChannels,
// made by represent/representation.h). Tests: tests/tonemap_test.cpp.
#pragma once

#include "color/adaptation.h"
#include "color/camera_characterization.h"
#include "color/detector.h"
#include "color/display_model.h"
#include "color/film.h"
#include "color/reference_white.h"
#include "spectral/cube.h"
#include "spectral/library.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace metamer {

// What the user chose (flags or the scene's "output" block).
struct TonemapSettings {
    std::string detector = "cie1931";
    Integration integration = Integration::Riemann;
    Adaptation adaptation = Adaptation::Bradford;
    std::string display = "srgb";
    int bits = 8;
    bool absolute = false;  // XYZ output in cd/m² (683 lm/W) instead of relative (white Y = 100)
};

// What the channels of the cube the display path reads are, when they are not simply the grid's
// bands (docs/representations.md).
struct DisplayChannels {
    enum class Kind {
        Bands,      // full: the grid's bands
        Projected,  // linear:K: the grid's bands, the pixels being projections onto `basis`
        Reduced,    // rgb, ac1c2: C channels that are not wavelengths
    };
    Kind kind = Kind::Bands;
    std::string mode = "full";  // the representation mode's name, for descriptions
    // Projected: an orthonormal basis on the grid (Σ_b e_i·e_j·Δλ = δij), [K][band]. Detectors are
    // linear, so their weights and the white are projected onto it.
    std::vector<std::vector<double>> basis;
    // Reduced: a light's channels from its bands, [C][band]; channel radiance → radiometric CIE
    // 1931 XYZ, [3][C]; what the mode is, for the detector's source.
    std::vector<std::vector<double>> lightAnalysis, toXyz;
    std::string description;

    // A band spectrum as the cube's channels see it: itself, its projection, or its C channels.
    std::vector<double> of(const std::vector<double>& bands, double step_nm) const;
};

enum class TonemapMode {
    Linear,         // XYZ = responseToXyz · r (observers, cameras)
    Film,           // XYZ = filmXyz(r)
    ResponsesOnly,  // a custom detector: no colorimetric path, only the responses are output
};

struct TonemapPlan {
    TonemapSettings settings;
    Grid grid;                // the cube's grid (channel indices 0..C−1 for reduced modes)
    std::string representation = "full";  // the representation mode (represent/representation.h)
    Detector detector;        // weights [channel][band]
    TonemapMode mode = TonemapMode::Linear;
    ReferenceWhite white;
    glm::dmat3 responseToXyz{1.0};  // Linear: responses → relative XYZ (white Y = 1)
    std::optional<FilmModel> film;  // Film
    glm::dvec3 sourceWhiteXyz{0.0}; // relative XYZ of the reference white as the detector sees it
    glm::dmat3 adaptation{1.0};     // relative XYZ → relative XYZ under the display white
    DisplayModel display;
    // Relative XYZ (white Y = 1) × xyzOutputScale = the XYZ written to the XYZ EXR: 100 (relative
    // colorimetry) or 683·Y_white in cd/m² (absolute; observers only).
    double xyzOutputScale = 100.0;
    std::string xyzUnits;           // "relative (reference white Y = 100)" or "cd/m²"
    std::string description;        // one line for logs and file metadata
    std::optional<CameraCharacterization> camera;
};

// `grid` is the spectral grid and `white` is on it. With `channels` of a reduced mode (rgb, ac1c2)
// the plan works on that mode's channels: the detector is the mode's channel → CIE 1931 XYZ map
// (the only observer such a mode can serve) and the reference white is expressed in channels; the
// cube the plan is applied to must be in those channels. With Projected channels the detector's
// weights and the white are projected onto the basis.
TonemapPlan makeTonemapPlan(const TonemapSettings& settings, const Grid& grid, const ReferenceWhite& white,
                            const SpectrumLibrary& library, const DisplayChannels& channels = {});

// What the display path produces, per pixel, row 0 at the top.
struct DisplayImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> responses;  // channels per pixel, detector units
    std::vector<float> xyz;        // 3 per pixel, scaled by xyzOutputScale (empty in ResponsesOnly)
    std::vector<uint16_t> counts;  // 3 per pixel, 0 .. 2^bits − 1 (empty in ResponsesOnly)
    size_t clippedPixels = 0;      // pixels whose linear display RGB left [0, 1]
    std::vector<uint8_t> clipped;  // per pixel, 1 where clipped (empty in ResponsesOnly)
};

// The CPU reference of the tonemap pass, in double precision, on a cube already filtered to
// pixels.
DisplayImage tonemapReference(const TonemapPlan& plan, const SpectralCube& cube);

// The per-pixel chain, exposed for tests: relative XYZ (white Y = 1) of one spectrum, before
// adaptation; responses are written to `responses` (plan.detector.channels.size() values).
glm::dvec3 relativeXyz(const TonemapPlan& plan, const float* radiance, double* responses);

}  // namespace metamer
