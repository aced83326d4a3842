// `import metamer`: the engine for Python (docs/python.md). A thin binding: metamer.render runs
// the same render job as `metamer render`, with the outputs kept in memory (RenderJob::capture),
// and hands the arrays to numpy without a copy; Render.save writes the CLI's files from them;
// metamer.compare and metamer.load_cube call the compare and io layers. One Vulkan context per
// device choice is made on first use and kept for the process (as metamer batch keeps one for its
// jobs), so a call does not pay the device start-up. Errors are metamer.InputError (what the CLI
// exits 2 on; also a ValueError) or metamer.Error, carrying the CLI's message.
// Tests: tests/python/test_module.py (pytest).
#include "compare/compare.h"
#include "compare/tolerance.h"
#include "core/error.h"
#include "core/json.h"
#include "io/spectral_image.h"
#include "render/outputs.h"
#include "render/render_job.h"
#include "render/render_settings.h"
#include "render/render_setup.h"
#include "sensor/capture.h"
#include "sensor/capture_files.h"
#include "spectral/kubelka_munk.h"
#include "spectral/library.h"
#include "spectral/resampling.h"
#include "vk/check.h"
#include "vk/context.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/format.h>

#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace metamer;

namespace {

PyObject* errorType = nullptr;       // metamer.Error (RuntimeError)
PyObject* inputErrorType = nullptr;  // metamer.InputError (metamer.Error, ValueError)
PyObject* notFoundType = nullptr;    // metamer.NotFoundError (metamer.InputError, FileNotFoundError)
PyObject* warningType = nullptr;     // metamer.Warning (UserWarning)

// A warning the filters turned into an exception (warnings.simplefilter("error", metamer.Warning)),
// held until the call that warned returns, then raised in its place (raisePendingWarning). Guarded
// by the GIL. The engine warns from inside work that cannot unwind at that point (a worker thread,
// a parser mid-scene), so the call finishes and its result is dropped: nothing is half-made, and
// Python renders write no files.
PyObject *pendingType = nullptr, *pendingValue = nullptr, *pendingTraceback = nullptr;

// The engine's warnings (core/error.h) as Python warnings of category metamer.Warning, so a
// notebook shows them under the cell and `warnings` filters them. Called from whatever thread
// warns, usually with the GIL released by a render: it takes the GIL itself.
void warnInPython(const std::string& line) {
    py::gil_scoped_acquire gil;
    const std::string text = printableMessage(line.rfind("warning: ", 0) == 0 ? line.substr(9) : line);
    if (PyErr_WarnEx(warningType, text.c_str(), 1) < 0) {
        if (pendingType) {
            PyErr_Clear();  // the first one is raised
        } else {
            PyErr_Fetch(&pendingType, &pendingValue, &pendingTraceback);
        }
    }
}

// A warning held from a call that then failed otherwise (an interrupt, an input error): dropped.
void discardPendingWarning() {
    Py_XDECREF(pendingType);
    Py_XDECREF(pendingValue);
    Py_XDECREF(pendingTraceback);
    pendingType = pendingValue = pendingTraceback = nullptr;
}

// After a call into the engine, with the GIL: the warning an "error" filter turned into an
// exception, raised now.
void raisePendingWarning() {
    if (!pendingType) return;
    PyErr_Restore(pendingType, pendingValue, pendingTraceback);
    pendingType = pendingValue = pendingTraceback = nullptr;
    throw py::error_already_set();
}

// Renders are serialized: a Vulkan queue takes one submitter at a time, and the GIL is released
// while a render runs. A pointer, so that a forked child can take a fresh one (forgetAtFork).
std::mutex* renderMutex = new std::mutex;

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

// A numpy view of `data` (shape, C order) that keeps `owner` alive; read-only, so the arrays
// stay what Render.save() writes.
//
// The strides are computed here, never by pybind11: Debian's pybind11 2.10 reads a dtype's item
// size from numpy 1's descriptor layout, which numpy 2 changed (it reads 0, and the array would
// repeat its first element).
template <typename T>
std::vector<py::ssize_t> cStrides(const std::vector<py::ssize_t>& shape) {
    std::vector<py::ssize_t> strides(shape.size());
    py::ssize_t s = py::ssize_t(sizeof(T));
    for (size_t i = shape.size(); i-- > 0;) {
        strides[i] = s;
        s *= shape[i];
    }
    return strides;
}

template <typename T>
py::object view(const std::vector<T>& data, std::vector<py::ssize_t> shape, py::handle owner) {
    if (data.empty()) return py::none();
    py::array a(py::dtype::of<T>(), shape, cStrides<T>(shape), data.data(), owner);
    a.attr("setflags")(py::arg("write") = false);
    return a;
}

// A float64 array, a copy of `v`.
py::array doubles(const std::vector<double>& v) {
    const std::vector<py::ssize_t> shape{py::ssize_t(v.size())};
    py::array a(py::dtype::of<double>(), shape, cStrides<double>(shape));
    std::copy(v.begin(), v.end(), static_cast<double*>(a.mutable_data()));
    return a;
}

// The Python result of metamer.render: the captured arrays and the job's report.
struct Render {
    CapturedRender captured;
    RenderJobResult result;
    bool spectral = true;
    std::vector<std::string> channelNames;  // non-spectral modes: the mode's channels
    int bits = 8;
    std::optional<std::vector<std::string>> responseChannels;  // the detector's, when there is a display path
    std::optional<std::string> responseUnits;
    bool unpickled = false;  // made by pickle from another Render: its arrays and report, not its scene
};

const char* typeName(const py::handle& x) { return Py_TYPE(x.ptr())->tp_name; }

bool isPath(const py::handle& x) {
    return py::isinstance<py::str>(x) || py::isinstance<py::bytes>(x) ||
           py::isinstance(x, py::module_::import("os").attr("PathLike"));
}

// A path argument: str, bytes or os.PathLike, read as os.fsencode reads it (a str in the file
// system's encoding, undecodable bytes kept as they were); anything else is a TypeError naming
// the argument. (py::str would have read b'x.json' as the text "b'x.json'".)
fs::path pathOf(const py::handle& x, const char* name) {
    if (!isPath(x))
        throw py::type_error(fmt::format("{}: expected a path (str, bytes or os.PathLike), got {}", name, typeName(x)));
    const std::string bytes = py::module_::import("os").attr("fsencode")(x).cast<py::bytes>();
    // The OS would read the path only up to the NUL: another file than the one named.
    if (bytes.find('\0') != std::string::npos) failInput(Where{"", name}, "the path holds a NUL byte");
    return fs::path(bytes);
}

// An integer argument: an int or a numpy integer (not a bool, not a float), within [lo, hi];
// else a TypeError or an InputError naming it, not pybind11's list of signatures.
long long integer(const py::handle& x, const char* name, long long lo, long long hi) {
    if (py::isinstance<py::bool_>(x) || !py::hasattr(x, "__index__"))
        throw py::type_error(fmt::format("{}: expected an integer, got {}", name, typeName(x)));
    const py::int_ i = py::module_::import("operator").attr("index")(x);
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow || v < lo || v > hi)
        failInput(Where{"", name}, "{} is out of range; expected {} … {}", py::str(py::handle(i)).cast<std::string>(), lo, hi);
    return v;
}

uint64_t unsignedInteger(const py::handle& x, const char* name) {
    if (py::isinstance<py::bool_>(x) || !py::hasattr(x, "__index__"))
        throw py::type_error(fmt::format("{}: expected an integer, got {}", name, typeName(x)));
    const py::int_ i = py::module_::import("operator").attr("index")(x);
    const unsigned long long v = PyLong_AsUnsignedLongLong(i.ptr());
    if (PyErr_Occurred()) {
        PyErr_Clear();
        failInput(Where{"", name}, "{} is out of range; expected 0 … 2⁶⁴ − 1", py::str(py::handle(i)).cast<std::string>());
    }
    return v;
}

// A number argument (int, float or a numpy number; not a bool), finite; else a TypeError or an
// InputError naming it.
double number(const py::handle& x, const char* name) {
    if (py::isinstance<py::bool_>(x) || py::isinstance<py::str>(x) || !py::hasattr(x, "__float__"))
        throw py::type_error(fmt::format("{}: expected a number, got {}", name, typeName(x)));
    const double v = PyFloat_AsDouble(x.ptr());
    if (PyErr_Occurred()) throw py::error_already_set();
    if (!std::isfinite(v)) failInput(Where{"", name}, "expected a finite number, got {}", v);
    return v;
}

std::optional<double> optionalNumber(const py::handle& x, const char* name) {
    if (x.is_none()) return std::nullopt;
    return number(x, name);
}

// A text argument (a str; None for "not given" where allowed); else a TypeError naming it.
std::string text(const py::handle& x, const char* name) {
    if (!py::isinstance<py::str>(x)) throw py::type_error(fmt::format("{}: expected a str, got {}", name, typeName(x)));
    try {
        return x.cast<std::string>();
    } catch (const py::cast_error&) {
        PyErr_Clear();
        failInput(Where{"", name}, "the text is not valid Unicode (a lone surrogate)");
    }
}

// An optional text argument: None for the scene's or the default choice; '' is refused, as the
// CLI refuses an empty flag value (`--grid ''`), rather than read as "not given".
std::string optionalText(const py::handle& x, const char* name) {
    if (x.is_none()) return {};
    std::string s = text(x, name);
    if (s.empty()) failInput(Where{"", name}, "empty; give a value, or None for the default");
    return s;
}

// A scene (or an override's value) given as Python objects, as JSON for the scene parser: dicts
// with str keys, lists, tuples and numpy arrays (a spectrum's values), str, bool, int, float,
// None and numpy scalars. What JSON cannot hold is refused at its key path: NaN and infinities
// (json.dumps would write NaN, which the parser refuses without saying where), other types, and
// nesting deeper than the parser takes (a dict that holds itself).
nlohmann::json toJson(const py::handle& v, const std::string& at, int depth = 0) {
    constexpr int kDeepest = 64;
    if (depth > kDeepest)
        failInput(Where{"", at}, "nested deeper than {} levels (a dict or list that holds itself?)", kDeepest);
    // Kept for the process (a static py::object would be released after the interpreter is gone).
    static const py::handle numpyGeneric = py::object(py::module_::import("numpy").attr("generic")).release();
    static const py::handle numpyArray = py::object(py::module_::import("numpy").attr("ndarray")).release();
    if (v.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
    if (py::isinstance(v, numpyArray) || py::isinstance(v, numpyGeneric))
        return toJson(v.attr("tolist")(), at, depth);  // Python numbers, lists of them
    if (py::isinstance<py::int_>(v)) {
        int overflow = 0;
        const long long i = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
        if (!overflow) return i;
        failInput(Where{"", at}, "{} is out of range for a scene's numbers", py::str(v).cast<std::string>());
    }
    if (py::isinstance<py::float_>(v)) {
        const double d = v.cast<double>();
        if (!std::isfinite(d)) failInput(Where{"", at}, "{} is not a number a scene holds (JSON has no NaN or infinity)", d);
        return d;
    }
    if (py::isinstance<py::str>(v)) return text(v, at.c_str());
    if (py::isinstance<py::dict>(v)) {
        nlohmann::json o = nlohmann::json::object();
        for (auto [key, value] : v.cast<py::dict>()) {
            if (!py::isinstance<py::str>(key))
                throw py::type_error(fmt::format("{}: a key must be a str, got {} {}", at, typeName(key),
                                                 py::repr(key).cast<std::string>()));
            const std::string k = text(key, at.c_str());
            o[k] = toJson(value, at + "." + k, depth + 1);
        }
        return o;
    }
    if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        nlohmann::json a = nlohmann::json::array();
        size_t i = 0;
        for (const py::handle& item : v) a.push_back(toJson(item, at + "." + std::to_string(i++), depth + 1));
        return a;
    }
    throw py::type_error(fmt::format("{}: a {} is not something a scene holds (dict, list, str, number, bool or None)",
                                     at, typeName(v)));
}

std::vector<std::string> stringList(const py::handle& value, const char* name) {
    if (value.is_none()) return {};
    if (py::isinstance<py::str>(value)) {
        // "cube,xyz": the CLI's comma-separated form.
        std::vector<std::string> out;
        std::string s = value.cast<std::string>();
        size_t start = 0;
        while (start <= s.size()) {
            size_t comma = s.find(',', start);
            std::string item = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            if (!item.empty()) out.push_back(item);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        return out;
    }
    // A sequence of str; not bytes, whose items would be read as numbers.
    if (py::isinstance<py::bytes>(value) || !py::hasattr(value, "__iter__"))
        throw py::type_error(fmt::format("{}: expected a str or a sequence of str, got {}", name, typeName(value)));
    std::vector<std::string> out;
    for (const py::handle& item : value) out.push_back(text(item, name));
    return out;
}

// overrides: ["KEY=VALUE", ...] as --set takes them, or {key: value} (values as JSON).
std::vector<std::string> overrideList(const py::handle& value) {
    if (value.is_none()) return {};
    if (py::isinstance<py::dict>(value)) {
        std::vector<std::string> out;
        for (auto [k, v] : value.cast<py::dict>()) {
            const std::string key = text(k, "overrides");
            const std::string value = py::isinstance<py::str>(v) ? text(v, ("overrides." + key).c_str())
                                                                 : toJson(v, "overrides." + key).dump();
            out.push_back(key + "=" + value);
        }
        return out;
    }
    return stringList(value, "overrides");
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

    discardPendingWarning();
    auto r = std::make_shared<Render>();
    job.capture = &r->captured;
    {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(*renderMutex);
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

// --- Pickling (concurrent.futures, multiprocessing, dask): a Render's arrays and report, so a
// worker can return one. The loaded scene and its textures stay behind: an unpickled Render has
// every attribute but cannot save() (which writes the scene's provenance and display path).

template <typename T>
py::bytes rawBytes(const std::vector<T>& v) {
    return py::bytes(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <typename T>
std::vector<T> fromRawBytes(const py::handle& b, const char* what) {
    const std::string s = b.cast<std::string>();
    if (s.size() % sizeof(T)) failInput(Where{"", "pickle"}, "{}: {} bytes is not a whole number of values", what, s.size());
    std::vector<T> v(s.size() / sizeof(T));
    std::memcpy(v.data(), s.data(), s.size());
    return v;
}

constexpr int kPickleVersion = 1;

py::tuple renderState(const Render& r) {
    const CapturedOutputs& c = r.captured.outputs;
    py::dict timings;
    for (const auto& [stage, ms] : r.result.timings.stages()) timings[py::str(stage)] = ms;
    py::dict d;
    d["width"] = c.width;
    d["height"] = c.height;
    d["cube"] = rawBytes(c.cube);
    d["cube_channels"] = c.cubeChannels;
    d["counts"] = rawBytes(c.counts);
    d["xyz"] = rawBytes(c.xyz);
    d["responses"] = rawBytes(c.responses);
    d["response_channels_count"] = c.responseChannels;
    d["edges"] = rawBytes(c.edges);
    d["grid"] = r.captured.grid.str();
    d["spectral"] = r.spectral;
    d["channel_names"] = r.channelNames;
    d["bits"] = r.bits;
    d["response_channels"] = r.responseChannels ? py::cast(*r.responseChannels) : py::none();
    d["response_units"] = r.responseUnits ? py::cast(*r.responseUnits) : py::none();
    d["xyz_units"] = r.result.xyzUnits;
    d["display_description"] = r.result.displayDescription;
    d["clipped_pixels"] = r.result.clippedPixels;
    d["camera_fit"] = r.result.cameraFitRmsDeltaE ? py::cast(*r.result.cameraFitRmsDeltaE) : py::none();
    d["backend"] = r.result.backendDescription;
    d["notes"] = r.result.notes;
    d["validation_errors"] = r.result.validationErrors;
    d["timings_ms"] = timings;
    return py::make_tuple(kPickleVersion, d);
}

std::shared_ptr<Render> renderFromState(const py::tuple& t) {
    if (t.size() != 2 || t[0].cast<int>() != kPickleVersion)
        failInput(Where{"", "pickle"}, "a metamer.Render pickled by another version of metamer (expected state version {})",
                  kPickleVersion);
    const py::dict d = t[1].cast<py::dict>();
    auto r = std::make_shared<Render>();
    CapturedOutputs& c = r->captured.outputs;
    c.width = d["width"].cast<int>();
    c.height = d["height"].cast<int>();
    c.cube = fromRawBytes<float>(d["cube"], "cube");
    c.cubeChannels = d["cube_channels"].cast<size_t>();
    c.counts = fromRawBytes<uint16_t>(d["counts"], "display");
    c.xyz = fromRawBytes<float>(d["xyz"], "xyz");
    c.responses = fromRawBytes<float>(d["responses"], "responses");
    c.responseChannels = d["response_channels_count"].cast<size_t>();
    c.edges = fromRawBytes<uint16_t>(d["edges"], "edges");
    const size_t pixels = size_t(c.width) * size_t(c.height);
    if (c.cube.size() != pixels * c.cubeChannels || c.xyz.size() % 3 || c.counts.size() % 3 ||
        c.responses.size() != (c.responses.empty() ? 0 : pixels * c.responseChannels))
        failInput(Where{"", "pickle"}, "a metamer.Render whose arrays do not match its {}×{} size", c.width, c.height);
    r->captured.grid = Grid::parse(d["grid"].cast<std::string>(), Where{"", "pickle"});
    r->spectral = d["spectral"].cast<bool>();
    r->channelNames = d["channel_names"].cast<std::vector<std::string>>();
    r->bits = d["bits"].cast<int>();
    if (!d["response_channels"].is_none()) r->responseChannels = d["response_channels"].cast<std::vector<std::string>>();
    if (!d["response_units"].is_none()) r->responseUnits = d["response_units"].cast<std::string>();
    r->result.xyzUnits = d["xyz_units"].cast<std::string>();
    r->result.displayDescription = d["display_description"].cast<std::string>();
    r->result.clippedPixels = d["clipped_pixels"].cast<size_t>();
    if (!d["camera_fit"].is_none()) r->result.cameraFitRmsDeltaE = d["camera_fit"].cast<double>();
    r->result.backendDescription = d["backend"].cast<std::string>();
    r->result.notes = d["notes"].cast<std::vector<std::string>>();
    r->result.validationErrors = d["validation_errors"].cast<uint32_t>();
    StageTimings& times = r->result.timings;
    const std::map<std::string, double*> stages{{"load", &times.load_ms},       {"upload", &times.upload_ms},
                                                {"shading", &times.shading_ms}, {"readback", &times.readback_ms},
                                                {"tonemap", &times.tonemap_ms}, {"write", &times.write_ms},
                                                {"total", &times.total_ms}};
    for (auto [stage, ms] : d["timings_ms"].cast<py::dict>())
        if (auto it = stages.find(stage.cast<std::string>()); it != stages.end()) *it->second = ms.cast<double>();
    r->unpickled = true;
    return r;
}

py::dict statsDict(const CompareStats& stats) {
    return py::module_::import("json").attr("loads")(statsToJson(stats).dump()).cast<py::dict>();
}

// A compare operand: a path to any file `metamer compare` reads, or a Render (its cube).
ImageData comparable(const py::object& x, const char* which) {
    if (py::isinstance<Render>(x)) {
        const Render& r = x.cast<const Render&>();
        if (r.captured.outputs.cube.empty() || !r.spectral)
            failInput(Where{"", which}, "this render kept no spectral cube (render with write=\"cube\")");
        SpectralCube cube;
        cube.width = r.captured.outputs.width;
        cube.height = r.captured.outputs.height;
        cube.grid = r.captured.grid;
        cube.data = r.captured.outputs.cube;
        ImageData d = fromCube(cube);
        d.source = which;
        return d;
    }
    // (cube, grid): a rows × columns × bands array of spectral radiance on the grid "start:end:step"
    // (the package's compare() makes this pair from arrays with wavelengths, xarray and load_cube).
    if (py::isinstance<py::tuple>(x) && py::len(x) == 2) {
        const py::tuple pair = x.cast<py::tuple>();
        const Grid grid = Grid::parse(text(pair[1], which), Where{"", which});
        const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(pair[0]);
        if (!a || a.ndim() != 3)
            throw py::type_error(fmt::format("{}: expected a rows × columns × bands array of numbers", which));
        if (a.shape(2) != grid.bands() || a.shape(0) < 1 || a.shape(1) < 1)
            failInput(Where{"", which}, "a {}×{}×{} array on the grid {} ({} bands); expected rows × columns × bands",
                      a.shape(0), a.shape(1), a.shape(2), grid.str(), grid.bands());
        SpectralCube cube;
        cube.height = int(a.shape(0));
        cube.width = int(a.shape(1));
        cube.grid = grid;
        cube.data.assign(a.data(), a.data() + a.size());
        ImageData d = fromCube(cube);
        d.source = which;
        return d;
    }
    if (!isPath(x))
        throw py::type_error(fmt::format("{}: expected a path (str, bytes or os.PathLike), a metamer.Render or a (cube, "
                                         "grid) pair, got {}", which, typeName(x)));
    return readComparable(pathOf(x, which));
}

py::dict compare(const py::object& a, const py::object& b, const py::object& mask, const py::object& tolerance,
                 bool resample, const py::object& detector, const py::object& adapt, const py::object& display,
                 const py::object& pixelThreshold, const py::object& relativeFloor, bool deltaE) {
    discardPendingWarning();
    // In `metamer compare`'s order: everything named is checked before the comparison.
    std::optional<Tolerance> limits;
    if (!tolerance.is_none()) limits = readTolerance(pathOf(tolerance, "tolerance"));
    ImageData A = comparable(a, "a"), B = comparable(b, "b");
    CompareRequest request;
    request.pixelThreshold = optionalNumber(pixelThreshold, "pixel_threshold");
    request.relativeFloor = optionalNumber(relativeFloor, "relative_floor");
    request.resample = resample;
    request.detector = text(detector, "detector");
    request.adapt = text(adapt, "adapt");
    request.display = text(display, "display");
    request.noDeltaE = !deltaE;
    CompareOptions o = makeCompareOptions(request, B, limits ? &*limits : nullptr);
    if (!mask.is_none()) o.mask = readMask(pathOf(mask, "mask"), B.width, B.height);
    CompareStats stats;
    {
        py::gil_scoped_release release;
        stats = compareImages(A, B, o);
    }
    raisePendingWarning();
    py::dict d = statsDict(stats);
    if (limits) {
        const Verdict v = judge(stats, *limits);
        d["passed"] = v.pass;
        d["failures"] = v.failures;
    }
    return d;
}

// metamer.load_cube: a spectral cube from EXR, HDF5 or ENVI, as a dict of numpy arrays.
py::dict loadCube(const py::object& path) {
    discardPendingWarning();
    const fs::path file = pathOf(path, "path");
    auto image = std::make_shared<SpectralImage>(readSpectralImage(file));
    raisePendingWarning();
    const SpectralCube& c = image->cube;
    // The array owns the cube through a capsule: no copy of a cube that may be GiBs.
    py::capsule owner(new std::shared_ptr<SpectralImage>(image),
                      [](void* p) { delete static_cast<std::shared_ptr<SpectralImage>*>(p); });
    py::dict d;
    d["cube"] = view(c.data, {c.height, c.width, c.bands()}, owner);
    d["wavelengths_nm"] = doubles(c.grid.wavelengths());
    d["grid"] = c.grid.str();
    const bool reflective = image->component == SpectralComponent::Reflective;
    d["quantity"] = reflective ? "reflectance" : "spectral radiance";
    d["units"] = reflective ? "1" : "W·sr⁻¹·m⁻²·nm⁻¹";
    return d;
}

// metamer.capture: the simulated sensor (docs/sensor.md) on a Render's cube or a cube file.
py::dict capture(const py::object& source, const py::object& sensorName, const py::object& seedArg,
                 const py::object& frameArg, const py::object& framesArg, const py::object& exposureArg, bool noise) {
    discardPendingWarning();
    const uint64_t seed = unsignedInteger(seedArg, "seed"), frame = unsignedInteger(frameArg, "frame");
    const int frames = int(integer(framesArg, "frames", INT_MIN, INT_MAX));
    const std::optional<double> exposure = optionalNumber(exposureArg, "exposure");
    if (frames < 1 || frames > 100000) failInput(Where{"frames"}, "expected 1 … 100000 frames, got {}", frames);
    if (exposure && !(*exposure > 0.0 && *exposure <= 1e6))  // the CLI's bounds (sensor/capture_files.cpp)
        failInput(Where{"exposure"}, "expected an exposure time in seconds, > 0 and at most 10⁶, got {:g}", *exposure);
    const SpectrumLibrary library;
    const SensorSpec sensor = readSensor(sensorFile(pathOf(sensorName, "sensor").string(), library), library);
    SpectralCube cube;
    if (py::isinstance<Render>(source)) {
        const Render& r = source.cast<const Render&>();
        if (!r.spectral || r.captured.outputs.cube.empty())
            failInput(Where{"source"}, "the render holds no spectral cube: render with write=\"cube\" in mode \"full\"");
        cube.width = r.captured.outputs.width;
        cube.height = r.captured.outputs.height;
        cube.grid = r.captured.grid;
        cube.data = r.captured.outputs.cube;
    } else {
        if (!isPath(source))
            throw py::type_error(fmt::format("source: expected a path (str, bytes or os.PathLike) or a metamer.Render, "
                                             "got {}", typeName(source)));
        cube = readRadianceCube(pathOf(source, "source"));
    }
    ExpectedElectrons e;
    std::vector<std::vector<uint16_t>> raws;
    {
        py::gil_scoped_release release;
        e = expectedElectrons(cube, sensor, exposure, noise);
        for (int f = 0; f < frames; ++f)
            raws.push_back(digitize(e.electrons, e.width, sensor, CaptureNoise{noise, seed, frame + uint64_t(f)}));
    }
    raisePendingWarning();
    const py::ssize_t h = e.height, w = e.width;
    py::array_t<uint16_t> raw = frames == 1 ? py::array_t<uint16_t>({h, w}) : py::array_t<uint16_t>({py::ssize_t(frames), h, w});
    uint16_t* out = raw.mutable_data();
    for (const auto& r : raws) out = std::copy(r.begin(), r.end(), out);
    py::array_t<double> electrons({h, w});
    std::copy(e.electrons.begin(), e.electrons.end(), electrons.mutable_data());
    py::list cfa;
    for (const auto& row : sensor.cfa) {
        py::list names;
        for (int c : row) names.append(sensor.channels[size_t(c)]);
        cfa.append(names);
    }
    py::dict d;
    d["raw"] = raw;
    d["electrons"] = electrons;
    d["channels"] = sensor.channels;
    d["cfa"] = cfa;
    d["black_level_dn"] = sensor.blackLevel_dn;
    d["white_level_dn"] = sensor.whiteLevel();
    d["conversion_gain_dn_per_e"] = sensor.gain_dn_per_e;
    d["exposure_s"] = e.exposure_s;
    d["auto_exposed"] = e.autoExposed;
    d["seed"] = seed;
    d["frame"] = frame;
    d["sensor"] = sensor.file.string();
    return d;
}

void translate(std::exception_ptr p) {
    try {
        if (p) std::rethrow_exception(p);
    } catch (const NotFoundError& e) {
        PyErr_SetString(notFoundType, printableMessage(e.text()).c_str());
    } catch (const Error& e) {
        PyErr_SetString(e.code() == ExitCode::BadInput ? inputErrorType : errorType,
                        printableMessage(e.text()).c_str());
    } catch (const std::bad_alloc&) {
        PyErr_SetString(PyExc_MemoryError, "out of memory");
    }
}

}  // namespace

PYBIND11_MODULE(_metamer, m) {
    m.doc() = "Metamer: full-spectral rendering of spectral radiance cubes (docs/python.md)";
    errorType = PyErr_NewException("metamer.Error", PyExc_RuntimeError, nullptr);
    py::object bases = py::make_tuple(py::handle(errorType), py::handle(PyExc_ValueError));
    inputErrorType = PyErr_NewException("metamer.InputError", bases.ptr(), nullptr);
    m.attr("Error") = py::handle(errorType);
    m.attr("InputError") = py::handle(inputErrorType);
    // A named file that does not exist: `except FileNotFoundError` catches it as for open().
    py::object notFoundBases = py::make_tuple(py::handle(inputErrorType), py::handle(PyExc_FileNotFoundError));
    notFoundType = PyErr_NewException("metamer.NotFoundError", notFoundBases.ptr(), nullptr);
    m.attr("NotFoundError") = py::handle(notFoundType);
    warningType = PyErr_NewException("metamer.Warning", PyExc_UserWarning, nullptr);
    m.attr("Warning") = py::handle(warningType);
    setWarningSink(&warnInPython);
    py::register_exception_translator(&translate);
    m.attr("__version__") = METAMER_VERSION;

    py::class_<Render, std::shared_ptr<Render>>(m, "Render", "A render held in memory (metamer.render)")
        .def_property_readonly(
            "cube",
            [](py::object self) -> py::object {
                const Render& r = self.cast<const Render&>();
                const CapturedOutputs& c = r.captured.outputs;
                return view(c.cube, {c.height, c.width, py::ssize_t(c.cubeChannels)}, self);
            },
            "rows × columns × bands float32 (read-only view): spectral radiance per band, W·sr⁻¹·m⁻²·nm⁻¹; "
            "a reduced mode's channels when mode is not spectral; None unless write has \"cube\"")
        .def_property_readonly("wavelengths_nm",
                               [](const Render& r) -> py::object {
                                   if (!r.spectral) return py::none();
                                   return doubles(r.captured.grid.wavelengths());
                               }, "the bands' centre wavelengths, nm (float64); None for a reduced mode")
        .def_property_readonly("grid", [](const Render& r) { return r.captured.grid.str(); },
                               "the spectral grid, \"START:END:STEP\" in nm (as grid= and --grid take it)")
        .def_property_readonly("channels",
                               [](const Render& r) -> py::object {
                                   if (r.spectral) return py::none();
                                   return py::cast(r.channelNames);
                               }, "a reduced mode's channel names (rgb, ac1c2, linear:K); None for spectral modes")
        .def_property_readonly("units",
                               [](const Render& r) {
                                   return r.spectral ? std::string("W·sr⁻¹·m⁻²·nm⁻¹")
                                                     : std::string("W·sr⁻¹·m⁻²·nm⁻¹ weighted by the mode's channels");
                               }, "the cube's units, readable (to_xarray() carries the CF form W sr-1 m-2 nm-1)")
        .def_property_readonly("width", [](const Render& r) { return r.captured.outputs.width; }, "columns, pixels")
        .def_property_readonly("height", [](const Render& r) { return r.captured.outputs.height; }, "rows, pixels")
        .def_property_readonly(
            "xyz",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.xyz, {c.height, c.width, 3}, self);
            },
            "rows × columns × 3 float32: XYZ as the detector sees the scene (xyz_units)")
        .def_property_readonly("xyz_units", [](const Render& r) { return r.result.xyzUnits; },
                               "what xyz holds: relative (white Y = 100) or absolute (cd/m²)")
        .def_property_readonly(
            "responses",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.responses, {c.height, c.width, py::ssize_t(c.responseChannels)}, self);
            },
            "rows × columns × channels float32: the detector's raw responses")
        .def_property_readonly("response_channels",
                               [](const Render& r) -> py::object {
                                   if (!r.responseChannels) return py::none();
                                   return py::cast(*r.responseChannels);
                               }, "the detector's channel names (e.g. X, Y, Z or R, G, B); None without a display path")
        .def_property_readonly("response_units",
                               [](const Render& r) -> py::object {
                                   if (!r.responseUnits) return py::none();
                                   return py::cast(*r.responseUnits);
                               }, "the units of responses, as the detector declares them")
        .def_property_readonly(
            "display",
            [](py::object self) -> py::object {
                const Render& r = self.cast<const Render&>();
                const CapturedOutputs& c = r.captured.outputs;
                if (c.counts.empty()) return py::none();
                if (r.bits == 16) return view(c.counts, {c.height, c.width, 3}, self);
                const std::vector<py::ssize_t> shape{c.height, c.width, 3};
                py::array a(py::dtype::of<uint8_t>(), shape, cStrides<uint8_t>(shape));  // 8-bit counts: a copy
                auto* out = static_cast<uint8_t*>(a.mutable_data());
                for (size_t i = 0; i < c.counts.size(); ++i) out[i] = uint8_t(c.counts[i]);
                return a;
            },
            "rows × columns × 3 display counts (uint8 or uint16 by bits), what the PNG holds")
        .def_property_readonly("display_description", [](const Render& r) { return r.result.displayDescription; },
                               "the display path: detector, adaptation, display model and bits")
        .def_property_readonly(
            "edges",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.edges, {c.height, c.width}, self);
            },
            "rows × columns uint16, 255 where a pixel's 3×3 neighbourhood sees more than one surface (cpu)")
        .def_property_readonly("clipped_pixels", [](const Render& r) { return r.result.clippedPixels; },
                               "pixels whose display counts clipped at 0 or full scale")
        .def_property_readonly("camera_fit_rms_delta_e2000",
                               [](const Render& r) { return r.result.cameraFitRmsDeltaE; },
                               "a camera detector's colour-correction fit, RMS ΔE2000 over its training set; None otherwise")
        .def_property_readonly("backend", [](const Render& r) { return r.result.backendDescription; },
                               "the device and the render plan (layers, passes, readback)")
        .def_property_readonly("notes", [](const Render& r) { return r.result.notes; },
                               "what the render told the user, one line each")
        .def_property_readonly("validation_errors", [](const Render& r) { return r.result.validationErrors; },
                               "Vulkan validation messages of error severity (with validation=True)")
        .def_property_readonly("timings_ms",
                               [](const Render& r) {
                                   py::dict d;
                                   for (const auto& [stage, ms] : r.result.timings.stages()) d[stage] = ms;
                                   return d;
                               }, "milliseconds per stage: load, upload, shading, readback, tonemap, write, total")
        .def(
            "save",
            [](const Render& r, const py::object& dir) {
                const fs::path out = pathOf(dir, "dir");
                if (r.unpickled)
                    failInput(Where{"", "dir"}, "this Render was unpickled: it holds the arrays and the report, not the "
                                                "scene its files' provenance and display path come from; save() it in "
                                                "the process that rendered it");
                std::vector<WrittenFile> written;
                {
                    py::gil_scoped_release release;
                    written = saveCapturedRender(r.captured, out);
                }
                std::vector<std::string> paths;
                for (const auto& w : written) paths.push_back(w.path.string());
                return paths;
            },
            py::arg("dir"), "Writes the files `metamer render --write ...` writes into dir; returns their paths")
        .def(py::pickle(&renderState, &renderFromState))
        .def("__repr__", [](const Render& r) {
            const CapturedOutputs& c = r.captured.outputs;
            return fmt::format("<metamer.Render {}×{} px, grid {}, {}>", c.width, c.height, r.captured.grid.str(),
                               r.result.backendDescription);
        });

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
    m.def("compare", &compare, py::arg("a"), py::arg("b"), py::kw_only(), py::arg("mask") = py::none(),
          py::arg("tolerance") = py::none(), py::arg("resample") = false, py::arg("detector") = "",
          py::arg("adapt") = "", py::arg("display") = "", py::arg("pixel_threshold") = py::none(),
          py::arg("relative_floor") = py::none(), py::arg("delta_e") = true,
          "Compares A against the reference B (paths, or Renders' cubes) as `metamer compare` does; the "
          "statistics as a dict (with \"passed\" and \"failures\" when a tolerance file is given)");
    m.def("load_cube", &loadCube, py::arg("path"),
          "Reads a spectral cube (OpenEXR, HDF5 or ENVI): a dict with cube (rows × columns × bands float32), "
          "wavelengths_nm, grid, quantity and units");

    m.def("capture", &capture, py::arg("source"), py::arg("sensor"), py::kw_only(), py::arg("seed") = 0,
          py::arg("frame") = 0, py::arg("frames") = 1, py::arg("exposure") = py::none(), py::arg("noise") = true,
          "What a simulated sensor records from a Render's cube or a cube file (docs/sensor.md): a dict with raw "
          "(rows × columns uint16 digital numbers; frames × rows × columns when frames > 1), electrons (the "
          "expected electrons, float64), channels, cfa, black and white levels, conversion gain, exposure");
    m.def("_context_count", [] { return contexts().size(); }, "Vulkan contexts made so far (tests)");
    m.def("_spectra_root", [] { return SpectrumLibrary::defaultRoot().string(); },
          "The spectra library a render reads when METAMER_SPECTRA is not set: the package's own copy "
          "when installed (tests)");
    // What keeps this machine from rendering ("" when a usable Vulkan device exists), for the
    // package's check at import (engine/python/metamer/__init__.py): no driver, or no device.
    m.def("_vulkan_problem", []() -> std::string {
        py::gil_scoped_release release;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_1;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        VkInstance instance = VK_NULL_HANDLE;
        if (VkResult r = vkCreateInstance(&ici, nullptr, &instance); r != VK_SUCCESS)
            return fmt::format("the Vulkan loader found no driver (vkCreateInstance returned {})", vk::resultName(r));
        const auto devices = vk::Context::listDevices(instance);
        vkDestroyInstance(instance, nullptr);
        if (devices.empty()) return "the Vulkan loader found no device";
        for (const auto& d : devices)
            if (d.score > 0) return "";
        return fmt::format("no Vulkan device is usable ({} found; `metamer devices` lists them)", devices.size());
    });

    // The Kubelka–Munk functions the paints use (spectral/kubelka_munk.h; docs/physics.md, "Paints
    // and coatings"), element-wise over numpy arrays: to turn measured reflectances into K/S and
    // back, and to check a paint before rendering it.
    py::module_ km = m.def_submodule("kubelka_munk", "Kubelka–Munk films and Saunderson's correction, per wavelength "
                                                     "(docs/physics.md, \"Paints and coatings\")");
    km.def("reflectance", py::vectorize([](double K, double S, double X, double substrate) {
               return kubelkaMunkOverSubstrate(K, S, X, substrate);
           }),
           py::arg("K"), py::arg("S"), py::arg("X"), py::arg("substrate") = 0.0,
           "R of a film (K, S per unit length; thickness X, inf for an opaque film) over a substrate");
    km.def("transmittance", py::vectorize([](double K, double S, double X) { return kubelkaMunkLayer(K, S, X).transmittance; }),
           py::arg("K"), py::arg("S"), py::arg("X"), "T of a film for diffuse light");
    km.def("infinite", py::vectorize([](double K, double S) { return kubelkaMunkInfinite(K, S); }), py::arg("K"),
           py::arg("S"), "R∞ = a − b of an opaque film");
    km.def("k_over_s", py::vectorize([](double r) { return kOverSFromInfinite(r); }), py::arg("r_infinite"),
           "K/S from R∞: (1 − R∞)²/(2R∞)");
    km.def("saunderson", py::vectorize([](double R, double k1, double k2) { return saundersonMeasured(R, k1, k2); }),
           py::arg("R"), py::arg("k1"), py::arg("k2"),
           "the reflectance measured with the specular component included: k1 + (1 − k1)(1 − k2)R/(1 − k2R)");
    km.def("saunderson_body", py::vectorize([](double R, double k1, double k2) { return saundersonBody(R, k1, k2); }),
           py::arg("R"), py::arg("k1"), py::arg("k2"), "the body part (what Metamer draws as ρd): the above less k1");
    km.def("saunderson_inverse",
           py::vectorize([](double measured, double k1, double k2) { return saundersonInverse(measured, k1, k2); }),
           py::arg("measured"), py::arg("k1"), py::arg("k2"),
           "the film's R from a measured reflectance (specular included)");
    km.def("k1", py::vectorize([](double n) { return saundersonK1(n); }), py::arg("n"), "((n − 1)/(n + 1))²");
    km.def("k2", py::vectorize([](double n) { return internalDiffuseReflectance(n); }), py::arg("n"),
           "the internal diffuse reflectance of a surface of index n (Fresnel integrated over the hemisphere)");

    py::module_::import("os").attr("register_at_fork")(py::arg("after_in_child") = py::cpp_function(&forgetAtFork));

    // The contexts go before the interpreter does: destroying a Vulkan device from a static
    // destructor after Python has finalized would race the driver's threads.
    py::module_::import("atexit").attr("register")(py::cpp_function([] {
        contexts().clear();
        setWarningSink(nullptr);  // stderr again once the interpreter goes
    }));
}
