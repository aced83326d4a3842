#include "app/bench_command.h"

#include "app/cli_checks.h"
#include "app/render_flags.h"

#include "bench/bench.h"
#include "bench/plot.h"
#include "core/error.h"
#include "vk/context.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace metamer {

namespace {

std::vector<double> parseSteps(const std::vector<std::string>& texts) {
    std::vector<double> steps;
    for (const auto& t : texts) {
        char* end = nullptr;
        double v = std::strtod(t.c_str(), &end);
        if (t.empty() || *end != '\0' || !std::isfinite(v))
            failInput(Where{"", "--steps"}, "'{}' is not a step in nm; expected e.g. 1,2,5,10,20", t);
        if (v < Grid::kMinStep || v > Grid::kMaxStep)
            failInput(Where{"", "--steps"}, "step {:g} nm is outside {:g}..{:g} nm", v, Grid::kMinStep, Grid::kMaxStep);
        if (std::find(steps.begin(), steps.end(), v) == steps.end()) steps.push_back(v);
    }
    return steps;
}

std::pair<int, int> parseSize(const std::string& text) {
    // "256x256"; the multiplication sign is accepted too, as the docs print sizes with it.
    std::string s = text;
    for (size_t p; (p = s.find("×")) != std::string::npos;) s.replace(p, std::string("×").size(), "x");
    int w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(s.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384)
        failInput(Where{"", "--size"}, "'{}' is not an image size; expected WIDTHxHEIGHT, e.g. 256x256", text);
    return {w, h};
}

std::string cell(double v, const char* f = "{:.3g}") {
    return std::isfinite(v) ? fmt::format(fmt::runtime(f), v) : "—";
}

void printTable(const BenchResult& r) {
    std::printf("%-9s %6s %-12s %4s %10s %10s %9s %9s %9s %9s %9s %11s\n", "mode", "step", "grid", "ch", "ms/frame",
                "first ms", "cube ms", "run ms", "ΔE00 mean", "ΔE00 p95", "ΔE00 max", "spec. RMSE");
    for (const BenchRow& row : r.rows) {
        if (row.skipped()) {
            std::printf("%-9s %6g %-12s skipped: %s\n", row.mode.name().c_str(), row.stepNm, row.grid.c_str(),
                        row.skippedReason.c_str());
            continue;
        }
        std::printf("%-9s %6g %-12s %4d %10s %10s %9s %9s %9s %9s %9s %11s\n", row.mode.name().c_str(), row.stepNm,
                    row.grid.c_str(), row.channels, cell(row.renderMsMedian, "{:.1f}").c_str(),
                    cell(row.renderMsFirst, "{:.1f}").c_str(), cell(row.cubeMsMedian, "{:.1f}").c_str(),
                    cell(row.runMs, "{:.0f}").c_str(),
                    cell(row.de2000Mean).c_str(), cell(row.de2000P95).c_str(), cell(row.de2000Max).c_str(),
                    cell(row.spectralRmseRelative).c_str());
    }
    std::vector<std::string> front;
    for (size_t i : paretoFront(r.rows)) front.push_back(r.rows[i].label());
    std::printf("Pareto front (time against ΔE00 p95): %s\n", fmt::format("{}", fmt::join(front, ", ")).c_str());
}

}  // namespace

CLI::App* addBenchCommand(CLI::App& app, BenchArgs& args) {
    auto* c = app.add_subcommand("bench",
                                 "measure time against accuracy for representation modes and spectral steps "
                                 "(reference: full spectral at 1 nm; docs/speed-vs-accuracy.md)");
    c->add_option("scene", args.scene, "scene file (JSON, docs/scene-format.md)")->required();
    c->add_option("--modes", args.modes, "modes, comma-separated (default full,rgb,ac1c2:4,ac1c2:8)")->delimiter(',');
    c->add_option("--steps", args.steps, "spectral steps in nm, comma-separated (default 1,2,5,10,20)")->delimiter(',');
    c->add_option("--frames", args.frames, "frames per configuration; the first is reported apart")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c->add_option("--size", args.size, "image size WIDTHxHEIGHT, e.g. 256x256 (default: the scene's camera)");
    c->add_option("--out,-o", args.out, "output folder (created if missing)")->check(outputFolder())->capture_default_str();
    addRenderFlag(c, "set", args.overrides)
        ->take_all();
    addRenderFlag(c, "device", args.device);
    addRenderFlag(c, "validation", args.validation);
    c->add_flag("--quiet,-q", args.quiet, "no progress lines on stderr");
    return c;
}

int runBenchCommand(const BenchArgs& args) {
    // Every flag is checked before the device starts and the (minutes-long) sweep begins.
    BenchConfig config;
    if (!args.modes.empty()) {
        config.modes.clear();
        for (const auto& m : args.modes) {
            Mode mode = parseMode(m, Where{"", "--modes"});
            bool dup = std::any_of(config.modes.begin(), config.modes.end(),
                                   [&](const Mode& x) { return x.name() == mode.name(); });
            if (!dup) config.modes.push_back(mode);
        }
    }
    if (!args.steps.empty()) config.steps = parseSteps(args.steps);
    config.frames = args.frames;
    if (!args.size.empty()) config.size = parseSize(args.size);
    config.overrides = args.overrides;

    vk::ContextOptions co = vk::contextOptionsFromEnvironment();
    co.validation = co.validation || args.validation;
    if (!args.device.empty()) {
        co.device = args.device;
        co.deviceFrom = "--device";
    }
    auto ctx = std::make_unique<vk::Context>(co);
    auto progress = [&](const std::string& line) {
        if (!args.quiet) std::fprintf(stderr, "%s\n", line.c_str());
    };
    BenchResult result = runBench(args.scene, config, *ctx, progress);
    ctx.reset();  // destroy before counting: leak reports arrive at device destruction

    std::filesystem::path out = args.out;
    auto csv = out / (result.sceneName + ".bench.csv");
    auto json = out / (result.sceneName + ".bench.json");
    auto png = out / (result.sceneName + ".bench.png");
    writeBenchCsv(csv, result);
    writeBenchJson(json, result);
    bool withText = writeBenchPlot(png, result);

    std::printf("%s on %s, %d×%d px, %d frames per configuration; reference full at 1 nm (%s); ΔE00 over %zu "
                "pixels with reference Y > %g\n",
                result.scene.c_str(), result.device.c_str(), result.width, result.height, result.frames,
                result.referenceGrid.str().c_str(), result.comparedPixels, kBenchMinY);
    for (const auto& n : result.notes) std::printf("note: %s\n", n.c_str());
    printTable(result);
    std::printf("wrote %s (one row per configuration)\n", csv.c_str());
    std::printf("wrote %s (the same, with the machine and the Pareto front)\n", json.c_str());
    std::printf("wrote %s (time against ΔE2000 p95%s)\n", png.c_str(), withText ? "" : "; no font: without text");
    if (uint32_t errors = vk::Context::validationErrorsAtExit()) {
        std::fprintf(stderr, "metamer: %u Vulkan validation error(s) (see above)\n", errors);
        return int(ExitCode::Failure);
    }
    return 0;
}

}  // namespace metamer
