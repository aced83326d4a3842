#include "app/compare_command.h"
#include "app/cli_checks.h"

#include "color/adaptation.h"
#include "color/cie_xyz.h"
#include "compare/compare.h"
#include "compare/heatmap.h"
#include "compare/tolerance.h"
#include "core/error.h"
#include "io/spectral_exr.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace metamer {

namespace {

// The CIE 1931 observer's data: a cube reaching into them has a colour to compare.
constexpr size_t kWorstBands = 5;

std::string describe(const ImageData& d) {
    std::string what = fmt::format("{}, {}×{}", d.kind, d.width, d.height);
    if (d.grid) return what + fmt::format(", {} bands on {} nm", d.grid->bands(), d.grid->str());
    return what + fmt::format(", channels {}", fmt::join(d.channels, ","));
}

// "550 nm" for a band of a cube, else the channel's own name.
std::string channelLabel(const CompareStats& s, size_t c) {
    if (s.grid) return fmt::format("{:g} nm", s.grid->wavelength(int(c)));
    return s.perChannel[c].name;
}

void printChannelTable(const CompareStats& s, const std::vector<size_t>& order) {
    std::printf("  %-14s %-10s %-10s %-10s\n", s.grid ? "band" : "channel", "max abs", "max rel", "rmse");
    for (size_t c : order) {
        const ChannelStats& cs = s.perChannel[c];
        std::printf("  %-14s %-10s %-10s %-10s\n", channelLabel(s, c).c_str(), formatNumber(cs.maxAbs).c_str(),
                    formatNumber(cs.maxRel).c_str(), formatNumber(cs.rmse).c_str());
    }
}

void printSummary(const CompareArgs& args, const ImageData& a, const ImageData& b, const CompareStats& s) {
    std::printf("A  %s: %s\n", args.a.c_str(), describe(a).c_str());
    std::printf("B  %s (reference): %s\n", args.b.c_str(), describe(b).c_str());
    if (!s.resampledFrom.empty())
        std::printf("   A resampled from %s onto B's grid %s (band averages of its piecewise-linear spectra)\n",
                    s.resampledFrom.c_str(), s.grid->str().c_str());
    const size_t pixels = size_t(s.width) * s.height - s.maskedPixels;
    if (s.maskedPixels)
        std::printf("masked: %zu of %zu pixels left out (%s)\n", s.maskedPixels, pixels + s.maskedPixels,
                    args.mask.c_str());
    if (s.maxAbs == 0.0 && s.nonFiniteMismatches == 0) {
        std::printf("identical: every value of A equals B's\n");
    } else {
        std::printf("max abs error     %s\n", formatNumber(s.maxAbs).c_str());
        std::printf("max rel error     %s  (at pixel %d,%d, %s; relative to max(|B|, %s × the channel's max |B|))\n",
                    formatNumber(s.maxRel).c_str(), s.worstX, s.worstY,
                    channelLabel(s, size_t(s.worstChannel)).c_str(), formatNumber(s.relativeFloor).c_str());
        std::printf("rmse              %s  (%s of mean |B|)\n", formatNumber(s.rmse).c_str(),
                    formatNumber(s.rmseRelative).c_str());
        std::printf("%s   max %s°, mean %s°\n", s.grid ? "spectral angle" : "vector angle  ",
                    formatNumber(s.spectralAngleMaxDeg).c_str(), formatNumber(s.spectralAngleMeanDeg).c_str());
        std::printf("pixels over %s relative error: %zu of %zu (%s%%)\n", formatNumber(s.pixelThreshold).c_str(),
                    s.pixelsOverThreshold, pixels, formatNumber(100.0 * s.fractionOverThreshold).c_str());
        if (s.nonFiniteMismatches)
            std::printf("non-finite: %zu values are NaN or infinite in one image and not in the other\n",
                        s.nonFiniteMismatches);
    }
    if (s.deltaE2000Mean)
        std::printf("ΔE2000            mean %s, p95 %s, max %s\n                  (%s)\n",
                    formatNumber(*s.deltaE2000Mean).c_str(), formatNumber(*s.deltaE2000P95).c_str(),
                    formatNumber(*s.deltaE2000Max).c_str(), s.deltaE2000Setup.c_str());

    std::vector<size_t> order(s.perChannel.size());
    std::iota(order.begin(), order.end(), size_t(0));
    if (args.verbose) {
        std::printf("per %s:\n", s.grid ? "band" : "channel");
        printChannelTable(s, order);
    } else if (s.maxAbs > 0.0 || s.nonFiniteMismatches) {
        std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
            return s.perChannel[x].maxRel > s.perChannel[y].maxRel;
        });
        order.resize(std::min(order.size(), kWorstBands));
        while (!order.empty() && s.perChannel[order.back()].maxAbs == 0.0) order.pop_back();
        std::printf("worst %s by max relative error (--verbose: all):\n", s.grid ? "bands" : "channels");
        printChannelTable(s, order);
    }
}

// --quiet: the statistics a tolerance file can gate, on one line.
void printOneLine(const CompareStats& s) {
    std::string line = fmt::format("max abs {}, max rel {}, rmse/mean|B| {}, angle max {}°, over {}: {} of {} pixels",
                                   formatNumber(s.maxAbs), formatNumber(s.maxRel), formatNumber(s.rmseRelative),
                                   formatNumber(s.spectralAngleMaxDeg), formatNumber(s.pixelThreshold),
                                   s.pixelsOverThreshold, size_t(s.width) * s.height - s.maskedPixels);
    if (s.maskedPixels) line += fmt::format(" ({} masked)", s.maskedPixels);
    if (s.deltaE2000P95)
        line += fmt::format(", ΔE2000 p95 {} max {}", formatNumber(*s.deltaE2000P95), formatNumber(*s.deltaE2000Max));
    if (s.nonFiniteMismatches) line += fmt::format(", {} non-finite mismatches", s.nonFiniteMismatches);
    std::printf("%s\n", line.c_str());
}

}  // namespace

CLI::App* addCompareCommand(CLI::App& app, CompareArgs& args) {
    auto* c = app.add_subcommand("compare",
                                 "compare an image or spectral cube A with a reference B (exit 0: within the "
                                 "tolerance, 1: outside, 2: unusable input)");
    c->add_option("a", args.a, "the image to check (spectral EXR, or any EXR/PNG)")->required();
    c->add_option("b", args.b, "the reference (golden) image, same size and channels")->required();
    c->add_option("--tolerance,-t", args.tolerance, "tolerance file (JSON, docs/compare.md); exit 1 when outside");
    c->add_option("--heatmap", args.heatmap, "write the per-pixel relative error as a PNG heat map");
    c->add_option("--json", args.json, "write the statistics (and the verdict) as JSON");
    c->add_flag("--resample", args.resample, "bring A onto B's spectral grid when they differ");
    c->add_option("--detector", args.detector,
                  "ΔE2000 detector: cie1931 (default), cie1964, camera:<name>, film:<name>");
    c->add_option("--adapt", args.adapt, "ΔE2000 adaptation to the display white (default bradford)");
    c->add_option("--display", args.display, "ΔE2000 display white: srgb (default) or crt");
    c->add_flag("--no-delta-e", args.noDeltaE, "skip ΔE2000 (computed by default for visible-range cubes)");
    c->add_option("--pixel-threshold", args.pixelThreshold,
                  "relative error above which a pixel counts as different (default 1e-3, or the tolerance file's)")
        ->check(nonNegativeNumber());
    c->add_option("--relative-floor", args.relativeFloor,
                  "relative errors are taken against at least this fraction of the channel's max |B| (default 1e-4)")
        ->check(nonNegativeNumber());
    c->add_option("--mask", args.mask,
                  "leave out the pixels where this image (e.g. the render's <scene>.edges.png) is non-zero");
    c->add_flag("--verbose,-v", args.verbose, "print every band (channel), not only the worst");
    c->add_flag("--quiet,-q", args.quiet, "print one line of statistics and the verdict only");
    return c;
}

int runCompare(const CompareArgs& args) {
    // Everything the user named is checked before the (possibly long) comparison.
    std::optional<Tolerance> tolerance;
    if (!args.tolerance.empty()) tolerance = readTolerance(args.tolerance);
    bool explicitDeltaE = !args.detector.empty() || !args.adapt.empty() || !args.display.empty();
    if (args.verbose && args.quiet) failInput(Where{"", "--quiet"}, "conflicts with --verbose");
    if (explicitDeltaE && args.noDeltaE)
        failInput(Where{"", "--no-delta-e"}, "conflicts with --detector/--adapt/--display");
    if (tolerance && tolerance->wantsDeltaE() && args.noDeltaE)
        failInput(Where{"", "--no-delta-e"}, "the tolerance file {} sets a ΔE2000 limit", tolerance->source);

    ImageData a = readComparable(args.a);
    ImageData b = readComparable(args.b);

    CompareRequest request;
    if (args.pixelThreshold >= 0.0) request.pixelThreshold = args.pixelThreshold;
    if (args.relativeFloor >= 0.0) request.relativeFloor = args.relativeFloor;
    request.resample = args.resample;
    request.detector = args.detector;
    request.adapt = args.adapt;
    request.display = args.display;
    request.noDeltaE = args.noDeltaE;
    CompareOptions options = makeCompareOptions(request, b, tolerance ? &*tolerance : nullptr);
    if (!args.mask.empty()) options.mask = readMask(args.mask, b.width, b.height);

    CompareStats stats = compareImages(a, b, options);
    if (args.quiet) printOneLine(stats);
    else printSummary(args, a, b, stats);

    std::optional<Verdict> verdict;
    if (tolerance) verdict = judge(stats, *tolerance);

    if (!args.heatmap.empty()) {
        writeHeatmap(args.heatmap, stats, stats.pixelThreshold);
        if (!args.quiet) std::printf("wrote %s (heat map: relative error per pixel, log scale around %s)\n", args.heatmap.c_str(),
                    formatNumber(stats.pixelThreshold).c_str());
    }
    if (!args.json.empty()) {
        nlohmann::json extra = {{"a", args.a}, {"b", args.b}};
        if (verdict)
            extra["tolerance"] = {{"file", tolerance->source},
                                  {"description", tolerance->description},
                                  {"pass", verdict->pass},
                                  {"failures", verdict->failures}};
        writeStatsJson(args.json, stats, extra);
        if (!args.quiet) std::printf("wrote %s (statistics)\n", args.json.c_str());
    }

    if (!verdict) return 0;
    if (verdict->pass) {
        std::printf("PASS: within the tolerance %s\n", tolerance->source.c_str());
        return 0;
    }
    std::string why = tolerance->description.empty() ? "" : fmt::format(" ({})", tolerance->description);
    std::printf("FAIL: outside the tolerance %s%s\n", tolerance->source.c_str(), why.c_str());
    for (const auto& f : verdict->failures) std::printf("  %s\n", f.c_str());
    return int(ExitCode::Failure);
}

}  // namespace metamer
