#include "sensor/capture.h"

#include "core/error.h"
#include "core/parallel_for.h"
#include "core/statistics.h"
#include "sensor/poisson.h"
#include "spectral/resampling.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>

namespace metamer {

namespace {

// Streams: the key is (seed, purpose), the counter (pixel, frame, 0), so a pixel's shot noise, read
// noise, PRNU and DSNU never share words, whatever the seeds.
constexpr uint64_t kPrnuStream = 1, kDsnuStream = 2, kShotStream = 3, kReadStream = 4;

}  // namespace

double standardNormal(CounterStream& stream) {
    const double u1 = stream.uniform(), u2 = stream.uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

double prnuGain(const SensorSpec& sensor, uint64_t pixel) {
    if (sensor.prnu == 0.0) return 1.0;
    CounterStream s({sensor.fpnSeed, kPrnuStream}, pixel, 0, 0);
    return std::max(0.0, 1.0 + sensor.prnu * standardNormal(s));
}

double dsnuOffset(const SensorSpec& sensor, uint64_t pixel) {
    if (sensor.dsnu_e == 0.0) return 0.0;
    CounterStream s({sensor.fpnSeed, kDsnuStream}, pixel, 0, 0);
    return sensor.dsnu_e * standardNormal(s);
}

void requireRadiance(const SpectralCube& cube, const Where& where) {
    const size_t bands = size_t(cube.grid.bands());
    for (size_t i = 0; i < cube.data.size(); ++i) {
        const float v = cube.data[i];
        if (std::isfinite(v) && v >= 0.0f) continue;
        const size_t pixel = i / bands;
        failInput(where, "pixel ({}, {}) holds {:g} at {:g} nm; a sensor captures finite spectral radiance ≥ 0",
                  pixel % size_t(cube.width), pixel / size_t(cube.width), double(v), cube.grid.wavelengths()[i % bands]);
    }
}

ExpectedElectrons expectedElectrons(const SpectralCube& scene, const SensorSpec& sensor, std::optional<double> exposure_s,
                                    bool fixedPattern, int threads) {
    // The lens's blur per band first (sensor/lens.h): the pixels see the optical image.
    std::optional<SpectralCube> optical;
    if (sensor.lens) optical = throughLens(scene, *sensor.lens, sensor.lensGeometry(), threads);
    const SpectralCube& cube = optical ? *optical : scene;
    const Grid& grid = cube.grid;
    const size_t bands = size_t(grid.bands());
    const std::vector<double> nm = grid.wavelengths(), lens = resample(sensor.lensTransmittance, grid);
    // Electrons per second per pixel from radiance L in band b on channel c:
    // A · π·T(λ)/(1 + 4N²(1 + m)²) · QE_c(λ) · λ/(hc) · Δλ · L — the camera equation's irradiance,
    // in photons, through the channel (cos⁴θ per pixel below). π·L·sin²θ' with the image-side
    // cone's sin θ' = 1/√(1 + 4N_w²), N_w = N(1 + m) the working f-number: EMVA 1288's and
    // ISETCam's form (docs/sensor.md); 4N_w² alone is its small-angle limit.
    const double workingF = sensor.fNumber * (1.0 + sensor.magnification);
    const double optics = std::numbers::pi / (1.0 + 4.0 * workingF * workingF);
    std::vector<std::vector<double>> weights;
    for (size_t c = 0; c < sensor.quantumEfficiency.size(); ++c)
        if (const CoverageGap gap = coverage(sensor.quantumEfficiency[c], grid); !gap.overlaps)
            failInput(Where{sensor.file.string(), "quantum_efficiency.table"},
                      "channel {}'s data ({:g} … {:g} nm) lie wholly outside the cube's grid ({:g} … {:g} nm): it would "
                      "record nothing",
                      sensor.channels[c], gap.data_lo, gap.data_hi, grid.start_nm, grid.end_nm);
    for (const Spectrum& qe : sensor.quantumEfficiency) {
        const std::vector<double> q = resample(qe, grid);
        std::vector<double> w(bands);
        for (size_t b = 0; b < bands; ++b)
            w[b] = sensor.pixelArea_m2() * optics * lens[b] * q[b] * (nm[b] * 1e-9) / (kPlanck * kSpeedOfLight) * grid.step_nm;
        weights.push_back(std::move(w));
    }
    ExpectedElectrons out;
    out.width = cube.width;
    out.height = cube.height;
    const size_t pixels = size_t(cube.width) * size_t(cube.height);
    std::vector<double> rate(pixels);  // signal electrons per second, before PRNU
    out.channel.resize(pixels);
    const double cx = 0.5 * cube.width, cy = 0.5 * cube.height;
    std::atomic<size_t> firstBad{pixels};  // the first pixel whose rate is not a number ≥ 0
    parallelFor(pixels, threads, 16384, [&](size_t i) {
        const int x = int(i % size_t(cube.width)), y = int(i / size_t(cube.width));
        const int c = sensor.channelAt(x, y);
        out.channel[i] = uint8_t(c);
        const float* L = cube.pixel(x, y);
        double r = 0.0;
        for (size_t b = 0; b < bands; ++b) r += weights[size_t(c)][b] * double(L[b]);
        if (sensor.cos4) {
            // θ between the optical axis and the ray from the exit pupil to the pixel's centre: a
            // thin lens focused at magnification m has its image f(1 + m) behind it, so
            // tan θ = (distance on the sensor) / (f(1 + m)).
            const double dx = (x + 0.5 - cx) * sensor.pitch_um * 1e-3, dy = (y + 0.5 - cy) * sensor.pitch_um * 1e-3;
            const double image = sensor.focalLength_mm * (1.0 + sensor.magnification);
            const double c2 = 1.0 / (1.0 + (dx * dx + dy * dy) / (image * image));
            r *= c2 * c2;
        }
        if (!std::isfinite(r) || r < 0.0) {
            size_t seen = firstBad.load();
            while (i < seen && !firstBad.compare_exchange_weak(seen, i)) {
            }
        }
        rate[i] = r;
    });
    if (const size_t bad = firstBad.load(); bad < pixels)
        failInput(Where{sensor.file.string()},
                  "pixel ({}, {}) receives {:g} electrons per second: the sensor's numbers overflow; the cube must "
                  "hold finite radiance ≥ 0",
                  bad % size_t(cube.width), bad / size_t(cube.width), rate[bad]);
    if (exposure_s) {
        out.exposure_s = *exposure_s;
    } else if (sensor.exposure_s) {
        out.exposure_s = *sensor.exposure_s;
    } else {
        // Auto-exposure: the 99th percentile of the signal reaches the chosen fraction of the full well.
        const double p99 = percentile(rate, 0.99);
        if (!(p99 > 0.0))
            failInput(Where{sensor.file.string(), "exposure_s"},
                      "auto-exposure needs light: the image's 99th-percentile pixel receives no signal; give an "
                      "exposure time");
        out.exposure_s = sensor.autoExposureFullWellFraction * sensor.fullWell_e / p99;
        out.autoExposed = true;
    }
    out.electrons.resize(pixels);
    const bool dsnu = fixedPattern && sensor.dsnu_e > 0.0;
    if (dsnu) out.darkOffset.resize(pixels);
    parallelFor(pixels, threads, 16384, [&](size_t i) {
        const double gain = fixedPattern ? prnuGain(sensor, i) : 1.0;
        out.electrons[i] = out.exposure_s * (rate[i] * gain + sensor.darkCurrent_e_per_s);
        if (dsnu) out.darkOffset[i] = dsnuOffset(sensor, i);
    });
    return out;
}

std::vector<double> ExpectedElectrons::recordedMean() const {
    std::vector<double> m = electrons;
    for (size_t i = 0; i < darkOffset.size(); ++i) m[i] += darkOffset[i];
    return m;
}

std::vector<uint16_t> digitize(const ExpectedElectrons& e, const SensorSpec& sensor, const CaptureNoise& noise) {
    return digitize(e.electrons, e.width, sensor, noise, e.darkOffset.empty() ? nullptr : &e.darkOffset);
}

std::vector<uint16_t> digitize(const std::vector<double>& expected, int width, const SensorSpec& sensor,
                               const CaptureNoise& noise, const std::vector<double>* darkOffset) {
    std::vector<uint16_t> raw(expected.size());
    const double white = double(sensor.whiteLevel());
    (void)width;
    // Each pixel draws from its own streams, so the pixels split between threads in any way give
    // the same numbers.
    parallelFor(expected.size(), noise.threads, 16384, [&](size_t i) {
        double electrons;
        if (noise.enabled) {
            CounterStream shot({noise.seed, kShotStream}, i, noise.frame, 0), read({noise.seed, kReadStream}, i, noise.frame, 0);
            const double mean = std::min(expected[i], kMaxPoissonMean);
            electrons = std::min(double(poisson(mean, shot)), sensor.fullWell_e);
            if (sensor.readNoise_e > 0.0) electrons += sensor.readNoise_e * standardNormal(read);
        } else {
            electrons = std::min(expected[i], sensor.fullWell_e);
        }
        // DSNU: the pixel's dark-signal offset, after the shot noise and the full well, like the
        // read noise (EMVA 1288): it may take a dark pixel below the black level.
        if (darkOffset) electrons += (*darkOffset)[i];
        const double dn = std::nearbyint(sensor.gain_dn_per_e * electrons) + sensor.blackLevel_dn;
        raw[i] = uint16_t(std::clamp(dn, 0.0, white));
    });
    return raw;
}

}  // namespace metamer
