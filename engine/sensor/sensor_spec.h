// A simulated camera sensor (docs/sensor.md): the optics, the pixel, its channels' quantum
// efficiencies and colour filter array, the exposure, and the EMVA 1288 linear model's constants
// (dark current, full well, conversion gain, read noise, PRNU, DSNU, black level, ADC bits), read
// from a sensor file. Input errors name the file and the key, as a scene's do.
// Tests: sensor/sensor_spec_test.cpp, tests/bad-inputs (the sensor- cases).
#pragma once

#include "isp/image_processor.h"
#include "sensor/lens.h"
#include "spectral/library.h"
#include "spectral/spectrum.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

struct SensorSpec {
    std::filesystem::path file;
    std::string description;

    // Optics: the camera equation E = π·L·T·cos⁴θ / (1 + 4N²(1 + m)²).
    double fNumber = 4.0;            // N
    Spectrum lensTransmittance;      // T(λ), 0 … 1 (constant 1 when not given)
    double magnification = 0.0;      // m (0: a distant scene)
    bool cos4 = false;               // the natural vignetting cos⁴θ …
    double focalLength_mm = 0.0;     // … with tan θ = (the pixel's distance to the centre) / (f(1 + m))
    std::optional<LensSpec> lens;    // the lens's blur per wavelength (sensor/lens.h); none: a perfect lens
    LensGeometry lensGeometry() const { return {pitch_um * 1e-3, fillFactor, fNumber * (1.0 + magnification)}; }

    // The pixel.
    double pitch_um = 0.0;           // square pixels
    double fillFactor = 1.0;         // of the pixel's area, 0 … 1
    std::vector<std::string> channels;  // names, in the quantum-efficiency table's column order
    std::vector<Spectrum> quantumEfficiency;  // per channel: electrons per photon, 0 … 1
    std::string qeSource;            // the table, and the peak it was scaled to
    // EMVA 1288's definition (true): the QE counts photons on the whole pixel, the fill factor
    // included; false: the photodiode's, multiplied by fillFactor.
    bool qeIncludesFillFactor = true;
    // The colour filter array: a tile of channel indices, rows × columns, repeated over the sensor
    // from its top-left pixel; pixel (x, y) has channel cfa[y % rows][x % columns].
    std::vector<std::vector<int>> cfa;
    std::string cfaName;             // "RGGB", "mono", or "custom"

    // Exposure and the linear model (EMVA 1288).
    std::optional<double> exposure_s;  // none: auto-exposure (docs/sensor.md)
    double autoExposureFullWellFraction = 0.7;
    double darkCurrent_e_per_s = 0.0;
    double fullWell_e = 0.0;
    double gain_dn_per_e = 0.0;      // K, the overall system gain
    double readNoise_e = 0.0;        // σ_r, electrons (Gaussian, temporal)
    double prnu = 0.0;               // σ of the pixels' relative gain (Gaussian, fixed)
    double dsnu_e = 0.0;             // σ of the pixels' dark signal offset, electrons (Gaussian, fixed)
    double blackLevel_dn = 0.0;
    int adcBits = 12;
    uint64_t fpnSeed = 1;            // the fixed-pattern maps' seed: one sensor, one pattern
    // How an RGB Bayer sensor's frames are developed (isp/image_processor.h) and what its DNGs'
    // colour tags say: the defaults when the file has no "processor".
    ProcessorSpec processor;
    std::vector<std::filesystem::path> inputs;  // the files it was read from (itself, its tables)

    // The area the QE's photons are counted on: the pixel's, times the fill factor when the QE
    // does not include it.
    double pixelArea_m2() const { return pitch_um * pitch_um * 1e-12 * (qeIncludesFillFactor ? 1.0 : fillFactor); }
    uint32_t whiteLevel() const { return (1u << adcBits) - 1u; }
    int channelAt(int x, int y) const {
        const auto& row = cfa[size_t(y) % cfa.size()];
        return row[size_t(x) % row.size()];
    }
};

// Reads a sensor file; library names (a quantum-efficiency table "cameras/nikon_d5100") resolve in
// `library`, file names ending in .csv relative to the sensor file's folder.
SensorSpec readSensor(const std::filesystem::path& file, const SpectrumLibrary& library);

// Whether `given` names a sensor file (it ends in .json or has a folder) rather than a library
// sensor: a relative file resolves against the folder of what names it (the working folder, a
// sweep's folder).
bool namesSensorFile(const std::string& given);

// The sensor file `given` names: itself when it ends in .json or has a folder, else the library
// sensor spectra/sensors/<given>.json (an input error naming --sensor and listing them if none).
std::filesystem::path sensorFile(const std::string& given, const SpectrumLibrary& library);

}  // namespace metamer
