#include "spectral/spectrum.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace metamer {

const char* kindName(SpectrumKind kind) {
    switch (kind) {
        case SpectrumKind::Light: return "light";
        case SpectrumKind::Reflectance: return "reflectance";
        case SpectrumKind::Excitation: return "excitation";
        case SpectrumKind::Emission: return "emission";
        case SpectrumKind::Observer: return "observer";
        case SpectrumKind::Transmittance: return "transmittance";
        case SpectrumKind::Absorbance: return "absorbance";
        case SpectrumKind::KubelkaMunk: return "Kubelka–Munk coefficient";
    }
    return "?";
}

Spectrum Spectrum::makeConstant(double value) {
    Spectrum s;
    s.constant = value;
    s.source = fmt::format("constant {:g}", value);
    return s;
}

double Spectrum::minWavelength() const {
    return constant ? -std::numeric_limits<double>::infinity() : wavelengths_nm.front();
}
double Spectrum::maxWavelength() const {
    return constant ? std::numeric_limits<double>::infinity() : wavelengths_nm.back();
}

double Spectrum::at(double nm) const {
    if (constant) return *constant;
    const auto& w = wavelengths_nm;
    if (nm < w.front() || nm > w.back()) return 0.0;
    size_t i = std::upper_bound(w.begin(), w.end(), nm) - w.begin();
    if (i == w.size()) return values.back();
    size_t j = i - 1;
    double t = (nm - w[j]) / (w[i] - w[j]);
    return values[j] + t * (values[i] - values[j]);
}

double Spectrum::integrate(double a, double b) const {
    if (b <= a) return 0.0;
    if (constant) return *constant * (b - a);
    const auto& w = wavelengths_nm;
    a = std::max(a, w.front());
    b = std::min(b, w.back());
    if (b <= a) return 0.0;
    // Segments [w[j], w[j+1]] intersecting [a, b]; exact trapezoid on each clipped piece.
    size_t j = std::upper_bound(w.begin(), w.end(), a) - w.begin();
    j = j == 0 ? 0 : j - 1;
    double sum = 0.0;
    for (; j + 1 < w.size() && w[j] < b; ++j) {
        double lo = std::max(a, w[j]), hi = std::min(b, w[j + 1]);
        if (hi <= lo) continue;
        sum += 0.5 * (at(lo) + at(hi)) * (hi - lo);
    }
    return sum;
}

double Spectrum::integral() const {
    if (constant) failRuntime("integral of constant spectrum '{}' is unbounded", source);
    return integrate(wavelengths_nm.front(), wavelengths_nm.back());
}

void Spectrum::validate(const Where& where) const {
    if (constant) {
        if (!std::isfinite(*constant)) failInput(where, "constant spectrum value must be finite");
        return;
    }
    if (wavelengths_nm.size() != values.size())
        failInput(where, "{} wavelengths but {} values", wavelengths_nm.size(), values.size());
    if (wavelengths_nm.size() < 2)
        failInput(where, "a sampled spectrum needs at least 2 points, got {}", wavelengths_nm.size());
    for (size_t i = 0; i < wavelengths_nm.size(); ++i) {
        if (!std::isfinite(wavelengths_nm[i]) || !std::isfinite(values[i]))
            failInput(where, "point {} ({} nm) is not a finite number", i, wavelengths_nm[i]);
        if (i > 0 && !(wavelengths_nm[i] > wavelengths_nm[i - 1]))
            failInput(where, "wavelengths must increase strictly: {} nm follows {} nm", wavelengths_nm[i],
                      wavelengths_nm[i - 1]);
    }
}

}  // namespace metamer
