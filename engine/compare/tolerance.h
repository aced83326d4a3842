// The gate of a regression test: which statistics of compare/compare.h may reach how far. A
// tolerance file is a flat JSON object; every criterion is optional (absent = not checked), and
// `description` says why the numbers are what they are. docs/compare.md, "Tolerance files".
#pragma once

#include "compare/compare.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

struct Tolerance {
    // Upper limits (inclusive) on CompareStats; JSON keys max_abs, max_rel, rmse_relative,
    // spectral_angle_max_deg, fraction_over_threshold, delta_e2000_p95, delta_e2000_max.
    std::optional<double> maxAbs, maxRel, rmseRelative, spectralAngleMaxDeg, fractionOverThreshold, deltaE2000P95,
        deltaE2000Max;
    // Settings of the comparison itself (CompareOptions); keys pixel_threshold, relative_floor.
    std::optional<double> pixelThreshold, relativeFloor;
    std::string description;  // free text: why these numbers
    std::string source;       // the file it was read from, for reports

    bool wantsDeltaE() const { return deltaE2000P95.has_value() || deltaE2000Max.has_value(); }
};

// Reads a tolerance file. Input errors (exit 2) name the file, the key and its line: JSON syntax,
// a top level that is not an object, an unknown key (with a did-you-mean), a duplicate key, a value
// that is not a number (description: not a string), a negative or non-finite number.
Tolerance readTolerance(const std::filesystem::path& path);

// The tolerance's pixel_threshold and relative_floor, where set, override `options`.
void applyTolerance(const Tolerance& tolerance, CompareOptions& options);

struct Verdict {
    bool pass = true;
    std::vector<std::string> failures;  // one per failed criterion: "rmse_relative 2.1e-03 > 1e-03"
};

// Checks every criterion the tolerance sets. A ΔE2000 criterion without ΔE2000 statistics fails
// (it could not be checked), and so do values that are NaN or infinite in one image only: no
// finite limit can be said to hold for them.
Verdict judge(const CompareStats& stats, const Tolerance& tolerance);

// What a caller asks of a comparison, as `metamer compare`'s flags (and metamer.compare's
// arguments) say it. Empty strings and unset numbers: the tolerance file's, else the defaults.
struct CompareRequest {
    std::optional<double> pixelThreshold, relativeFloor;
    bool resample = false;
    std::string detector, adapt, display;  // ΔE2000 through these (each: the default when empty)
    bool noDeltaE = false;
};

// The options of a comparison against the reference `b`: the tolerance's settings, then the
// request's. ΔE2000 is computed where asked (a detector, adaptation or display named, a ΔE limit
// in the tolerance) and by default where B is a cube with visible bands and the library has the
// CIE 1931 observer. The mask is the caller's (readMask).
CompareOptions makeCompareOptions(const CompareRequest& request, const ImageData& b, const Tolerance* tolerance);

// "2.1e-03", "0.5", "0": numbers in verdicts and summaries, short and unambiguous.
std::string formatNumber(double v);

}  // namespace metamer
