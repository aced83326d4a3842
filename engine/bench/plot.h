// The bench's picture: time per frame (x, log) against ΔE2000 p95 (y, log), one marker per
// configuration coloured by mode and labelled, and the Pareto front joined by a line. Drawn with
// OpenImageIO's ImageBufAlgo; text needs a TrueType font file (DejaVu Sans from Debian's
// fonts-dejavu-core), without which the plot is drawn without text and a warning is given.
// Tests: engine/bench/bench_test.cpp.
#pragma once

#include "bench/bench.h"

#include <filesystem>
#include <string>

namespace metamer {

// Where the plot's font is looked for; METAMER_FONT overrides.
std::filesystem::path benchPlotFont();

// ΔE2000 p95 values below this are drawn at it (a log axis has no 0); the plot says so.
constexpr double kBenchPlotFloor = 1e-4;

struct BenchPlotOptions {
    int width = 960, height = 640;
    std::filesystem::path font = benchPlotFont();  // empty or missing: no text
};

// Writes an 8-bit sRGB PNG atomically. Returns false when it had to draw without text.
bool writeBenchPlot(const std::filesystem::path& path, const BenchResult& result, const BenchPlotOptions& options = {});

}  // namespace metamer
