#include "color/display_model.h"

#include "color/srgb.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

// The typical CRT of Brainard (1997), "The Psychophysics Toolbox", Spatial Vision 10: the
// phosphors' spectral power distributions as colour-science distributes them ("Typical CRT
// Brainard 1997", via Machado 2010), integrated with the CIE 1931 2° observer at 5 nm
// (tests/data/color/colorimetry/generate.py prints these). Chromaticity (x, y) and each primary's
// share of the white's luminance.
struct Primary {
    double x, y, luminance;
};
constexpr Primary kCrtPrimaries[3] = {
    {0.61885377, 0.34403993, 0.21619951},  // red
    {0.27649399, 0.60491706, 0.69750721},  // green
    {0.15119002, 0.06108496, 0.08629328},  // blue
};
// Black level and flare as a fraction of the white, with the white's chromaticity: a 200:1
// contrast, typical of a CRT in a dim room.
constexpr double kCrtBlackFraction = 0.005;
// GOG parameters, the same for the three channels: an illustrative well-adjusted CRT, not a fit
// to Brainard's monitor. gain + offset = 1 so that full drive gives R = 1; the negative offset
// puts the cutoff at d = 0.02/1.02, exactly count 5 of 255 and 1285 of 65535 (both are 51·k).
constexpr double kCrtGain = 1.02;
constexpr double kCrtOffset = -0.02;
constexpr double kCrtGamma = 2.4;

// The linear part of the encode rule: a channel more than this outside [0, 1] counts as clipped.
// Far above double rounding in the matrices (1e-15), far below one 16-bit count near white.
constexpr double kClipTolerance = 1e-6;

DisplayModel srgbDisplay() {
    DisplayModel d;
    d.kind = DisplayKind::Srgb;
    d.name = "srgb";
    d.rgbToXyz = glm::inverse(xyzToLinearSrgbMatrix());
    d.whiteXyz = kD65WhiteXyz;
    d.blackXyz = glm::dvec3(0.0);
    return d;
}

DisplayModel crtDisplay() {
    DisplayModel d;
    d.kind = DisplayKind::CrtGog;
    d.name = "crt";
    // Columns: each primary's XYZ at full drive, Y = its luminance share, so the three sum to a
    // white with Y = 1 (the shares are renormalized in case their rounding does not sum to 1).
    const double sum = kCrtPrimaries[0].luminance + kCrtPrimaries[1].luminance + kCrtPrimaries[2].luminance;
    glm::dmat3 phosphors;
    for (int c = 0; c < 3; ++c) {
        const Primary& p = kCrtPrimaries[c];
        const double Y = p.luminance / sum;
        phosphors[c] = glm::dvec3(Y * p.x / p.y, Y, Y * (1.0 - p.x - p.y) / p.y);
    }
    d.whiteXyz = phosphors * glm::dvec3(1.0);
    d.blackXyz = kCrtBlackFraction * d.whiteXyz;
    d.rgbToXyz = (1.0 - kCrtBlackFraction) * phosphors;
    d.gain = glm::dvec3(kCrtGain);
    d.offset = glm::dvec3(kCrtOffset);
    d.gamma = glm::dvec3(kCrtGamma);
    return d;
}

}  // namespace

DisplayModel parseDisplay(const std::string& name, int bits, const Where& where) {
    DisplayModel d;
    if (name == "srgb")
        d = srgbDisplay();
    else if (name == "crt")
        d = crtDisplay();
    else {
        std::string suggestion = closestMatch(name, {"srgb", "crt"});
        if (!suggestion.empty())
            failInput(where, "unknown display '{}'; did you mean '{}'? (choices: srgb, crt)", name, suggestion);
        failInput(where, "unknown display '{}' (choices: srgb, crt)", name);
    }
    if (bits != 8 && bits != 16) failInput(where, "display bits must be 8 or 16, not {}", bits);
    d.bits = bits;
    return d;
}

double maxCount(const DisplayModel& display) { return std::ldexp(1.0, display.bits) - 1.0; }

glm::dvec3 cutoffCounts(const DisplayModel& display) {
    if (display.kind == DisplayKind::Srgb) return glm::dvec3(0.0);
    const double n = maxCount(display);
    glm::dvec3 cutoff;
    for (int c = 0; c < 3; ++c) {
        // The cutoff in counts: gain·count/n + offset = 0. Rounded, because the encoder rounds a
        // linear 0 (and the ~1e-16 noise around it after the matrices) to round(c₀); writing every
        // count up to there as 0 keeps black at 0 whether or not c₀ is an integer.
        const double c0 = -display.offset[c] * n / display.gain[c];
        cutoff[c] = std::clamp(std::round(c0), -1.0, n);
    }
    return cutoff;
}

EncodeResult encodeXyz(const DisplayModel& display, const glm::dvec3& xyz) {
    const double n = maxCount(display);
    const glm::dvec3 cutoff = cutoffCounts(display);
    glm::dvec3 rgb = glm::inverse(display.rgbToXyz) * (xyz - display.blackXyz);
    EncodeResult result{glm::dvec3(0.0), false};
    for (int c = 0; c < 3; ++c) {
        double r = rgb[c];
        // Not finite (NaN from a broken input) counts as out of range and shows as black.
        if (!std::isfinite(r) || r < -kClipTolerance || r > 1.0 + kClipTolerance) result.clipped = true;
        r = std::isfinite(r) ? std::clamp(r, 0.0, 1.0) : 0.0;
        const double v = display.kind == DisplayKind::Srgb
                             ? srgbEncode(r)
                             : (std::pow(r, 1.0 / display.gamma[c]) - display.offset[c]) / display.gain[c];
        double count = std::clamp(std::round(v * n), 0.0, n);
        if (count <= cutoff[c]) count = 0.0;
        result.counts[c] = count;
    }
    return result;
}

glm::dvec3 linearRgbOfCounts(const DisplayModel& display, const glm::dvec3& counts) {
    const double n = maxCount(display);
    glm::dvec3 rgb;
    for (int c = 0; c < 3; ++c) {
        const double d = std::clamp(counts[c], 0.0, n) / n;
        rgb[c] = display.kind == DisplayKind::Srgb
                     ? srgbDecode(d)
                     : std::pow(std::max(display.gain[c] * d + display.offset[c], 0.0), display.gamma[c]);
    }
    return rgb;
}

glm::dvec3 decodeCounts(const DisplayModel& display, const glm::dvec3& counts) {
    return display.rgbToXyz * linearRgbOfCounts(display, counts) + display.blackXyz;
}

}  // namespace metamer
