// Display models: relative XYZ (the display's white has Y = 1) ↔ the digital counts a display is
// driven with. Two kinds: sRGB (IEC 61966-2-1) and a CRT characterized by the gain–offset–gamma
// (GOG) model of Berns (1996). docs/color.md, "Display models", has every parameter, the
// out-of-gamut rule and what "clipped" means.
//
// The tonemap pass evaluates the same formulas on the GPU, so each step is one line there:
//   encode: RGB = clamp(rgbToXyz⁻¹ · (XYZ − black), 0, 1); v = transfer⁻¹(RGB);
//           counts = clamp(round(v · (2^bits − 1)), 0, 2^bits − 1); counts ≤ cutoffCounts → 0.
#pragma once

#include "core/error.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <string>

namespace metamer {

enum class DisplayKind { Srgb, CrtGog };

struct DisplayModel {
    DisplayKind kind = DisplayKind::Srgb;
    std::string name;            // "srgb", "crt"
    // Linear RGB (0..1 each) → XYZ of the light the display adds to its black. For sRGB, RGB
    // (1,1,1) is the D65 white with Y = 1. For the CRT, the phosphor matrix scaled so that
    // rgbToXyz·(1,1,1) + blackXyz = whiteXyz, i.e. full drive measures Y = 1 including the black.
    glm::dmat3 rgbToXyz{1.0};
    glm::dvec3 whiteXyz{0.0};    // XYZ shown at full drive (Y = 1): the adopted white, the adaptation destination
    glm::dvec3 blackXyz{0.0};    // XYZ shown at zero drive (black level and flare), added to every colour; 0 for sRGB
    // GOG (Berns 1996), per channel: R = ⟨gain·d + offset⟩₊^gamma, d = count / (2^bits − 1).
    // Unused for sRGB, whose transfer function is fixed by the standard.
    glm::dvec3 gain{1.0}, offset{0.0}, gamma{2.2};
    int bits = 8;                // 8 or 16
};

// "srgb" or "crt" (the typical CRT of Brainard 1997, see docs/color.md), with 8 or 16 bits per
// channel. Anything else is an input error at `where`.
DisplayModel parseDisplay(const std::string& name, int bits, const Where& where);

// The largest count, 2^bits − 1.
double maxCount(const DisplayModel& display);

// Per channel, the largest count the encoder writes as 0: round(c₀), with c₀ = −offset·(2^bits − 1)/gain
// the GOG cutoff in counts (gain·d + offset = 0). Counts up to c₀ show the black level; when c₀
// is fractional, round(c₀) may be the first count above it, whose drive is under half a count
// (light indistinguishable from black). 0 for sRGB (only count 0 is black); −1 for a channel
// whose offset is positive (no count is black, and 0 is not special).
glm::dvec3 cutoffCounts(const DisplayModel& display);

struct EncodeResult {
    glm::dvec3 counts;  // integers as doubles, 0 .. 2^bits − 1
    bool clipped;       // a linear channel was outside [0, 1] by more than 1e-6 (or not finite)
};

// Relative XYZ (display white Y = 1) → digital counts: subtract the black, linear RGB =
// rgbToXyz⁻¹ · XYZ, clip each channel to [0, 1], invert the transfer function (sRGB encoding, or
// d = (R^(1/γ) − offset)/gain), round to the nearest count, and write counts at or below the
// cutoff as 0.
EncodeResult encodeXyz(const DisplayModel& display, const glm::dvec3& xyz);

// Digital counts → the display's linear RGB: its transfer function alone (sRGB decoding, or the
// GOG function), 0 … 1. Counts are clamped to 0 .. 2^bits − 1 but not rounded.
glm::dvec3 linearRgbOfCounts(const DisplayModel& display, const glm::dvec3& counts);

// Digital counts → the XYZ the display shows: the forward model (sRGB decoding, or the GOG
// function), rgbToXyz, plus the black. Counts are clamped to 0 .. 2^bits − 1 but not rounded.
glm::dvec3 decodeCounts(const DisplayModel& display, const glm::dvec3& counts);

}  // namespace metamer
