// Lights by temperature (issue 49): Planck's law reproduces CIE illuminant A (defined by it, with the
// old c2 = 1.435·10⁻² m·K at 2848 K), and the CIE daylight model colour-science's
// sd_CIE_illuminant_D_series at three temperatures (values below printed by colour-science 0.4.7,
// M1 and M2 rounded to three decimals as the CIE does).
#include "spectral/illuminant_models.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;

namespace {
const SpectrumLibrary& library() {
    static const SpectrumLibrary lib;
    return lib;
}
}  // namespace

TEST(IlluminantModels, ABlackbodyAtAsTemperatureIsIlluminantA) {
    const double kelvin = 2848.0 * kPlanckC2 / 1.435e-2;  // 2855.54 K on today's c2
    const Spectrum b = blackbodySpectrum(kelvin, Where{"t"});
    const Spectrum& a = library().get("illuminants/A", Where{});
    ASSERT_EQ(b.wavelengths_nm.size(), a.wavelengths_nm.size());
    for (size_t i = 0; i < a.values.size(); ++i) EXPECT_NEAR(b.values[i] / a.values[i], 1.0, 2e-7) << a.wavelengths_nm[i];
    EXPECT_DOUBLE_EQ(b.at(560), 100.0);
    // Hotter is bluer: the 450/650 ratio grows with temperature.
    const Spectrum cool = blackbodySpectrum(2000, Where{"t"}), hot = blackbodySpectrum(10000, Where{"t"});
    EXPECT_LT(cool.at(450) / cool.at(650), hot.at(450) / hot.at(650));
    EXPECT_THROW(blackbodySpectrum(100, Where{"t"}), Error);
    EXPECT_THROW(blackbodySpectrum(std::nan(""), Where{"t"}), Error);
}

TEST(IlluminantModels, CieDaylightEqualsColourSciencesDSeries) {
    struct Case {
        double cct, x, y;
        double values[7];  // at 300, 400, 450, 500, 600, 700, 830 nm, 100 at 560
    };
    const Case cases[] = {
        {5000, 0.345741, 0.35866615, {0.0192, 49.2603, 87.1997, 95.7015, 97.7064, 91.6552, 74.4775}},
        {6504, 0.31271406, 0.3291191, {0.03412, 82.7983, 117.0435, 109.3707, 90.0004, 71.5958, 60.3027}},
        {10000, 0.2787996, 0.2919672, {0.06006, 138.7361, 162.6778, 129.9021, 83.5018, 57.4177, 49.6721}},
    };
    const double nm[7] = {300, 400, 450, 500, 600, 700, 830};
    for (const Case& c : cases) {
        double x = 0, y = 0;
        daylightChromaticity(c.cct, x, y, Where{"t"});
        EXPECT_NEAR(x, c.x, 1e-6) << c.cct;
        EXPECT_NEAR(y, c.y, 1e-6) << c.cct;
        const Spectrum d = daylightSpectrum(c.cct, library(), Where{"t"});
        for (int i = 0; i < 7; ++i) EXPECT_NEAR(d.at(nm[i]), c.values[i], 1e-4 * std::max(1.0, c.values[i])) << c.cct << " K, " << nm[i];
    }
    // 6504 K against the CIE's own D65 table: the same construction (the table's 5 nm values are
    // interpolated from the CIE's 10 nm ones, so not to the last digit).
    const Spectrum d65 = daylightSpectrum(6504, library(), Where{"t"});
    const Spectrum& table = library().get("illuminants/D65", Where{});
    for (double w = 400; w <= 700; w += 10) EXPECT_NEAR(d65.at(w) / table.at(w), 1.0, 2e-3) << w;
    EXPECT_THROW(daylightSpectrum(3000, library(), Where{"t"}), Error);
    EXPECT_THROW(daylightSpectrum(30000, library(), Where{"t"}), Error);
}
