// Lights given by a number instead of a table (issue 49: random draws of lights by family): a
// blackbody at a temperature (Planck's law) and CIE daylight at a correlated colour temperature
// (the CIE D series: S0 + M1·S1 + M2·S2, CIE 15:2004 §3.1), each a relative spectral power
// distribution normalized to 100 at 560 nm, as the library's illuminants are. A scene writes them
// as a light's spectrum {"blackbody_k": T} and {"daylight_cct": T} (docs/scene-format.md).
// Tests: engine/spectral/illuminant_models_test.cpp.
#pragma once

#include "core/error.h"
#include "spectral/library.h"
#include "spectral/spectrum.h"

namespace metamer {

// Planck's second radiation constant c2 = hc/k (CODATA 2018, exact), m·K.
inline constexpr double kPlanckC2 = 1.438776877e-2;

// The range each model is defined over: Planck's law anywhere, but below 500 K nothing is visible
// and past 10⁵ K the shape no longer changes; CIE's daylight locus from 4000 K to 25 000 K.
inline constexpr double kBlackbodyMinK = 500.0, kBlackbodyMaxK = 1e5;
inline constexpr double kDaylightMinK = 4000.0, kDaylightMaxK = 25000.0;

// Planck's law at `kelvin` on 300 … 830 nm every 1 nm, 100 at 560 nm; an input error at `where`
// outside [kBlackbodyMinK, kBlackbodyMaxK].
Spectrum blackbodySpectrum(double kelvin, const Where& where);

// The CIE daylight chromaticity x_D, y_D of a correlated colour temperature (CIE 15:2004 eq. 3.3,
// 3.4), and the spectrum: M1, M2 from them, rounded to three decimals as the CIE prescribes (so
// 6504 K reproduces the D65 table's construction), S0 + M1·S1 + M2·S2 from the library's
// illuminants/daylight_components on 300 … 830 nm every 5 nm, 100 at 560 nm. Input errors at
// `where` outside [kDaylightMinK, kDaylightMaxK].
void daylightChromaticity(double cct, double& x, double& y, const Where& where);
Spectrum daylightSpectrum(double cct, const SpectrumLibrary& library, const Where& where);

}  // namespace metamer
