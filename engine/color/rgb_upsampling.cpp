#include "color/rgb_upsampling.h"

#include "core/cpu_count.h"
#include "core/file_reads.h"

#include "color/lab.h"
#include "color/srgb.h"
#include "spectral/csv.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <unistd.h>

#ifndef METAMER_RGB_TABLE_FILE
#define METAMER_RGB_TABLE_FILE ""
#endif

namespace fs = std::filesystem;

namespace metamer {

namespace {

constexpr const char* kIlluminant = "illuminants/D65";
constexpr const char* kObserver = "observers/cie1931_2deg";

// The fit's wavelength variable: u = (λ − kCentre)/kHalfWidth spans [−1, 1] over 360–830 nm.
constexpr double kCentre = 0.5 * (RgbUpsampler::kFitMinNm + RgbUpsampler::kFitMaxNm);
constexpr double kHalfWidth = 0.5 * (RgbUpsampler::kFitMaxNm - RgbUpsampler::kFitMinNm);

// Bump when the table's meaning changes (weights, model, layout); old files are then rebuilt.
constexpr std::uint32_t kFormatVersion = 2;
constexpr char kMagic[8] = {'M', 'T', 'R', 'G', 'B', 'S', 'I', 'G'};

const glm::dmat3& linearSrgbToXyz() {
    static const glm::dmat3 m = glm::inverse(xyzToLinearSrgbMatrix());
    return m;
}

// 64-bit FNV-1a.
struct Fnv {
    std::uint64_t h = 1469598103934665603ull;
    void add(const void* data, size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
    void add(const std::vector<double>& v) { add(v.data(), v.size() * sizeof(double)); }
};

// u-domain coefficients (a0·u² + a1·u + a2) ↔ nm coefficients (c0·λ² + c1·λ + c2), λ = m + h·u.
RgbUpsampler::Coefficients uToNm(const glm::dvec3& a) {
    const double m = kCentre, h = kHalfWidth;
    const double c0 = a[0] / (h * h);
    const double c1 = a[1] / h - 2.0 * m * c0;
    const double c2 = a[0] * (m / h) * (m / h) - a[1] * (m / h) + a[2];
    return {c0, c1, c2};
}

glm::dvec3 nmToU(const RgbUpsampler::Coefficients& c) {
    const double m = kCentre, h = kHalfWidth;
    return {c.c0 * h * h, h * (2.0 * c.c0 * m + c.c1), (c.c0 * m + c.c1) * m + c.c2};
}

bool isBlack(const glm::dvec3& v) { return v.x == 0.0 && v.y == 0.0 && v.z == 0.0; }
bool isWhite(const glm::dvec3& v) { return v.x == 1.0 && v.y == 1.0 && v.z == 1.0; }

double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }

}  // namespace

// --- The model ----------------------------------------------------------------------------------

double RgbUpsampler::sigmoid(double x) {
    if (std::isnan(x)) return 0.5;
    if (std::abs(x) > 1e100) return x > 0.0 ? 1.0 : 0.0;  // x² would overflow
    return 0.5 + x / (2.0 * std::sqrt(1.0 + x * x));
}

double RgbUpsampler::reflectance(const Coefficients& c, double lambda_nm) {
    const double l = std::clamp(lambda_nm, kFitMinNm, kFitMaxNm);
    return sigmoid((c.c0 * l + c.c1) * l + c.c2);
}

namespace {

// ∫ρ over [a, b] by 3-point Gauss–Legendre.
double gaussLegendre3(const RgbUpsampler::Coefficients& c, double a, double b) {
    static const double kNode = std::sqrt(0.6);
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    return half * ((8.0 / 9.0) * RgbUpsampler::reflectance(c, mid) +
                   (5.0 / 9.0) * (RgbUpsampler::reflectance(c, mid - half * kNode) +
                                  RgbUpsampler::reflectance(c, mid + half * kNode)));
}

// Adaptive: halves an interval until the two halves agree with the whole to `tolerance` (an
// absolute error of the integral). Smooth spectra stop at the first level; the steep ones at the
// gamut boundary (transitions narrower than a nanometre) refine only around their transition.
double adaptiveIntegral(const RgbUpsampler::Coefficients& c, double a, double b, double whole, double tolerance,
                        int depth) {
    const double mid = 0.5 * (a + b);
    const double left = gaussLegendre3(c, a, mid), right = gaussLegendre3(c, mid, b);
    if (depth <= 0 || std::abs(left + right - whole) <= tolerance) return left + right;
    return adaptiveIntegral(c, a, mid, left, 0.5 * tolerance, depth - 1) +
           adaptiveIntegral(c, mid, b, right, 0.5 * tolerance, depth - 1);
}

// The real roots of c0·λ² + c1·λ + c2 (none, one or two; NaN marks a missing one).
std::array<double, 2> quadraticRoots(const RgbUpsampler::Coefficients& c) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (c.c0 == 0.0) return {c.c1 != 0.0 ? -c.c2 / c.c1 : nan, nan};
    const double d = c.c1 * c.c1 - 4.0 * c.c0 * c.c2;
    if (d < 0.0) return {nan, nan};
    // The numerically stable pair: q = −(c1 + sign(c1)·√d)/2, roots q/c0 and c2/q.
    const double q = -0.5 * (c.c1 + std::copysign(std::sqrt(d), c.c1));
    return {q / c.c0, q != 0.0 ? c.c2 / q : nan};
}

}  // namespace

std::vector<double> RgbUpsampler::bands(const Coefficients& c, const Grid& grid) {
    const int n = grid.bands();
    std::vector<double> out(static_cast<size_t>(n));
    if (grid.resampling != Resampling::BandMean) {
        for (int i = 0; i < n; ++i) out[static_cast<size_t>(i)] = reflectance(c, grid.wavelength(i));
        return out;
    }
    const double lo = reflectance(c, kFitMinNm), hi = reflectance(c, kFitMaxNm);
    const double tolerance = kBandTolerance * grid.step_nm;
    for (int i = 0; i < n; ++i) {
        const double a = grid.wavelength(i) - 0.5 * grid.step_nm;
        const double b = grid.wavelength(i) + 0.5 * grid.step_nm;
        // ρ is held constant outside the fit range, so those parts are exact.
        double sum = 0.0;
        if (a < kFitMinNm) sum += lo * (std::min(b, kFitMinNm) - a);
        if (b > kFitMaxNm) sum += hi * (b - std::max(a, kFitMaxNm));
        const double a1 = std::max(a, kFitMinNm), b1 = std::min(b, kFitMaxNm);
        if (b1 > a1) {
            // Split where q(λ) = 0, the centre of a transition, so that no transition can hide
            // between the sample points of both levels.
            double cuts[4] = {a1, b1, b1, b1};
            int nc = 1;
            for (double r : quadraticRoots(c))
                if (r > a1 && r < b1) cuts[nc++] = r;
            cuts[nc++] = b1;
            if (nc == 4 && cuts[2] < cuts[1]) std::swap(cuts[1], cuts[2]);  // two roots inside: in order
            for (int k = 0; k + 1 < nc; ++k)
                sum += adaptiveIntegral(c, cuts[k], cuts[k + 1], gaussLegendre3(c, cuts[k], cuts[k + 1]),
                                        tolerance, 40);
        }
        out[static_cast<size_t>(i)] = sum / grid.step_nm;
    }
    return out;
}

std::vector<double> RgbUpsampler::bands(const glm::dvec3& linearRgb, const Grid& grid) const {
    return bands(fit(linearRgb), grid);
}

glm::dvec3 RgbUpsampler::clampLinearRgb(const glm::dvec3& v) {
    glm::dvec3 out;
    for (int i = 0; i < 3; ++i) out[i] = std::isnan(v[i]) || v[i] < 0.0 ? 0.0 : v[i];
    const double m = std::max({out.x, out.y, out.z});
    if (m > 1.0) {
        out /= m;
        // The largest channel is exactly 1 (an infinite one makes the colour that channel alone).
        for (int i = 0; i < 3; ++i) {
            if (std::isnan(out[i])) out[i] = 1.0;  // inf/inf: the infinite channels
            if (out[i] > 1.0) out[i] = 1.0;
        }
        if (std::isinf(m))
            for (int i = 0; i < 3; ++i) out[i] = std::isinf(v[i]) ? 1.0 : 0.0;
    }
    return out;
}

glm::dvec3 RgbUpsampler::decodeSrgb(const glm::dvec3& e) {
    return {srgbDecode(e.x), srgbDecode(e.y), srgbDecode(e.z)};
}

glm::dvec3 RgbUpsampler::labOfLinearRgb(const glm::dvec3& rgb) {
    return xyzToLab(linearSrgbToXyz() * rgb, kD65WhiteXyz);
}

// --- Colour weights -----------------------------------------------------------------------------

RgbUpsampler::RgbUpsampler(const SpectrumLibrary& library) {
    const Spectrum& d65 = library.get(kIlluminant, Where{});
    if (!library.contains(kObserver))
        failInput(Where{}, "no observer '{}' in the spectra library ({})", kObserver, library.root().string());
    const fs::path observerPath = library.root() / (std::string(kObserver) + ".csv");
    SpectralTable cmf = readSpectralTable(observerPath, 3);
    if (cmf.columns.size() != 3)
        failInput(Where{observerPath.string()}, "an observer needs exactly 3 value columns, found {}",
                  cmf.columns.size());

    // The RGB mode's definition (docs/representations.md "RGB"): at 1 nm over 360–830 nm,
    // w_c(λ) = [M·x̄ȳz̄(λ)]_c·D65(λ) / n_c with n_c = Σ [M·x̄ȳz̄]_c·D65, so ρ ≡ 1 gives (1, 1, 1).
    Spectrum cmfSpectra[3];
    for (int c = 0; c < 3; ++c) {
        cmfSpectra[c].wavelengths_nm = cmf.wavelengths_nm;
        cmfSpectra[c].values = cmf.columns[static_cast<size_t>(c)];
    }
    const glm::dmat3& m = xyzToLinearSrgbMatrix();
    std::vector<glm::dvec4> raw;  // λ, r, g, b before normalization
    glm::dvec3 n(0.0);
    for (int i = 0; i <= static_cast<int>(kFitMaxNm - kFitMinNm); ++i) {
        const double l = kFitMinNm + i;
        const double e = d65.at(l);
        if (e == 0.0) continue;
        const glm::dvec3 rgb = m * glm::dvec3(cmfSpectra[0].at(l), cmfSpectra[1].at(l), cmfSpectra[2].at(l)) * e;
        n += rgb;
        raw.emplace_back(l, rgb);
    }
    if (raw.empty() || !(n.x > 0.0 && n.y > 0.0 && n.z > 0.0))
        failInput(Where{d65.source}, "D65 and the CIE 1931 observer do not overlap over {}–{} nm", kFitMinNm,
                  kFitMaxNm);
    for (const auto& r : raw) {
        u_.push_back((r[0] - kCentre) / kHalfWidth);
        wr_.push_back(r[1] / n.x);
        wg_.push_back(r[2] / n.y);
        wb_.push_back(r[3] / n.z);
    }

    Fnv f;
    f.add(&kFormatVersion, sizeof kFormatVersion);
    f.add(d65.wavelengths_nm);
    f.add(d65.values);
    f.add(cmf.wavelengths_nm);
    for (const auto& col : cmf.columns) f.add(col);
    fingerprint_ = f.h;
}

glm::dvec3 RgbUpsampler::colorU(const glm::dvec3& a, glm::dmat3* jacobian) const {
    const size_t n = u_.size();
    const double* u = u_.data();
    const double* wr = wr_.data();
    const double* wg = wg_.data();
    const double* wb = wb_.data();
    const double a0 = a[0], a1 = a[1], a2 = a[2];
    if (!jacobian) {
        double r = 0, g = 0, b = 0;
#pragma omp simd reduction(+ : r, g, b)
        for (size_t i = 0; i < n; ++i) {
            const double x = (a0 * u[i] + a1) * u[i] + a2;
            const double s = 0.5 + 0.5 * x / std::sqrt(1.0 + x * x);
            r += wr[i] * s, g += wg[i] * s, b += wb[i] * s;
        }
        return {r, g, b};
    }
    // Sums of w·S and of w·S'·(u², u, 1), S'(x) = ½·(1 + x²)^(−3/2).
    double r = 0, g = 0, b = 0;
    double r0 = 0, r1 = 0, r2 = 0, g0 = 0, g1 = 0, g2 = 0, b0 = 0, b1 = 0, b2 = 0;
#pragma omp simd reduction(+ : r, g, b, r0, r1, r2, g0, g1, g2, b0, b1, b2)
    for (size_t i = 0; i < n; ++i) {
        const double x = (a0 * u[i] + a1) * u[i] + a2;
        const double inv = 1.0 / std::sqrt(1.0 + x * x);
        const double s = 0.5 + 0.5 * x * inv;
        const double d2 = 0.5 * inv * inv * inv, d1 = d2 * u[i], d0 = d1 * u[i];
        r += wr[i] * s, g += wg[i] * s, b += wb[i] * s;
        r0 += wr[i] * d0, r1 += wr[i] * d1, r2 += wr[i] * d2;
        g0 += wg[i] * d0, g1 += wg[i] * d1, g2 += wg[i] * d2;
        b0 += wb[i] * d0, b1 += wb[i] * d1, b2 += wb[i] * d2;
    }
    *jacobian = glm::dmat3(glm::dvec3(r0, g0, b0), glm::dvec3(r1, g1, b1), glm::dvec3(r2, g2, b2));
    return {r, g, b};
}

glm::dvec3 RgbUpsampler::linearRgbOf(const Coefficients& c) const {
    if (c.c0 == 0.0 && c.c1 == 0.0 && std::abs(c.c2) >= kSaturated) return glm::dvec3(c.c2 > 0 ? 1.0 : 0.0);
    return colorU(nmToU(c), nullptr);
}

glm::dvec3 RgbUpsampler::labOf(const Coefficients& c) const { return labOfLinearRgb(linearRgbOf(c)); }

// --- The solver ---------------------------------------------------------------------------------

glm::dvec3 RgbUpsampler::solveU(const glm::dvec3& target, glm::dvec3 a, double tolerance, int maxIterations,
                                double* residual, int* iterations) const {
    const glm::dvec3 labTarget = labOfLinearRgb(target);
    const glm::dmat3& toXyz = linearSrgbToXyz();
    auto evaluate = [&](const glm::dvec3& coeffs, glm::dmat3* jac) {
        glm::dmat3 jRgb;
        const glm::dvec3 rgb = colorU(coeffs, jac ? &jRgb : nullptr);
        const glm::dvec3 xyz = toXyz * rgb;
        if (jac) *jac = xyzToLabJacobian(xyz, kD65WhiteXyz) * toXyz * jRgb;
        return xyzToLab(xyz, kD65WhiteXyz) - labTarget;
    };
    glm::dmat3 j;
    glm::dvec3 r = evaluate(a, &j);
    double cost = glm::dot(r, r);
    double mu = 1e-8;  // Levenberg–Marquardt damping, relative to diag(JᵀJ)
    int it = 0;
    const double tol2 = tolerance * tolerance;
    while (it < maxIterations && cost > tol2) {
        ++it;
        const glm::dmat3 jt = glm::transpose(j);
        const glm::dmat3 jtj = jt * j;
        const glm::dvec3 g = jt * r;
        bool accepted = false;
        while (mu < 1e12) {
            glm::dmat3 h = jtj;
            for (int k = 0; k < 3; ++k) h[k][k] += mu * std::max(jtj[k][k], 1e-300);
            const glm::dvec3 step = -(glm::inverse(h) * g);
            const glm::dvec3 next = a + step;
            if (std::isfinite(next.x) && std::isfinite(next.y) && std::isfinite(next.z)) {
                glm::dmat3 jn;
                const glm::dvec3 rn = evaluate(next, &jn);
                const double cn = glm::dot(rn, rn);
                if (std::isfinite(cn) && cn < cost) {
                    a = next;
                    r = rn;
                    j = jn;
                    cost = cn;
                    mu = std::max(mu * 0.1, 1e-12);
                    accepted = true;
                    break;
                }
            }
            mu *= 10.0;
        }
        if (!accepted) break;  // no step reduces the residual: a local minimum
    }
    if (residual) *residual = std::sqrt(cost);
    if (iterations) *iterations = it;
    return a;
}

RgbUpsampler::Solution RgbUpsampler::solve(const glm::dvec3& linearRgb, const Coefficients& start) const {
    const glm::dvec3 rgb = clampLinearRgb(linearRgb);
    if (isBlack(rgb)) return {kBlack, 0.0, 0};
    if (isWhite(rgb)) return {kWhite, 0.0, 0};
    Solution s;
    const glm::dvec3 a = solveU(rgb, nmToU(start), kResidualTolerance, kMaxIterations, &s.residual, &s.iterations);
    s.coefficients = uToNm(a);
    return s;
}

// --- The table ----------------------------------------------------------------------------------

size_t RgbUpsampler::offset(int l, int xi, int yi, int zi) const {
    const size_t r = static_cast<size_t>(resolution_);
    return ((((static_cast<size_t>(l) * r + static_cast<size_t>(zi)) * r + static_cast<size_t>(yi)) * r +
             static_cast<size_t>(xi)) *
            3);
}

RgbUpsampler::Coefficients RgbUpsampler::node(int l, int xi, int yi, int zi) const {
    const double* p = &table_[offset(l, xi, yi, zi)];
    return uToNm(glm::dvec3(p[0], p[1], p[2]));
}

glm::dvec3 RgbUpsampler::nodeColor(int l, int xi, int yi, int zi) const {
    const double z = z_[static_cast<size_t>(zi)];
    const double step = 1.0 / (resolution_ - 1);
    glm::dvec3 rgb;
    rgb[l] = z;
    rgb[(l + 1) % 3] = xi * step * z;
    rgb[(l + 2) % 3] = yi * step * z;
    return rgb;
}

RgbUpsampler RgbUpsampler::build(const SpectrumLibrary& library, int resolution, int threads,
                                 BuildStats* stats) {
    if (resolution < 3) failRuntime("RGB up-sampling table: resolution {} is below 3", resolution);
    const auto t0 = std::chrono::steady_clock::now();
    RgbUpsampler up(library);
    const int res = resolution;
    up.resolution_ = res;
    up.z_.resize(static_cast<size_t>(res));
    for (int k = 0; k < res; ++k) up.z_[static_cast<size_t>(k)] = smoothstep(smoothstep(k / double(res - 1)));
    up.table_.assign(static_cast<size_t>(3) * res * res * res * 3, 0.0);
    const int zStart = res / 5;

    std::atomic<long> iterations{0};
    std::mutex statsMutex;
    double maxResidual = 0.0;
    int unconverged = 0;

    // Solves one node from the given starting points (the first that converges wins; otherwise the
    // best) and stores it.
    auto solveNode = [&](int l, int xi, int yi, int zi, std::initializer_list<const double*> starts,
                         double* worst, int* bad, long* its) {
        const glm::dvec3 target = up.nodeColor(l, xi, yi, zi);
        glm::dvec3 best(0.0);
        double bestResidual = INFINITY;
        auto attempt = [&](const glm::dvec3& start) {
            double residual;
            int n;
            const glm::dvec3 a = up.solveU(target, start, kResidualTolerance, kMaxIterations, &residual, &n);
            *its += n;
            if (residual < bestResidual) {
                bestResidual = residual;
                best = a;
            }
        };
        for (const double* s : starts) {
            if (!s) continue;
            attempt(glm::dvec3(s[0], s[1], s[2]));
            if (bestResidual <= kResidualTolerance) break;
        }
        if (bestResidual > kResidualTolerance) attempt(glm::dvec3(0.0));
        double* out = &up.table_[up.offset(l, xi, yi, zi)];
        out[0] = best[0], out[1] = best[1], out[2] = best[2];
        *worst = std::max(*worst, bestResidual);
        if (bestResidual > kResidualTolerance) ++*bad;
    };
    auto at = [&](int l, int xi, int yi, int zi) -> const double* {
        if (xi >= res || yi >= res || zi < 0 || zi >= res) return nullptr;
        return &up.table_[up.offset(l, xi, yi, zi)];
    };

    // Work items: first the three start layers (one per l), then every (l, x, y) column.
    const int columns = 3 * res * res;
    std::atomic<int> nextLayer{0}, nextColumn{0};
    auto worker = [&] {
        double worst = 0.0;
        int bad = 0;
        long its = 0;
        for (int l; (l = nextLayer++) < 3;) {
            // From the grey corner (x = y = 1) towards x = y = 0, each node from a solved neighbour.
            for (int yi = res - 1; yi >= 0; --yi)
                for (int xi = res - 1; xi >= 0; --xi)
                    solveNode(l, xi, yi, zStart, {at(l, xi + 1, yi, zStart), at(l, xi, yi + 1, zStart)}, &worst,
                              &bad, &its);
        }
        return std::make_tuple(worst, bad, its);
    };
    auto columnWorker = [&] {
        double worst = 0.0;
        int bad = 0;
        long its = 0;
        for (int c; (c = nextColumn++) < columns;) {
            const int l = c / (res * res), yi = (c / res) % res, xi = c % res;
            for (int zi = zStart + 1; zi < res; ++zi)
                solveNode(l, xi, yi, zi, {at(l, xi, yi, zi - 1)}, &worst, &bad, &its);
            for (int zi = zStart - 1; zi >= 0; --zi)
                solveNode(l, xi, yi, zi, {at(l, xi, yi, zi + 1)}, &worst, &bad, &its);
        }
        return std::make_tuple(worst, bad, its);
    };
    auto runPhase = [&](auto&& fn) {
        const int n = std::max(1, threads);
        std::vector<std::thread> pool;
        auto body = [&] {
            auto [w, b, i] = fn();
            std::lock_guard<std::mutex> lock(statsMutex);
            maxResidual = std::max(maxResidual, w);
            unconverged += b;
            iterations += i;
        };
        for (int t = 1; t < n; ++t) pool.emplace_back(body);
        body();
        for (auto& t : pool) t.join();
    };
    runPhase(worker);
    runPhase(columnWorker);
    // The z = 0 layer is black whatever x and y say. Its fits converge (L* → 0), but only the
    // visible part goes to 0: past 780 nm, where D65 is 0, the solver leaves the spectrum free
    // and some nodes rose to ρ = 1 at 830 nm. Store the exact black instead.
    for (int l = 0; l < 3; ++l)
        for (int yi = 0; yi < res; ++yi)
            for (int xi = 0; xi < res; ++xi) {
                double* out = &up.table_[up.offset(l, xi, yi, 0)];
                const glm::dvec3 black = nmToU(kBlack);
                out[0] = black[0], out[1] = black[1], out[2] = black[2];
            }

    up.source_ = "built in memory";
    if (stats) {
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        stats->maxResidual = maxResidual;
        stats->unconverged = unconverged;
        stats->iterations = iterations;
    }
    return up;
}

RgbUpsampler::Coefficients RgbUpsampler::lookup(const glm::dvec3& linearRgb) const {
    const glm::dvec3 rgb = clampLinearRgb(linearRgb);
    if (isBlack(rgb)) return kBlack;
    if (isWhite(rgb)) return kWhite;
    if (resolution_ == 0) failRuntime("RGB up-sampling: no table (use RgbUpsampler::srgb or build)");
    const int l = rgb.x >= rgb.y && rgb.x >= rgb.z ? 0 : (rgb.y >= rgb.z ? 1 : 2);
    const double z = rgb[l];
    const double x = rgb[(l + 1) % 3] / z, y = rgb[(l + 2) % 3] / z;
    const int last = resolution_ - 2;
    auto cell = [&](double v, int* i) {
        const double f = v * (resolution_ - 1);
        *i = std::clamp(static_cast<int>(f), 0, last);
        return f - *i;
    };
    int xi, yi;
    const double tx = cell(x, &xi), ty = cell(y, &yi);
    const int zi = std::clamp(static_cast<int>(std::upper_bound(z_.begin(), z_.end(), z) - z_.begin()) - 1, 0, last);
    const double tz = (z - z_[static_cast<size_t>(zi)]) / (z_[static_cast<size_t>(zi) + 1] - z_[static_cast<size_t>(zi)]);
    glm::dvec3 a(0.0);
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const double w = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty) * (dz ? tz : 1.0 - tz);
                const double* p = &table_[offset(l, xi + dx, yi + dy, zi + dz)];
                a += w * glm::dvec3(p[0], p[1], p[2]);
            }
    return uToNm(a);
}

RgbUpsampler::Coefficients RgbUpsampler::fit(const glm::dvec3& linearRgb, FitReport* report) const {
    const glm::dvec3 rgb = clampLinearRgb(linearRgb);
    const Coefficients start = lookup(rgb);
    if (isBlack(rgb) || isWhite(rgb)) {
        if (report) *report = {};
        return start;
    }
    double residual = INFINITY;
    int iterations = 0;
    glm::dvec3 a(0.0);
    // In the cell next to white the interpolation is dominated by the white node's huge c2 and
    // the start is poor; go straight to the cold start there.
    const bool besideWhite = std::min({rgb.x, rgb.y, rgb.z}) > (resolution_ - 2.0) / (resolution_ - 1.0) &&
                             std::max({rgb.x, rgb.y, rgb.z}) > z_[static_cast<size_t>(resolution_ - 2)];
    if (!besideWhite) a = solveU(rgb, nmToU(start), kFitTolerance, kFitIterations, &residual, &iterations);
    if (residual > kFitTolerance) {
        // The interpolated start was poor (a cell next to white, whose node runs to +∞): start
        // again from the flat spectrum ½, from which every corner of the gamut converges.
        double coldResidual;
        int coldIterations;
        const glm::dvec3 cold = solveU(rgb, glm::dvec3(0.0), kFitTolerance, kMaxIterations, &coldResidual, &coldIterations);
        iterations += coldIterations;
        if (coldResidual < residual) a = cold, residual = coldResidual;
    }
    if (report) *report = {residual, iterations};
    return uToNm(a);
}

RgbUpsampler::Coefficients RgbUpsampler::fitEncoded(const glm::dvec3& srgbEncoded) const {
    // Decoded first, then clamped in linear terms like any other input (srgbDecode extends the power
    // law above 1 and the linear segment below 0).
    return fit(decodeSrgb(srgbEncoded));
}

// --- Files --------------------------------------------------------------------------------------

namespace {

struct FileHeader {
    char magic[8];
    std::uint32_t version;
    std::uint32_t resolution;
    std::uint64_t fingerprint;
};

}  // namespace

void RgbUpsampler::write(const fs::path& path) const {
    if (resolution_ == 0) failRuntime("RGB up-sampling: no table to write to {}", path.string());
    std::error_code ec;
    if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
    const fs::path temp = path.string() + ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        FileHeader h{};
        std::memcpy(h.magic, kMagic, sizeof kMagic);
        h.version = kFormatVersion;
        h.resolution = static_cast<std::uint32_t>(resolution_);
        h.fingerprint = fingerprint_;
        out.write(reinterpret_cast<const char*>(&h), sizeof h);
        out.write(reinterpret_cast<const char*>(z_.data()), static_cast<std::streamsize>(z_.size() * sizeof(double)));
        out.write(reinterpret_cast<const char*>(table_.data()),
                  static_cast<std::streamsize>(table_.size() * sizeof(double)));
        out.close();
        if (!out) {
            fs::remove(temp, ec);
            failRuntime("cannot write the RGB up-sampling table {}", temp.string());
        }
    }
    fs::rename(temp, path, ec);
    if (ec) {
        fs::remove(temp, ec);
        failRuntime("cannot rename the RGB up-sampling table to {}: {}", path.string(), ec.message());
    }
}

bool RgbUpsampler::read(const fs::path& path) {
    noteFileRead(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    FileHeader h{};
    if (!in.read(reinterpret_cast<char*>(&h), sizeof h)) return false;
    if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.version != kFormatVersion ||
        h.fingerprint != fingerprint_ || h.resolution < 3 || h.resolution > 1024)
        return false;
    const int res = static_cast<int>(h.resolution);
    std::vector<double> z(static_cast<size_t>(res));
    std::vector<double> table(static_cast<size_t>(3) * res * res * res * 3);
    if (!in.read(reinterpret_cast<char*>(z.data()), static_cast<std::streamsize>(z.size() * sizeof(double))) ||
        !in.read(reinterpret_cast<char*>(table.data()),
                 static_cast<std::streamsize>(table.size() * sizeof(double))))
        return false;
    if (in.peek() != std::char_traits<char>::eof()) return false;  // trailing bytes: not ours
    if (z.front() != 0.0 || z.back() != 1.0 || !std::is_sorted(z.begin(), z.end()) ||
        std::adjacent_find(z.begin(), z.end()) != z.end())
        return false;
    for (double v : table)
        if (!std::isfinite(v)) return false;
    resolution_ = res;
    z_ = std::move(z);
    table_ = std::move(table);
    source_ = path.string();
    return true;
}

// --- The shared instance ------------------------------------------------------------------------

const RgbUpsampler& RgbUpsampler::srgb(const SpectrumLibrary& library) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<RgbUpsampler>> instances;
    std::lock_guard<std::mutex> lock(mutex);
    std::error_code ec;
    fs::path key = fs::weakly_canonical(library.root(), ec);
    if (ec) key = library.root();
    auto& slot = instances[key.string()];
    if (slot) return *slot;

    auto up = std::make_unique<RgbUpsampler>(library);
    // Candidates: $METAMER_RGB_TABLE alone if set; else the build tree's table, then the installed one.
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("METAMER_RGB_TABLE"); env && *env) {
        candidates.emplace_back(env);
    } else {
        if (*METAMER_RGB_TABLE_FILE) candidates.emplace_back(METAMER_RGB_TABLE_FILE);
        fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        if (!ec)
            candidates.push_back(exe.parent_path().parent_path() / "share" / "metamer" /
                                 fs::path(METAMER_RGB_TABLE_FILE).filename());
    }
    bool loaded = false;
    for (const auto& c : candidates)
        if (!c.filename().empty() && up->read(c)) {
            loaded = true;
            break;
        }
    if (!loaded) {
        BuildStats stats;
        const int threads = usableCpuCount();
        *up = build(library, kDefaultResolution, threads, &stats);
        warn(Where{candidates.empty() ? std::string() : candidates.front().string()},
             fmt::format("no RGB up-sampling table made from this spectra library's D65 and CIE 1931 tables "
                         "({}); built one in memory at resolution {} in {:.1f} s",
                         library.root().string(), kDefaultResolution, stats.seconds));
    }
    slot = std::move(up);
    return *slot;
}

}  // namespace metamer
