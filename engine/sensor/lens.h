// The lens between the radiance cube and the sensor, per wavelength (issue 48, item 1;
// docs/camera.md, "The lens"): each band of the cube is filtered by the lens's optical transfer
// function on the sensor's pixel grid — the diffraction of a circular aperture at the working
// f-number, defocus (a focus error plus the longitudinal chromatic aberration at that band), the
// pixel's own aperture and an optional 4-spot optical low-pass filter — and scaled about the image
// centre by the lateral chromatic aberration. Convolution by FFT (FFTW, Debian's libfftw3): the
// image is padded with zero radiance, so outside the frame the scene is dark (docs say what that
// means at the borders). Nothing of this runs for a sensor without `optics.lens`.
// Tests: engine/sensor/lens_test.cpp, tests/python/test_lens.py (scipy's Bessel functions).
#pragma once

#include "spectral/cube.h"
#include "spectral/spectrum.h"

#include <optional>
#include <vector>

namespace metamer {

struct LensSpec {
    bool diffraction = true;          // the circular aperture's Airy pattern at each band's λ
    double defocus_um = 0.0;          // the sensor's distance from the best focus (either sign), µm
    std::optional<Spectrum> focusShift_um;  // longitudinal CA: best focus per λ, µm, added to defocus
    std::optional<Spectrum> lateralCa;      // lateral CA: relative magnification change per λ (0.001 = +0.1 %)
    bool pixelAperture = true;        // the pixel integrates over its square aperture, pitch·√fill factor
    double olpf_um = 0.0;             // a 4-spot birefringent low-pass filter's spot separation, µm (0: none)
    // The wavefront error over the exit pupil, in waves per λ: zernike[j − 1] is Noll's term j
    // (RMS-normalized over the unit disc: Z₂ = 2ρ cos θ, Z₄ = √3(2ρ² − 1), …). With any term, the
    // pupil's OTF is computed from it (diffraction included) instead of the closed form.
    std::vector<Spectrum> zernike;
};

// Noll's Zernike term j ≥ 1 at (ρ, θ) on the unit disc (Noll 1976, J. Opt. Soc. Am. 66, 207).
double zernike(int j, double rho, double theta);

struct LensGeometry {
    double pitch_mm = 0.0;            // the sensor's pixel pitch
    double fillFactor = 1.0;
    double workingF = 0.0;            // N(1 + m)
};

// The lens's OTF at spatial frequency (fx, fy) cycles/mm, for wavelength λ: the product of the
// diffraction OTF (2/π)(acos ν − ν√(1 − ν²)), ν = f·λ·N_w; the geometric defocus blur
// 2J₁(πdf)/(πdf) of a disc of diameter d = |Δz|/N_w; the pixel aperture sinc(a·fx)·sinc(a·fy),
// a = pitch·√fill; and the OLPF cos(π·s·fx)·cos(π·s·fy).
double lensTransfer(const LensSpec& lens, const LensGeometry& g, double wavelength_nm, double fx, double fy);

// The blur-circle diameter (mm) at wavelength λ: |defocus + focus shift(λ)| / N_w.
double defocusDiameter_mm(const LensSpec& lens, const LensGeometry& g, double wavelength_nm);

// The lens's discrete kernel at wavelength λ on the pixel grid: what a pixel of the cube (a square
// of constant radiance, the pitch wide) sends to the pixels around it, through the OTF above —
// the continuous PSF convolved with the scene pixel's square (and the sensor pixel's aperture,
// an OLPF), sampled at the pixels' centres. Computed by an inverse FFT on a grid 4–16 times finer
// than the pixels (fine enough to hold the diffraction cutoff), so it is ≥ 0 and rings nowhere;
// `radius` pixels reach 20 Airy radii (the rings beyond hold < 1 % of the light, folded in: the
// weights sum to 1, so a flat field keeps its level exactly).
struct LensKernel {
    int radius = 0;
    std::vector<double> weights;  // (2·radius + 1)², row by row, centre at [radius][radius]
    double foldedIn = 0.0;
};
LensKernel lensKernel(const LensSpec& lens, const LensGeometry& g, double wavelength_nm);

// The cube as the sensor's pixels receive it through `lens`: every band filtered by the OTF and
// scaled by its lateral CA. Radiance units are kept (the camera equation follows). Bands run on
// `threads` threads (0: one per CPU).
SpectralCube throughLens(const SpectralCube& cube, const LensSpec& lens, const LensGeometry& g, int threads = 0);

}  // namespace metamer
