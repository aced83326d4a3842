#include "spectral/bispectral.h"

#include <algorithm>
#include <cmath>

namespace metamer {

namespace {

// Index j with w[j] ≤ x ≤ w[j+1] and the fraction t of the way from w[j] to w[j+1]; the caller
// has checked that x lies inside [w.front(), w.back()].
void locate(const std::vector<double>& w, double x, size_t& j, double& t) {
    size_t i = std::upper_bound(w.begin(), w.end(), x) - w.begin();
    if (i == w.size()) {
        j = w.size() - 2;
        t = 1.0;
        return;
    }
    j = i - 1;
    t = (x - w[j]) / (w[i] - w[j]);
}

void validateAxis(const std::vector<double>& w, const Where& where, const char* axis) {
    if (w.size() < 2) failInput(where, "a Donaldson matrix needs at least 2 {} wavelengths, got {}", axis, w.size());
    for (size_t i = 0; i < w.size(); ++i) {
        if (!std::isfinite(w[i]) || !(w[i] > 0))
            failInput(where, "{} wavelength {} ({:g}) must be a positive finite number", axis, i, w[i]);
        if (i > 0 && !(w[i] > w[i - 1]))
            failInput(where, "{} wavelengths must increase strictly: {:g} nm follows {:g} nm", axis, w[i], w[i - 1]);
    }
}

}  // namespace

double BispectralMatrix::at(double in, double out) const {
    if (in < in_nm.front() || in > in_nm.back() || out < out_nm.front() || out > out_nm.back()) return 0.0;
    size_t i, o;
    double s, t;
    locate(in_nm, in, i, s);
    locate(out_nm, out, o, t);
    return (1 - s) * ((1 - t) * value(i, o) + t * value(i, o + 1)) +
           s * ((1 - t) * value(i + 1, o) + t * value(i + 1, o + 1));
}

double BispectralMatrix::integral() const {
    double sum = 0.0;
    for (size_t i = 0; i + 1 < in_nm.size(); ++i)
        for (size_t o = 0; o + 1 < out_nm.size(); ++o)
            sum += (in_nm[i + 1] - in_nm[i]) * (out_nm[o + 1] - out_nm[o]) * 0.25 *
                   (value(i, o) + value(i + 1, o) + value(i, o + 1) + value(i + 1, o + 1));
    return sum;
}

void BispectralMatrix::validate(const Where& where) const {
    validateAxis(in_nm, where, "excitation (λin)");
    validateAxis(out_nm, where, "emission (λout)");
    if (values.size() != in_nm.size() * out_nm.size())
        failInput(where, "{} values for {} × {} wavelengths", values.size(), in_nm.size(), out_nm.size());
    for (size_t i = 0; i < in_nm.size(); ++i)
        for (size_t o = 0; o < out_nm.size(); ++o) {
            double v = value(i, o);
            if (!std::isfinite(v))
                failInput(where, "D({:g} nm, {:g} nm) is not a finite number", in_nm[i], out_nm[o]);
            if (v < 0)
                failInput(where, "D({:g} nm, {:g} nm) = {:g} is negative: re-radiated power is ≥ 0", in_nm[i],
                          out_nm[o], v);
        }
}

BispectralMatrix BispectralMatrix::outer(const Spectrum& excitation, const Spectrum& emission) {
    if (excitation.isConstant() || emission.isConstant())
        failRuntime("BispectralMatrix::outer needs sampled spectra");
    BispectralMatrix d;
    d.in_nm = excitation.wavelengths_nm;
    d.out_nm = emission.wavelengths_nm;
    d.values.reserve(d.in_nm.size() * d.out_nm.size());
    for (double a : excitation.values)
        for (double e : emission.values) d.values.push_back(a * e);
    d.source = "outer(" + excitation.source + ", " + emission.source + ")";
    return d;
}

std::vector<double> BandWeights::apply(const std::vector<double>& values) const {
    std::vector<double> out(first.size(), 0.0);
    for (size_t b = 0; b < first.size(); ++b)
        for (size_t k = 0; k < weights[b].size(); ++k) out[b] += weights[b][k] * values[first[b] + k];
    return out;
}

BandWeights bandWeights(const std::vector<double>& w, const Grid& grid) {
    // resample() in spectrum.cpp, written per data value: on the segment [w_j, w_j+1] the
    // function is v_j·(1 − t) + v_j+1·t, so its integral over a clipped piece [a, b] is
    // (b − a)·((1 − t̄)·v_j + t̄·v_j+1) with t̄ the piece's mean t.
    const int n = grid.bands();
    const double h = 0.5 * grid.step_nm;
    BandWeights bw;
    bw.first.assign(n, 0);
    bw.weights.assign(n, {});
    const size_t last = w.size() - 1;
    for (int b = 0; b < n; ++b) {
        const double c = grid.wavelength(b), lo = c - h, hi = c + h;
        const double a0 = std::max(lo, w.front()), b0 = std::min(hi, w.back());
        const bool centreInside = c >= w.front() && c <= w.back();
        if (b0 <= a0 && !centreInside) continue;
        // Data indices touched: the segments overlapping [a0, b0], and the ends when extended.
        size_t j0 = std::upper_bound(w.begin(), w.end(), a0) - w.begin();
        j0 = j0 == 0 ? 0 : j0 - 1;
        size_t j1 = std::upper_bound(w.begin(), w.end(), b0) - w.begin();
        j1 = std::min(j1, last);
        if (centreInside) {
            if (lo < w.front()) j0 = 0;
            if (hi > w.back()) j1 = last;
        }
        std::vector<double> weight(j1 - j0 + 1, 0.0);
        for (size_t j = j0; j < j1; ++j) {
            const double a = std::max(a0, w[j]), e = std::min(b0, w[j + 1]);
            if (e <= a) continue;
            const double span = w[j + 1] - w[j];
            const double tMean = (0.5 * (a + e) - w[j]) / span;
            weight[j - j0] += (e - a) * (1.0 - tMean);
            weight[j + 1 - j0] += (e - a) * tMean;
        }
        // The end rule: a band whose centre lies inside the data holds the end value over the
        // part of the band the data do not reach.
        if (centreInside) {
            if (lo < w.front()) weight[0] += w.front() - lo;
            if (hi > w.back()) weight[last - j0] += hi - w.back();
        }
        for (double& x : weight) x /= grid.step_nm;
        bw.first[b] = j0;
        bw.weights[b] = std::move(weight);
    }
    return bw;
}

std::vector<double> resampleMatrix(const BispectralMatrix& d, const Grid& grid) {
    const size_t n = size_t(grid.bands());
    const BandWeights win = bandWeights(d.in_nm, grid), wout = bandWeights(d.out_nm, grid);
    // First along λout for every data row, then along λin: R = Win · D · Woutᵀ.
    std::vector<double> rows(d.inCount() * n, 0.0);  // [data i][band o]
    for (size_t i = 0; i < d.inCount(); ++i) {
        const double* row = &d.values[i * d.outCount()];
        for (size_t o = 0; o < n; ++o) {
            double s = 0.0;
            for (size_t k = 0; k < wout.weights[o].size(); ++k) s += wout.weights[o][k] * row[wout.first[o] + k];
            rows[i * n + o] = s;
        }
    }
    std::vector<double> r(n * n, 0.0);
    for (size_t b = 0; b < n; ++b)
        for (size_t k = 0; k < win.weights[b].size(); ++k) {
            const double wk = win.weights[b][k];
            if (wk == 0.0) continue;
            const double* src = &rows[(win.first[b] + k) * n];
            double* dst = &r[b * n];
            for (size_t o = 0; o < n; ++o) dst[o] += wk * src[o];
        }
    return r;
}

CoverageGap coverageOf(const std::vector<double>& w, const Grid& grid) {
    CoverageGap g;
    g.data_lo = w.front();
    g.data_hi = w.back();
    g.covered = g.data_lo <= grid.start_nm && g.data_hi >= grid.end_nm;
    g.overlaps = g.data_hi >= grid.start_nm && g.data_lo <= grid.end_nm;
    return g;
}

}  // namespace metamer
