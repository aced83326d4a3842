#include "sensor/lens.h"

#include "core/cpu_count.h"
#include "sensor/fftw_planner.h"
#include "spectral/resampling.h"

#include <fftw3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numbers>
#include <thread>
#include <vector>

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;

double sinc(double x) { return std::abs(x) < 1e-12 ? 1.0 : std::sin(kPi * x) / (kPi * x); }

// A spectrum's value at λ: linear between its points, the end values beyond them.
double valueAt(const Spectrum& s, double nm) {
    if (s.isConstant()) return *s.constant;
    const auto& w = s.wavelengths_nm;
    if (nm <= w.front()) return s.values.front();
    if (nm >= w.back()) return s.values.back();
    const size_t i = size_t(std::upper_bound(w.begin(), w.end(), nm) - w.begin());
    const double t = (nm - w[i - 1]) / (w[i] - w[i - 1]);
    return s.values[i - 1] + t * (s.values[i] - s.values[i - 1]);
}

// A size ≥ n whose factors are 2, 3, 5 and 7 (FFTW is fastest on those).
int fftSize(int n) {
    for (int m = std::max(n, 1);; ++m) {
        int k = m;
        for (int p : {2, 3, 5, 7})
            while (k % p == 0) k /= p;
        if (k == 1) return m;
    }
}

}  // namespace

double zernike(int j, double rho, double theta) {
    int n = 0;
    while ((n + 1) * (n + 2) / 2 < j) ++n;
    const int k = j - n * (n + 1) / 2 - 1;  // 0 … n within the order
    const int m = n % 2 == 0 ? 2 * ((k + 1) / 2) : 2 * (k / 2) + 1;
    double radial = 0.0;
    auto factorial = [](int x) {
        double f = 1.0;
        for (int i = 2; i <= x; ++i) f *= i;
        return f;
    };
    for (int s = 0; s <= (n - m) / 2; ++s)
        radial += (s % 2 ? -1.0 : 1.0) * factorial(n - s) /
                  (factorial(s) * factorial((n + m) / 2 - s) * factorial((n - m) / 2 - s)) * std::pow(rho, n - 2 * s);
    if (m == 0) return std::sqrt(double(n + 1)) * radial;
    const double norm = std::sqrt(2.0 * (n + 1)) * radial;
    return j % 2 == 0 ? norm * std::cos(m * theta) : norm * std::sin(m * theta);
}

double defocusDiameter_mm(const LensSpec& lens, const LensGeometry& g, double nm) {
    const double dz_um = lens.defocus_um + (lens.focusShift_um ? valueAt(*lens.focusShift_um, nm) : 0.0);
    return std::abs(dz_um) * 1e-3 / g.workingF;
}

double lensTransfer(const LensSpec& lens, const LensGeometry& g, double nm, double fx, double fy) {
    const double f = std::hypot(fx, fy);
    double h = 1.0;
    if (lens.diffraction) {
        const double nu = f * nm * 1e-6 * g.workingF;  // f in cycles/mm, λ in mm
        h *= nu >= 1.0 ? 0.0 : 2.0 / kPi * (std::acos(nu) - nu * std::sqrt(1.0 - nu * nu));
    }
    if (const double d = defocusDiameter_mm(lens, g, nm); d > 0.0 && f > 0.0) {
        const double x = kPi * d * f;
        h *= 2.0 * std::cyl_bessel_j(1.0, x) / x;
    }
    if (lens.pixelAperture) {
        const double a = g.pitch_mm * std::sqrt(g.fillFactor);
        h *= sinc(a * fx) * sinc(a * fy);
    }
    if (lens.olpf_um > 0.0) {
        const double s = lens.olpf_um * 1e-3;
        h *= std::cos(kPi * s * fx) * std::cos(kPi * s * fy);
    }
    return h;
}

LensKernel lensKernel(const LensSpec& lens, const LensGeometry& g, double nm) {
    // How far the blur reaches: 20 Airy radii (the rings beyond hold < 1 % of the light), the
    // defocus disc, the OLPF's spots, a pixel.
    double reach_mm = 2.0 * g.pitch_mm;
    if (lens.diffraction) reach_mm = std::max(reach_mm, 20.0 * 1.22 * nm * 1e-6 * g.workingF);
    reach_mm = std::max(reach_mm, 0.5 * defocusDiameter_mm(lens, g, nm) + 2.0 * g.pitch_mm);
    reach_mm = std::max(reach_mm, lens.olpf_um * 1e-3 + 2.0 * g.pitch_mm);
    LensKernel k;
    k.radius = int(std::ceil(reach_mm / g.pitch_mm)) + 1;
    // The fine grid resolves the OTF: its Nyquist frequency s/(2p) reaches the diffraction cutoff
    // 1/(λN_w); without diffraction the pixel's own sinc² bounds what matters.
    const double cutoff = lens.diffraction ? 1.0 / (nm * 1e-6 * g.workingF) : 0.0;
    const int s = std::clamp(int(std::ceil(2.0 * cutoff * g.pitch_mm)) + 1, 4, 16);
    const int M = fftSize(2 * k.radius + 1), N = s * M;
    const double fine = g.pitch_mm / s;  // the fine grid's spacing
    const size_t NN = size_t(N) * size_t(N);
    fftw_complex *h, *work;
    fftw_plan inverse, forward;
    {
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        h = fftw_alloc_complex(NN);
        work = fftw_alloc_complex(NN);
        inverse = fftw_plan_dft_2d(N, N, h, h, FFTW_BACKWARD, FFTW_ESTIMATE);
        forward = fftw_plan_dft_2d(N, N, work, work, FFTW_FORWARD, FFTW_ESTIMATE);
    }
    auto frequency = [&](int k) { return double(k <= N / 2 ? k : k - N) / (N * fine); };
    // An aberrated pupil (Zernike terms at this λ): its OTF computed, not closed-form — the
    // coherent transfer function circ(|f|/(f_c/2))·exp(−2πi·W), W in waves over the unit pupil,
    // its inverse transform squared (the PSF), transformed back and normalized to 1 at f = 0.
    std::vector<double> waves(lens.zernike.size());
    bool aberrated = false;
    for (size_t j = 0; j < waves.size(); ++j) aberrated |= (waves[j] = valueAt(lens.zernike[j], nm)) != 0.0;
    if (aberrated) {
        const double pupil = 0.5 * cutoff;  // the CTF's radius, cycles/mm
        for (int ky = 0; ky < N; ++ky)
            for (int kx = 0; kx < N; ++kx) {
                const double fx = frequency(kx), fy = frequency(ky), rho = std::hypot(fx, fy) / pupil;
                fftw_complex& c = h[size_t(ky) * N + size_t(kx)];
                if (rho > 1.0) {
                    c[0] = c[1] = 0.0;
                    continue;
                }
                const double theta = std::atan2(fy, fx);
                double w = 0.0;
                for (size_t j = 0; j < waves.size(); ++j)
                    if (waves[j] != 0.0) w += waves[j] * zernike(int(j) + 1, rho, theta);
                c[0] = std::cos(2.0 * kPi * w);
                c[1] = -std::sin(2.0 * kPi * w);
            }
        fftw_execute(inverse);  // the amplitude PSF, in place
        for (size_t i = 0; i < NN; ++i) {
            work[i][0] = h[i][0] * h[i][0] + h[i][1] * h[i][1];
            work[i][1] = 0.0;
        }
        fftw_execute(forward);  // the OTF, unnormalized: work[0] is the PSF's total
        const double dc = work[0][0];
        for (size_t i = 0; i < NN; ++i) work[i][0] /= dc, work[i][1] /= dc;
    }
    // H(f) = OTF(f) · sinc(p·f) (the scene's pixel: a square of constant radiance) on the fine
    // grid's frequencies; its inverse transform sampled at the pixels' centres is the kernel.
    LensSpec rest = lens;
    rest.diffraction = lens.diffraction && !aberrated;  // the pupil's OTF holds the diffraction
    for (int ky = 0; ky < N; ++ky)
        for (int kx = 0; kx < N; ++kx) {
            const double fx = frequency(kx), fy = frequency(ky);
            const double r = lensTransfer(rest, g, nm, fx, fy) * sinc(g.pitch_mm * fx) * sinc(g.pitch_mm * fy);
            const size_t i = size_t(ky) * N + size_t(kx);
            h[i][0] = aberrated ? r * work[i][0] : r;
            h[i][1] = aberrated ? r * work[i][1] : 0.0;
        }
    fftw_execute(inverse);
    auto psfAt = [&](size_t fy, size_t fx) { return h[fy * size_t(N) + fx][0]; };
    const int side = 2 * k.radius + 1;
    k.weights.assign(size_t(side) * size_t(side), 0.0);
    double sum = 0.0;
    for (int y = -k.radius; y <= k.radius; ++y)
        for (int x = -k.radius; x <= k.radius; ++x) {
            const size_t fy = size_t(((y * s) % N + N) % N), fx = size_t(((x * s) % N + N) % N);
            // ≥ 0: the kernel is a convolution of non-negative functions; the fine grid's round-off
            // and truncation leave only tiny negatives.
            const double v = std::max(psfAt(fy, fx), 0.0);
            k.weights[size_t(y + k.radius) * side + size_t(x + k.radius)] = v;
            sum += v;
        }
    // The tails beyond the radius (< 1 %) are folded in: a flat field keeps its level exactly.
    // FFTW's inverse is unnormalized: the fine samples of a unit-energy PSF sum to N², the pixel
    // centres' (every s-th) to N²/s².
    k.foldedIn = 1.0 - sum * double(s) * double(s) / (double(N) * double(N));
    for (double& v : k.weights) v /= sum;
    {
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        fftw_destroy_plan(inverse);
        fftw_destroy_plan(forward);
        fftw_free(h);
        fftw_free(work);
    }
    return k;
}

SpectralCube throughLens(const SpectralCube& cube, const LensSpec& lens, const LensGeometry& g, int threads) {
    const int W = cube.width, H = cube.height;
    const size_t bands = size_t(cube.grid.bands());
    const std::vector<double> nm = cube.grid.wavelengths();
    std::vector<LensKernel> kernels(bands);
    int pad = 0;
    for (size_t b = 0; b < bands; ++b) {
        kernels[b] = lensKernel(lens, g, nm[b]);
        pad = std::max(pad, kernels[b].radius + 1);
    }
    // Zero radiance around the frame, as wide as the widest kernel: the convolution is linear, not
    // circular, and light from outside the frame (there is none) cannot wrap in.
    const int PW = fftSize(W + 2 * pad), PH = fftSize(H + 2 * pad);
    const int CW = PW / 2 + 1;

    SpectralCube out(W, H, cube.grid);
    size_t t = threads > 0 ? size_t(threads) : size_t(usableCpuCount());
    t = std::clamp<size_t>(t, 1, bands);
    std::atomic<size_t> next{0};
    auto worker = [&] {
        double *image, *kernel;
        fftw_complex *spectrum, *kernelSpectrum;
        fftw_plan forward, forwardKernel, backward;
        {
            std::lock_guard<std::mutex> lock(fftwPlannerMutex());
            image = fftw_alloc_real(size_t(PW) * size_t(PH));
            kernel = fftw_alloc_real(size_t(PW) * size_t(PH));
            spectrum = fftw_alloc_complex(size_t(CW) * size_t(PH));
            kernelSpectrum = fftw_alloc_complex(size_t(CW) * size_t(PH));
            forward = fftw_plan_dft_r2c_2d(PH, PW, image, spectrum, FFTW_ESTIMATE);
            forwardKernel = fftw_plan_dft_r2c_2d(PH, PW, kernel, kernelSpectrum, FFTW_ESTIMATE);
            backward = fftw_plan_dft_c2r_2d(PH, PW, spectrum, image, FFTW_ESTIMATE);
        }
        for (size_t b; (b = next.fetch_add(1)) < bands;) {
            std::fill(image, image + size_t(PW) * size_t(PH), 0.0);
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x)
                    image[size_t(y + pad) * PW + size_t(x + pad)] = double(cube.pixel(x, y)[b]);
            // The kernel, centred on the origin (wrapped), so the product leaves the image in place.
            const LensKernel& k = kernels[b];
            const int side = 2 * k.radius + 1;
            std::fill(kernel, kernel + size_t(PW) * size_t(PH), 0.0);
            for (int y = -k.radius; y <= k.radius; ++y)
                for (int x = -k.radius; x <= k.radius; ++x)
                    kernel[size_t((y + PH) % PH) * PW + size_t((x + PW) % PW)] =
                        k.weights[size_t(y + k.radius) * side + size_t(x + k.radius)];
            fftw_execute(forward);
            fftw_execute(forwardKernel);
            const double norm = 1.0 / (double(PW) * double(PH));
            for (size_t i = 0; i < size_t(CW) * size_t(PH); ++i) {
                const double re = spectrum[i][0] * kernelSpectrum[i][0] - spectrum[i][1] * kernelSpectrum[i][1];
                const double im = spectrum[i][0] * kernelSpectrum[i][1] + spectrum[i][1] * kernelSpectrum[i][0];
                spectrum[i][0] = re * norm;
                spectrum[i][1] = im * norm;
            }
            fftw_execute(backward);
            // Lateral CA: the band's image scaled by 1 + δ(λ) about the image centre, bilinear.
            const double m = 1.0 + (lens.lateralCa ? valueAt(*lens.lateralCa, nm[b]) : 0.0);
            const double cx = 0.5 * W, cy = 0.5 * H;
            auto at = [&](int x, int y) {
                return x < -pad || y < -pad || x >= W + pad || y >= H + pad ? 0.0
                                                                             : image[size_t(y + pad) * PW + size_t(x + pad)];
            };
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    double v;
                    if (m == 1.0) {
                        v = at(x, y);
                    } else {
                        const double sx = cx + (x + 0.5 - cx) / m - 0.5, sy = cy + (y + 0.5 - cy) / m - 0.5;
                        const int x0 = int(std::floor(sx)), y0 = int(std::floor(sy));
                        const double tx = sx - x0, ty = sy - y0;
                        // The scaled image keeps its energy: 1/m² per unit area.
                        v = ((1 - tx) * (1 - ty) * at(x0, y0) + tx * (1 - ty) * at(x0 + 1, y0) +
                             (1 - tx) * ty * at(x0, y0 + 1) + tx * ty * at(x0 + 1, y0 + 1)) / (m * m);
                    }
                    // FFT round-off leaves ±1e-16 of the peak where the image is dark: radiance ≥ 0.
                    out.pixel(x, y)[b] = float(std::max(v, 0.0));
                }
        }
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        for (fftw_plan p : {forward, forwardKernel, backward}) fftw_destroy_plan(p);
        fftw_free(image);
        fftw_free(kernel);
        fftw_free(spectrum);
        fftw_free(kernelSpectrum);
    };
    std::vector<std::thread> pool;
    for (size_t k = 1; k < t; ++k) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    return out;
}

}  // namespace metamer
