// RGB → reflectance spectrum up-sampling with the sigmoid-of-quadratic model of W. Jakob and
// J. Hanika, "A Low-Dimensional Function Space for Efficient Spectral Upsampling", Computer
// Graphics Forum 38(2) (Eurographics 2019):
//
//     ρ(λ) = S(c0·λ² + c1·λ + c2),   S(x) = ½ + x / (2·√(1 + x²)),   λ in nm
//
// S is smooth and maps ℝ into the open interval (0, 1), so every up-sampled spectrum is a smooth,
// bounded reflectance. For a linear sRGB colour the three coefficients are chosen so that the
// spectrum's colour under D65 (CIE 1931 observer, white diffuser → (1, 1, 1): the same definition
// as the RGB mode, docs/representations.md "RGB") equals the colour; the fit minimizes the
// CIELAB distance. Fitting is an iterative solve, so the project precomputes the coefficients on a
// 3-D table (built at build time by tools/rgb_upsampling_table.cpp) and interpolates them.
// docs/upsampling.md gives the method, the table and the measured round-trip errors.
#pragma once

#include "spectral/grid.h"
#include "spectral/resampling.h"
#include "spectral/library.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

// The model's coefficients for λ in nm: c0 in nm⁻², c1 in nm⁻¹, c2 dimensionless.
struct SigmoidCoefficients {
    double c0 = 0.0, c1 = 0.0, c2 = 0.0;
};

class RgbUpsampler {
public:
    using Coefficients = SigmoidCoefficients;

    // The wavelength range the fit sees (the CIE 1931 table's range; D65 is 0 past 780 nm).
    // Outside it the model's quadratic is unconstrained and would run to 0 or 1 far in the UV or
    // IR, so reflectance() holds the end values there: ρ(λ) = S(q(clamp(λ, 360, 830))).
    static constexpr double kFitMinNm = 360.0;
    static constexpr double kFitMaxNm = 830.0;

    // The coefficients of the constant spectra 0 and 1. S reaches 0 and 1 only in the limit, but
    // with |c2| = 2^30 the formula rounds to exactly 0 and 1 in double and in float (1 + c2² == c2²,
    // √(c2²) == |c2|), so black and white texels give exact zero and unit reflectance.
    static constexpr double kSaturated = 1073741824.0;  // 2^30
    static constexpr Coefficients kBlack{0.0, 0.0, -kSaturated};
    static constexpr Coefficients kWhite{0.0, 0.0, kSaturated};

    // The up-sampler for linear sRGB under D65 with the CIE 1931 observer, both taken from
    // `library` (illuminants/D65, observers/cie1931_2deg). Made once per library root and kept for
    // the process's life (thread-safe). Loads the table built with the project when its fingerprint
    // (a hash of the colour weights computed from `library` and the table's format) matches;
    // otherwise builds the table in memory at kDefaultResolution and warns (seconds, see
    // docs/upsampling.md). Throws an input error naming the library when D65 or the observer are
    // missing or malformed.
    static const RgbUpsampler& srgb(const SpectrumLibrary& library);

    // The coefficients for a linear sRGB colour: the table's interpolated coefficients (lookup()),
    // polished by the solver until the spectrum's colour is within kFitTolerance (ΔE*ab) of the
    // target (typically one or two iterations, about 5 µs per colour; a cold start from the flat
    // spectrum ½ when the interpolated start does not converge in kFitIterations, which happens
    // next to white).
    // Inputs are first brought into [0, 1]³ by clampLinearRgb(); exact (0, 0, 0) gives kBlack and
    // exact (1, 1, 1) gives kWhite.
    struct FitReport {
        double residual = 0.0;  // ΔE*ab left
        int iterations = 0;
    };
    static constexpr double kFitTolerance = 1e-4;
    static constexpr int kFitIterations = 20;
    Coefficients fit(const glm::dvec3& linearRgb, FitReport* report = nullptr) const;
    // The same for an sRGB-encoded colour (the transfer function of IEC 61966-2-1 is removed first,
    // color/srgb.h), as 8-bit PNG and JPEG textures store it: fit(decodeSrgb(encoded)).
    Coefficients fitEncoded(const glm::dvec3& srgbEncoded) const;
    // The table alone: trilinear interpolation of the node coefficients (about 0.1 µs), the
    // paper's scheme. Its colour error is largest next to white, where the nodes' coefficients run
    // to +∞, and at the gamut's faces (up to ~1 ΔE00, docs/upsampling.md). Same clamping and
    // exact black and white as fit().
    Coefficients lookup(const glm::dvec3& linearRgb) const;

    // The direct solve behind the table, without interpolation (Gauss–Newton on the CIELAB
    // residual with Levenberg–Marquardt damping; about 15 µs from a flat start) to
    // kResidualTolerance. `start` is the initial guess.
    // Inputs are clamped as by fit().
    struct Solution {
        Coefficients coefficients;
        double residual = 0.0;  // CIE 1976 ΔE*ab between the spectrum's colour and the target
        int iterations = 0;
    };
    Solution solve(const glm::dvec3& linearRgb, const Coefficients& start = {}) const;

    // ρ(λ) of the model, with λ held to [kFitMinNm, kFitMaxNm] (see above). In [0, 1]: strictly
    // inside for every table node (tested); kBlack and kWhite give exactly 0 and 1.
    static double reflectance(const Coefficients& c, double lambda_nm);
    // S(x) = ½ + x / (2·√(1 + x²)).
    static double sigmoid(double x);

    // The spectrum on a render grid. The model is a function known at every wavelength, not data,
    // so under the grid's rule (docs/physics.md, "Resampling") band i holds its value at the band
    // centre, ρ(λi) — what a table of it sampled at λi would give. Under Resampling::BandMean it
    // holds the mean of ρ over [λi − Δ/2, λi + Δ/2], by adaptive 3-point Gauss–Legendre to
    // kBandTolerance (spectra at the gamut boundary have transitions narrower than a nanometre,
    // which a fixed rule would miss; about 4 µs for 89 bands). Reflectance factor, 0..1.
    static constexpr double kBandTolerance = 1e-9;
    std::vector<double> bands(const glm::dvec3& linearRgb, const Grid& grid) const;
    static std::vector<double> bands(const Coefficients& c, const Grid& grid);

    // The colour of the model spectrum under D65, in linear sRGB with the white diffuser at
    // (1, 1, 1): Σλ w(λ)·ρ(λ) at 1 nm over 360–830 nm, the quantity the fit matches.
    glm::dvec3 linearRgbOf(const Coefficients& c) const;
    // Its CIELAB, relative to D65 (the white diffuser is (100, 0, 0)).
    glm::dvec3 labOf(const Coefficients& c) const;
    // The target's CIELAB (linear sRGB → XYZ → L*a*b*, same white).
    static glm::dvec3 labOfLinearRgb(const glm::dvec3& linearRgb);

    // The clamping rule for inputs: NaN and negative channels become 0 (no reflectance is
    // negative; such values come from out-of-gamut or HDR data); then, if the largest channel
    // exceeds 1, the colour is divided by it (keeps the chromaticity: a reflectance cannot exceed
    // the white diffuser, and a per-channel clamp would shift the hue).
    static glm::dvec3 clampLinearRgb(const glm::dvec3& linearRgb);
    // IEC 61966-2-1 decoding per channel (color/srgb.h srgbDecode).
    static glm::dvec3 decodeSrgb(const glm::dvec3& encoded);

    // --- The table -------------------------------------------------------------------------
    // Indexed by the largest channel l (3), its value z (res samples, denser near 0 and 1:
    // z_k = s(s(k/(res − 1))), s(t) = 3t² − 2t³) and the other two channels divided by it
    // (x = rgb[(l+1) mod 3]/z, y = rgb[(l+2) mod 3]/z; res uniform samples in [0, 1] each).
    static constexpr int kDefaultResolution = 64;

    // Builds a table by solving every node, outward from the centre: for each l, the layer
    // z = z_{res/5} is solved from the grey corner (x = y = 1, a flat spectrum) towards x = y = 0,
    // each node starting from its solved neighbour; then every (x, y) column marches up to z = 1 and
    // down to z = 0 from that layer, each node starting from the previous one. Columns are
    // independent and spread over `threads` threads; the result does not depend on the count.
    struct BuildStats {
        double seconds = 0.0;
        double maxResidual = 0.0;  // largest node ΔE*ab
        int unconverged = 0;       // nodes whose residual stayed above kResidualTolerance
        long iterations = 0;       // Gauss–Newton iterations over all nodes
    };
    static RgbUpsampler build(const SpectrumLibrary& library, int resolution, int threads,
                              BuildStats* stats = nullptr);
    // The solver stops at this ΔE*ab (or after kMaxIterations).
    static constexpr double kResidualTolerance = 1e-6;
    static constexpr int kMaxIterations = 200;

    // Binary table file: a header (magic, format version, resolution, fingerprint), the z samples,
    // then the coefficients. Writing is atomic (temporary file + rename).
    void write(const std::filesystem::path& path) const;
    // Reads a table file; returns false (and leaves *this alone) when the file is missing,
    // malformed or was made from other colour weights than this up-sampler's.
    bool read(const std::filesystem::path& path);

    int resolution() const { return resolution_; }
    const std::vector<double>& zSamples() const { return z_; }
    // A node's coefficients (l: largest channel 0..2; xi, yi, zi: 0..res−1).
    Coefficients node(int l, int xi, int yi, int zi) const;
    // The linear sRGB colour a node stands for.
    glm::dvec3 nodeColor(int l, int xi, int yi, int zi) const;
    // Where the table came from, for messages: a file path or "built in memory".
    const std::string& source() const { return source_; }
    std::uint64_t fingerprint() const { return fingerprint_; }

    // The colour weights alone, without a table (for tests and the build tool).
    explicit RgbUpsampler(const SpectrumLibrary& library);

private:
    // The fit works in the centred, scaled wavelength u = (λ − 595 nm)/235 nm ∈ [−1, 1], where
    // the coefficients are well conditioned; the table stores these and fit() converts to nm.
    // 1 nm samples where D65 > 0, as separate arrays (the solver's inner loop vectorizes).
    std::vector<double> u_, wr_, wg_, wb_;
    std::uint64_t fingerprint_ = 0;
    int resolution_ = 0;
    std::vector<double> z_;
    std::vector<double> table_;  // [l][zi][yi][xi][3], u-domain coefficients
    std::string source_;

    size_t offset(int l, int xi, int yi, int zi) const;
    glm::dvec3 solveU(const glm::dvec3& target, glm::dvec3 start, double tolerance, int maxIterations,
                      double* residual, int* iterations) const;
    glm::dvec3 colorU(const glm::dvec3& a, glm::dmat3* jacobian) const;
};

}  // namespace metamer
