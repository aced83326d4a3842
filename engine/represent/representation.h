// Representation modes: how a renderer holds spectra, and so what it can and cannot predict
// (Johnson & Fairchild 1999, "Methods for color calculation"; docs/representations.md).
//
//   full       sampled spectra on the grid: the truth, up to the grid
//   rgb        three numbers per light and per reflectance, multiplied channel by channel, as RGB
//              renderers do (reflectances: linear sRGB under D65 with white = 1; lights: linear
//              sRGB of their XYZ; spectra/quadrature/rgb.json)
//   ac1c2[:N]  Meyer (1988): N point samples (default 4) at wavelengths chosen by quadrature in
//              the AC1C2 opponent space, multiplied per sample, integrated to XYZ with weights
//              (spectra/quadrature/ac1c2_N.csv)
//
// Every mode multiplies per channel, so the renderers see a "grid" of C channels and run
// unchanged; what differs is how spectra become channels (analysis) and how channel radiance
// becomes XYZ (the detector of the display path). rgb and ac1c2 keep no spectra: only the CIE 1931
// observer can see them, the cube they produce is a channel image, and fluorescence (which needs
// wavelengths) is not representable — as in the RGB and AC1C2 renderers the paper compares.
#pragma once

#include "core/error.h"
#include "scene/scene_on_grid.h"
#include "spectral/library.h"

#include <string>
#include <vector>

namespace metamer {

enum class ModeKind { Full, Rgb, Ac1c2 };

struct Mode {
    ModeKind kind = ModeKind::Full;
    int samples = 0;  // ac1c2: N
    std::string name() const;  // "full", "rgb", "ac1c2:4"
    bool spectral() const { return kind == ModeKind::Full; }
};

// "full", "rgb", "ac1c2" (= ac1c2:4), "ac1c2:N" with N in 3..8. Input errors name `where`.
Mode parseMode(const std::string& text, const Where& where);

struct Representation {
    Mode mode;
    Grid grid;                                   // the scene's spectral grid
    std::vector<std::string> channelNames;       // "R","G","B" / "436.1 nm", ... / band names for full
    // Channel values from band values (non-full modes): c = Σ_b analysis[c][b]·v_b.
    std::vector<std::vector<double>> lightAnalysis, reflectanceAnalysis;
    // Channel radiance → CIE 1931 XYZ, radiometric like Σ L·x̄·Δλ (non-full modes): [3][channel].
    std::vector<std::vector<double>> toXyz;
    std::string description;                     // one line for logs and file metadata

    int channels() const { return mode.spectral() ? grid.bands() : int(toXyz.empty() ? 0 : toXyz[0].size()); }
    // The grid the renderers see: the real one in full mode, else channel indices 0..C-1.
    Grid renderGrid() const;
};

Representation makeRepresentation(const Mode& mode, const Grid& grid, const SpectrumLibrary& library);

// The scene's spectra in the mode's channels (a copy; full mode returns `spectra` unchanged).
// Fluorescent materials lose their fluorescence in non-spectral modes (with a warning).
SceneOnGrid represent(const SceneOnGrid& spectra, const Representation& representation, const Scene& scene);

// A light spectrum (band values) in the mode's channels.
std::vector<double> lightChannels(const Representation& representation, const std::vector<double>& bands);

}  // namespace metamer
