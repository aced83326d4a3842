// A small line plot for the probe panel: one or more spectra (radiance against wavelength) or
// channel values in one box, y from 0 (or the lowest value, if negative) to the largest value.
// Drawn with ImGui's draw list; hovering the box shows the nearest band's values.
// Tests: tests/preview_test.sh.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace metamer::preview {

struct PlotSeries {
    std::string label;
    std::vector<float> values;  // one per x
    uint32_t colour = 0xffffffff;  // ImGui's ABGR packing (IM_COL32)
};

// x: wavelengths in nm (spectral), else channel indices with `channelNames` as labels.
void plotSpectra(const char* id, const std::vector<double>& x, const std::vector<std::string>& channelNames,
                 const std::vector<PlotSeries>& series, const char* yUnit, float width, float height);

}  // namespace metamer::preview
