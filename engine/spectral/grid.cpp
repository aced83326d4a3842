#include "spectral/grid.h"

#include <cmath>
#include <cstdlib>

namespace metamer {

int Grid::bands() const {
    // Rounded: end = start + k*step is checked by validate() to 1e-6 of a step.
    return static_cast<int>(std::llround((end_nm - start_nm) / step_nm)) + 1;
}

std::vector<double> Grid::wavelengths() const {
    std::vector<double> w(bands());
    for (int i = 0; i < bands(); ++i) w[i] = wavelength(i);
    return w;
}

void Grid::validate(const Where& where) const {
    if (!std::isfinite(start_nm) || !std::isfinite(end_nm) || !std::isfinite(step_nm))
        failInput(where, "grid values must be finite numbers");
    if (step_nm < kMinStep || step_nm > kMaxStep)
        failInput(where.child("step_nm"), "step {} nm is outside {}..{} nm", step_nm, kMinStep, kMaxStep);
    if (start_nm < kMinWavelength || end_nm > kMaxWavelength)
        failInput(where, "grid {}..{} nm is outside {}..{} nm", start_nm, end_nm, kMinWavelength,
                  kMaxWavelength);
    if (end_nm < start_nm)
        failInput(where.child("end_nm"), "end {} nm is below start {} nm", end_nm, start_nm);
    double k = (end_nm - start_nm) / step_nm;
    if (std::fabs(k - std::round(k)) > 1e-6)
        failInput(where.child("end_nm"), "end {} nm is not start {} nm + a whole number of {} nm steps",
                  end_nm, start_nm, step_nm);
}

Grid Grid::parse(const std::string& text, const Where& where) {
    Grid g;
    double v[3];
    const char* p = text.c_str();
    for (int i = 0; i < 3; ++i) {
        char* end = nullptr;
        v[i] = std::strtod(p, &end);
        bool sepOk = (i < 2) ? (*end == ':') : (*end == '\0');
        if (end == p || !sepOk)
            failInput(where, "'{}' is not a grid; expected START:END:STEP in nm, e.g. 300:740:5", text);
        p = end + 1;
    }
    g.start_nm = v[0];
    g.end_nm = v[1];
    g.step_nm = v[2];
    g.validate(where);
    return g;
}

Resampling parseResampling(const std::string& name, const Where& where) {
    if (name == "interpolate") return Resampling::Interpolate;
    if (name == "sprague") return Resampling::Sprague;
    if (name == "band-mean") return Resampling::BandMean;
    std::string near = closestMatch(name, {"interpolate", "sprague", "band-mean"});
    failInput(where, "'{}' is not a resampling rule; expected interpolate, sprague or band-mean{}", name,
              near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near));
}

const char* resamplingName(Resampling resampling) {
    switch (resampling) {
        case Resampling::Interpolate: return "interpolate";
        case Resampling::Sprague: return "sprague";
        case Resampling::BandMean: return "band-mean";
    }
    return "?";
}

std::string Grid::str() const { return fmt::format("{:g}:{:g}:{:g}", start_nm, end_nm, step_nm); }

}  // namespace metamer
