// libFuzzer target: the spectrum reader. The input's bytes become a CSV file that
// readSpectralTable and readSpectrumCsv read; what they accept must keep the promises of
// spectral/csv.h (finite, strictly increasing wavelengths; finite values; one column per header
// name) and must survive what every caller does next: validate, resample onto the default grid
// (and a fine one under every rule), integrate. Input errors (metamer::Error) are expected; anything else is a finding.
#include "fuzz_support.h"

#include "spectral/csv.h"
#include "spectral/grid.h"
#include "spectral/resampling.h"
#include "spectral/spectrum.h"

#include <cmath>
#include <cstdint>

using namespace metamer;

namespace {

void checkTable(const SpectralTable& t, size_t minColumns) {
    METAMER_FUZZ_CHECK(t.wavelengths_nm.size() >= 2);
    METAMER_FUZZ_CHECK(t.columns.size() >= minColumns);
    METAMER_FUZZ_CHECK(t.columnNames.empty() || t.columnNames.size() == t.columns.size());
    for (size_t i = 0; i < t.wavelengths_nm.size(); ++i) {
        METAMER_FUZZ_CHECK(std::isfinite(t.wavelengths_nm[i]) && t.wavelengths_nm[i] > 0);
        if (i > 0) METAMER_FUZZ_CHECK(t.wavelengths_nm[i] > t.wavelengths_nm[i - 1]);
    }
    for (const auto& c : t.columns) {
        METAMER_FUZZ_CHECK(c.size() == t.wavelengths_nm.size());
        for (double v : c) METAMER_FUZZ_CHECK(std::isfinite(v));
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::silenceWarnings();
    fuzz::workDir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::filesystem::path file = fuzz::workDir() / "input.csv";
    fuzz::writeFile(file, data, size);

    try {
        SpectralTable t = readSpectralTable(file, 1);
        checkTable(t, 1);
        // Detectors ask for three columns: the same text read with a higher minimum.
        if (t.columns.size() >= 3) checkTable(readSpectralTable(file, 3), 3);
    } catch (const Error&) {
    }

    try {
        Spectrum s = readSpectrumCsv(file);
        s.validate(Where{file.string()});
        const Grid grid;  // the default 300:740:5
        std::vector<double> bands = resample(s, grid);
        METAMER_FUZZ_CHECK(bands.size() == static_cast<size_t>(grid.bands()));
        // Finite data on a finite grid give finite band means, unless the data's own integral
        // overflows (values near DBL_MAX), which is not a reader's fault.
        double peak = 0;
        for (double v : s.values) peak = std::max(peak, std::fabs(v));
        if (peak < 1e300)
            for (double b : bands) METAMER_FUZZ_CHECK(std::isfinite(b));
        // Every rule, on a grid finer than most data (Sprague's weights stay below 20 in size).
        for (Resampling rule : {Resampling::Interpolate, Resampling::Sprague, Resampling::BandMean}) {
            Grid fine{300, 740, 0.5};
            fine.resampling = rule;
            const std::vector<double> v = resample(s, fine);
            METAMER_FUZZ_CHECK(v.size() == static_cast<size_t>(fine.bands()));
            if (peak < 1e290)
                for (double b : v) METAMER_FUZZ_CHECK(std::isfinite(b));
        }
        coverage(s, grid);
        s.at(0.5 * (s.minWavelength() + s.maxWavelength()));
        s.integral();
    } catch (const Error&) {
    }
    return 0;
}
