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
//   linear:K   Peercy (1993): spectra as K coefficients on a basis from characteristic-vector
//              analysis of the scene's own spectra (lights, the light its materials reflect,
//              texel by texel where textured, and emit), products through the basis. Evaluated here exactly but by projection: inputs are
//              projected onto the basis, rendered on the grid, and each pixel projected again —
//              the same numbers as Peercy's K×K products (all steps are linear), at the cost of a
//              full-spectral render (docs/representations.md, "Linear").
//
// Every mode multiplies per channel, so the renderers see a "grid" of C channels and run
// unchanged; what differs is how spectra become channels (analysis) and how channel radiance
// becomes XYZ (the detector of the display path). rgb and ac1c2 keep no spectra: only the CIE 1931
// observer can see them, the cube they produce is a channel image, and fluorescence (which needs
// wavelengths) is not representable — as in the RGB and AC1C2 renderers the paper compares.
// Tests: tests/representation_test.cpp, tests/textures_test.cpp (linear:K on textures),
// tests/donaldson_test.cpp.
#pragma once

#include "color/tonemap.h"
#include "core/error.h"
#include "scene/scene_on_grid.h"
#include "spectral/library.h"

#include <string>
#include <vector>

namespace metamer {

enum class ModeKind { Full, Rgb, Ac1c2, Linear };

struct Mode {
    ModeKind kind = ModeKind::Full;
    int samples = 0;  // ac1c2: N; linear: K
    std::string name() const;  // "full", "rgb", "ac1c2:4", "linear:6"
    // The renderers see band spectra (full, and linear's projected spectra).
    bool spectral() const { return kind == ModeKind::Full || kind == ModeKind::Linear; }
};

// "full", "rgb", "ac1c2" (= ac1c2:4), "ac1c2:N" with N in 3..8, "linear:K" with K in 1..12.
// Input errors name `where`.
Mode parseMode(const std::string& text, const Where& where);

// A simulated sensor captures a spectral cube: a channel mode (rgb, ac1c2) is an input error
// naming `where` (`--mode`, a sweep's `render.mode`), said before anything renders.
void requireSpectralModeForSensor(const std::string& mode, const Where& where);

struct Representation {
    Mode mode;
    Grid grid;                                   // the scene's spectral grid
    std::vector<std::string> channelNames;       // "R","G","B" / "436.1 nm", ... / band names for full
    // Channel values from band values (non-full modes): c = Σ_b analysis[c][b]·v_b.
    std::vector<std::vector<double>> lightAnalysis, reflectanceAnalysis;
    // Channel radiance → CIE 1931 XYZ, radiometric like Σ L·x̄·Δλ (non-full modes): [3][channel].
    std::vector<std::vector<double>> toXyz;
    // Linear: the basis e_k(λ) [K][band], orthonormal under Σ_b e_i·e_j·Δλ, and the fraction of the
    // analysed spectra's energy it keeps.
    std::vector<std::vector<double>> basis;
    double energyKept = 1.0;
    std::string description;                     // one line for logs and file metadata

    int channels() const { return mode.spectral() ? grid.bands() : int(toXyz.empty() ? 0 : toXyz[0].size()); }
    // The grid the renderers see: the real one in full mode, else channel indices 0..C-1.
    Grid renderGrid() const;
};

// `spectra` (the scene's, on `grid`) are what linear:K analyses; the other modes ignore them.
Representation makeRepresentation(const Mode& mode, const Grid& grid, const SpectrumLibrary& library,
                                  const SceneOnGrid* spectra = nullptr);

// Linear: the projection of a band spectrum onto the basis, as band values (identity otherwise).
std::vector<double> project(const Representation& representation, const std::vector<double>& bands);
// Linear: projects every pixel of a cube onto the basis, in place (Peercy's result).
void projectCube(const Representation& representation, std::vector<float>& data, int bands);

// The scene's spectra in the mode's channels (a copy; full mode returns `spectra` unchanged).
// Fluorescent materials lose their fluorescence in non-spectral modes (with a warning).
SceneOnGrid represent(const SceneOnGrid& spectra, const Representation& representation, const Scene& scene);

// A light spectrum (band values) in the mode's channels.
std::vector<double> lightChannels(const Representation& representation, const std::vector<double>& bands);

// What the display path needs to know of the mode's channels (color/tonemap.h).
DisplayChannels displayChannels(const Representation& representation);

}  // namespace metamer
