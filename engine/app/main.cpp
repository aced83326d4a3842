// metamer: the command-line tool. A thin shell: parse arguments, call the engine, print one line
// per error, map errors to exit codes (README.md, "Exit codes").
#include "app/batch_command.h"    // metamer batch
#include "app/bench_command.h"    // metamer bench
#include "app/cli_checks.h"       // checks every command line gets
#include "app/capture_command.h"  // metamer capture
#include "sensor/capture_files.h"
#include "sensor/sensor_spec.h"
#include "app/compare_command.h"  // metamer compare
#include "app/markdown_reference.h"  // metamer --markdown-reference: docs/cli.md
#include "app/progress_line.h"   // render --progress
#include "app/preview_command.h"  // metamer preview
#include "app/render_flags.h"     // the render flags, shared with preview, bench and batch
#include "core/cpu_count.h"
#include "core/error.h"
#include "core/file_reads.h"
#include "io/atomic_file.h"
#include "render/output_path.h"
#include "render/render_job.h"
#include "represent/representation.h"
#include "vk/context.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <cerrno>
#include <fcntl.h>
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
    // One line in the log (a Slurm task's shows why it ended), written with write(): the only
    // output a signal handler may do.
    static const char term[] =
        "metamer: stopped by SIGTERM (a time limit, scancel or kill): files being written were removed; what "
        "finished is kept, and a rerun does the rest\n";
    static const char other[] =
        "metamer: interrupted: files being written were removed; what finished is kept, and a rerun does the rest\n";
    if (sig == SIGTERM)
        (void)!::write(STDERR_FILENO, term, sizeof term - 1);
    else
        (void)!::write(STDERR_FILENO, other, sizeof other - 1);
    removeLiveTempFiles();
    _exit(128 + sig);
}

void printError(const std::string& message) { std::fprintf(stderr, "metamer: %s\n", printableMessage(message).c_str()); }

void printTimings(const RenderJobResult& r) {
    const StageTimings& t = r.timings;
    std::printf("timings (ms):");
    for (const auto& [stage, ms] : t.stages()) std::printf("%s %s %.1f", stage == std::string("load") ? "" : " ", stage, ms);
    std::printf("\n");
    if (t.shadow_ms > 0) std::printf("shadow maps: %.1f ms of the upload (drawn once per scene)\n", t.shadow_ms);
    double bandPixels = double(r.width) * r.height * r.grid.bands();
    if (r.displayOnly) {
        // The display path: a frame is the response pass (or, with slabs, interreflection or
        // emitters, the band passes: Scene::displayNeedsBands) and the tonemap pass.
        const char* what = r.responsePass ? "response pass: the detector's channels, no bands"
                                          : "band passes: this scene needs the bands (docs/color.md, The response pass)";
        if (t.frames > 1)
            std::printf("frames: %d (%s); first frame shading %.1f ms "
                        "(includes shader compilation); median of the other %d: shading %.1f ms, tonemap %.1f ms, "
                        "frame %.1f ms\n",
                        t.frames, what, t.first_shading_ms, t.frames - 1, t.median_shading_ms, t.median_tonemap_ms,
                        t.median_shading_ms + t.median_tonemap_ms);
        else
            std::printf("%s: one frame, includes shader compilation; --frames N for steady state\n", what);
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
    vk::Context::sizeDriverThreads();
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
    vkDestroyInstance(instance, nullptr);
    for (const auto& d : devices)
        std::printf("%u: %s (%s, score %d%s)%s%s\n", d.index, d.name.c_str(), vk::deviceTypeName(d.type), d.score,
                    d.score ? "" : ", unusable", d.uuid.empty() ? "" : " UUID ", d.uuid.c_str());
    if (devices.empty()) {
        std::fprintf(stderr, "metamer: no usable Vulkan device: the loader found none\n");
        return int(ExitCode::NoDevice);
    }
    // Which one a render here would take, and why (vk/device_choice.h); an error if none.
    const vk::DeviceChoice choice = vk::chooseDevice(devices, vk::deviceRequestFromEnvironment());
    std::printf("a render uses %u (%s)\n", devices[choice.position].index, choice.reason.c_str());
    return 0;
}

// Warnings dropped: `metamer render -q` prints errors only.
void dropWarning(const std::string&) {}

// A standard stream the caller closed (`2>&-`) leaves its descriptor free, and the next file opened
// takes it: an output's temporary would receive the progress lines or the error messages. Each
// closed one of 0–2 is opened on /dev/null first, in order, so each takes its own number.
void reopenClosedStandardStreams() {
    for (int fd = 0; fd <= 2; ++fd)
        if (::fcntl(fd, F_GETFD) == -1 && errno == EBADF) {
            const int opened = ::open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
            if (opened != fd && opened >= 0) ::close(opened);  // not ours to fill: leave it
        }
}

}  // namespace

int main(int argc, char** argv) {
    reopenClosedStandardStreams();
    gMainThread = pid_t(::syscall(SYS_gettid));
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);

    CLI::App app{"metamer: full-spectral rendering for color-imaging research"};
    app.require_subcommand(1);
    // The same string as the Python module's metamer.__version__ (one CMake project version).
    app.set_version_flag("--version", std::string("metamer ") + metamerVersion());

    // docs/cli.md's reference, from these declarations (hidden: group "").
    app.add_flag_callback("--markdown-reference", [&app] {
        std::fputs(markdownReference(app).c_str(), stdout);
        throw CLI::Success();
    }, "print docs/cli.md's reference block")->group("");

    RenderSettings settings;
    bool timings = false, quiet = false, progress = false;
    std::string scenePath, outText = "out";
    auto* render = app.add_subcommand("render", "render a scene to a spectral radiance cube (EXR) and a quick-look PNG");
    render->add_option("scene", scenePath, "scene file (JSON, docs/scene-format.md); - reads it from stdin, its "
                                           "relative paths then resolved against the current folder")->required();
    render->add_option("--out,--output,-o", outText, "output folder (created if missing), or NAME.exr, NAME.h5, NAME.mat, NAME.hdr "
                       "or NAME.png: every output named NAME.* in that file's folder; another image's extension "
                       "(.tiff, .jpg, ...) is an error (docs/cli.md, \"Output names\")")
        ->capture_default_str();
    addRenderFlags(render, settings, kAllRenderFlags);
    auto* timingsFlag = render->add_flag("--timings", timings, "print per-stage timings");
    auto* progressFlag = render->add_flag("--progress,!--no-progress", progress,
                                          "strips, passes, frames or rows done, time elapsed and left, on stderr "
                                          "(default: when stderr is a terminal)");
    render->add_flag("--quiet,-q", quiet, "print nothing but errors")
        ->excludes(render->get_option("--verbose"))
        ->excludes(timingsFlag)
        ->excludes(progressFlag);
    // A simulated sensor's capture of the rendered cube, as `metamer capture` (docs/sensor.md).
    std::string sensor;
    uint64_t sensorSeed = 0;
    std::optional<double> sensorExposure;
    render->add_option("--sensor", sensor, "capture the rendered cube with a simulated sensor (a .json file or a library "
                                           "sensor; docs/sensor.md): raw PNG, DNG and metadata beside the cube");
    render->add_option("--seed", sensorSeed, "--sensor: the temporal noise's seed")->capture_default_str();
    render->add_option("--exposure", sensorExposure, "--sensor: exposure time in seconds (default: the sensor file's)");

    auto* devices = app.add_subcommand("devices", "list Vulkan devices and their scores");

    // --- metamer compare (engine/app/compare_command.cpp, docs/compare.md)
    CompareArgs compareArgs;
    auto* compare = addCompareCommand(app, compareArgs);
    // --- end metamer compare

    // --- metamer capture (engine/app/capture_command.cpp, docs/sensor.md)
    CaptureArgs captureArgs;
    auto* capture = addCaptureCommand(app, captureArgs);
    // --- end metamer capture

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

    // --threads on every command that works (core/cpu_count.h).
    std::optional<int> threads;
    for (CLI::App* sub : app.get_subcommands({}))
        if (sub != devices)
            sub->add_option("--threads", threads, "CPU threads for the thread pools, OpenEXR and lavapipe (default: "
                            "SLURM_CPUS_PER_TASK, at most the CPUs this process may run on; else those CPUs)");

    try {
        checkVerb(app, argc, argv);  // before CLI11: `metamer rendr --help` is an error, not the top-level help
        app.parse(argc, argv);
        checkParsedValues(app);
        setThreadCount(threads);  // before any pool, EXR or Vulkan instance
    } catch (const Error& e) {
        printError(e.text());
        return int(e.code());
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ExtrasError&) {
        try {
            failUnexpectedArguments(app);
        } catch (const Error& e) {
            printError(e.text());
            return int(e.code());
        }
    } catch (const CLI::ParseError& e) {
        // A bad command line is bad input like any other: one "metamer: " line, exit code 2.
        if (e.get_exit_code() == 0) return app.exit(e);
        printError(e.what());
        return int(ExitCode::BadInput);
    }

    try {
        if (devices->parsed()) return listDevices();
        if (compare->parsed()) return runCompare(compareArgs);  // metamer compare
        if (capture->parsed()) return runCapture(captureArgs);  // metamer capture
        if (bench->parsed()) return runBenchCommand(benchArgs);  // metamer bench
        if (batch->parsed()) return runBatchCommand(batchArgs);  // metamer batch
        if (preview->parsed()) return runPreviewCommand(previewArgs);  // metamer preview

        if (quiet) {
            // Errors only: they go to stderr; everything the render reports goes to stdout or is a warning.
            setWarningSink(dropWarning);
            if (!std::freopen("/dev/null", "w", stdout)) failRuntime("-q: cannot silence stdout");
        }
        RenderJob job;
        const OutputPath out = parseOutputPath(outText, "--out");
        job.outDir = out.folder;
        job.outStem = out.stem;
        job.outExtension = out.extension;
        if (scenePath == "-") {
            // The scene from stdin: named <stdin> in messages; its relative paths resolve against the
            // current folder (the parent of a relative name), which is also the folder it may read.
            job.sceneText = readWholeStream(stdin, Where{"<stdin>"}, "scene read from standard input");
            job.scene = "<stdin>";
            if (job.outStem.empty()) job.outStem = "stdin";
        } else {
            job.scene = scenePath;
        }
        applyRenderSettings(settings, job, [](const std::string& name) { return "--" + name; });
        std::optional<ProgressLine> progressLine;
        const bool terminal = ::isatty(STDERR_FILENO) != 0;
        if (progressFlag->count() ? progress : terminal && !quiet) {
            progressLine.emplace(stderr, terminal);
            job.progress = [&progressLine](const RenderProgress& p) { (*progressLine)(p); };
        }
        std::optional<CaptureRequest> capture;
        std::optional<StagingFolder> captureStaging;
        CaptureFiles captured;
        if (!sensor.empty()) {
            // Before the render: a channel mode would write its image, then find no cube to capture.
            requireSpectralModeForSensor(job.mode, Where{"", "--mode"});
            const SpectrumLibrary library;
            readSensor(sensorFile(sensor, library), library);  // its mistakes before the render
            capture = CaptureRequest{};
            capture->sensor = sensor;
            capture->seed = sensorSeed;
            capture->exposure = sensorExposure;
            job.writeCube = true;
            // The capture reads the cube before anything is renamed into place, and its files
            // join the render's: all appear together, or none (an unlit scene's auto-exposure fails).
            job.beforeCommit = [&](const std::vector<AtomicOutput*>& files) {
                captured = stageCaptureOfRender(*capture, files, SpectrumLibrary(), *captureStaging);
                return std::vector<StagingFolder*>{&*captureStaging};
            };
            captureStaging.emplace(job.outDir, "capture");
        } else if (sensorExposure || sensorSeed) {
            failInput(Where{sensorExposure ? "--exposure" : "--seed"}, "goes with --sensor (a simulated sensor's capture)");
        }

        RenderJobResult r = runRenderJob(job);
        progressLine.reset();
        if (job.verbose) std::printf("%s\nthreads: %d (%s)\n", r.backendDescription.c_str(), r.threads,
                                     r.threadsSource.c_str());
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
        for (const std::string& line : captured.lines) std::printf("%s\n", line.c_str());
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
