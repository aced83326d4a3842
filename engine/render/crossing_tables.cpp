#include "render/crossing_tables.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace metamer {

namespace {
// h·ln2·K: the interpolation's error bound (crossing_tables.h) is (0.15)⁴/384·e^0.15 ≈ 1.5e-6.
constexpr double kStep = 0.15;
}  // namespace

double crossingTableBound() { return std::pow(kStep, 4) / 384.0 * std::exp(kStep); }

CrossingAxes crossingAxes(const std::vector<double>& mostDepth, const std::vector<glm::vec4>& depthSpectra, int bandLayers,
                          size_t bands, int firstLayer, int endLayer, int maxNodes) {
    CrossingAxes axes;
    axes.channels.resize(mostDepth.size());
    for (size_t e = 0; e < axes.channels.size(); ++e) {
        CrossingAxis& a = axes.channels[e];
        const double most = mostDepth[e];
        // The channel's rows as float, as the shader reads them; K over the detector's bands.
        a.log2Tau.assign(bands, 0.0);
        double K = 0.0;
        for (size_t b = 0; b < bands; ++b) {
            a.log2Tau[b] = double(depthSpectra[e * size_t(bandLayers) + b / 4][int(b % 4)]);
            const int layer = int(b / 4);
            if (layer >= firstLayer && layer < endLayer) K = std::max(K, std::fabs(a.log2Tau[b]));
        }
        if (!(most > 0.0) || !std::isfinite(most)) continue;
        a.h = K > 0.0 ? kStep / (std::log(2.0) * K) : most;
        const double nodes = std::ceil(most / a.h) + 1.0;
        if (nodes > double(maxNodes)) continue;  // no table: this channel's pixels sum per band
        a.nodes = std::max(2, int(nodes));
        a.first = axes.totalNodes;
        axes.totalNodes += a.nodes;
        a.powers.resize(size_t(a.nodes) * bands);
        for (int i = 0; i < a.nodes; ++i)
            for (size_t b = 0; b < bands; ++b) a.powers[size_t(i) * bands + b] = std::exp2(double(i) * a.h * a.log2Tau[b]);
    }
    return axes;
}

void appendCrossingTable(std::vector<glm::vec4>& out, const CrossingAxes& axes, const std::vector<std::vector<double>>& weighted) {
    const size_t padded = weighted.size(), perValue = padded / 4;
    const size_t bands = weighted.empty() ? 0 : weighted[0].size();
    bool any = false;
    for (const auto& w : weighted)
        for (double v : w) any = any || v != 0.0;
    for (const CrossingAxis& a : axes.channels) {
        if (a.nodes == 0) continue;
        for (int i = 0; i < a.nodes; ++i) {
            std::vector<glm::vec4> value(perValue, glm::vec4(0.0f)), slope(perValue, glm::vec4(0.0f));
            if (any) {
                const double* power = &a.powers[size_t(i) * bands];
                for (size_t c = 0; c < padded; ++c) {
                    double f = 0.0, df = 0.0;
                    for (size_t b = 0; b < bands; ++b) {
                        const double term = weighted[c][b] * power[b];
                        f += term;
                        df += term * a.log2Tau[b];
                    }
                    value[c / 4][int(c % 4)] = float(f);
                    slope[c / 4][int(c % 4)] = float(df * std::log(2.0) * a.h);
                }
            }
            out.insert(out.end(), value.begin(), value.end());
            out.insert(out.end(), slope.begin(), slope.end());
        }
    }
}

double crossingTableAt(const std::vector<glm::vec4>& out, size_t table, const CrossingAxes& axes, int e, int c,
                       size_t perValue, double x) {
    const CrossingAxis& a = axes.channels[size_t(e)];
    const double u = x / a.h;
    const int i = std::min(int(u), a.nodes - 2);
    const double t = u - i;
    auto at = [&](int node, int which) {
        return double(out[table + (size_t(a.first + node) * 2 + size_t(which)) * perValue + size_t(c / 4)][c % 4]);
    };
    const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t), h01 = t * t * (3 - 2 * t),
                 h11 = t * t * (t - 1);
    return h00 * at(i, 0) + h10 * at(i, 1) + h01 * at(i + 1, 0) + h11 * at(i + 1, 1);
}

}  // namespace metamer
