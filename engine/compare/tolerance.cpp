#include "compare/tolerance.h"

#include "color/adaptation.h"
#include "color/cie_xyz.h"
#include "core/error.h"
#include "core/file_reads.h"
#include "core/json.h"

#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace metamer {

namespace {

using Json = nlohmann::ordered_json;

// 1-based line of a byte offset.
int lineAt(const std::string& text, size_t offset) {
    int line = 1;
    for (size_t i = 0; i < offset && i < text.size(); ++i) line += text[i] == '\n';
    return line;
}

// The line of a top-level key, for messages (the first occurrence of "key" in the text).
int lineOfKey(const std::string& text, const std::string& key) {
    size_t at = text.find('"' + key + '"');
    return at == std::string::npos ? 0 : lineAt(text, at);
}

struct Criterion {
    const char* key;
    std::optional<double> Tolerance::*field;
};

const std::vector<Criterion>& limits() {
    static const std::vector<Criterion> k = {
        {"max_abs", &Tolerance::maxAbs},
        {"max_rel", &Tolerance::maxRel},
        {"rmse_relative", &Tolerance::rmseRelative},
        {"spectral_angle_max_deg", &Tolerance::spectralAngleMaxDeg},
        {"fraction_over_threshold", &Tolerance::fractionOverThreshold},
        {"delta_e2000_p95", &Tolerance::deltaE2000P95},
        {"delta_e2000_max", &Tolerance::deltaE2000Max},
    };
    return k;
}

const std::vector<Criterion>& settings() {
    static const std::vector<Criterion> k = {
        {"pixel_threshold", &Tolerance::pixelThreshold},
        {"relative_floor", &Tolerance::relativeFloor},
    };
    return k;
}

}  // namespace

Tolerance readTolerance(const fs::path& path) {
    const std::string file = path.string();
    // A tolerance file is a few lines of JSON: 1 MiB is generous.
    const std::string text = readWholeFile(path, Where{file}, "tolerance file", std::uintmax_t(1) << 20);

    // The one JSON reader (core/json.h): duplicate keys (two max_rel entries are a mistake whichever
    // was meant), numbers beyond a double and deep nesting are errors naming the line and key.
    const Json j = parseJson(text, file);
    if (!j.is_object()) failInput(Where{file}, "must be a JSON object of criteria, not {}", jsonTypeName(j));

    std::vector<std::string> known = {"description"};
    for (const auto& c : limits()) known.push_back(c.key);
    for (const auto& c : settings()) known.push_back(c.key);

    Tolerance t;
    t.source = file;
    for (const auto& [key, value] : j.items()) {
        Where where{file, key, lineOfKey(text, key)};
        if (key == "description") {
            if (!value.is_string()) failInput(where, "must be a string, not {}", jsonTypeName(value));
            t.description = value.get<std::string>();
            continue;
        }
        const Criterion* criterion = nullptr;
        for (const auto* list : {&limits(), &settings()})
            for (const auto& c : *list)
                if (key == c.key) criterion = &c;
        if (!criterion) {
            std::string suggestion = closestMatch(key, known);
            failInput(where, "unknown key{}; known keys: {}",
                      suggestion.empty() ? "" : fmt::format(" (did you mean '{}'?)", suggestion),
                      fmt::format("{}", fmt::join(known, ", ")));
        }
        if (!value.is_number()) failInput(where, "must be a number, not {}", jsonTypeName(value));
        double v = value.get<double>();
        if (!std::isfinite(v)) failInput(where, "must be a finite number");
        if (v < 0.0) failInput(where, "must be ≥ 0, not {}", formatNumber(v));
        t.*(criterion->field) = v;
    }
    return t;
}

void applyTolerance(const Tolerance& tolerance, CompareOptions& options) {
    if (tolerance.pixelThreshold) options.pixelThreshold = *tolerance.pixelThreshold;
    if (tolerance.relativeFloor) options.relativeFloor = *tolerance.relativeFloor;
}

Verdict judge(const CompareStats& stats, const Tolerance& tolerance) {
    Verdict v;
    auto check = [&](const char* key, const std::optional<double>& limit, std::optional<double> value) {
        if (!limit) return;
        if (!value) {
            v.failures.push_back(fmt::format("{} not computed (needs spectral cubes and a detector)", key));
            return;
        }
        // Written so that NaN fails: NaN ≤ limit is false.
        if (!(*value <= *limit)) v.failures.push_back(fmt::format("{} {} > {}", key, formatNumber(*value),
                                                                  formatNumber(*limit)));
    };
    check("max_abs", tolerance.maxAbs, stats.maxAbs);
    check("max_rel", tolerance.maxRel, stats.maxRel);
    check("rmse_relative", tolerance.rmseRelative, stats.rmseRelative);
    check("spectral_angle_max_deg", tolerance.spectralAngleMaxDeg, stats.spectralAngleMaxDeg);
    check("fraction_over_threshold", tolerance.fractionOverThreshold, stats.fractionOverThreshold);
    check("delta_e2000_p95", tolerance.deltaE2000P95, stats.deltaE2000P95);
    check("delta_e2000_max", tolerance.deltaE2000Max, stats.deltaE2000Max);
    bool anyLimit = false;
    for (const auto& c : limits()) anyLimit = anyLimit || (tolerance.*(c.field)).has_value();
    if (anyLimit && stats.nonFiniteMismatches > 0)
        v.failures.push_back(fmt::format("{} values are NaN or infinite in one image and not in the other",
                                         stats.nonFiniteMismatches));
    v.pass = v.failures.empty();
    return v;
}

std::string formatNumber(double v) {
    if (v == 0.0) return "0";
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    double a = std::fabs(v);
    if (a >= 1e-2 && a < 1e5) return fmt::format("{:.4g}", v);
    // Scientific with up to 3 significant digits and no trailing zeros: 2.1e-03, 1e-03.
    std::string s = fmt::format("{:.2e}", v);
    size_t e = s.find('e');
    std::string mantissa = s.substr(0, e);
    if (mantissa.find('.') != std::string::npos) {
        while (mantissa.back() == '0') mantissa.pop_back();
        if (mantissa.back() == '.') mantissa.pop_back();
    }
    return mantissa + s.substr(e);
}

CompareOptions makeCompareOptions(const CompareRequest& request, const ImageData& b, const Tolerance* tolerance) {
    constexpr double kVisibleLo = 360.0, kVisibleHi = 830.0;
    CompareOptions options;
    if (tolerance) applyTolerance(*tolerance, options);
    if (request.pixelThreshold) options.pixelThreshold = *request.pixelThreshold;
    if (request.relativeFloor) options.relativeFloor = *request.relativeFloor;
    options.resample = request.resample;
    // ΔE2000 by default where there is a colour to see; on request (flags, a ΔE limit) always, so
    // that an unusable request is an error rather than a silent omission.
    const bool named = !request.detector.empty() || !request.adapt.empty() || !request.display.empty();
    const bool requested = named || (tolerance && tolerance->wantsDeltaE());
    bool visible = b.grid && b.grid->start_nm <= kVisibleHi && b.grid->end_nm >= kVisibleLo;
    if (visible && !requested && !request.noDeltaE && !SpectrumLibrary().contains(kCie1931Observer)) {
        // Only a default: a comparison of radiance does not need the spectra library.
        warn(Where{}, fmt::format("no ΔE2000: the spectra library at {} has no {}",
                                  SpectrumLibrary::defaultRoot().string(), kCie1931Observer));
        visible = false;
    }
    if (!request.noDeltaE && (requested || visible)) {
        TonemapSettings settings;
        if (!request.detector.empty()) settings.detector = request.detector;
        if (!request.adapt.empty()) settings.adaptation = parseAdaptation(request.adapt, Where{"", "--adapt"});
        if (!request.display.empty()) settings.display = request.display;
        options.display = settings;
    }
    return options;
}

}  // namespace metamer
