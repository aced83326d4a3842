// The simulated sensor's capture (docs/sensor.md): from a noise-free spectral radiance cube to
// what the sensor records. Two steps, each testable alone:
//   1. expectedElectrons: the camera equation, the channels' quantum efficiencies through the CFA,
//      the exposure, dark current and the fixed patterns (PRNU, DSNU) — the mean electron count of
//      every pixel, the truth the noise is drawn around;
//   2. digitize: Poisson shot noise (of signal and dark current together), the full well, Gaussian
//      read noise, the conversion gain, the black level and the ADC's range.
// Random numbers come from counter-based streams (sensor/counter_rng.h) keyed by (seed, frame) and
// pixel, and the fixed patterns from their own seed: the same files on any machine, in any order,
// and frames that differ only in their temporal noise.
// Tests: sensor/capture_test.cpp, tests/python/test_sensor.py.
#pragma once

#include "sensor/counter_rng.h"
#include "sensor/sensor_spec.h"
#include "spectral/cube.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace metamer {

// Planck's constant and the speed of light (SI, exact since 2019).
constexpr double kPlanck = 6.62607015e-34, kSpeedOfLight = 299792458.0;

struct ExpectedElectrons {
    int width = 0, height = 0;
    double exposure_s = 0.0;
    bool autoExposed = false;
    // μe per pixel, row 0 at the top: t·(signal·(1 + PRNU) + dark current), ≥ 0 — the mean of the
    // Poisson count the pixel collects.
    std::vector<double> electrons;
    // o per pixel: the DSNU offset (e⁻, of either sign), added after the shot noise as EMVA 1288
    // defines it; empty without DSNU (or without fixed patterns).
    std::vector<double> darkOffset;
    std::vector<uint8_t> channel;  // the CFA's channel per pixel
    // μe + o: the mean signal the pixel records, in electrons, before the full well, read noise and
    // quantization (`<stem>.electrons.exr`); negative where DSNU takes a dark pixel below 0.
    std::vector<double> recordedMean() const;
};

// That every value of `cube` is finite radiance ≥ 0: else an input error at `where` (the cube's
// file, or the Python argument that gave it) naming the first pixel and band that is not.
void requireRadiance(const SpectralCube& cube, const Where& where);

// μe of every pixel of `cube` (spectral radiance, W·sr⁻¹·m⁻²·nm⁻¹) seen by `sensor`, exposed for
// `exposure_s` (the sensor's own when not given, auto-exposure when it has none); without
// `fixedPattern`, every pixel has gain 1 and no dark offset (a noise-free capture). A channel whose
// quantum-efficiency data lie wholly outside the cube's grid is an input error at the sensor's
// table (it would record nothing, as a scene's spectrum outside the grid is refused).
ExpectedElectrons expectedElectrons(const SpectralCube& cube, const SensorSpec& sensor,
                                    std::optional<double> exposure_s = std::nullopt, bool fixedPattern = true,
                                    int threads = 0);

struct CaptureNoise {
    bool enabled = true;     // false: DN = round(K·min(μe, full well)) + black, nothing drawn
    uint64_t seed = 0;       // the temporal noise's seed …
    uint64_t frame = 0;      // … and frame: each (seed, frame) is one exposure's noise
    int threads = 0;         // 0: one per CPU; the result is the same for any count
};

// The raw image: digital numbers per pixel, 0 … 2^bits − 1: DN = round(K·(min(Poisson(μe), full
// well) + o + σ_r·z)) + black, clipped (without noise: round(K·(min(μe, full well) + o)) + black).
std::vector<uint16_t> digitize(const ExpectedElectrons& expected, const SensorSpec& sensor, const CaptureNoise& noise);
// The same from μe alone, with the dark offsets o when given.
std::vector<uint16_t> digitize(const std::vector<double>& expectedElectrons, int width, const SensorSpec& sensor,
                               const CaptureNoise& noise, const std::vector<double>* darkOffset = nullptr);

// The fixed patterns of `sensor` at pixel index i (y·width + x): its gain factor 1 + PRNU·z₁ and
// its dark offset DSNU·z₂ in electrons, z standard normal from the sensor's fpn_seed.
double prnuGain(const SensorSpec& sensor, uint64_t pixel);
double dsnuOffset(const SensorSpec& sensor, uint64_t pixel);

// A standard normal variate from two uniforms of `stream` (Box–Muller, the cosine branch).
double standardNormal(CounterStream& stream);

}  // namespace metamer
