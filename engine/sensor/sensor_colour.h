// What the image processor and a raw converter need to develop a simulated RGB sensor's raw
// frames: the processor's colour correction and the DNG colour matrix that matches it, fitted from
// the sensor's own quantum efficiencies on the ColorChecker under the processor's illuminant
// (isp/image_processor), and its CFA in DNG's colour codes. docs/camera.md.
// Tests: tests/python/test_sensor.py, tests/python/test_isp.py (rawpy develops the DNG as the processor does).
#pragma once

#include "sensor/sensor_spec.h"

#include <array>
#include <optional>

namespace metamer {

struct SensorColour {
    std::array<uint8_t, 4> cfa{};          // the 2 × 2 tile: 0 red, 1 green, 2 blue
    // The processor's fit under its illuminant (isp/image_processor.h): the DNG's ColorMatrix1 is
    // processor.dngColorMatrix, and its AsShotNeutral the neutral a frame's white balance used.
    ProcessorColour processor;
};

// The colour data of a sensor with a 2 × 2 CFA of three channels named r…, g…, b…, fitted for its
// processor (its "processor" section's illuminant and correction); nothing for any other (a
// monochrome sensor, a multispectral filter array), which has no DNG and is not developed.
std::optional<SensorColour> sensorColour(const SensorSpec& sensor, const SpectrumLibrary& library);

}  // namespace metamer
