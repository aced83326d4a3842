// Raw sensor images as DNG (Adobe's Digital Negative, a TIFF with DNG's tags), written through
// libtiff: a 2 × 2 Bayer mosaic (or a monochrome LinearRaw image) of 16-bit digital numbers with its CFA pattern, black and white
// levels, a colour matrix (XYZ → camera under D65) and the as-shot neutral, so that raw converters
// (LibRaw/rawpy, dcraw, darktable, RawTherapee) open and develop it. Written through an
// AtomicOutput: the file appears whole or not at all. docs/sensor.md, "Outputs".
// Tests: tests/python/test_sensor.py (rawpy reads it back).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

struct DngRaw {
    int width = 0, height = 0;
    const uint16_t* pixels = nullptr;  // width × height digital numbers, row 0 at the top
    // The CFA tile, 2 × 2, row by row, in DNG's colour codes: 0 red, 1 green, 2 blue.
    std::array<uint8_t, 4> cfa{0, 1, 1, 2};
    // A monochrome sensor: LinearRaw, one sample per pixel, no CFA, colour matrix or neutral.
    bool monochrome = false;
    double blackLevel = 0.0;
    uint32_t whiteLevel = 65535;
    std::array<double, 9> colorMatrix1{};  // XYZ (D65 white, Y = 1) → camera, row-major
    std::array<double, 3> asShotNeutral{1.0, 1.0, 1.0};  // the camera's response to the white, max 1
    std::string model = "Metamer simulated sensor";
    std::string description;
};

void writeDng(const std::filesystem::path& path, const DngRaw& raw);

}  // namespace metamer
