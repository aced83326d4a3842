// The spectral grid: the wavelengths at which every spectrum is sampled and the cube is written.
// Band i is centred at start + i*step and stands for the interval [λi - step/2, λi + step/2].
#pragma once

#include "core/error.h"

#include <string>
#include <vector>

namespace metamer {

struct Grid {
    double start_nm = 300.0;
    double end_nm = 740.0;
    double step_nm = 5.0;

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
