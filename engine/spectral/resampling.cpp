#include "spectral/resampling.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace metamer {

namespace {

// The data's spacing is uniform when every interval equals the first to 1e-9 of it.
bool uniformlySpaced(const std::vector<double>& w) {
    const double h = w[1] - w[0];
    for (size_t k = 1; k + 1 < w.size(); ++k)
        if (std::fabs((w[k + 1] - w[k]) - h) > 1e-9 * h) return false;
    return true;
}

// The index of the data point within kCoincidence_nm of x, or w.size().
size_t coincidentPoint(const std::vector<double>& w, double x) {
    size_t k = std::lower_bound(w.begin(), w.end(), x - kCoincidence_nm) - w.begin();
    return k < w.size() && std::fabs(w[k] - x) <= kCoincidence_nm ? k : w.size();
}

// The spacing of the data interval that holds x (x not a data point), or of the nearest end
// interval when x lies outside the data.
double localSpacing(const std::vector<double>& w, double x) {
    if (x <= w.front()) return w[1] - w[0];
    if (x >= w.back()) return w.back() - w[w.size() - 2];
    size_t j = std::upper_bound(w.begin(), w.end(), x) - w.begin() - 1;
    return w[j + 1] - w[j];
}

// Rule 2: the mean over [c − Δ/2, c + Δ/2] of the piecewise-linear data, 0 outside them, with the
// end value held over the part of the band past the data's end when the centre lies inside the
// data. On the segment [w_j, w_j+1] the function is v_j·(1 − t) + v_j+1·t, so its integral over a
// clipped piece [a, e] is (e − a)·((1 − t̄)·v_j + t̄·v_j+1), t̄ the piece's mean t.
void bandMeanWeights(const std::vector<double>& w, double c, double step, size_t& first, std::vector<double>& out) {
    const double lo = c - 0.5 * step, hi = c + 0.5 * step;
    const double a0 = std::max(lo, w.front()), b0 = std::min(hi, w.back());
    const bool centreInside = c >= w.front() && c <= w.back();
    out.clear();
    if (b0 <= a0 && !centreInside) return;
    const size_t last = w.size() - 1;
    size_t j0 = std::upper_bound(w.begin(), w.end(), a0) - w.begin();
    j0 = j0 == 0 ? 0 : j0 - 1;
    size_t j1 = std::upper_bound(w.begin(), w.end(), b0) - w.begin();
    j1 = std::min(j1, last);
    if (centreInside) {
        if (lo < w.front()) j0 = 0;
        if (hi > w.back()) j1 = last;
    }
    out.assign(j1 - j0 + 1, 0.0);
    for (size_t j = j0; j < j1; ++j) {
        const double a = std::max(a0, w[j]), e = std::min(b0, w[j + 1]);
        if (e <= a) continue;
        const double tMean = (0.5 * (a + e) - w[j]) / (w[j + 1] - w[j]);
        out[j - j0] += (e - a) * (1.0 - tMean);
        out[j + 1 - j0] += (e - a) * tMean;
    }
    if (centreInside) {
        if (lo < w.front()) out[0] += w.front() - lo;
        if (hi > w.back()) out[last - j0] += hi - w.back();
    }
    for (double& x : out) x /= step;
    first = j0;
}

}  // namespace

std::vector<double> spragueWeights(size_t n, size_t j, double t, size_t& first) {
    // CIE 167:2005: the interval [y0, y1] is y0 + a1·t + … + a5·t⁵ with aₖ = (rowₖ · (y−2 … y3))/24.
    static constexpr int kPoly[5][6] = {{2, -16, 0, 16, -2, 0},
                                        {-1, 16, -30, 16, -1, 0},
                                        {-9, 39, -70, 66, -33, 7},
                                        {13, -64, 126, -124, 61, -12},
                                        {-5, 25, -50, 50, -25, 5}};
    // The two points beyond each end, from the six end values, /209.
    static constexpr int kEnds[4][6] = {{884, -1960, 3033, -2648, 1080, -180},   // y−2
                                        {508, -540, 488, -367, 144, -24},        // y−1
                                        {-24, 144, -367, 488, -540, 508},        // yn
                                        {-180, 1080, -2648, 3033, -1960, 884}};  // yn+1
    const long nn = long(n), jj = long(j);
    long lo = std::max(0L, jj - 2), hi = std::min(nn - 1, jj + 3);
    if (jj - 2 < 0) hi = std::max(hi, 5L);
    if (jj + 3 > nn - 1) lo = std::min(lo, nn - 6);
    first = size_t(lo);
    std::vector<double> out(size_t(hi - lo + 1), 0.0);
    double tk[6] = {1, t, t * t, t * t * t, t * t * t * t, t * t * t * t * t};
    for (int m = 0; m < 6; ++m) {
        double weight = m == 2 ? 1.0 : 0.0;
        for (int k = 0; k < 5; ++k) weight += kPoly[k][m] * tk[k + 1] / 24.0;
        const long d = jj - 2 + m;  // the value's index; −2, −1, n, n + 1 are the extrapolated points
        if (d >= 0 && d < nn) {
            out[size_t(d - lo)] += weight;
            continue;
        }
        const int row = d == -2 ? 0 : d == -1 ? 1 : d == nn ? 2 : 3;
        const long base = row < 2 ? 0 : nn - 6;
        for (int i = 0; i < 6; ++i) out[size_t(base + i - lo)] += weight * kEnds[row][i] / 209.0;
    }
    return out;
}

BandRule bandRule(const std::vector<double>& w, const Grid& grid, int band) {
    const double c = grid.wavelength(band);
    if (grid.resampling == Resampling::BandMean) return BandRule::BandMean;
    if (coincidentPoint(w, c) < w.size()) return BandRule::Tabulated;
    if (grid.step_nm > localSpacing(w, c) * (1.0 + 1e-9)) return BandRule::BandMean;
    if (c < w.front() || c > w.back()) return BandRule::Outside;
    return BandRule::Interpolated;
}

BandWeights bandWeights(const std::vector<double>& w, const Grid& grid) {
    const int n = grid.bands();
    BandWeights bw;
    bw.first.assign(n, 0);
    bw.weights.assign(n, {});
    const bool sprague = grid.resampling == Resampling::Sprague && w.size() >= 6 && uniformlySpaced(w);
    for (int b = 0; b < n; ++b) {
        const double c = grid.wavelength(b);
        switch (bandRule(w, grid, b)) {
            case BandRule::Tabulated:
                bw.first[b] = coincidentPoint(w, c);
                bw.weights[b] = {1.0};
                break;
            case BandRule::BandMean: bandMeanWeights(w, c, grid.step_nm, bw.first[b], bw.weights[b]); break;
            case BandRule::Outside: break;
            case BandRule::Interpolated: {
                const size_t j = std::upper_bound(w.begin(), w.end(), c) - w.begin() - 1;
                const double t = (c - w[j]) / (w[j + 1] - w[j]);
                if (sprague) {
                    bw.weights[b] = spragueWeights(w.size(), j, t, bw.first[b]);
                } else {
                    bw.first[b] = j;
                    bw.weights[b] = {1.0 - t, t};
                }
                break;
            }
        }
    }
    return bw;
}

std::vector<double> BandWeights::apply(const std::vector<double>& values) const {
    std::vector<double> out(first.size(), 0.0);
    for (size_t b = 0; b < first.size(); ++b) out[b] = at(b, values.data());
    return out;
}

std::vector<double> resample(const Spectrum& s, const Grid& grid) {
    if (s.constant) return std::vector<double>(size_t(grid.bands()), *s.constant);
    return bandWeights(s.wavelengths_nm, grid).apply(s.values);
}

CoverageGap coverageOf(const std::vector<double>& w, const Grid& grid) {
    CoverageGap g;
    g.data_lo = w.front();
    g.data_hi = w.back();
    // Band centres are what matter: a band is covered when its centre lies inside the data.
    g.covered = g.data_lo <= grid.start_nm && g.data_hi >= grid.end_nm;
    g.overlaps = g.data_hi >= grid.start_nm && g.data_lo <= grid.end_nm;
    return g;
}

CoverageGap coverage(const Spectrum& s, const Grid& grid) {
    if (s.constant) return CoverageGap{};
    return coverageOf(s.wavelengths_nm, grid);
}

}  // namespace metamer
