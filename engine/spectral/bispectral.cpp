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

}  // namespace metamer
