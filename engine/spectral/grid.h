// The spectral grid: the wavelengths at which every spectrum is sampled and the cube is written.
// Band i is centred at start + i*step and stands for the interval [λi - step/2, λi + step/2].
#pragma once

#include "core/error.h"

#include <string>
#include <vector>

namespace metamer {

// How spectra given as data become band values on a grid (docs/physics.md, "Resampling";
// spectral/resampling.h). In every rule a spectrum is 0 outside its data (the coverage policy).
enum class Resampling {
    // The default, the practice of CIE 15 and colour-science: a band whose centre is a data point
    // takes the tabulated value; where the grid is coarser than the data around the centre, the
    // band mean; elsewhere the linear interpolant at the centre.
    Interpolate,
    // The same, with CIE 167's Sprague (1880) quintic in place of the linear interpolant for
    // uniformly spaced data of at least 6 points (linear otherwise).
    Sprague,
    // Every band the mean of the piecewise-linear data over the band, for band-limited
    // instruments (the rule before issue 13).
    BandMean,
};

// "interpolate" / "sprague" / "band-mean"; anything else is an input error at `where`.
Resampling parseResampling(const std::string& name, const Where& where);
const char* resamplingName(Resampling resampling);

struct Grid {
    double start_nm = 300.0;
    double end_nm = 740.0;
    double step_nm = 5.0;
    // Not part of the grid's identity (operator==): two cubes on equal grids have the same bands
    // whatever rule put spectra on them.
    Resampling resampling = Resampling::Interpolate;

    // Limits a grid must respect (documented in docs/scene-format.md).
    static constexpr double kMinWavelength = 200.0;
    static constexpr double kMaxWavelength = 2500.0;
    static constexpr double kMinStep = 0.5;
    static constexpr double kMaxStep = 50.0;

    int bands() const;
    int layers() const { return (bands() + 3) / 4; }  // RGBA32F layers, 4 bands each
    double wavelength(int band) const { return start_nm + band * step_nm; }
    std::vector<double> wavelengths() const;

    // Throws an input error naming `where` when the grid is outside the limits above or
    // end is not start + k*step.
    void validate(const Where& where) const;

    // "300:740:5" (the --grid flag). Validates.
    static Grid parse(const std::string& text, const Where& where);
    std::string str() const;  // "300:740:5"

    bool operator==(const Grid& o) const {
        return start_nm == o.start_nm && end_nm == o.end_nm && step_nm == o.step_nm;
    }
};

}  // namespace metamer
