// What a raw converter needs to develop a simulated RGB sensor's raw file: the DNG colour matrix
// (CIE 1931 XYZ → the camera's raw space under D65) and the as-shot neutral, from the sensor's own
// quantum efficiencies by the ColorChecker characterization of color/camera_characterization, and
// its CFA in DNG's colour codes. docs/sensor.md, "Outputs".
// Tests: tests/python/test_sensor.py (rawpy develops the DNG).
#pragma once

#include "sensor/sensor_spec.h"

#include <array>
#include <optional>

namespace metamer {

struct SensorColour {
    std::array<uint8_t, 4> cfa{};          // the 2 × 2 tile: 0 red, 1 green, 2 blue
    std::array<double, 9> xyzToCamera{};   // row-major; the D65 white maps to a maximum of 1
    std::array<double, 3> asShotNeutral{}; // the camera's raw response to the D65 white, maximum 1
    double rmsDeltaE2000 = 0.0;            // of the characterization on the 24 patches
};

// The colour data of a sensor with a 2 × 2 CFA of three channels named r…, g…, b…; nothing for
// any other (a monochrome sensor, a multispectral filter array), which has no DNG.
std::optional<SensorColour> sensorColour(const SensorSpec& sensor, const SpectrumLibrary& library);

}  // namespace metamer
