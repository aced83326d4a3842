#include "color/astm_e308.h"

#include "color/cie_xyz.h"
#include "spectral/resampling.h"

#include <fmt/ranges.h>

#include <cmath>

namespace metamer {

namespace {

constexpr int kPracticeNm = int(kAstmE308EndNm - kAstmE308StartNm) + 1;  // 421 whole nm

// Lagrange basis polynomial j over the nodes 0 … count−1, at position x.
double lagrange(int j, int count, double x) {
    double l = 1.0;
    for (int i = 0; i < count; ++i)
        if (i != j) l *= (x - i) / double(j - i);
    return l;
}

// ASTM E2022's table for samples every `interval` nm from 360 nm: [channel][sample].
std::vector<std::vector<double>> e2022Table(const std::vector<std::vector<double>>& cmf, const std::vector<double>& s,
                                            int interval) {
    const int samples = (kPracticeNm - 1) / interval + 1;
    const int complete = (samples - 1) * interval;  // 1 nm index of the last sample
    std::vector<std::vector<double>> w(cmf.size(), std::vector<double>(size_t(samples), 0.0));
    for (size_t c = 0; c < cmf.size(); ++c) {
        for (int m = 0; m <= complete; ++m) {
            const double sc = s[size_t(m)] * cmf[c][size_t(m)];
            const int k = m / interval, rest = m % interval;
            if (rest == 0) {
                w[c][size_t(k)] += sc;
                continue;
            }
            // Between samples k and k + 1: quadratic through the first or last three samples in the
            // end intervals, cubic through k − 1 … k + 2 inside.
            const double r = double(rest) / interval;
            int firstNode = k - 1, nodes = 4;
            double x = 1.0 + r;
            if (k == 0) {
                firstNode = 0, nodes = 3, x = r;
            } else if (k == samples - 2) {
                firstNode = samples - 3, nodes = 3;
            }
            for (int j = 0; j < nodes; ++j) w[c][size_t(firstNode + j)] += lagrange(j, nodes, x) * sc;
        }
        // An incomplete last interval (not for 1, 5, 10, 20 nm over 360–780) goes to the last sample.
        for (int m = complete + 1; m < kPracticeNm; ++m) w[c][size_t(samples - 1)] += s[size_t(m)] * cmf[c][size_t(m)];
    }
    return w;
}

// Adds the weights of table samples outside [lo, hi] (sample indices) to samples lo and hi.
void foldEnds(std::vector<double>& w, int lo, int hi) {
    for (int k = 0; k < lo; ++k) w[size_t(lo)] += w[size_t(k)], w[size_t(k)] = 0;
    for (int k = hi + 1; k < int(w.size()); ++k) w[size_t(hi)] += w[size_t(k)], w[size_t(k)] = 0;
}

bool wholeNm(double x) { return std::fabs(x - std::round(x)) < 1e-9; }

}  // namespace

std::vector<std::vector<double>> astmE308Weights(const std::vector<std::vector<double>>& cmf,
                                                 const std::vector<double>& s, const Grid& grid, const Where& where) {
    if (s.size() != size_t(kPracticeNm))
        failRuntime("ASTM E308: the illuminant needs {} values (360–780 nm at 1 nm), got {}", kPracticeNm, s.size());
    const double step = grid.step_nm;
    const int interval = int(std::lround(step));
    if (!wholeNm(step) || (interval != 1 && interval != 5 && interval != 10 && interval != 20))
        failInput(where, "ASTM E308 weights exist for 1, 5, 10 and 20 nm data; the grid {} has a {:g} nm step",
                  grid.str(), step);
    const int alignment = interval == 20 ? 10 : interval;  // the table's samples fall on multiples of this
    if (!wholeNm(grid.start_nm) || std::lround(grid.start_nm) % alignment != 0)
        failInput(where, "ASTM E308 needs band centres on multiples of {} nm (its tables' wavelengths); the grid {} "
                  "starts at {:g} nm",
                  alignment, grid.str(), grid.start_nm);
    // The grid's bands inside the practice range.
    int b0 = -1, b1 = -1;
    for (int b = 0; b < grid.bands(); ++b) {
        const double l = grid.wavelength(b);
        if (l < kAstmE308StartNm - 1e-9 || l > kAstmE308EndNm + 1e-9) continue;
        if (b0 < 0) b0 = b;
        b1 = b;
    }
    if (b0 < 0 || b1 - b0 < 2)
        failInput(where, "ASTM E308 needs at least 3 bands inside 360–780 nm; the grid {} has {}", grid.str(),
                  b0 < 0 ? 0 : b1 - b0 + 1);
    const int lo = int(std::lround(grid.wavelength(b0) - kAstmE308StartNm));  // nm above 360
    const int hi = int(std::lround(grid.wavelength(b1) - kAstmE308StartNm));
    std::vector<std::vector<double>> out(cmf.size(), std::vector<double>(size_t(grid.bands()), 0.0));
    for (size_t c = 0; c < cmf.size(); ++c) {
        if (interval <= 5) {
            // Summation at the data's own wavelengths; the practice range's samples beyond the data
            // go to the end bands as everywhere in E308.
            std::vector<double> w(size_t((kPracticeNm - 1) / interval + 1), 0.0);
            for (size_t k = 0; k < w.size(); ++k) w[k] = s[k * interval] * cmf[c][k * interval] * interval;
            foldEnds(w, lo / interval, hi / interval);
            for (int b = b0; b <= b1; ++b) out[c][size_t(b)] = w[size_t(lo / interval + (b - b0))];
            continue;
        }
        std::vector<double> w10 = e2022Table(cmf, s, 10)[c];
        foldEnds(w10, lo / 10, hi / 10);
        if (interval == 10) {
            for (int b = b0; b <= b1; ++b) out[c][size_t(b)] = w10[size_t(lo / 10 + (b - b0))];
            continue;
        }
        // 20 nm: v10[2j] = v[j]; v10[2j+1] from v[j−1 … j+2] (−1, 9, 9, −1)/16, with
        // p(−1) = 3v0 − 3v1 + v2 and p(n) = v(n−3) − 3v(n−2) + 3v(n−1) past the ends.
        const int n = b1 - b0 + 1;
        std::vector<double> w20(size_t(n), 0.0);
        auto addP = [&](int j, double weight) {
            if (j >= 0 && j < n) {
                w20[size_t(j)] += weight;
            } else if (j < 0) {
                w20[0] += 3 * weight, w20[1] -= 3 * weight, w20[2] += weight;
            } else {
                w20[size_t(n - 3)] += weight, w20[size_t(n - 2)] -= 3 * weight, w20[size_t(n - 1)] += 3 * weight;
            }
        };
        for (int m = 0; m <= 2 * (n - 1); ++m) {
            const double wm = w10[size_t(lo / 10 + m)];
            if (m % 2 == 0) {
                w20[size_t(m / 2)] += wm;
                continue;
            }
            const int j = m / 2;
            addP(j - 1, -wm / 16), addP(j, 9 * wm / 16), addP(j + 1, 9 * wm / 16), addP(j + 2, -wm / 16);
        }
        for (int b = b0; b <= b1; ++b) out[c][size_t(b)] = w20[size_t(b - b0)];
    }
    return out;
}

std::vector<double> practiceRangeIlluminant(const ReferenceWhite& white) {
    std::vector<double> s(size_t(kPracticeNm), 0.0);
    for (const auto& [spectrum, factor] : white.terms) {
        if (spectrum.isConstant()) {
            for (double& v : s) v += *spectrum.constant * factor;
            continue;
        }
        // Inside the data: Sprague from uniform data (CIE 167, as the standard and colour-science
        // interpolate an illuminant to 1 nm), linear otherwise; beyond them the end values held.
        Grid oneNm{kAstmE308StartNm, kAstmE308EndNm, 1.0};
        oneNm.resampling = Resampling::Sprague;
        const std::vector<double> v = resample(spectrum, oneNm);
        for (int m = 0; m < kPracticeNm; ++m) {
            const double l = kAstmE308StartNm + m;
            double x = v[size_t(m)];
            if (l < spectrum.minWavelength()) x = spectrum.values.front();
            if (l > spectrum.maxWavelength()) x = spectrum.values.back();
            s[size_t(m)] += x * factor;
        }
    }
    return s;
}

void applyAstmE308(Detector& d, const SpectrumLibrary& library, const ReferenceWhite& white, const Where& where) {
    if (d.kind != DetectorKind::Observer)
        failInput(where, "ASTM E308 weighting factors are defined for the CIE observers (cie1931, cie1964), not {}",
                  d.name);
    const ColorMatchingFunctions cmfs = loadObserver(library, d.source, Grid{kAstmE308StartNm, kAstmE308EndNm, 1.0});
    const std::vector<std::vector<double>> w =
        astmE308Weights({cmfs.x, cmfs.y, cmfs.z}, practiceRangeIlluminant(white), d.grid, where);
    std::vector<std::string> dropped;
    for (size_t b = 0; b < white.irradiance.size(); ++b) {
        const double e = white.irradiance[b];
        bool lost = false;
        for (size_t c = 0; c < 3; ++c) {
            d.weights[c][b] = e != 0.0 ? w[c][b] / e : 0.0;
            lost = lost || (e == 0.0 && w[c][b] != 0.0);
        }
        if (lost) dropped.push_back(fmt::format("{:g}", d.grid.wavelength(int(b))));
    }
    if (!dropped.empty())
        warn(where, fmt::format("ASTM E308: the reference white {} has no power at {} nm, where its weighting "
                                "factor is not 0; those bands are left out",
                                white.source, fmt::join(dropped, ", ")));
    d.integration = Integration::AstmE308;
}

}  // namespace metamer
