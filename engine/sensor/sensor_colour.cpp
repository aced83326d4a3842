#include "sensor/sensor_colour.h"

#include "core/error.h"
#include "spectral/resampling.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace metamer {

std::optional<SensorColour> sensorColour(const SensorSpec& sensor, const SpectrumLibrary& library) {
    if (sensor.channels.size() != 3 || sensor.cfa.size() != 2 || sensor.cfa[0].size() != 2) return std::nullopt;
    // Channel index → DNG colour code, by the channel's first letter.
    std::array<int, 3> code{-1, -1, -1}, byCode{-1, -1, -1};
    for (size_t c = 0; c < 3; ++c) {
        const char first = char(std::tolower(static_cast<unsigned char>(sensor.channels[c].empty() ? ' ' : sensor.channels[c][0])));
        const int k = first == 'r' ? 0 : first == 'g' ? 1 : first == 'b' ? 2 : -1;
        if (k < 0 || byCode[size_t(k)] >= 0) return std::nullopt;
        code[c] = k;
        byCode[size_t(k)] = int(c);
    }
    SensorColour out;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) out.cfa[size_t(y * 2 + x)] = uint8_t(code[size_t(sensor.cfa[size_t(y)][size_t(x)])]);

    // The camera as a detector of photons: weight QE·T·λ·Δλ per band, in R, G, B order.
    const Grid grid{380, 780, 5};
    const std::vector<double> nm = grid.wavelengths(), lens = resample(sensor.lensTransmittance, grid);
    Detector camera;
    camera.name = "sensor " + sensor.file.string();
    camera.kind = DetectorKind::Camera;
    camera.channels = {"R", "G", "B"};
    camera.grid = grid;
    for (int k = 0; k < 3; ++k) {
        const std::vector<double> qe = resample(sensor.quantumEfficiency[size_t(byCode[size_t(k)])], grid);
        std::vector<double> w(nm.size());
        for (size_t b = 0; b < nm.size(); ++b) w[b] = qe[b] * lens[b] * nm[b] * grid.step_nm;
        camera.weights.push_back(std::move(w));
    }
    const std::string& light = sensor.processor.illuminant;
    const std::vector<double> illuminant = resample(library.get(light, Where{sensor.file.string(), "processor"}), grid);
    out.processor = fitProcessorColour(camera, illuminant, grid, library, sensor.processor,
                                       Where{sensor.file.string(), "quantum_efficiency"});
    return out;
}

}  // namespace metamer
