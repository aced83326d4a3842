#include "isp/image_processor.h"

#include "color/camera_characterization.h"
#include "color/delta_e.h"
#include "color/lab.h"
#include "color/srgb.h"
#include "core/parallel_for.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace metamer {

WhiteBalance parseWhiteBalance(const std::string& name, const Where& where) {
    if (name == "illuminant") return WhiteBalance::Illuminant;
    if (name == "grey-world") return WhiteBalance::GreyWorld;
    if (name == "patch") return WhiteBalance::Patch;
    failInput(where, "unknown white balance '{}'; expected illuminant, grey-world or patch", name);
}

std::string whiteBalanceName(WhiteBalance w) {
    switch (w) {
        case WhiteBalance::Illuminant: return "illuminant";
        case WhiteBalance::GreyWorld: return "grey-world";
        case WhiteBalance::Patch: return "patch";
    }
    return "?";
}

int patchCoordinate(double v, const Where& where) {
    if (!(v >= 0 && v <= 65536 && std::floor(v) == v))
        failInput(where, "expected a whole number of pixels, 0 … 65536; got {:g}", v);
    return int(v);
}

int displayBits(long long bits, const Where& where) {
    if (bits != 8 && bits != 16) failInput(where, "expected 8 or 16 bits per channel, got {}", bits);
    return int(bits);
}

ProcessorColour fitProcessorColour(const Detector& camera, const std::vector<double>& illuminantOnGrid,
                                   const Grid& grid, const SpectrumLibrary& library, const ProcessorSpec& spec,
                                   const Where& where) {
    const CameraCharacterization c =
        characterizeCamera(camera, illuminantOnGrid, library, grid, Integration::Riemann, CameraFit::WhitePreserving);
    auto singular = [&] {
        failInput(where, "the R, G and B channels' sensitivities are linearly dependent: the ColorChecker fit has no "
                  "colour correction (and the DNG no ColorMatrix1, AsShotNeutral)");
    };
    // The targets: the patches' XYZ under the illuminant, adapted to D65. Least squares is linear in
    // its targets, so the 3 × 3 fitted to adapted targets is the adaptation times the one fitted to
    // the XYZ themselves (the white-preserving constraint moves with them).
    ProcessorColour out;
    out.display = parseDisplay(spec.display, spec.bits, where.child("display"));
    const glm::dvec3 displayWhite = out.display.whiteXyz / out.display.whiteXyz.y;
    const glm::dmat3 cat = adaptationMatrix(spec.adaptation, c.whiteXyz, displayWhite);
    const glm::dvec3 white = cat * c.whiteXyz;
    std::vector<glm::dvec3> target;
    for (const glm::dvec3& xyz : c.patchXyz) target.push_back(cat * xyz);

    out.linearToXyz = adaptationMatrix(spec.adaptation, c.whiteXyz, kD65WhiteXyz) * c.rawToXyz;
    const double det = glm::determinant(out.linearToXyz);
    if (!std::isfinite(det) || std::abs(det) < 1e-12) singular();
    const glm::dvec3 raw = 1.0 / c.whiteBalance;  // the white's raw response
    const double peak = std::max({raw.x, raw.y, raw.z});
    out.illuminantNeutral = raw / peak;

    if (spec.correction == CorrectionForm::Linear) {
        const glm::dmat3 m = cat * c.rawToXyz;
        out.toXyz.form = CorrectionForm::Linear;
        out.toXyz.columns = {m[0], m[1], m[2]};
    } else {
        out.toXyz = fitColourCorrection(spec.correction, c.patchBalancedRaw, target, where);
    }

    // ColorMatrix1: XYZ → raw, diag(n̂)·M⁻¹, so that the D65 white (M·1 = white) maps to n̂.
    const glm::dmat3 inverse = glm::inverse(out.linearToXyz);
    for (int r = 0; r < 3; ++r)
        for (int col = 0; col < 3; ++col) {
            const double v = out.illuminantNeutral[r] * inverse[col][r];  // glm: [column][row]
            if (!std::isfinite(v)) singular();
            out.dngColorMatrix[size_t(r * 3 + col)] = v;
        }

    double sum2 = 0.0;
    for (size_t p = 0; p < target.size(); ++p) {
        const double de = deltaE2000(xyzToLab(applyColourCorrection(out.toXyz, c.patchBalancedRaw[p]), white),
                                     xyzToLab(target[p], white));
        out.patchDeltaE2000.push_back(de);
        sum2 += de * de;
    }
    out.rmsDeltaE2000 = std::sqrt(sum2 / double(target.size()));
    return out;
}

namespace {

// Step 1 at site i: v = max(DN − black, 0) / (white − black).
double normalizedSite(const RawFrame& f, size_t i) { return std::max(double(f.dn[i]) - f.black, 0.0) / (f.white - f.black); }

int siteColour(const RawFrame& f, int x, int y) { return f.cfa[size_t((y & 1) * 2 + (x & 1))]; }

}  // namespace

bool developable(int width, int height) { return width >= 2 && height >= 2; }

glm::dvec3 whiteBalanceNeutral(const RawFrame& f, const ProcessorSpec& spec, const ProcessorColour& colour,
                               const Where& where) {
    if (spec.whiteBalance == WhiteBalance::Illuminant) return colour.illuminantNeutral;
    int x0 = 0, y0 = 0, x1 = f.width, y1 = f.height;
    if (spec.whiteBalance == WhiteBalance::Patch) {
        const auto& [px, py, pw, ph] = spec.patch;
        if (px < 0 || py < 0 || pw < 2 || ph < 2 || px > f.width - pw || py > f.height - ph)
            failInput(where.child("patch"),
                      "the patch [{}, {}, {}, {}] (x, y, width, height) is not a rectangle of at least 2 × 2 pixels "
                      "inside the {}×{} frame",
                      px, py, pw, ph, f.width, f.height);
        x0 = px, y0 = py, x1 = px + pw, y1 = py + ph;
    }
    glm::dvec3 sum(0.0), count(0.0);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const int c = siteColour(f, x, y);
            sum[c] += normalizedSite(f, size_t(y) * size_t(f.width) + size_t(x));
            count[c] += 1.0;
        }
    const glm::dvec3 mean = sum / count;
    const double peak = std::max({mean.x, mean.y, mean.z});
    for (int c = 0; c < 3; ++c)
        if (!(mean[c] > 0.0))
            failInput(spec.whiteBalance == WhiteBalance::Patch ? where.child("patch") : where.child("white_balance"),
                      "the {} white balance finds no signal above black in channel {} of the frame: no neutral to "
                      "balance to",
                      whiteBalanceName(spec.whiteBalance), "RGB"[c]);
    return mean / peak;
}

DevelopedImage develop(const RawFrame& f, const ProcessorSpec& spec, const ProcessorColour& colour,
                       const Where& where) {
    if (!(f.white > f.black)) failInput(where, "the white level {:g} is not above the black level {:g}", f.white, f.black);
    if (!developable(f.width, f.height))
        failInput(where, "a {}×{} frame cannot be developed: demosaicing a 2 × 2 CFA needs at least 2 × 2 pixels", f.width,
                  f.height);
    DevelopedImage out;
    out.width = f.width;
    out.height = f.height;
    out.neutral = whiteBalanceNeutral(f, spec, colour, where);
    out.gains = std::max({out.neutral.x, out.neutral.y, out.neutral.z}) / out.neutral;
    std::vector<double> balanced(size_t(f.width) * size_t(f.height));
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const size_t i = size_t(y) * size_t(f.width) + size_t(x);
            balanced[i] = std::min(normalizedSite(f, i) * out.gains[siteColour(f, x, y)], 1.0);
        }
    const std::vector<double> rgb = demosaic(balanced, f.width, f.height, f.cfa, spec.demosaic, DemosaicBorder::Mirror);
    out.xyz.resize(rgb.size());
    out.linearRgb.resize(rgb.size());
    const glm::dmat3 toRgb = glm::inverse(colour.display.rgbToXyz);
    parallelFor(rgb.size() / 3, 0, 16384, [&](size_t p) {
        const size_t i = 3 * p;
        const glm::dvec3 xyz = applyColourCorrection(colour.toXyz, {rgb[i], rgb[i + 1], rgb[i + 2]}) * spec.exposure;
        const glm::dvec3 linear = toRgb * (xyz - colour.display.blackXyz);
        for (int c = 0; c < 3; ++c) out.xyz[i + size_t(c)] = xyz[c], out.linearRgb[i + size_t(c)] = linear[c];
    });
    return out;
}

std::vector<uint16_t> encodeCounts(const DevelopedImage& image, const DisplayModel& display) {
    std::vector<uint16_t> out(image.xyz.size());
    parallelFor(out.size() / 3, 0, 16384, [&](size_t p) {
        const size_t i = 3 * p;
        const glm::dvec3 counts = encodeXyz(display, {image.xyz[i], image.xyz[i + 1], image.xyz[i + 2]}).counts;
        for (int c = 0; c < 3; ++c) out[i + size_t(c)] = uint16_t(counts[c]);
    });
    return out;
}

}  // namespace metamer
