#include "python/render_class.h"

#include "core/error.h"
#include "python/arguments.h"
#include "python/bindings.h"
#include "python/numpy_views.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <cstring>
#include <map>
#include <memory>

namespace metamer::python {

namespace fs = std::filesystem;

namespace {

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

constexpr int kPickleVersion = 2;  // 2: the ground truth

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
    d["reflectance"] = rawBytes(c.reflectance);
    d["illumination"] = rawBytes(c.illumination);
    d["truth_bands"] = c.truthBands;
    d["object_ids"] = rawBytes(c.geometry.object);
    d["material_ids"] = rawBytes(c.geometry.material);
    d["depth"] = rawBytes(c.geometry.depth_m);
    d["normal"] = rawBytes(c.geometry.normal);
    d["truth_mask"] = rawBytes(c.geometry.mask);
    d["ids_legend"] = c.legend;
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
    c.reflectance = fromRawBytes<float>(d["reflectance"], "reflectance");
    c.illumination = fromRawBytes<float>(d["illumination"], "illumination");
    c.truthBands = d["truth_bands"].cast<size_t>();
    GeometryMaps& g = c.geometry;
    g.width = c.width;
    g.height = c.height;
    g.object = fromRawBytes<int32_t>(d["object_ids"], "object_ids");
    g.material = fromRawBytes<int32_t>(d["material_ids"], "material_ids");
    g.depth_m = fromRawBytes<float>(d["depth"], "depth");
    g.normal = fromRawBytes<float>(d["normal"], "normal");
    g.mask = fromRawBytes<uint8_t>(d["truth_mask"], "truth_mask");
    c.legend = d["ids_legend"].cast<std::string>();
    // A state is input: its sizes within what a render can make (camera.width and height 1..16384)
    // before anything is multiplied by them, and every array exactly that size or absent (issue 51,
    // class 9: a forged negative size passed, its arrays read out of bounds later).
    constexpr int kMaxSide = 16384;
    if (c.width < 1 || c.width > kMaxSide || c.height < 1 || c.height > kMaxSide)
        failInput(Where{"", "pickle"}, "a metamer.Render of {}×{} pixels; a render is 1 … {} pixels on a side", c.width,
                  c.height, kMaxSide);
    if (c.cubeChannels < 1 || c.cubeChannels > 100000)
        failInput(Where{"", "pickle"}, "a metamer.Render of {} cube channels", c.cubeChannels);
    const size_t pixels = size_t(c.width) * size_t(c.height);
    auto sized = [&](size_t n, size_t per) { return n == 0 || n == pixels * per; };
    if (c.cube.size() != pixels * c.cubeChannels || !sized(c.xyz.size(), 3) || !sized(c.counts.size(), 3) ||
        !sized(c.edges.size(), 1) || c.responseChannels > 100000 || !sized(c.responses.size(), c.responseChannels) ||
        c.truthBands > 100000 || !sized(c.reflectance.size(), c.truthBands) || !sized(c.illumination.size(), c.truthBands) ||
        !sized(g.object.size(), 1) || !sized(g.material.size(), 1) || !sized(g.depth_m.size(), 1) ||
        !sized(g.normal.size(), 3) || !sized(g.mask.size(), 1))
        failInput(Where{"", "pickle"}, "a metamer.Render whose arrays do not match its {}×{} size", c.width, c.height);
    r->captured.grid = Grid::parse(d["grid"].cast<std::string>(), Where{"", "pickle"});
    r->spectral = d["spectral"].cast<bool>();
    r->channelNames = d["channel_names"].cast<std::vector<std::string>>();
    r->bits = d["bits"].cast<int>();
    if (r->bits != 8 && r->bits != 16) failInput(Where{"", "pickle"}, "a metamer.Render of {} display bits", r->bits);
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
                                                {"tonemap", &times.tonemap_ms}, {"ground_truth", &times.ground_truth_ms},
                                                {"write", &times.write_ms},
                                                {"total", &times.total_ms}};
    for (auto [stage, ms] : d["timings_ms"].cast<py::dict>())
        if (auto it = stages.find(stage.cast<std::string>()); it != stages.end()) *it->second = ms.cast<double>();
    r->unpickled = true;
    return r;
}

}  // namespace

void bindRenderClass(py::module_& m) {
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
        // The ground truth (write=["reflectance", "illumination", "ids", "depth", "normal"]; docs/io.md).
        .def_property_readonly(
            "reflectance",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.reflectance, {c.height, c.width, py::ssize_t(c.truthBands)}, self);
            },
            "rows × columns × bands float32: the diffuse reflectance factor of the surface seen (relative)")
        .def_property_readonly(
            "illumination",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.illumination, {c.height, c.width, py::ssize_t(c.truthBands)}, self);
            },
            "rows × columns × bands float32: irradiance/π at the surface seen, W·sr⁻¹·m⁻²·nm⁻¹")
        .def_property_readonly(
            "object_ids",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.geometry.object, {c.height, c.width}, self);
            },
            "rows × columns int32: the object (mesh) seen at each pixel's central sample, −1 background (ids_legend)")
        .def_property_readonly(
            "material_ids",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.geometry.material, {c.height, c.width}, self);
            },
            "rows × columns int32: its material, −1 background (ids_legend)")
        .def_property_readonly(
            "ids_legend",
            [](const Render& r) -> py::object {
                const std::string& legend = r.captured.outputs.legend;
                if (legend.empty()) return py::none();
                return py::module_::import("json").attr("loads")(legend);
            },
            "the names behind object_ids and material_ids: {objects: [{id, name, material}], materials: [{id, name}]}")
        .def_property_readonly(
            "depth",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.geometry.depth_m, {c.height, c.width}, self);
            },
            "rows × columns float32: metres from the camera along the ray, 0 at the background")
        .def_property_readonly(
            "normal",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.geometry.normal, {c.height, c.width, 3}, self);
            },
            "rows × columns × 3 float32: the shading normal in the camera frame (x right, y up, z to the camera)")
        .def_property_readonly(
            "truth_mask",
            [](py::object self) -> py::object {
                const CapturedOutputs& c = self.cast<const Render&>().captured.outputs;
                return view(c.geometry.mask, {c.height, c.width}, self);
            },
            "rows × columns uint8: why radiance ≠ reflectance × illumination (1 background, 2 fluorescent, 4 specular, "
            "8 transparent in front, 16 self-luminous, 32 edge); 0 where it is equal")
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
                               }, "milliseconds per stage: load, upload, shading, readback, tonemap, ground_truth, "
                                  "write, total")
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
}

}  // namespace metamer::python
