// `metamer capture CUBE --sensor SENSOR`: what a simulated camera sensor records from a rendered
// spectral radiance cube (sensor/, docs/sensor.md) — the raw mosaic, the expected electrons and
// the metadata. Registered on the main CLI11 app by main.cpp.
// Tests: tests/python/test_sensor.py, tests/bad-inputs (the sensor- cases).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace metamer {

struct CaptureArgs {
    std::string cube;            // a spectral radiance cube: EXR, HDF5 or ENVI
    std::string sensor;          // a sensor file, or a library sensor's name
    std::string out = "out";
    uint64_t seed = 0, frame = 0;
    int frames = 1;              // frames seed … with frame numbers frame, frame + 1, …
    std::optional<double> exposure;
    bool noNoise = false;
    std::string illuminant;      // the scene's light for the image processor; empty: the sensor file's
};

CLI::App* addCaptureCommand(CLI::App& app, CaptureArgs& args);

// Writes, per frame, OUT/<stem>.raw[.<frame>].png and the frame's metadata; once,
// OUT/<stem>.electrons.exr. Returns 0; bad input throws (exit 2).
int runCapture(const CaptureArgs& args);

}  // namespace metamer
