// metamer.render: the same render job as `metamer render` (render/render_job.h), its arguments
// through the CLI's one conversion (render/render_settings.h), its outputs kept in memory
// (RenderJob::capture) as a metamer.Render (python/render_class). One Vulkan context per device
// choice is made on first use and kept for the process, forgotten by a forked child; renders are
// serialized, with the GIL released; Python's signal handlers and `progress` run between strips.
// Tests: tests/python/test_module.py (known answers, the CLI's files, fork, Ctrl-C, progress).
#include "core/error.h"
#include "python/arguments.h"
#include "python/bindings.h"
#include "python/errors.h"
#include "python/render_class.h"
#include "render/outputs.h"
#include "render/render_job.h"
#include "render/render_settings.h"
#include "render/render_setup.h"
#include "vk/context.h"

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/format.h>

#include <climits>
#include <map>
#include <memory>
#include <mutex>

namespace metamer::python {

namespace fs = std::filesystem;

namespace {

// Renders are serialized: a Vulkan queue takes one submitter at a time, and the GIL is released
// while a render runs. A pointer, so that a forked child can take a fresh one (forgetAtFork).
std::mutex* renderMutex = new std::mutex;
// Whether this thread is inside a render: its `progress` callback runs on it, and a render started
// from there would wait for the lock its own thread holds (issue 51, class 9: a deadlock).
thread_local bool insideRender = false;

// One context per (validation, device) asked for, kept until the interpreter exits.
std::map<std::pair<bool, std::string>, std::unique_ptr<vk::Context>>& contexts() {
    static std::map<std::pair<bool, std::string>, std::unique_ptr<vk::Context>> c;
    return c;
}

// fork() copies the process's memory but only the thread that called it: a Vulkan device made
// before the fork (lavapipe's queue and rasterizer threads, a GPU driver's mappings) is a husk in
// the child, and a render on it waits forever for threads that are not there. So the child
// forgets the inherited contexts, without destroying them (that would wait too), and makes a
// fresh one on its first render; the lock is new as well, since another thread may have held it
// at the fork. Run by os.register_at_fork(after_in_child=...); `spawn` needs none of this.
void forgetAtFork() {
    for (auto& [choice, context] : contexts()) (void)context.release();  // leaked on purpose
    contexts().clear();
    renderMutex = new std::mutex;  // the parent's may be locked; leaked with it
}

vk::Context& contextFor(const RenderJob& job) {
    const vk::ContextOptions options = jobContextOptions(job);
    auto& slot = contexts()[{options.validation, options.device}];
    if (!slot) slot = std::make_unique<vk::Context>(options);
    return *slot;
}

// render()'s docstring: what it does, then each keyword it shares with `metamer render`, with the
// flag's own help (render/render_settings.h), so the two cannot drift.
const std::string& renderDoc() {
    static const std::string doc = [] {
        std::string d =
            "Renders a scene (a path, or a dict in the scene format) and keeps the outputs that `write` names "
            "(default: the cube; also \"xyz\", \"responses\", \"display\"/\"png\", \"edges\") in memory; `format` is "
            "the cube's containers for Render.save(); `name` and `base_dir` place a dict scene.\n\n"
            "The keywords `metamer render` shares, with its help:\n";
        const std::pair<const char*, const char*> shared[] = {
            {"grid", "grid"},       {"overrides", "set"},       {"backend", "backend"},   {"detector", "detector"},
            {"adapt", "adapt"},     {"display", "display"},     {"bits", "bits"},         {"integration", "integration"},
            {"xyz", "xyz"},         {"mode", "mode"},           {"write", "write"},       {"resample", "resample"},
            {"ssaa", "ssaa"},       {"validation", "validation"}, {"device", "device"},
            {"allow_outside_paths", "allow-outside-paths"},     {"format", "format"},
            {"memory_budget", "memory-budget"}, {"half", "half"}, {"compression", "compression"},
            {"strict_coverage", "strict-coverage"}, {"readback", "readback"}};
        for (const auto& [keyword, flag] : shared)
            d += std::string("  ") + keyword + " (--" + flag + "): " + renderSettingHelp(flag) + "\n";
        return d;
    }();
    return doc;
}

std::shared_ptr<Render> render(const py::object& scene, const py::object& grid, const py::object& overrides,
                               const py::object& backend, const py::object& detector, const py::object& adapt,
                               const py::object& display, const py::object& bits, const py::object& integration,
                               const py::object& xyz, const py::object& mode, const py::object& write,
                               const py::object& resample, const py::object& ssaa, bool validation,
                               const py::object& device, bool allowOutsidePaths, const py::object& nameArg,
                               const py::object& baseDir, const py::object& format, const py::object& memoryBudget,
                               bool half, const py::object& compression, bool strictCoverage, const py::object& readback,
                               const py::object& progress, bool interruptible) {
    RenderJob job;
    if (py::isinstance<py::dict>(scene)) {
        // A scene given as a dict: its relative paths resolve against base_dir (default: the
        // current folder), and `name` is its stem for messages and Render.save() — the rule every
        // output name follows (render/outputs.h), so that no hidden or outside file is written.
        const std::string name = text(nameArg, "name");
        requireOutputStem(name, Where{"", "name"});
        fs::path base = baseDir.is_none() ? fs::current_path() : pathOf(baseDir, "base_dir");
        job.scene = base / (name + ".json");
        job.sceneText = toJson(scene, "scene").dump();
    } else if (isPath(scene)) {
        job.scene = pathOf(scene, "scene");
    } else {
        throw py::type_error(fmt::format("scene: expected a path (str, bytes or os.PathLike) or a dict in the scene "
                                         "format, got {}", typeName(scene)));
    }
    // The keyword arguments the CLI shares, through the one conversion (render/render_settings.h);
    // errors name the keyword.
    RenderSettings settings;
    settings.grid = optionalText(grid, "grid");
    settings.resample = optionalText(resample, "resample");
    settings.overrides = overrideList(overrides);
    settings.backend = text(backend, "backend");
    settings.ssaa = int(integer(ssaa, "ssaa", INT_MIN, INT_MAX));
    settings.detector = optionalText(detector, "detector");
    settings.adapt = optionalText(adapt, "adapt");
    settings.display = optionalText(display, "display");
    settings.bits = bits.is_none() ? 0 : int(integer(bits, "bits", INT_MIN, INT_MAX));
    if (!bits.is_none() && settings.bits == 0) failInput(Where{"", "bits"}, "0 bits; expected 8 or 16");
    settings.integration = optionalText(integration, "integration");
    settings.xyz = optionalText(xyz, "xyz");
    settings.mode = text(mode, "mode");
    settings.write = write.is_none() ? std::vector<std::string>{"cube"} : stringList(write, "write");
    for (auto& o : settings.write)
        if (o == "display") o = "png";  // the display image is the CLI's PNG
    if (!format.is_none()) settings.format = stringList(format, "format");
    settings.validation = validation;
    settings.half = half;
    settings.compression = text(compression, "compression");
    settings.strictCoverage = strictCoverage;
    settings.readback = text(readback, "readback");
    settings.device = text(device, "device");
    settings.allowOutsidePaths = allowOutsidePaths;
    if (!memoryBudget.is_none()) {
        settings.memoryBudgetMiB = number(memoryBudget, "memory_budget");
        if (!(settings.memoryBudgetMiB > 0))
            failInput(Where{"", "memory_budget"}, "{:g} MiB; expected a budget > 0 in MiB", settings.memoryBudgetMiB);
    }
    applyRenderSettings(settings, job, [](const std::string& name) {
        return name == "allow-outside-paths"   ? "allow_outside_paths"
               : name == "memory-budget"     ? "memory_budget"
               : name == "strict-coverage" ? "strict_coverage"
                                             : name;
    });
    // Given lists are the job's even when empty (refused there, as an empty --write is).
    job.write = settings.write;
    if (!format.is_none()) job.format = settings.format;

    // Between strips, passes and rows (render/render_progress.h), on this thread: Python's signal
    // handlers run (Ctrl-C, a notebook's interrupt: KeyboardInterrupt), then `progress`, called as
    // progress(unit, done, total, seconds). Either may raise; the render then stops between two
    // submissions and keeps nothing. With `interruptible`, images over kInterruptPixels samples
    // render in strips of that size so that a stop waits for one strip (about 0.1–0.3 s on
    // lavapipe), not the whole image; strips equal one frame to float rounding (a few edge pixels
    // to 3·10⁻⁴ relative, tests/strips_test.cpp), so False keeps the CLI's whole frame bit for bit.
    if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
        throw py::type_error(fmt::format("progress: expected a callable or None, got {}", typeName(progress)));
    job.progress = [&progress](const RenderProgress& p) {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!progress.is_none()) progress(p.unit, p.done, p.total, p.seconds);
    };
    constexpr size_t kInterruptPixels = size_t(1) << 18;  // 512²
    job.stripPixels = interruptible ? kInterruptPixels : 0;

    if (insideRender)
        throw std::runtime_error("metamer.render was called from inside a render (its progress callback): it would "
                              "wait for itself; start the next render after this one returns");
    discardPendingWarning();
    auto r = std::make_shared<Render>();
    job.capture = &r->captured;
    {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(*renderMutex);
        insideRender = true;
        struct Leave {
            ~Leave() { insideRender = false; }
        } leave;
        if (job.backend == Backend::Gpu) job.context = &contextFor(job);
        r->result = runRenderJob(job);
    }
    raisePendingWarning();
    const Representation& rep = r->captured.loaded->representation;
    r->spectral = rep.mode.spectral();
    if (!r->spectral) r->channelNames = rep.channelNames;
    if (r->captured.plan) {
        r->bits = r->captured.plan->display.bits;
        r->responseChannels = r->captured.plan->detector.channels;
        r->responseUnits = r->captured.plan->detector.units;
    }
    return r;
}

}  // namespace

void bindRender(py::module_& m) {
    m.def("render", &render, py::arg("scene"), py::kw_only(), py::arg("grid") = py::none(),
          py::arg("overrides") = py::none(), py::arg("backend") = "gpu", py::arg("detector") = py::none(),
          py::arg("adapt") = py::none(), py::arg("display") = py::none(), py::arg("bits") = py::none(),
          py::arg("integration") = py::none(), py::arg("xyz") = py::none(), py::arg("mode") = "full",
          py::arg("write") = py::none(), py::arg("resample") = py::none(), py::arg("ssaa") = 1,
          py::arg("validation") = false, py::arg("device") = "", py::arg("allow_outside_paths") = false,
          py::arg("name") = "scene", py::arg("base_dir") = py::none(), py::arg("format") = py::none(),
          py::arg("memory_budget") = py::none(), py::arg("half") = false, py::arg("compression") = "piz",
          py::arg("strict_coverage") = false, py::arg("readback") = "auto", py::arg("progress") = py::none(),
          py::arg("interruptible") = true, renderDoc().c_str());
    m.def("_context_count", [] { return contexts().size(); }, "Vulkan contexts made so far (tests)");
    py::module_::import("os").attr("register_at_fork")(py::arg("after_in_child") = py::cpp_function(&forgetAtFork));
    // The contexts go before the interpreter does: destroying a Vulkan device from a static
    // destructor after Python has finalized would race the driver's threads.
    py::module_::import("atexit").attr("register")(py::cpp_function([] { contexts().clear(); }));
}

}  // namespace metamer::python
