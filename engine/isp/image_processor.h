// The image processor after the raw (issue 48, item 2; docs/camera.md, "The image processor"): a
// Bayer raw frame to a displayable sRGB image, in the order a raw converter runs —
//   1. black level and white level: v = max(DN − black, 0) / (white − black);
//   2. white balance: gains g_c = max(n) / n_c for the camera's neutral n (its raw response to the
//      named illuminant's white, or the frame's grey world, or a patch of it), each site clipped at
//      1 after its gain (a saturated site is white, as a raw converter clips);
//   3. demosaicing (isp/demosaic);
//   4. the colour correction: balanced raw → CIE 1931 XYZ adapted to the display's white (D65 for
//      sRGB), fitted on the 24 ColorChecker patches as the camera sees them under the illuminant
//      (3 × 3 white-preserving, or root-polynomial), times the exposure;
//   5. the display model's encoding (color/display_model: sRGB, or the CRT's gain-offset-gamma),
//      as the render's display PNG is encoded.
// The DNG a capture writes carries the same numbers (ColorMatrix1 = diag(n̂_illuminant)·M⁻¹,
// AsShotNeutral = n̂), so LibRaw, which builds its camera → sRGB matrix from those two tags,
// develops the DNG to the processor's image: tests/python/test_isp.py checks it within rounding.
// The processor knows a camera as a detector (color/detector.h): the sensor builds that from its
// quantum efficiencies (sensor/sensor_colour). Tests: engine/isp/image_processor_test.cpp,
// tests/python/test_isp.py.
#pragma once

#include "color/adaptation.h"
#include "color/detector.h"
#include "color/display_model.h"
#include "isp/colour_correction.h"
#include "isp/demosaic.h"
#include "spectral/library.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace metamer {

enum class WhiteBalance {
    Illuminant,  // the camera's response to the named illuminant's white (a perfect diffuser)
    GreyWorld,   // the frame's mean per channel: the scene averages to grey
    Patch,       // the mean per channel in a rectangle of the frame that is known to be neutral
};

// "illuminant", "grey-world" or "patch"; an input error at `where` otherwise.
WhiteBalance parseWhiteBalance(const std::string& name, const Where& where);
std::string whiteBalanceName(WhiteBalance w);

// What a sensor file's "processor" section says (docs/sensor.md, "The sensor file").
struct ProcessorSpec {
    WhiteBalance whiteBalance = WhiteBalance::Illuminant;
    std::array<int, 4> patch{};  // x, y, width, height in pixels, for WhiteBalance::Patch
    // The scene's light, a library illuminant: the colour correction is fitted under it, and the
    // "illuminant" white balance is its white.
    std::string illuminant = "illuminants/D65";
    DemosaicMethod demosaic = DemosaicMethod::Malvar2004;
    CorrectionForm correction = CorrectionForm::Linear;
    Adaptation adaptation = Adaptation::Bradford;  // the illuminant's white → the display's
    double exposure = 1.0;                         // linear gain: white level × exposure → display white
    std::string display = "srgb";                  // the output's display model: "srgb" or "crt"
    int bits = 8;                                  // its counts: 8 or 16
};

// The bounds of a processor's numbers, wherever they are given (a sensor file's "processor",
// Python's keywords): a gain past 10⁴ makes every pixel white, below 10⁻⁴ black.
inline constexpr double kMinProcessorExposure = 1e-4, kMaxProcessorExposure = 1e4;
// A patch coordinate: a whole number of pixels, 0 … 65536; an input error at `where` otherwise.
int patchCoordinate(double v, const Where& where);
// The counts' bits, 8 or 16; an input error at `where` otherwise.
int displayBits(long long bits, const Where& where);

// The processor's colour for one camera under one illuminant: fitted once per capture.
struct ProcessorColour {
    glm::dvec3 illuminantNeutral{1.0};  // the camera's raw response to the illuminant's white, max 1
    DisplayModel display;               // the output's (its white is the adaptation's destination)
    ColourCorrection toXyz;             // balanced raw → XYZ adapted to the display's white (Y = 1)
    // The 3 × 3 white-preserving fit adapted to D65, whatever the display: what the DNG holds (a raw
    // converter's XYZ are D65's), equal to toXyz's for an sRGB display and the linear correction.
    glm::dmat3 linearToXyz{1.0};
    // XYZ → the camera's raw, row-major, diag(illuminantNeutral)·linearToXyz⁻¹: the D65 white maps to
    // illuminantNeutral (DNG's ColorMatrix1, with CalibrationIlluminant1 D65).
    std::array<double, 9> dngColorMatrix{};
    std::vector<double> patchDeltaE2000;  // of toXyz on the 24 patches (CIELAB of the display's white)
    double rmsDeltaE2000 = 0.0;
};

// Fits the processor's colour for `camera` (3 channels R, G, B; weights per photon or per watt, on
// `grid`) under `illuminantOnGrid`: an input error at `where` (the camera's sensitivities) when its
// channels are linearly dependent (no colour matrix exists).
ProcessorColour fitProcessorColour(const Detector& camera, const std::vector<double>& illuminantOnGrid,
                                   const Grid& grid, const SpectrumLibrary& library, const ProcessorSpec& spec,
                                   const Where& where);

// One raw frame as the sensor wrote it.
struct RawFrame {
    int width = 0, height = 0;
    const uint16_t* dn = nullptr;     // width × height digital numbers, row 0 at the top
    double black = 0.0, white = 0.0;  // the black level and the white (saturation) level, DN
    std::array<int, 4> cfa{};         // the 2 × 2 tile's colours, row by row: 0 R, 1 G, 2 B
};

struct DevelopedImage {
    int width = 0, height = 0;
    glm::dvec3 neutral{1.0};  // the white balance's neutral (max 1): the DNG's AsShotNeutral
    glm::dvec3 gains{1.0};    // max(neutral) / neutral
    // width × height × 3 CIE 1931 XYZ adapted to the display's white, times the exposure: a perfect
    // diffuser lit by the illuminant at the white level is the display's white (Y = 1) at exposure 1
    std::vector<double> xyz;
    // width × height × 3: the display's linear RGB, rgbToXyz⁻¹·(XYZ − black), not clipped (for
    // sRGB: linear sRGB, the perfect diffuser above 1, 1, 1)
    std::vector<double> linearRgb;
};

// The neutral of `frame` the white balance uses (max 1); input errors at `where` (the sensor
// file's processor) for a patch outside the frame or a channel with no signal in it.
glm::dvec3 whiteBalanceNeutral(const RawFrame& frame, const ProcessorSpec& spec, const ProcessorColour& colour,
                               const Where& where);

// Whether a frame this size can be developed: demosaicing needs 2 × 2 pixels.
bool developable(int width, int height);

// Steps 1–4 above; an input error at `where` for a frame that is not developable.
DevelopedImage develop(const RawFrame& frame, const ProcessorSpec& spec, const ProcessorColour& colour,
                       const Where& where);

// Step 5: the display model's counts (its bits) per pixel, R, G, B, as color/display_model's
// encodeXyz writes the render's display PNG.
std::vector<uint16_t> encodeCounts(const DevelopedImage& image, const DisplayModel& display);

}  // namespace metamer
