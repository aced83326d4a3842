#include "compare/compare.h"

#include "io/exr_file.h"
#include "io/image_reader.h"
#include "io/spectral_image.h"
#include "core/json.h"
#include "core/statistics.h"
#include "spectral/resampling.h"

#include "color/cie_xyz.h"
#include "color/delta_e.h"
#include "color/lab.h"
#include "core/error.h"
#include "core/file_reads.h"
#include "io/atomic_file.h"
#include "io/spectral_exr.h"
#include "spectral/spectrum.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>

namespace fs = std::filesystem;

namespace metamer {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRadToDeg = 180.0 / M_PI;

// Grids read from channel names (files without a metamer:grid attribute) carry 6 decimals, so two
// files on the same grid may disagree in the last bits of start or step.
bool sameGrid(const Grid& a, const Grid& b) {
    if (a.bands() != b.bands()) return false;
    for (int i = 0; i < a.bands(); ++i)
        if (std::fabs(a.wavelength(i) - b.wavelength(i)) > 1e-6) return false;
    return true;
}

std::string nameOf(const ImageData& image, const char* fallback) {
    return image.source.empty() ? std::string(fallback) : image.source;
}

std::string describeChannels(const ImageData& image) {
    if (image.grid) return fmt::format("{} bands on {}", image.grid->bands(), image.grid->str());
    std::string names;
    for (size_t c = 0; c < image.channels.size() && c < 8; ++c) names += (c ? "," : "") + image.channels[c];
    if (image.channels.size() > 8) names += ",...";
    return fmt::format("channels {}", names);
}

// A's bands on B's grid. Resampling is linear in the band values, so the map is a matrix: column j
// is spectral/spectrum.h's band averaging of the piecewise-linear "hat" that is 1 at A's band j
// and 0 at the others. Building it once keeps a 1024×1024 cube at one multiply-add per non-zero
// weight instead of one resample() call per pixel.
ImageData resampleOnto(const ImageData& a, const Grid& target, const std::string& bName) {
    const Grid& from = *a.grid;
    const int na = from.bands(), nb = target.bands();
    if (na < 2)
        failInput(Where{nameOf(a, "A")}, "cannot resample a one-band cube onto {}'s grid {}", bName, target.str());
    Spectrum hat;
    hat.wavelengths_nm = from.wavelengths();
    hat.values.assign(na, 0.0);
    hat.source = nameOf(a, "A");
    if (CoverageGap gap = coverage(hat, target); !gap.covered)
        warn(Where{nameOf(a, "A")},
             fmt::format("its grid {} does not reach every band of {}'s grid {}; bands beyond its data hold its end "
                         "values or are 0 (docs/physics.md, \"Resampling\")",
                         from.str(), bName, target.str()));
    std::vector<std::vector<double>> weights(nb, std::vector<double>(na, 0.0));
    for (int j = 0; j < na; ++j) {
        hat.values[j] = 1.0;
        std::vector<double> column = resample(hat, target);
        hat.values[j] = 0.0;
        for (int i = 0; i < nb; ++i) weights[i][j] = column[i];
    }
    // Each target band touches only a few source bands: keep their range.
    std::vector<int> first(nb, 0), last(nb, -1);
    for (int i = 0; i < nb; ++i)
        for (int j = 0; j < na; ++j)
            if (weights[i][j] != 0.0) {
                if (last[i] < 0) first[i] = j;
                last[i] = j;
            }

    ImageData out;
    out.width = a.width;
    out.height = a.height;
    out.grid = target;
    out.source = a.source;
    out.kind = a.kind;
    std::string prefix = a.reflective() ? "T" : "S0";
    for (double w : target.wavelengths()) out.channels.push_back(prefix + spectralChannelName(w).substr(2));
    const size_t pixels = size_t(a.width) * a.height;
    out.data.assign(pixels * nb, 0.0f);
    for (size_t p = 0; p < pixels; ++p) {
        const float* src = a.data.data() + p * na;
        float* dst = out.data.data() + p * nb;
        for (int i = 0; i < nb; ++i) {
            double v = 0.0;
            for (int j = first[i]; j <= last[i]; ++j) v += weights[i][j] * src[j];
            dst[i] = float(v);
        }
    }
    return out;
}

// A's channels in B's order (plain images may store the same channels in another order); `a`
// itself, uncopied, when the order already agrees.
const ImageData& reorderLike(ImageData& storage, const ImageData& a, const ImageData& b, const std::string& aName, const std::string& bName) {
    const size_t n = b.channels.size();
    std::vector<size_t> from(n);
    std::vector<std::string> missing, extra;
    for (size_t c = 0; c < n; ++c) {
        auto it = std::find(a.channels.begin(), a.channels.end(), b.channels[c]);
        if (it == a.channels.end()) missing.push_back(b.channels[c]);
        else from[c] = size_t(it - a.channels.begin());
    }
    for (const auto& name : a.channels)
        if (std::find(b.channels.begin(), b.channels.end(), name) == b.channels.end()) extra.push_back(name);
    if (!missing.empty() || !extra.empty() || a.channels.size() != n)
        failInput(Where{aName}, "has {} but the reference {} has {}{}{}", describeChannels(a), bName,
                  describeChannels(b), missing.empty() ? "" : fmt::format(" (missing: {})", fmt::join(missing, ",")),
                  extra.empty() ? "" : fmt::format(" (not in the reference: {})", fmt::join(extra, ",")));
    bool identity = true;
    for (size_t c = 0; c < n; ++c) identity = identity && from[c] == c;
    if (identity) return a;
    storage = a;
    storage.channels = b.channels;
    const size_t pixels = size_t(a.width) * a.height;
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < n; ++c) storage.data[p * n + c] = a.data[p * n + from[c]];
    return storage;
}

// The ΔE2000 of every pixel through the chosen detector, adaptation and display white. A cube
// carries no scene, so there is no light to call white: the white is an equal-energy spectrum —
// for radiance, at the level whose CIE 1931 Y is B's 99th percentile of Y over its lit pixels
// (the quick-look PNG's exposure rule: stable against a few highlights, and taken from the
// reference alone so A's errors cannot move it); for reflectance, the perfect reflector (1 in every
// band). The tonemap plan then does exactly what a render does with that white.
void addDeltaE(const ImageData& a, const ImageData& b, const TonemapSettings& settings, CompareStats& stats) {
    auto masked = [&](size_t p) { return !stats.mask.empty() && stats.mask[p] != 0; };
    const Grid& grid = *b.grid;
    const int bands = grid.bands();
    const size_t pixels = size_t(b.width) * b.height;
    SpectrumLibrary library;
    ColorMatchingFunctions cmf = loadCie1931(library, grid);
    double yOfUnit = 0.0;  // CIE 1931 Y of radiance 1 in every band
    for (int i = 0; i < bands; ++i) yOfUnit += cmf.y[i] * grid.step_nm;
    if (!(yOfUnit > 0.0))
        failInput(Where{"", "--detector"},
                  "ΔE2000 needs visible light, but the grid {} lies outside the CIE 1931 observer's data", grid.str());

    double level = 1.0;
    std::string white;
    if (b.reflective()) {
        white = "the perfect reflector (T = 1) under an equal-energy light";
    } else {
        std::vector<double> lit;
        lit.reserve(pixels);
        for (size_t p = 0; p < pixels; ++p) {
            double y = spectrumToXyz(b.data.data() + p * bands, cmf).y;
            if (std::isfinite(y) && y > 0.0) lit.push_back(y);
        }
        if (lit.empty()) {
            white = "an equal-energy radiance of 1 W·sr⁻¹·m⁻²·nm⁻¹ (the reference is black)";
        } else {
            double y99 = percentile(lit, 0.99);
            level = y99 / yOfUnit;
            white = fmt::format("an equal-energy radiance of {:.4g} W·sr⁻¹·m⁻²·nm⁻¹ (the reference's 99th-percentile "
                                "CIE 1931 Y, {:.4g})",
                                level, y99);
        }
    }

    // The white: a perfect diffuser's radiance E/π of `level`, i.e. an irradiance of level·π.
    ReferenceWhite reference;
    reference.source = "lights.0 (equal-energy white, at normal incidence)";
    reference.terms = {{Spectrum::makeConstant(level * M_PI), 1.0}};
    reference.irradiance.assign(size_t(bands), level * M_PI);
    reference.radiance.assign(size_t(bands), level * M_PI / M_PI);  // as E/π, to the bit
    TonemapPlan plan = makeTonemapPlan(settings, grid, reference, library);
    if (plan.mode == TonemapMode::ResponsesOnly)
        failInput(Where{"", "--detector"}, "{} has no colorimetric path to CIELAB; ΔE2000 needs an observer, a camera "
                  "or a film", plan.detector.name);

    std::vector<double> responses(plan.detector.channels.size());
    auto lab = [&](const float* radiance) {
        glm::dvec3 xyz = plan.adaptation * relativeXyz(plan, radiance, responses.data());
        return xyzToLab(xyz, plan.display.whiteXyz);
    };
    std::vector<double> de;
    de.reserve(pixels);
    double sum = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
        if (masked(p)) continue;
        double d = deltaE2000(lab(a.data.data() + p * bands), lab(b.data.data() + p * bands));
        if (!std::isfinite(d)) continue;  // NaN or Inf radiance: counted in nonFiniteMismatches
        de.push_back(d);
        sum += d;
    }
    if (!de.empty()) {
        stats.deltaE2000Mean = sum / double(de.size());
        stats.deltaE2000Max = *std::max_element(de.begin(), de.end());
        stats.deltaE2000P95 = percentile(de, 0.95);
    }
    stats.deltaE2000Setup = fmt::format("detector {}, white {}, adaptation {} to the {} display white, CIELAB relative "
                                        "to that display white",
                                        plan.detector.name, white, adaptationName(settings.adaptation),
                                        plan.display.name);
}


}  // namespace

bool ImageData::reflective() const { return grid && !channels.empty() && channels.front().rfind("T.", 0) == 0; }

ImageData fromCube(const SpectralCube& cube) {
    ImageData d;
    d.width = cube.width;
    d.height = cube.height;
    d.grid = cube.grid;
    for (double w : cube.grid.wavelengths()) d.channels.push_back(spectralChannelName(w));
    d.data = cube.data;
    d.kind = "spectral radiance";
    return d;
}

ImageData readComparable(const fs::path& path) {
    Where where{path.string()};
    requireRegularFile(path, where, "image");

    // Spectral channels decide the reader: the layout's own parser (grid, wavelength order) is in
    // io/spectral_exr; HDF5 and ENVI files are cubes (io/spectral_image).
    const std::optional<CubeFormat> format = cubeFormatOf(path);
    if ((format && *format != CubeFormat::Exr) ||
        (imageSignature(path) == "openexr" && hasSpectralChannels(readExrHeader(path, where).channels))) {
        SpectralImage image = readSpectralImage(path);
        ImageData d;
        d.width = image.cube.width;
        d.height = image.cube.height;
        d.grid = image.cube.grid;
        for (double w : image.cube.grid.wavelengths()) d.channels.push_back(spectralChannelName(w));
        d.data = std::move(image.cube.data);  // a 1024×1024×89 cube is 356 MiB: no copy
        d.kind = "spectral radiance";
        d.source = path.string();
        if (image.component == SpectralComponent::Reflective) {
            for (auto& c : d.channels) c = "T" + c.substr(2);
            d.kind = "reflectance";
        }
        return d;
    }

    RasterImage img = readRasterImage(path, where);
    ImageData d;
    d.width = img.width;
    d.height = img.height;
    d.channels = img.channels;
    d.source = path.string();
    d.data = std::move(img.pixels);
    // Integer images come as counts: what a display image means (an error of 1 is one count).
    d.kind = img.floatingPoint ? fmt::format("{} {}", img.format, img.bits == 16 ? "half" : "float")
                               : fmt::format("{} {}-bit counts", img.format, img.bits);
    d.countBits = img.floatingPoint ? 0 : img.bits;
    return d;
}

std::vector<uint8_t> readMask(const fs::path& path, int width, int height) {
    ImageData m = readComparable(path);
    if (m.width != width || m.height != height)
        failInput(Where{path.string()}, "the mask is {}×{} but the images are {}×{}", m.width, m.height, width, height);
    const size_t n = m.channels.size();
    std::vector<uint8_t> mask(size_t(width) * height, 0);
    for (size_t p = 0; p < mask.size(); ++p)
        for (size_t c = 0; c < n; ++c)
            if (m.data[p * n + c] != 0.0f) mask[p] = 1;
    return mask;
}

CompareStats compareImages(const ImageData& aIn, const ImageData& b, const CompareOptions& options) {
    const std::string aName = nameOf(aIn, "A"), bName = nameOf(b, "B (the reference)");
    Where aWhere{aName};
    if (aIn.width != b.width || aIn.height != b.height)
        failInput(aWhere, "is {}×{} but the reference {} is {}×{}", aIn.width, aIn.height, bName, b.width, b.height);
    // Counts of an 8-bit and a 16-bit image are on scales 257 apart: a difference of them means
    // nothing. (A PNG and a JPEG of 8 bits each are on one scale.)
    if (aIn.countBits && b.countBits && aIn.countBits != b.countBits)
        failInput(aWhere, "holds {} but the reference {} holds {}: counts on different scales (convert one first)",
                  aIn.kind, bName, b.kind);
    for (const ImageData* image : {&aIn, &b})
        if (image->data.size() != size_t(image->width) * image->height * image->channels.size())
            failInput(Where{nameOf(*image, "image")}, "holds {} values, not {}×{}×{}", image->data.size(),
                      image->width, image->height, image->channels.size());
    if (b.channels.empty()) failInput(Where{bName}, "has no channels");

    // Bring A into B's layout: same grid (resampled if allowed) or the same channels in B's order.
    ImageData resampled;
    const ImageData* a = &aIn;
    std::string resampledFrom;
    if (aIn.grid.has_value() != b.grid.has_value())
        failInput(aWhere, "is {} ({}) but the reference {} is {} ({})", aIn.grid ? "a spectral cube" : "not spectral",
                  describeChannels(aIn), bName, b.grid ? "a spectral cube" : "not spectral", describeChannels(b));
    if (b.grid) {
        if (aIn.reflective() != b.reflective())
            failInput(aWhere, "holds {} but the reference {} holds {}", aIn.reflective() ? "reflectance (T)" : "radiance (S0)",
                      bName, b.reflective() ? "reflectance (T)" : "radiance (S0)");
        if (!sameGrid(*aIn.grid, *b.grid)) {
            if (!options.resample)
                failInput(aWhere, "grid {} ({} bands) differs from the reference {}'s grid {} ({} bands); resample "
                          "(--resample) to bring A onto B's grid",
                          aIn.grid->str(), aIn.grid->bands(), bName, b.grid->str(), b.grid->bands());
            resampled = resampleOnto(aIn, *b.grid, bName);
            a = &resampled;
            resampledFrom = aIn.grid->str();
        }
    } else {
        a = &reorderLike(resampled, aIn, b, aName, bName);
    }

    const size_t n = b.channels.size();
    const size_t pixels = size_t(b.width) * b.height;
    CompareStats s;
    s.width = b.width;
    s.height = b.height;
    s.channels = n;
    s.grid = b.grid;
    s.resampledFrom = resampledFrom;
    s.pixelThreshold = options.pixelThreshold;
    s.relativeFloor = options.relativeFloor;
    if (!options.mask.empty() && options.mask.size() != pixels)
        failInput(Where{"", "mask"}, "{} mask entries for {}×{} pixels", options.mask.size(), b.width, b.height);
    s.mask = options.mask;
    auto masked = [&](size_t p) { return !options.mask.empty() && options.mask[p] != 0; };

    // Each channel's scale for the relative-error floor: its largest |b|. A channel that is 0
    // everywhere borrows the image's largest |b|; an all-black reference uses 1, so the relative
    // error becomes |a − b| / relativeFloor.
    std::vector<double> scale(n, 0.0);
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < n; ++c)
            if (double v = std::fabs(double(b.data[p * n + c])); std::isfinite(v)) scale[c] = std::max(scale[c], v);
    double overall = *std::max_element(scale.begin(), scale.end());
    if (!(overall > 0.0)) overall = 1.0;
    std::vector<double> floorOf(n);
    for (size_t c = 0; c < n; ++c) floorOf[c] = options.relativeFloor * (scale[c] > 0.0 ? scale[c] : overall);

    std::vector<double> sumSq(n, 0.0);
    s.perChannel.resize(n);
    for (size_t c = 0; c < n; ++c) s.perChannel[c].name = b.channels[c];
    s.pixelError.assign(pixels, 0.0f);
    double sumAbsB = 0.0;
    size_t countB = 0;
    double angleSum = 0.0;
    size_t angleCount = 0;
    std::vector<double> ua(n), ub(n);
    for (size_t p = 0; p < pixels; ++p) {
        if (masked(p)) {
            ++s.maskedPixels;
            continue;
        }
        const float* pa = a->data.data() + p * n;
        const float* pb = b.data.data() + p * n;
        double pixelMax = 0.0;
        double normA = 0.0, normB = 0.0;
        bool finitePixel = true;
        for (size_t c = 0; c < n; ++c) {
            double va = pa[c], vb = pb[c];
            double abs = 0.0, rel = 0.0;
            if (std::isfinite(va) && std::isfinite(vb)) {
                abs = std::fabs(va - vb);
                double denominator = std::max(std::fabs(vb), floorOf[c]);
                rel = abs == 0.0 ? 0.0 : denominator > 0.0 ? abs / denominator : kInf;
                sumAbsB += std::fabs(vb);
                ++countB;
                normA += va * va;
                normB += vb * vb;
            } else {
                finitePixel = false;
                // The same infinity, or NaN in both, is no difference; anything else is unbounded.
                bool same = va == vb || (std::isnan(va) && std::isnan(vb));
                if (!same) {
                    abs = rel = kInf;
                    ++s.nonFiniteMismatches;
                }
            }
            ChannelStats& cs = s.perChannel[c];
            cs.maxAbs = std::max(cs.maxAbs, abs);
            cs.maxRel = std::max(cs.maxRel, rel);
            sumSq[c] += abs * abs;
            if (rel > s.maxRel) {
                s.maxRel = rel;
                s.worstX = int(p % size_t(b.width));
                s.worstY = int(p / size_t(b.width));
                s.worstChannel = int(c);
            }
            s.maxAbs = std::max(s.maxAbs, abs);
            pixelMax = std::max(pixelMax, rel);
        }
        s.pixelError[p] = float(pixelMax);
        if (pixelMax > options.pixelThreshold) ++s.pixelsOverThreshold;
        // The angle 2·atan2(|â − b̂|, |â + b̂|) between the unit vectors is exact at 0° and 90°,
        // where acos of the dot product loses half the digits.
        if (finitePixel && normA > 0.0 && normB > 0.0) {
            normA = std::sqrt(normA);
            normB = std::sqrt(normB);
            double diff = 0.0, sum = 0.0;
            for (size_t c = 0; c < n; ++c) {
                double x = pa[c] / normA, y = pb[c] / normB;
                diff += (x - y) * (x - y);
                sum += (x + y) * (x + y);
            }
            double angle = 2.0 * std::atan2(std::sqrt(diff), std::sqrt(sum)) * kRadToDeg;
            s.spectralAngleMaxDeg = std::max(s.spectralAngleMaxDeg, angle);
            angleSum += angle;
            ++angleCount;
        }
    }
    const size_t counted = pixels - s.maskedPixels;
    double totalSq = 0.0;
    for (size_t c = 0; c < n; ++c) {
        s.perChannel[c].rmse = counted ? std::sqrt(sumSq[c] / double(counted)) : 0.0;
        totalSq += sumSq[c];
    }
    s.rmse = counted ? std::sqrt(totalSq / double(counted * n)) : 0.0;
    double meanAbsB = countB ? sumAbsB / double(countB) : 0.0;
    s.rmseRelative = s.rmse == 0.0 ? 0.0 : meanAbsB > 0.0 ? s.rmse / meanAbsB : kInf;
    s.spectralAngleMeanDeg = angleCount ? angleSum / double(angleCount) : 0.0;
    s.fractionOverThreshold = counted ? double(s.pixelsOverThreshold) / double(counted) : 0.0;

    if (options.display) {
        if (!b.grid)
            failInput(Where{"", "--detector"}, "ΔE2000 needs spectral cubes; {} has {}", bName, describeChannels(b));
        addDeltaE(*a, b, *options.display, s);
    }
    return s;
}

nlohmann::json statsToJson(const CompareStats& s) {
    using nlohmann::json;
    json j;
    j["width"] = s.width;
    j["height"] = s.height;
    j["channels"] = s.channels;
    if (s.grid) j["grid"] = s.grid->str();
    if (!s.resampledFrom.empty()) j["resampled_from"] = s.resampledFrom;
    j["relative_floor"] = s.relativeFloor;
    j["pixel_threshold"] = s.pixelThreshold;
    j["max_abs"] = jsonNumber(s.maxAbs);
    j["max_rel"] = jsonNumber(s.maxRel);
    j["rmse"] = jsonNumber(s.rmse);
    j["rmse_relative"] = jsonNumber(s.rmseRelative);
    j["spectral_angle_max_deg"] = jsonNumber(s.spectralAngleMaxDeg);
    j["spectral_angle_mean_deg"] = jsonNumber(s.spectralAngleMeanDeg);
    j["fraction_over_threshold"] = jsonNumber(s.fractionOverThreshold);
    j["pixels_over_threshold"] = s.pixelsOverThreshold;
    j["masked_pixels"] = s.maskedPixels;
    j["non_finite_mismatches"] = s.nonFiniteMismatches;
    if (s.worstChannel >= 0)
        j["worst"] = {{"x", s.worstX}, {"y", s.worstY}, {"channel", s.perChannel[size_t(s.worstChannel)].name}};
    if (s.deltaE2000Mean) {
        j["delta_e2000_mean"] = jsonNumber(*s.deltaE2000Mean);
        j["delta_e2000_p95"] = jsonNumber(*s.deltaE2000P95);
        j["delta_e2000_max"] = jsonNumber(*s.deltaE2000Max);
        j["delta_e2000_setup"] = s.deltaE2000Setup;
    }
    json channels = json::array();
    for (const auto& c : s.perChannel)
        channels.push_back({{"name", c.name}, {"max_abs", jsonNumber(c.maxAbs)}, {"max_rel", jsonNumber(c.maxRel)},
                            {"rmse", jsonNumber(c.rmse)}});
    j["per_channel"] = channels;
    return j;
}

void writeStatsJson(const fs::path& path, const CompareStats& stats, const nlohmann::json& extra) {
    nlohmann::json j = statsToJson(stats);
    if (extra.is_object())
        for (const auto& [key, value] : extra.items()) j[key] = value;
    writeFileAtomically(path, j.dump(2) + "\n");
}

}  // namespace metamer
