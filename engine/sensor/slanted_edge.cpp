#include "sensor/slanted_edge.h"

#include "sensor/fftw_planner.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kOversampling = 4;

// The centroid of a row's derivative |I(x+1) − I(x)| (at x + 1/2 … shifted to pixel centres),
// Hamming-windowed about a first estimate so that noise far from the edge does not pull it.
double rowCentroid(const double* row, int width) {
    std::vector<double> d(size_t(width - 1));
    for (int x = 0; x + 1 < width; ++x) d[size_t(x)] = row[x + 1] - row[x];
    auto centroid = [&](const std::vector<double>& w) {
        double s = 0.0, sx = 0.0;
        for (size_t x = 0; x < d.size(); ++x) s += std::abs(d[x]) * w[x], sx += std::abs(d[x]) * w[x] * (double(x) + 0.5);
        return s > 0.0 ? sx / s : -1.0;
    };
    const double first = centroid(std::vector<double>(d.size(), 1.0));
    if (first < 0.0) return first;
    std::vector<double> w(d.size());
    const double half = 0.5 * double(d.size());
    for (size_t x = 0; x < d.size(); ++x) {
        const double u = (double(x) + 0.5 - first) / half;
        w[x] = std::abs(u) >= 1.0 ? 0.0 : 0.54 + 0.46 * std::cos(kPi * u);
    }
    return centroid(w);
}

}  // namespace

EdgeSfr slantedEdgeSfr(const std::vector<double>& image, int width, int height, const Where& where) {
    if (width < 16 || height < 16 || image.size() != size_t(width) * size_t(height))
        failInput(where, "a slanted-edge region needs at least 16 × 16 pixels; got {} × {}", width, height);
    double lo = image.front(), hi = image.front();
    for (double v : image) lo = std::min(lo, v), hi = std::max(hi, v);
    if (!(hi > lo)) failInput(where, "the region has no contrast: no edge to measure");

    // 1. The edge's position in each row, and a line x = a + b·y fitted to them.
    std::vector<double> ys, xs;
    for (int y = 0; y < height; ++y) {
        const double c = rowCentroid(image.data() + size_t(y) * size_t(width), width);
        if (c >= 0.0) ys.push_back(y + 0.5), xs.push_back(c);
    }
    if (ys.size() < 8) failInput(where, "an edge was found in only {} rows", ys.size());
    double my = 0.0, mx = 0.0;
    for (size_t i = 0; i < ys.size(); ++i) my += ys[i], mx += xs[i];
    my /= double(ys.size()), mx /= double(ys.size());
    double sxy = 0.0, syy = 0.0;
    for (size_t i = 0; i < ys.size(); ++i) sxy += (ys[i] - my) * (xs[i] - mx), syy += (ys[i] - my) * (ys[i] - my);
    const double b = sxy / syy, a = mx - b * my;
    EdgeSfr out;
    out.angle_deg = std::atan(b) * 180.0 / kPi;
    // The rows must sweep the edge through at least one pixel for the 4× bins to fill, and the
    // edge must stay near-vertical for the rows to see it.
    if (std::abs(out.angle_deg) < 1.0 || std::abs(out.angle_deg) > 20.0)
        failInput(where, "the edge is {:.2f}° from the vertical; the slanted-edge method needs 1° … 20°", out.angle_deg);

    // 2. Every pixel binned by its distance from the line along the normal, 1/4 pixel per bin.
    const double norm = std::sqrt(1.0 + b * b);
    const int bins = kOversampling * width;
    std::vector<double> sum(size_t(bins), 0.0), count(size_t(bins), 0.0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double d = (x + 0.5 - (a + b * (y + 0.5))) / norm;  // pixels, along the normal
            const int bin = int(std::floor(d * kOversampling)) + bins / 2;
            if (bin < 0 || bin >= bins) continue;
            sum[size_t(bin)] += image[size_t(y) * width + size_t(x)];
            count[size_t(bin)] += 1.0;
        }
    // Bins near the ends may be empty: only the run of filled bins around the edge is used.
    int first = bins / 2, last = bins / 2;
    while (first > 0 && count[size_t(first - 1)] > 0.0) --first;
    while (last + 1 < bins && count[size_t(last + 1)] > 0.0) ++last;
    const int n = last - first + 1;
    if (n < 4 * kOversampling) failInput(where, "too few pixels on either side of the edge");
    std::vector<double> esf(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) esf[size_t(i)] = sum[size_t(first + i)] / count[size_t(first + i)];

    // 3. The LSF: the ESF's central difference, Hamming-windowed about its centroid.
    std::vector<double> lsf(size_t(n), 0.0);
    for (int i = 1; i + 1 < n; ++i) lsf[size_t(i)] = 0.5 * (esf[size_t(i + 1)] - esf[size_t(i - 1)]);
    double s = 0.0, si = 0.0;
    for (int i = 0; i < n; ++i) s += std::abs(lsf[size_t(i)]), si += std::abs(lsf[size_t(i)]) * i;
    const double centre = si / s;
    const double half = std::max(centre, double(n - 1) - centre);
    for (int i = 0; i < n; ++i) lsf[size_t(i)] *= 0.54 + 0.46 * std::cos(kPi * (i - centre) / half);

    // 4. |DFT| normalized at 0, divided by the central difference's transfer sin(2πfΔ)/(2πfΔ)
    //    (Δ = 1/4 pixel), up to twice the Nyquist frequency.
    double* in;
    fftw_complex* spectrum;
    fftw_plan plan;
    {
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        in = fftw_alloc_real(size_t(n));
        spectrum = fftw_alloc_complex(size_t(n / 2 + 1));
        plan = fftw_plan_dft_r2c_1d(n, in, spectrum, FFTW_ESTIMATE);
    }
    std::copy(lsf.begin(), lsf.end(), in);
    fftw_execute(plan);
    const double dc = std::hypot(spectrum[0][0], spectrum[0][1]);
    for (int k = 0; k <= n / 2; ++k) {
        const double f = double(k) * kOversampling / n;  // cycles per pixel
        if (f > 1.0) break;
        const double x = 2.0 * kPi * f / kOversampling;
        const double derivative = k == 0 ? 1.0 : std::sin(x) / x;
        out.frequency.push_back(f);
        out.mtf.push_back(std::hypot(spectrum[k][0], spectrum[k][1]) / dc / derivative);
    }
    {
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        fftw_destroy_plan(plan);
        fftw_free(in);
        fftw_free(spectrum);
    }
    for (size_t k = 1; k < out.mtf.size(); ++k)
        if (out.mtf[k] <= 0.5) {
            const double t = (out.mtf[k - 1] - 0.5) / (out.mtf[k - 1] - out.mtf[k]);
            out.mtf50 = out.frequency[k - 1] + t * (out.frequency[k] - out.frequency[k - 1]);
            break;
        }
    return out;
}

}  // namespace metamer
