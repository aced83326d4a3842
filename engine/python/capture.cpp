// metamer.capture: the simulated sensor of `metamer capture` (sensor/capture.h, docs/sensor.md) on
// a Render's cube or a cube file: the expected electrons and the digitized frames, as numpy arrays
// equal to the CLI's files for the same seed and frame.
// Tests: tests/python/test_sensor.py.
#include "core/error.h"
#include "core/memory_limits.h"
#include "python/arguments.h"
#include "python/bindings.h"
#include "python/errors.h"
#include "python/render_class.h"
#include "sensor/capture.h"
#include "io/atomic_file.h"
#include "sensor/capture_files.h"
#include "spectral/library.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <optional>

namespace metamer::python {

namespace {

// metamer.capture: the simulated sensor (docs/sensor.md) on a Render's cube or a cube file.
py::dict capture(const py::object& source, const py::object& sensorName, const py::object& seedArg,
                 const py::object& frameArg, const py::object& framesArg, const py::object& exposureArg, bool noise,
                 const py::object& outArg, const py::object& illuminantArg) {
    discardPendingWarning();
    const uint64_t seed = unsignedInteger(seedArg, "seed"), frame = unsignedInteger(frameArg, "frame");
    const int frames = int(integer(framesArg, "frames", INT_MIN, INT_MAX));
    const std::optional<double> exposure = optionalNumber(exposureArg, "exposure");
    checkCaptureNumbers(exposure, frame, frames, "");
    const SpectrumLibrary library;
    CaptureRequest request;
    request.sensor = pathOf(sensorName, "sensor").string();
    if (!illuminantArg.is_none()) request.illuminant = text(illuminantArg, "illuminant");
    request.illuminantKey = "illuminant";
    const SensorSpec sensor = readCaptureSensor(request, library);
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
    requireRadiance(cube, py::isinstance<Render>(source) ? Where{"", "source"} : Where{pathOf(source, "source").string()});
    ExpectedElectrons e;
    {
        py::gil_scoped_release release;
        e = expectedElectrons(cube, sensor, exposure, noise);
    }
    raisePendingWarning();
    // The frames go straight into the array returned (each frame made once, not held twice), which
    // must fit the quarter of the machine's memory every decoded image is held to (issue 51,
    // class 9: 100 000 frames of 256² took 4.6 GB before anything was checked).
    const uint64_t bytes = uint64_t(e.width) * uint64_t(e.height) * uint64_t(frames) * sizeof(uint16_t);
    if (bytes > decodedImageLimitBytes())
        failInput(Where{"frames"}, "{} frames of {}×{} would take {}; the limit is {}, a quarter of this machine's memory ({})",
                  frames, e.width, e.height, memorySize(bytes), memorySize(decodedImageLimitBytes()),
                  memorySize(machineMemoryBytes()));
    const py::ssize_t h = e.height, w = e.width;
    py::array_t<uint16_t> raw = frames == 1 ? py::array_t<uint16_t>({h, w}) : py::array_t<uint16_t>({py::ssize_t(frames), h, w});
    uint16_t* out = raw.mutable_data();
    for (int f = 0; f < frames; ++f) {
        // Between frames Python's signal handlers run: Ctrl-C stops a long capture there.
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        py::gil_scoped_release release;
        const std::vector<uint16_t> r = digitize(e, sensor, CaptureNoise{noise, seed, frame + uint64_t(f)});
        out = std::copy(r.begin(), r.end(), out);
    }
    py::array_t<double> electrons({h, w});
    const std::vector<double> recorded = e.recordedMean();
    std::copy(recorded.begin(), recorded.end(), electrons.mutable_data());
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
    if (!outArg.is_none()) {
        // The files `metamer capture` writes — raw PNGs, DNGs, JSON, electrons — byte for byte,
        // into `out`, all put in place together, from the electrons above (the frames are
        // digitized again for them; the camera equation and the lens are not run again).
        request.seed = seed;
        request.frame = frame;
        request.frames = frames;
        request.exposure = exposure;
        request.noise = noise;
        if (py::isinstance<Render>(source)) {
            request.stem = source.cast<const Render&>().captured.stem;
            request.cubeName = request.stem + " (a metamer.Render in memory)";
        } else {
            request.cube = pathOf(source, "source");
        }
        StagingFolder staging(pathOf(outArg, "out"), "capture");
        CaptureFiles files;
        {
            py::gil_scoped_release release;
            files = stageCaptureFiles(e, sensor, request, library, staging);
            commitTogether({}, {&staging});
        }
        py::list written;
        for (const auto& f : files.files) written.append(f.string());
        d["files"] = written;
    }
    return d;
}

}  // namespace

void bindCapture(py::module_& m) {
    m.def("capture", &capture, py::arg("source"), py::arg("sensor"), py::kw_only(), py::arg("seed") = 0,
          py::arg("frame") = 0, py::arg("frames") = 1, py::arg("exposure") = py::none(), py::arg("noise") = true,
          py::arg("out") = py::none(), py::arg("illuminant") = py::none(),
          "What a simulated sensor records from a Render's cube or a cube file (docs/sensor.md): a dict with raw "
          "(rows × columns uint16 digital numbers; frames × rows × columns when frames > 1), electrons (the "
          "mean recorded electrons μe + DSNU offset, float64), channels, cfa, black and white levels, conversion "
          "gain, exposure; with out=FOLDER also the files `metamer capture` writes (raw PNG, DNG, developed sRGB "
          "PNG, JSON per frame, the electrons EXR), listed under files; illuminant: the scene's light for the image "
          "processor and the DNG (a library spectrum), instead of the sensor file's");
}

}  // namespace metamer::python
