#pragma once
// Single-crossing tables (issue 50): the response pass through filters without a per-band sum where
// a pixel's light path crosses one sheet or medium channel only.
//
// Through channel e at optical depth x (sheets: crossings; media: path length in the frame's unit),
// a detector-weighted spectrum r_b (a record w_cb·ρ_b·E_lb, or w_cb·ê_b/λ_b) responds
//     F(x) = Σ_b r_b·2^(x·k_eb),        k_eb ≤ 0: channel e's log2 τ per unit depth,
// a smooth function of one variable known once per scene. It is tabulated at x_i = i·h with F and
// h·F', and read by cubic Hermite interpolation. Its error on [x_i, x_i + h] is at most
// h⁴/384·max|F''''| ≤ (h·ln2·K)⁴/384 · 2^(h·K) · G(x), with K = max_b |k_eb| over the detector's
// bands and G(x) = Σ_b |r_b|·2^(x·k_eb) (= F(x) for a detector with non-negative weights): with
// h·ln2·K = 0.15 that is 1.5 × 10⁻⁶ of the value itself, under the response pass's bound of 10⁻⁵.
// x runs up to twice the most one path can cross (the camera's and a light's path added): a sheet
// material's triangles, a medium's bounding-box diagonal (a straight line inside a box is at most
// its diagonal long).
// Tests: engine/render/spectral_packing_test.cpp (CrossingTablesInterpolateEveryChannelWithinTheCertifiedBound),
// tests/response_pass_test.cpp (through filters, against the cube path).
#include <glm/glm.hpp>

#include <cstddef>

#include <vector>

namespace metamer {

// Channel e's nodes x_i = i·h, i < nodes (0: no table — the pixel sums per band), and their index
// among all channels' nodes (a table's rows are [channel's first + i]).
struct CrossingAxis {
    double h = 0.0;
    int nodes = 0;
    int first = 0;
    std::vector<double> log2Tau;  // k_eb per band: the channel's rows, as float, as the shader reads them
    std::vector<double> powers;   // 2^(x_i·k_eb), [node][band]
};
struct CrossingAxes {
    std::vector<CrossingAxis> channels;
    int totalNodes = 0;
};

// The sheets' and media's channels: their axes, from each channel's deepest crossing `mostDepth[e]`
// (0: not drawn) and its rows in `depthSpectra` (bandLayers vec4 per channel, `bands` bands), for the
// band layers [firstLayer, endLayer) a detector sees. At most maxNodes per channel.
CrossingAxes crossingAxes(const std::vector<double>& mostDepth, const std::vector<glm::vec4>& depthSpectra, int bandLayers,
                          size_t bands, int firstLayer, int endLayer, int maxNodes = 2048);

// The error bound's factor (h·ln2·K)⁴/384·2^(h·K) of an axis built by crossingAxes.
double crossingTableBound();

// Appends the table of the weighted spectra `weighted` [channel][band] (vec4-padded channels:
// weighted.size() a multiple of 4) for every channel with nodes: per channel, node i, F as
// weighted.size()/4 vec4 then h·F' as many (the layout spectral.frag's respondFromTable reads).
void appendCrossingTable(std::vector<glm::vec4>& out, const CrossingAxes& axes, const std::vector<std::vector<double>>& weighted);

// F(x) for channel e by the same interpolation (C++, for tests): channel c of the table at `table`.
double crossingTableAt(const std::vector<glm::vec4>& out, size_t table, const CrossingAxes& axes, int e, int c,
                       size_t vec4PerValue, double x);

}  // namespace metamer
