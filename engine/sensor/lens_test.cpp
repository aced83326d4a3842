// The lens per wavelength (issue 48, item 1) against closed forms computed here: the diffraction
// MTF of a circular aperture, an Airy pattern's encircled energy 1 − J₀² − J₁² (the standard
// library's Bessel functions), a defocused point's blur circle, the pixel aperture's sinc, and the
// lateral CA's shift of a point's image per band.
#include "sensor/lens.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

using namespace metamer;

namespace {

constexpr double kPi = std::numbers::pi;

// One bright pixel at (x, y) in every band of a W × H cube.
SpectralCube point(int W, int H, int x, int y, const Grid& grid) {
    SpectralCube c(W, H, grid);
    for (int b = 0; b < grid.bands(); ++b) c.pixel(x, y)[b] = 1.0f;
    return c;
}

// The fraction of band b's light within radius r (pixels) of (cx, cy), pixel centres counted.
double encircled(const SpectralCube& c, int b, double cx, double cy, double r) {
    double in = 0.0, all = 0.0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const double v = c.pixel(x, y)[b];
            all += v;
            if (std::hypot(x - cx, y - cy) <= r) in += v;
        }
    return in / all;
}

}  // namespace

TEST(Lens, TheTransferFunctionIsTheProductOfItsClosedForms) {
    LensSpec lens;
    lens.pixelAperture = false;
    const LensGeometry g{0.005, 1.0, 4.0};  // 5 µm pixels, f/4
    // Diffraction: ν = f·λ·N, cut off at 1/(λN) = 454.5 cycles/mm at 550 nm.
    const double cutoff = 1.0 / (550e-6 * 4.0);
    for (double nu : {0.0, 0.1, 0.5, 0.9, 1.0, 1.2}) {
        const double want = nu >= 1.0 ? 0.0 : 2.0 / kPi * (std::acos(nu) - nu * std::sqrt(1.0 - nu * nu));
        EXPECT_NEAR(lensTransfer(lens, g, 550, nu * cutoff, 0.0), want, 1e-12) << nu;
        EXPECT_NEAR(lensTransfer(lens, g, 550, 0.6 * nu * cutoff, 0.8 * nu * cutoff), want, 1e-12) << nu;  // isotropic
    }
    // Defocus alone: 2J₁(πdf)/(πdf), d = |Δz|/N; its first zero at πdf = 3.8317.
    lens.diffraction = false;
    lens.defocus_um = -80.0;
    EXPECT_NEAR(defocusDiameter_mm(lens, g, 550), 0.02, 1e-15);
    EXPECT_NEAR(lensTransfer(lens, g, 550, 3.831705970207512 / (kPi * 0.02), 0.0), 0.0, 1e-9);
    // Longitudinal CA adds its focus shift per λ: +80 µm at 700 nm brings 700 nm into focus.
    lens.focusShift_um = Spectrum{{400, 700}, {0, 80}};
    EXPECT_NEAR(defocusDiameter_mm(lens, g, 700), 0.0, 1e-15);
    EXPECT_NEAR(defocusDiameter_mm(lens, g, 550), 0.01, 1e-15);
    // The pixel aperture, a = pitch·√fill: sinc(a·fx)·sinc(a·fy), zero at f = 1/a.
    LensSpec pixel;
    pixel.diffraction = false;
    const LensGeometry half{0.005, 0.25, 4.0};  // a = 2.5 µm
    EXPECT_NEAR(lensTransfer(pixel, half, 550, 400.0, 0.0), 0.0, 1e-12);
    EXPECT_NEAR(lensTransfer(pixel, half, 550, 200.0, 200.0), std::pow(std::sin(kPi / 2) / (kPi / 2), 2), 1e-12);
    // The OLPF's 4 spots s apart: cos(πs·fx)·cos(πs·fy), zero at f = 1/(2s).
    pixel.pixelAperture = false;
    pixel.olpf_um = 5.0;
    EXPECT_NEAR(lensTransfer(pixel, half, 550, 100.0, 0.0), 0.0, 1e-12);
}

TEST(Lens, APointsImageHoldsTheAiryPatternsEncircledEnergy) {
    // f/8 at 500 and 600 nm on 0.5 µm pixels: the first dark ring at 1.22λN = 4.88 and 5.86 µm
    // (9.8 and 11.7 pixels). EE(r) = 1 − J₀²(πr/λN) − J₁²(πr/λN) (Born & Wolf 8.5).
    LensSpec lens;
    lens.pixelAperture = false;  // a point, not a pixel, is what the Airy pattern describes
    const LensGeometry g{0.0005, 1.0, 8.0};
    const Grid grid{500, 600, 100};
    const SpectralCube img = throughLens(point(201, 201, 100, 100, grid), lens, g, 2);
    for (int b = 0; b < 2; ++b) {
        const double lambdaN_px = (500.0 + 100.0 * b) * 1e-6 * 8.0 / 0.0005;
        for (double rings : {0.5, 1.22, 2.23, 5.0}) {
            const double r = rings * lambdaN_px, x = kPi * r / lambdaN_px;
            const double want = 1.0 - std::pow(std::cyl_bessel_j(0.0, x), 2) - std::pow(std::cyl_bessel_j(1.0, x), 2);
            // Pixel centres sample the disc's edge: ±1/2 pixel of radius is the tolerance's scale.
            EXPECT_NEAR(encircled(img, b, 100, 100, r), want, 0.02) << "band " << b << ", r = " << rings << " λN";
        }
        EXPECT_NEAR(encircled(img, b, 100, 100, 1.22 * lambdaN_px), 0.838, 0.02);  // the Airy disc's 83.8 %
    }
    // What the frame keeps: more than the circle it encloses (r = 100 pixels, 1 − J₀² − J₁² =
    // 0.984 at 500 nm), less than all: the rings beyond the frame leave it (zero padding).
    double total = 0.0;
    for (int y = 0; y < 201; ++y)
        for (int x = 0; x < 201; ++x) total += img.pixel(x, y)[0];
    const double x100 = kPi * 100.0 / (500e-6 * 8.0 / 0.0005);
    EXPECT_GT(total, 1.0 - std::pow(std::cyl_bessel_j(0.0, x100), 2) - std::pow(std::cyl_bessel_j(1.0, x100), 2));
    EXPECT_LT(total, 1.0);
}

TEST(Lens, ADefocusedPointIsADiscOfDiameterDefocusOverN) {
    // 80 µm from focus at f/2: a blur circle of 40 µm = 40 pixels of 1 µm, uniform: EE(r) = (2r/d)².
    LensSpec lens;
    lens.diffraction = false;
    lens.pixelAperture = false;
    lens.defocus_um = 80.0;
    const LensGeometry g{0.001, 1.0, 2.0};
    const SpectralCube img = throughLens(point(161, 161, 80, 80, Grid{500, 600, 100}), lens, g, 1);
    EXPECT_NEAR(encircled(img, 0, 80, 80, 10.0), 0.25, 0.02);
    EXPECT_NEAR(encircled(img, 0, 80, 80, 14.14), 0.5, 0.02);
    EXPECT_GT(encircled(img, 0, 80, 80, 22.0), 0.97);  // all of it within the circle (and a pixel)
}

TEST(Lens, LateralCaMovesAPointsImageByItsMagnificationPerBand) {
    // +1 % at 600 nm, 0 at 500 nm: a point 39.5 pixels right of the centre lands 0.395 pixel
    // further out in the 600 nm band only. The point is defocused into an 8-pixel disc first: the
    // band's image is resampled (bilinear), which is exact in the mean for an image that is
    // smooth on the pixel grid, as a lens's image is.
    LensSpec lens;
    lens.diffraction = false;
    lens.pixelAperture = false;
    lens.defocus_um = 160.0;  // d = 160 µm / 4 = 40 µm = 8 pixels
    lens.lateralCa = Spectrum{{500, 600}, {0.0, 0.01}};
    const LensGeometry g{0.005, 1.0, 4.0};
    const SpectralCube img = throughLens(point(100, 60, 89, 30, Grid{500, 600, 100}), lens, g, 1);
    for (int b = 0; b < 2; ++b) {
        double sum = 0.0, sx = 0.0, sy = 0.0;
        for (int y = 0; y < 60; ++y)
            for (int x = 0; x < 100; ++x) {
                const double v = img.pixel(x, y)[b];
                sum += v, sx += v * (x + 0.5), sy += v * (y + 0.5);
            }
        const double want = 50.0 + 39.5 * (b == 0 ? 1.0 : 1.01);
        EXPECT_NEAR(sx / sum, want, 0.01) << b;
        EXPECT_NEAR(sy / sum, 30.5 + 0.5 * (b == 0 ? 0.0 : 0.01), 0.01) << b;
        EXPECT_NEAR(sum, 1.0, 2e-3) << b;  // scaled images keep their energy (to the resampling's 0.13 %)
    }
}

TEST(Lens, AFlatFieldKeepsItsLevelAndAnEdgeDoesNotRing) {
    // Everything on: f/2.8 diffraction, 20 µm of defocus, the pixel aperture at fill 0.5, an OLPF.
    LensSpec lens;
    lens.defocus_um = 20.0;
    lens.olpf_um = 3.0;
    const LensGeometry g{0.004, 0.5, 2.8};
    const Grid grid{400, 700, 100};
    SpectralCube flat(64, 48, grid), edge(64, 48, grid);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            for (int b = 0; b < grid.bands(); ++b) {
                flat.pixel(x, y)[b] = 0.25f;
                edge.pixel(x, y)[b] = x >= 32 ? 1.0f : 0.0f;
            }
    const SpectralCube f = throughLens(flat, lens, g, 2), e = throughLens(edge, lens, g, 2);
    for (int b = 0; b < grid.bands(); ++b) {
        // Away from the frame's edges (where the dark outside blurs in) the level is kept.
        EXPECT_NEAR(f.pixel(32, 24)[b], 0.25, 1e-6) << b;
        // The kernel is ≥ 0: no overshoot above 1, no undershoot below 0, monotonic across the edge
        // (farther than the kernel from the frame, whose dark outside blurs in).
        for (int x = 1; x < 64; ++x) {
            EXPECT_LE(e.pixel(x, 24)[b], 1.0f + 1e-6f);
            EXPECT_GE(e.pixel(x, 24)[b], 0.0f);
            if (x > 16 && x < 46) EXPECT_GE(e.pixel(x, 24)[b] + 1e-6f, e.pixel(x - 1, 24)[b]) << b << " " << x;
        }
        EXPECT_LT(lensKernel(lens, g, 400.0 + 100.0 * b).foldedIn, 0.01) << b;
    }
}

TEST(Lens, TheKernelsMtfIsTheDiffractionMtfTimesThePixelsSincPerBand) {
    // f/16 on 1 µm pixels: the cutoff 1/(λN) (125 cycles/mm at 500 nm) lies below the pixels'
    // Nyquist frequency (500), so the kernel's Fourier transform is the closed form
    // (2/π)(acos ν − ν√(1 − ν²)) · sinc(p·f) itself — no alias — to the < 1 % of tails folded in.
    LensSpec lens;
    lens.pixelAperture = false;
    const LensGeometry g{0.001, 1.0, 16.0};
    for (double nm : {400.0, 550.0, 700.0}) {
        const LensKernel k = lensKernel(lens, g, nm);
        const int side = 2 * k.radius + 1;
        const double cutoff = 1.0 / (nm * 1e-6 * 16.0);
        for (double nu : {0.1, 0.25, 0.5, 0.75, 0.9}) {
            const double f = nu * cutoff;
            double mtf = 0.0;
            for (int y = -k.radius; y <= k.radius; ++y)
                for (int x = -k.radius; x <= k.radius; ++x)
                    mtf += k.weights[size_t(y + k.radius) * side + size_t(x + k.radius)] * std::cos(2 * kPi * f * x * 0.001);
            const double sinc = std::sin(kPi * 0.001 * f) / (kPi * 0.001 * f);
            const double want = 2.0 / kPi * (std::acos(nu) - nu * std::sqrt(1.0 - nu * nu)) * sinc;
            EXPECT_NEAR(mtf, want, 0.01) << nm << " nm, ν = " << nu;
        }
    }
}

// The lens's cost (docs/performance.md, "The lens"): a figure, not an assertion. Run with
// --gtest_also_run_disabled_tests --gtest_filter='Lens.DISABLED_Timing*'.
TEST(Lens, DISABLED_TimingThroughLens) {
    LensSpec lens;
    lens.defocus_um = 10.0;
    const LensGeometry g{0.00478, 1.0, 4.0};  // the bundled APS-C sensor's pixels at f/4
    // 4096² with 8 bands (a whole 89-band cube and its blurred copy are 12 GB): the cost is per band.
    for (int side : {1024, 2048, 4096}) {
        SpectralCube cube(side, side, side == 4096 ? Grid{300, 335, 5} : Grid{300, 740, 5});
        for (size_t i = 0; i < cube.data.size(); ++i) cube.data[i] = float(i % 1013) / 1013.0f;
        std::vector<double> ms;
        for (int run = 0; run < 3; ++run) {
            const auto t0 = std::chrono::steady_clock::now();
            const SpectralCube out = throughLens(cube, lens, g);
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        std::sort(ms.begin(), ms.end());
        const int bands = cube.grid.bands();
        std::printf("lens: %d² × %d bands: median %.0f ms of 3 (%.1f ms a band)\n", side, bands, ms[1], ms[1] / bands);
    }
}

TEST(Lens, NollsZernikeTermsAreOrthonormalOverTheUnitDisc) {
    EXPECT_NEAR(zernike(1, 0.3, 1.0), 1.0, 1e-15);
    EXPECT_NEAR(zernike(2, 0.5, 0.0), 1.0, 1e-15);                       // 2ρ cos θ
    EXPECT_NEAR(zernike(3, 0.5, kPi / 2), 1.0, 1e-15);                   // 2ρ sin θ
    EXPECT_NEAR(zernike(4, 1.0, 0.0), std::sqrt(3.0), 1e-15);            // √3(2ρ² − 1)
    EXPECT_NEAR(zernike(11, 0.5, 0.0), std::sqrt(5.0) * (6 * 0.0625 - 6 * 0.25 + 1), 1e-14);  // spherical
    EXPECT_NEAR(zernike(7, 1.0, kPi / 2), std::sqrt(8.0), 1e-14);        // coma √8(3ρ³ − 2ρ) sin θ
    // (1/π)∫ Z_j Z_k = δ_jk for the first 15 terms, by the midpoint rule in (ρ, θ).
    const int nr = 400, nt = 400;
    for (int j = 1; j <= 15; ++j)
        for (int k = j; k <= 15; ++k) {
            double sum = 0.0;
            for (int a = 0; a < nr; ++a)
                for (int b = 0; b < nt; ++b) {
                    const double rho = (a + 0.5) / nr, theta = 2 * kPi * (b + 0.5) / nt;
                    sum += zernike(j, rho, theta) * zernike(k, rho, theta) * rho;
                }
            EXPECT_NEAR(sum * (1.0 / nr) * (2 * kPi / nt) / kPi, j == k ? 1.0 : 0.0, 2e-4) << j << ", " << k;
        }
}

TEST(Lens, AnAberratedPupilGivesTiltsShiftAndDefocussStrehlRatio) {
    // f/8 at 550 nm on 1 µm pixels (λN = 4.4 pixels).
    const LensGeometry g{0.001, 1.0, 8.0};
    LensSpec lens;
    lens.pixelAperture = false;
    auto centroid = [](const LensKernel& k) {
        const int side = 2 * k.radius + 1;
        double sx = 0.0, sum = 0.0;
        for (int y = -k.radius; y <= k.radius; ++y)
            for (int x = -k.radius; x <= k.radius; ++x) {
                const double v = k.weights[size_t(y + k.radius) * side + size_t(x + k.radius)];
                sx += v * x, sum += v;
            }
        return sx / sum;
    };
    const LensKernel perfect = lensKernel(lens, g, 550);
    // A piston only (a constant phase) takes the pupil's path and must give the closed form's kernel.
    lens.zernike = {Spectrum::makeConstant(0.3)};
    const LensKernel piston = lensKernel(lens, g, 550);
    ASSERT_EQ(piston.radius, perfect.radius);
    double worst = 0.0;
    for (size_t i = 0; i < perfect.weights.size(); ++i)
        worst = std::max(worst, std::abs(piston.weights[i] - perfect.weights[i]));
    const double peak = perfect.weights[perfect.weights.size() / 2];
    EXPECT_LT(worst, 0.02 * peak);
    // Tilt: Noll's Z₂ with c waves moves the image by 4c·λ·N_w toward +x: 0.25 waves → 4.4 pixels.
    lens.zernike = {Spectrum::makeConstant(0.0), Spectrum::makeConstant(0.25)};
    const double shift = centroid(lensKernel(lens, g, 550));
    EXPECT_NEAR(shift, 4.4, 0.1);
    EXPECT_NEAR(centroid(perfect), 0.0, 1e-9);
    // Defocus: Z₄ with c waves RMS has the Strehl ratio (sin a / a)², a = 2π√3·c — 0.9048 at
    // c = 0.05 (Mahajan); the peak pixel's ratio to the perfect lens's, to 1.5 % (the pixel
    // averages over 1/4.4 of λN).
    lens.zernike = {Spectrum::makeConstant(0.0), Spectrum::makeConstant(0.0), Spectrum::makeConstant(0.0),
                    Spectrum::makeConstant(0.05)};
    const LensKernel defocused = lensKernel(lens, g, 550);
    const double a = 2 * kPi * std::sqrt(3.0) * 0.05;
    const double strehl = defocused.weights[defocused.weights.size() / 2] / peak;
    std::printf("pupil path: piston's worst kernel difference %.4f of the peak; tilt shift %.4f px (4.4); defocus "
                "peak ratio %.4f (Strehl %.4f)\n", worst / peak, shift, strehl, std::pow(std::sin(a) / a, 2));
    EXPECT_NEAR(strehl, std::pow(std::sin(a) / a, 2), 0.015);
}
