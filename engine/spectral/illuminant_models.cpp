#include "spectral/illuminant_models.h"

#include "spectral/csv.h"

#include <fmt/format.h>

#include <cmath>

namespace metamer {

namespace {

// Relative Planck radiance at λ nm for c2/T = k (the constant factors cancel in the ratio to 560 nm).
double planck(double nm, double c2OverT) {
    const double m = nm * 1e-9;
    return 1.0 / (std::pow(m, 5.0) * std::expm1(c2OverT / m));
}

Spectrum normalizedAt560(Spectrum s) {
    const double at560 = s.at(560.0);
    for (double& v : s.values) v *= 100.0 / at560;
    return s;
}

}  // namespace

Spectrum blackbodySpectrum(double kelvin, const Where& where) {
    if (!(kelvin >= kBlackbodyMinK && kelvin <= kBlackbodyMaxK))
        failInput(where, "expected a blackbody temperature of {:g} … {:g} K, got {:g}", kBlackbodyMinK, kBlackbodyMaxK,
                  kelvin);
    Spectrum s;
    const double k = kPlanckC2 / kelvin;
    for (int nm = 300; nm <= 830; ++nm) {
        s.wavelengths_nm.push_back(nm);
        s.values.push_back(planck(nm, k));
    }
    s = normalizedAt560(std::move(s));
    s.source = fmt::format("blackbody {:g} K", kelvin);
    return s;
}

void daylightChromaticity(double cct, double& x, double& y, const Where& where) {
    if (!(cct >= kDaylightMinK && cct <= kDaylightMaxK))
        failInput(where, "expected a daylight correlated colour temperature of {:g} … {:g} K (the CIE's daylight locus), "
                  "got {:g}", kDaylightMinK, kDaylightMaxK, cct);
    const double t = cct, t2 = t * t, t3 = t2 * t;
    x = cct <= 7000.0 ? -4.6070e9 / t3 + 2.9678e6 / t2 + 0.09911e3 / t + 0.244063
                      : -2.0064e9 / t3 + 1.9018e6 / t2 + 0.24748e3 / t + 0.237040;
    y = -3.000 * x * x + 2.870 * x - 0.275;
}

Spectrum daylightSpectrum(double cct, const SpectrumLibrary& library, const Where& where) {
    double x = 0.0, y = 0.0;
    daylightChromaticity(cct, x, y, where);
    const double m = 0.0241 + 0.2562 * x - 0.7341 * y;
    const double m1 = std::round((-1.3515 - 1.7703 * x + 5.9114 * y) / m * 1000.0) / 1000.0;
    const double m2 = std::round((0.0300 - 31.4424 * x + 30.0717 * y) / m * 1000.0) / 1000.0;
    const std::string table = "illuminants/daylight_components";
    const SpectralTable s = readSpectralTable(library.root() / (table + ".csv"), 3);
    if (s.columns.size() != 3) failRuntime("{} has {} columns; expected s0, s1, s2", table, s.columns.size());
    Spectrum out;
    out.wavelengths_nm = s.wavelengths_nm;
    for (size_t i = 0; i < s.wavelengths_nm.size(); ++i)
        out.values.push_back(s.columns[0][i] + m1 * s.columns[1][i] + m2 * s.columns[2][i]);
    out = normalizedAt560(std::move(out));
    out.source = fmt::format("CIE daylight {:g} K", cct);
    return out;
}

}  // namespace metamer
