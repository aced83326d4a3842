// metamer: the command-line tool. A thin shell: parse arguments, call the engine, print one line
// per error, map errors to exit codes (README.md, "Exit codes").
#include "app/batch_command.h"    // metamer batch
#include "app/bench_command.h"    // metamer bench
#include "app/cli_checks.h"       // checks every command line gets
#include "app/compare_command.h"  // metamer compare
#include "app/preview_command.h"  // metamer preview
#include "core/error.h"
#include "io/atomic_file.h"
#include "render/render_job.h"
#include "vk/context.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <sys/syscall.h>
#include <unistd.h>

using namespace metamer;

namespace {

// An interrupted run leaves no partial output: temporary files are removed, finished files were
// renamed into place atomically, earlier files are untouched.
//
// Output files are created only by the main thread, after their temporary name is registered.
// The kernel may deliver SIGINT to any thread (the CPU renderer's, the driver's); handled there,
// the unlink could run between the main thread's registering a name and creating the file, and
// _exit would then leave that file behind. So a signal caught elsewhere is passed on to the main
// thread, where the handler runs either before the file exists (and it never will) or after.
pid_t gMainThread = 0;

extern "C" void onSignal(int sig) {
    if (pid_t(::syscall(SYS_gettid)) != gMainThread) {
        ::syscall(SYS_tgkill, ::getpid(), gMainThread, sig);
        return;
    }
    removeLiveTempFiles();
    _exit(128 + sig);
}

void printError(const std::string& message) { std::fprintf(stderr, "metamer: %s\n", printableMessage(message).c_str()); }

void printTimings(const RenderJobResult& r) {
    const StageTimings& t = r.timings;
    std::printf("timings (ms): load %.1f  upload %.1f  shading %.1f  readback %.1f  tonemap %.1f  write %.1f  "
                "total %.1f\n",
                t.load_ms, t.upload_ms, t.shading_ms, t.readback_ms, t.tonemap_ms, t.write_ms, t.total_ms);
    if (t.shadow_ms > 0) std::printf("shadow maps: %.1f ms of the upload (drawn once per scene)\n", t.shadow_ms);
    double bandPixels = double(r.width) * r.height * r.grid.bands();
    if (r.responsePass) {
        // The display path without the bands: a frame is the response pass and the tonemap pass.
        if (t.frames > 1)
            std::printf("frames: %d (response pass: the detector's channels, no bands); first frame shading %.1f ms "
                        "(includes shader compilation); median of the other %d: shading %.1f ms, tonemap %.1f ms, "
                        "frame %.1f ms\n",
                        t.frames, t.first_shading_ms, t.frames - 1, t.median_shading_ms, t.median_tonemap_ms,
                        t.median_shading_ms + t.median_tonemap_ms);
        else
            std::printf("response pass (the detector's channels, no bands): one frame, includes shader compilation; "
                        "--frames N for steady state\n");
        return;
    }
    if (t.frames > 1) {
        std::printf("frames: %d; first frame shading %.1f ms (includes shader compilation); median of the other "
                    "%d: shading %.1f ms, readback %.1f ms\n",
                    t.frames, t.first_shading_ms, t.frames - 1, t.median_shading_ms, t.median_readback_ms);
        std::printf("throughput (median frame): %.3f G band-pixels/s in shading, %.3f including readback\n",
                    bandPixels / (t.median_shading_ms * 1e6),
                    bandPixels / ((t.median_shading_ms + t.median_readback_ms) * 1e6));
    } else if (t.shading_ms > 0) {
        std::printf("throughput: %.3f G band-pixels/s in shading, %.3f including readback (one frame, includes "
                    "shader compilation; --frames N for steady state)\n",
                    bandPixels / (t.shading_ms * 1e6), bandPixels / ((t.shading_ms + t.readback_ms) * 1e6));
    }
}

int listDevices() {
    vk::ContextOptions o;
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    VkInstance instance;
    if (vkCreateInstance(&ici, nullptr, &instance) != VK_SUCCESS) {
        std::fprintf(stderr, "metamer: no usable Vulkan device: no Vulkan driver\n");
        return int(ExitCode::NoDevice);
    }
    auto devices = vk::Context::listDevices(instance);
    for (const auto& d : devices)
        std::printf("%u: %s (score %d%s)\n", d.index, d.name.c_str(), d.score, d.score ? "" : ", unusable");
    vkDestroyInstance(instance, nullptr);
    if (devices.empty()) {
        std::fprintf(stderr, "metamer: no usable Vulkan device: the loader found none\n");
        return int(ExitCode::NoDevice);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    gMainThread = pid_t(::syscall(SYS_gettid));
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);

    CLI::App app{"metamer: full-spectral rendering for color-imaging research"};
    app.require_subcommand(1);

    RenderJob job;
    std::string gridText, resampleText, backend = "gpu", readback = "auto";
    bool timings = false, strictCoverage = false, noPng = false;
    auto* render = app.add_subcommand("render", "render a scene to a spectral radiance cube (EXR) and a quick-look PNG");
    render->add_option("scene", job.scene, "scene file (JSON, docs/scene-format.md)")->required();
    render->add_option("--out,-o", job.outDir, "output folder (created if missing)")->check(outputFolder())->capture_default_str();
    render->add_option("--grid", gridText, "spectral grid START:END:STEP in nm, e.g. 300:740:5 (overrides the scene)");
    render->add_option("--resample", resampleText,
                       "how spectra go onto the grid: interpolate (default: tabulated values at data points, "
                       "linear between, band means where the grid is coarser), sprague or band-mean");
    render->add_option("--set", job.overrides, "override a scene value: KEY=VALUE, e.g. lights.0.spectrum=illuminants/A")
        ->take_all();
    render->add_option("--backend", backend, "gpu (Vulkan) or cpu (double-precision reference)")
        ->check(CLI::IsMember({"gpu", "cpu"}))
        ->capture_default_str();
    render->add_option("--ssaa", job.ssaa, "supersampling: N×N samples per pixel (1-4)")
        ->check(CLI::Range(1, 4))
        ->capture_default_str();
    render->add_flag("--half", job.half, "write float16 instead of float32");
    render->add_option("--compression", job.compression, "the cube's OpenEXR compression: piz (default), zip[:1-9], zips, rle, none, ... (docs/io.md)")
        ->capture_default_str();
    render->add_flag("--strict-coverage", strictCoverage, "error when a spectrum's data do not cover the grid");
    render->add_option("--readback", readback, "auto, map (linear host-visible image) or copy")
        ->check(CLI::IsMember({"auto", "map", "copy"}))
        ->capture_default_str();
    std::string detector, adapt, display, integration, xyz;
    int bits = 0;
    std::vector<std::string> write;
    render->add_option("--detector", detector,
                       "cie1931, cie1964, camera:<name>, film:<name> or csv:<path> (default: the scene's output "
                       "block, else cie1931)");
    render->add_option("--adapt", adapt, "chromatic adaptation: none, vonkries-xyz, vonkries, bradford, cat02, cat16");
    render->add_option("--display", display, "display model: srgb or crt");
    render->add_option("--bits", bits, "display counts: 8 or 16 bits")->check(CLI::IsMember({8, 16}));
    render->add_option("--integration", integration, "riemann (default), trapezoid or astm-e308 (ASTM E308 weighting factors)");
    double budgetMiB = 0;
    render->add_option("--memory-budget", budgetMiB,
                       "MiB the render may hold at once (default: a quarter of the machine's memory); a larger "
                       "image is rendered in strips and streamed to the files")
        ->check(positiveNumber("MiB"));
    render->add_option("--mode", job.mode, "representation: full (default), rgb, ac1c2[:N], linear:K (docs/representations.md)")
        ->capture_default_str();
    render->add_option("--xyz", xyz, "XYZ output scale: relative (white Y = 100) or absolute (cd/m²)");
    render->add_option("--write", write, "outputs, comma-separated: cube, png, xyz, responses, edges (default cube,png)")
        ->delimiter(',');
    std::vector<std::string> format;
    render->add_option("--format", format, "the cube's containers, comma-separated: exr (default), hdf5, hdf5:gzip[:1-9], "
                       "envi[:bsq|bil|bip] (docs/io.md)")
        ->delimiter(',');
    render->add_flag("--no-png", noPng, "skip the display PNG");
    render->add_flag("--timings", timings, "print per-stage timings");
    render->add_option("--frames", job.frames, "render N frames (timing: first frame and median of the rest)")
        ->check(CLI::Range(1, 1000));
    render->add_flag("--validation", job.validation, "enable Vulkan validation layers; any error fails the run");
    render->add_option("--device", job.device, "Vulkan device index or name substring (default: best; env METAMER_DEVICE)");
    render->add_flag("--verbose,-v", job.verbose, "print the chosen device and the render plan");
    render->add_flag("--allow-outside-paths", job.allowOutsidePaths,
                     "let the scene read files outside its own folder tree and the spectra library "
                     "(docs/scene-format.md)");

    auto* devices = app.add_subcommand("devices", "list Vulkan devices and their scores");

    // --- metamer compare (engine/app/compare_command.cpp, docs/compare.md)
    CompareArgs compareArgs;
    auto* compare = addCompareCommand(app, compareArgs);
    // --- end metamer compare

    // --- metamer bench (engine/app/bench_command.cpp, docs/speed-vs-accuracy.md)
    BenchArgs benchArgs;
    auto* bench = addBenchCommand(app, benchArgs);
    // --- end metamer bench

    // --- metamer batch (engine/app/batch_command.cpp, docs/batch.md)
    BatchArgs batchArgs;
    auto* batch = addBatchCommand(app, batchArgs);
    // --- end metamer batch

    // --- metamer preview (engine/app/preview_command.cpp, docs/preview.md)
    PreviewArgs previewArgs;
    auto* preview = addPreviewCommand(app, previewArgs);
    // --- end metamer preview

    try {
        checkVerb(app, argc, argv);  // before CLI11: `metamer rendr --help` is an error, not the top-level help
        app.parse(argc, argv);
        checkParsedValues(app);
    } catch (const Error& e) {
        printError(e.text());
        return int(e.code());
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // A bad command line is bad input like any other: one "metamer: " line, exit code 2.
        if (e.get_exit_code() == 0) return app.exit(e);
        printError(e.what());
        return int(ExitCode::BadInput);
    }

    try {
        if (devices->parsed()) return listDevices();
        if (compare->parsed()) return runCompare(compareArgs);  // metamer compare
        if (bench->parsed()) return runBenchCommand(benchArgs);  // metamer bench
        if (batch->parsed()) return runBatchCommand(batchArgs);  // metamer batch
        if (preview->parsed()) return runPreviewCommand(previewArgs);  // metamer preview

        job.backend = backend == "cpu" ? Backend::Cpu : Backend::Gpu;
        job.readback = readback == "map" ? Readback::Map : readback == "copy" ? Readback::Copy : Readback::Auto;
        job.coverage = strictCoverage ? CoveragePolicy::Error : CoveragePolicy::ZeroWithWarning;
        if (budgetMiB > 0) job.memoryBudget = size_t(budgetMiB * (1 << 20));
        if (!detector.empty()) job.detector = detector;
        if (!adapt.empty()) job.adaptation = adapt;
        if (!display.empty()) job.display = display;
        if (bits) job.bits = bits;
        if (!integration.empty()) job.integration = integration;
        if (!xyz.empty()) job.xyz = xyz;
        if (!write.empty()) job.write = write;
        if (!format.empty()) job.format = format;
        if (noPng) {
            // --no-png: whatever would be written, but not the PNG.
            std::vector<std::string> w = job.write ? *job.write : std::vector<std::string>{"cube"};
            w.erase(std::remove(w.begin(), w.end(), "png"), w.end());
            job.write = w;
        }
        if (!gridText.empty()) job.grid = Grid::parse(gridText, Where{"", "--grid"});
        if (!resampleText.empty()) job.resampling = parseResampling(resampleText, Where{"", "--resample"});

        RenderJobResult r = runRenderJob(job);
        if (job.verbose) std::printf("%s\n", r.backendDescription.c_str());
        for (const auto& f : r.written) std::printf("wrote %s (%s)\n", f.path.c_str(), f.what.c_str());
        if (r.clampedToHalf)
            std::printf("note: %zu values beyond the float16 range were clamped to ±65504\n", r.clampedToHalf);
        if (!r.displayDescription.empty())
            std::printf("display: %zu of %d pixels clipped (outside the display gamut or range)\n", r.clippedPixels,
                        r.width * r.height);
        if (r.cameraFitRmsDeltaE)
            std::printf("camera characterization: rms ΔE2000 %.2f over the 24 ColorChecker patches\n",
                        *r.cameraFitRmsDeltaE);
        for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
        if (timings) printTimings(r);
        if (r.validationErrors) {
            std::fprintf(stderr, "metamer: %u Vulkan validation error(s) (see above)\n", r.validationErrors);
            return int(ExitCode::Failure);
        }
        return 0;
    } catch (const Error& e) {
        printError(e.text());
        return int(e.code());
    } catch (const std::bad_alloc&) {
        printError("out of memory");
        return int(ExitCode::Failure);
    } catch (const std::exception& e) {
        printError(e.what());
        return int(ExitCode::Failure);
    }
}
