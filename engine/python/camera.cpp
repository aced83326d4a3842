// metamer.demosaic, metamer.fit_colour_correction, metamer.develop and metamer.slanted_edge_sfr: the
// image processor (isp/) and the slanted-edge SFR (sensor/slanted_edge.h) on numpy arrays;
// metamer/_api.py converts its arguments to C-ordered arrays of the right type first.
// Tests: tests/python/test_isp.py.
#include "core/error.h"
#include "color/delta_e.h"
#include "color/detector_registry.h"
#include "isp/camera_metrics.h"
#include "isp/colour_correction.h"
#include "isp/demosaic.h"
#include "isp/image_processor.h"
#include "python/arguments.h"
#include "python/bindings.h"
#include "python/numpy_views.h"
#include "sensor/sensor_colour.h"
#include "sensor/sensor_spec.h"
#include "sensor/slanted_edge.h"
#include "spectral/resampling.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace metamer::python {

namespace {

// A C-ordered float64 rows × columns array as a vector (the wrapper made it so).
std::vector<double> plane(const py::buffer& b, const char* name, int& width, int& height) {
    const py::buffer_info info = b.request();
    if (info.ndim != 2 || info.format != py::format_descriptor<double>::format() ||
        info.strides[1] != py::ssize_t(sizeof(double)) || info.strides[0] != info.shape[1] * py::ssize_t(sizeof(double)))
        failInput(Where{"", name}, "expected a C-ordered float64 array of rows × columns");
    height = int(info.shape[0]);
    width = int(info.shape[1]);
    const double* p = static_cast<const double*>(info.ptr);
    return std::vector<double>(p, p + size_t(width) * size_t(height));
}

py::array demosaicArray(const py::buffer& mosaic, const std::string& cfa, const std::string& method) {
    int w = 0, h = 0;
    const std::vector<double> m = plane(mosaic, "mosaic", w, h);
    const std::array<int, 4> pattern = bayerPattern(cfa, Where{"", "cfa"});
    const DemosaicMethod how = parseDemosaicMethod(method, Where{"", "method"});
    std::vector<double> rgb;
    {
        py::gil_scoped_release release;
        rgb = demosaic(m, w, h, pattern, how);
    }
    const std::vector<py::ssize_t> shape{h, w, 3};
    py::array a(py::dtype::of<double>(), shape, cStrides<double>(shape));
    std::copy(rgb.begin(), rgb.end(), static_cast<double*>(a.mutable_data()));
    return a;
}

py::dict sfr(const py::buffer& image) {
    int w = 0, h = 0;
    const std::vector<double> v = plane(image, "image", w, h);
    const EdgeSfr s = slantedEdgeSfr(v, w, h, Where{"", "image"});
    py::dict d;
    d["frequency"] = doubles(s.frequency);
    d["mtf"] = doubles(s.mtf);
    d["mtf50"] = s.mtf50;
    d["angle_deg"] = s.angle_deg;
    return d;
}

// Rows of three: a C-ordered float64 N × 3 array as N vectors.
std::vector<glm::dvec3> triples(const py::buffer& b, const char* name) {
    int w = 0, h = 0;
    const std::vector<double> v = plane(b, name, w, h);
    if (w != 3) failInput(Where{"", name}, "expected N × 3 values (a row per patch); got {} columns", w);
    std::vector<glm::dvec3> out;
    for (int i = 0; i < h; ++i) out.push_back(glm::dvec3(v[size_t(i) * 3], v[size_t(i) * 3 + 1], v[size_t(i) * 3 + 2]));
    return out;
}

py::array fitCorrection(const py::buffer& rgb, const py::buffer& xyz, const std::string& form) {
    const ColourCorrection c = fitColourCorrection(parseCorrectionForm(form, Where{"", "form"}), triples(rgb, "rgb"),
                                                   triples(xyz, "xyz"), Where{"", "rgb"});
    const std::vector<py::ssize_t> shape{3, py::ssize_t(c.columns.size())};
    py::array a(py::dtype::of<double>(), shape, cStrides<double>(shape));
    double* out = static_cast<double*>(a.mutable_data());
    for (size_t t = 0; t < c.columns.size(); ++t)
        for (int r = 0; r < 3; ++r) out[size_t(r) * c.columns.size() + t] = c.columns[t][r];
    return a;
}

// metamer.develop: a raw frame (rows × columns uint16, as metamer.capture returns) developed by the
// sensor's processor (isp/image_processor.h), with any of its settings given here instead.
py::dict developRaw(const py::buffer& rawArg, const py::object& sensorName, const py::object& whiteBalance,
                    const py::object& patch, const py::object& illuminant, const py::object& demosaicName,
                    const py::object& correction, const py::object& exposure, const py::object& displayName,
                    const py::object& bits) {
    const py::buffer_info info = rawArg.request();
    if (info.ndim != 2 || info.format != py::format_descriptor<uint16_t>::format() ||
        info.strides[1] != py::ssize_t(sizeof(uint16_t)) || info.strides[0] != info.shape[1] * py::ssize_t(sizeof(uint16_t)))
        failInput(Where{"", "raw"}, "expected one frame: a C-ordered uint16 array of rows × columns (metamer.capture's raw)");
    const SpectrumLibrary library;
    SensorSpec sensor = readSensor(sensorFile(pathOf(sensorName, "sensor").string(), library), library);
    ProcessorSpec& p = sensor.processor;
    if (!whiteBalance.is_none()) p.whiteBalance = parseWhiteBalance(text(whiteBalance, "white_balance"), Where{"", "white_balance"});
    if (!patch.is_none()) {
        const std::vector<double> r = patch.cast<std::vector<double>>();
        if (r.size() != 4) failInput(Where{"", "patch"}, "expected [x, y, width, height] in pixels; got {} numbers", r.size());
        for (size_t i = 0; i < 4; ++i) p.patch[i] = patchCoordinate(r[i], Where{"", "patch"});
    }
    if (p.whiteBalance == WhiteBalance::Patch && p.patch[2] == 0)
        failInput(Where{"", "patch"}, "the patch white balance needs patch=[x, y, width, height], a neutral area of the frame");
    if (!illuminant.is_none()) {
        p.illuminant = text(illuminant, "illuminant");
        library.get(p.illuminant, Where{"", "illuminant"});
    }
    if (!demosaicName.is_none()) p.demosaic = parseDemosaicMethod(text(demosaicName, "demosaic"), Where{"", "demosaic"});
    if (!correction.is_none())
        p.correction = parseCorrectionForm(text(correction, "colour_correction"), Where{"", "colour_correction"});
    if (!bits.is_none()) p.bits = displayBits(integer(bits, "bits", 8, 16), Where{"", "bits"});
    if (!displayName.is_none()) {
        p.display = text(displayName, "display");
        parseDisplay(p.display, p.bits, Where{"", "display"});  // named here, not at the fit
    }
    if (const std::optional<double> e = optionalNumber(exposure, "exposure")) {
        if (!(*e >= kMinProcessorExposure && *e <= kMaxProcessorExposure))
            failInput(Where{"", "exposure"}, "expected a gain of 10⁻⁴ … 10⁴, got {:g}", *e);
        p.exposure = *e;
    }
    const std::optional<SensorColour> colour = sensorColour(sensor, library);
    if (!colour)
        failInput(Where{"", "sensor"}, "{} is not an RGB Bayer sensor (its CFA is {}): only those are developed",
                  sensor.file.string(), sensor.cfaName);
    RawFrame f{int(info.shape[1]), int(info.shape[0]), static_cast<const uint16_t*>(info.ptr), sensor.blackLevel_dn,
               double(sensor.whiteLevel()), {}};
    for (size_t i = 0; i < 4; ++i) f.cfa[i] = colour->cfa[i];
    if (!developable(f.width, f.height))
        failInput(Where{"", "raw"}, "a {}×{} frame cannot be developed: demosaicing needs at least 2 × 2 pixels", f.width,
                  f.height);
    DevelopedImage d;
    {
        py::gil_scoped_release release;
        d = develop(f, p, colour->processor, Where{});
    }
    const std::vector<py::ssize_t> shape{py::ssize_t(f.height), py::ssize_t(f.width), 3};
    auto doublesOf = [&](const std::vector<double>& v) {
        py::array a(py::dtype::of<double>(), shape, cStrides<double>(shape));
        std::copy(v.begin(), v.end(), static_cast<double*>(a.mutable_data()));
        return a;
    };
    const DisplayModel& display = colour->processor.display;
    const std::vector<uint16_t> counts = encodeCounts(d, display);
    py::array encoded = display.bits == 8 ? py::array(py::dtype::of<uint8_t>(), shape, cStrides<uint8_t>(shape))
                                          : py::array(py::dtype::of<uint16_t>(), shape, cStrides<uint16_t>(shape));
    if (display.bits == 8)
        std::copy(counts.begin(), counts.end(), static_cast<uint8_t*>(encoded.mutable_data()));
    else
        std::copy(counts.begin(), counts.end(), static_cast<uint16_t*>(encoded.mutable_data()));
    const ProcessorColour& c = colour->processor;
    const std::vector<py::ssize_t> three{3, 3}, terms{3, py::ssize_t(c.toXyz.columns.size())};
    py::array matrix(py::dtype::of<double>(), three, cStrides<double>(three));
    std::copy(c.dngColorMatrix.begin(), c.dngColorMatrix.end(), static_cast<double*>(matrix.mutable_data()));
    py::array columns(py::dtype::of<double>(), terms, cStrides<double>(terms));
    for (size_t t = 0; t < c.toXyz.columns.size(); ++t)
        for (int r = 0; r < 3; ++r) static_cast<double*>(columns.mutable_data())[size_t(r) * c.toXyz.columns.size() + t] = c.toXyz.columns[t][r];
    py::dict out;
    out["xyz"] = doublesOf(d.xyz);
    out["linear_rgb"] = doublesOf(d.linearRgb);
    out["counts"] = encoded;
    out["display"] = display.name;
    out["neutral"] = std::vector<double>{d.neutral.x, d.neutral.y, d.neutral.z};
    out["gains"] = std::vector<double>{d.gains.x, d.gains.y, d.gains.z};
    out["illuminant_neutral"] = std::vector<double>{c.illuminantNeutral.x, c.illuminantNeutral.y, c.illuminantNeutral.z};
    out["dng_color_matrix"] = matrix;
    out["correction"] = columns;
    out["colorchecker_delta_e2000"] = c.patchDeltaE2000;
    out["illuminant"] = p.illuminant;
    out["white_balance"] = whiteBalanceName(p.whiteBalance);
    return out;
}

// CIE 1931 XYZ (Y = 100) of a library illuminant's perfect white, or three numbers as given.
glm::dvec3 whiteOf(const py::object& white) {
    if (py::isinstance<py::str>(white)) {
        const SpectrumLibrary library;
        const std::string name = white.cast<std::string>();
        const Grid grid{360, 830, 1};
        const std::vector<double> e = resample(library.get(name, Where{"", "white"}), grid);
        const Detector cmf = makeDetector("cie1931", library, grid, Integration::Riemann, Where{"", "white"});
        const glm::dvec3 xyz = detectorResponse3(cmf, e.data());
        if (!(xyz.y > 0.0)) failInput(Where{"", "white"}, "'{}' has no luminance", name);
        return 100.0 * xyz / xyz.y;
    }
    const std::vector<double> v = white.cast<std::vector<double>>();
    if (v.size() != 3) failInput(Where{"", "white"}, "expected the white's X, Y, Z or a library illuminant; got {} numbers", v.size());
    return {v[0], v[1], v[2]};
}

py::dict developedError(const py::buffer& developed, const py::buffer& reference, const py::object& white,
                        const std::string& adaptation, int exposureFrom) {
    if (exposureFrom < 0) failInput(Where{"", "exposure_from"}, "expected a colour's index, ≥ 0; got {}", exposureFrom);
    const DevelopedColourError e =
        developedColourError(triples(developed, "developed"), triples(reference, "reference"), whiteOf(white),
                             parseAdaptation(adaptation, Where{"", "adaptation"}), size_t(exposureFrom), Where{"", "developed"});
    auto rows = [](const std::vector<glm::dvec3>& v) {
        const std::vector<py::ssize_t> shape{py::ssize_t(v.size()), 3};
        py::array a(py::dtype::of<double>(), shape, cStrides<double>(shape));
        double* out = static_cast<double*>(a.mutable_data());
        for (const glm::dvec3& x : v) *out++ = x.x, *out++ = x.y, *out++ = x.z;
        return a;
    };
    py::dict d;
    d["delta_e2000"] = doubles(e.deltaE2000);
    d["developed_lab"] = rows(e.developedLab);
    d["reference_lab"] = rows(e.referenceLab);
    d["exposure_scale"] = e.exposureScale;
    return d;
}

py::dict photonTransferOf(const py::buffer& a, const py::buffer& b, const py::object& sensorName,
                          const std::vector<int>& rect, const std::string& channel) {
    const py::buffer_info ia = a.request(), ib = b.request();
    for (const auto* info : {&ia, &ib})
        if (info->ndim != 2 || info->format != py::format_descriptor<uint16_t>::format() ||
            info->strides[1] != py::ssize_t(sizeof(uint16_t)) || info->strides[0] != info->shape[1] * py::ssize_t(sizeof(uint16_t)))
            failInput(Where{"", info == &ia ? "a" : "b"}, "expected a frame: a C-ordered uint16 array of rows × columns");
    if (ia.shape != ib.shape) failInput(Where{"", "b"}, "the two frames differ in size");
    if (rect.size() != 4) failInput(Where{"", "rect"}, "expected [x, y, width, height]; got {} numbers", rect.size());
    const SpectrumLibrary library;
    const SensorSpec sensor = readSensor(sensorFile(pathOf(sensorName, "sensor").string(), library), library);
    const auto it = std::find(sensor.channels.begin(), sensor.channels.end(), channel);
    if (it == sensor.channels.end())
        failInput(Where{"", "channel"}, "'{}' is not a channel of {} (its channels are {})", channel, sensor.file.string(),
                  fmt::format("{}", fmt::join(sensor.channels, ", ")));
    const PhotonTransferPoint p = photonTransfer(
        static_cast<const uint16_t*>(ia.ptr), static_cast<const uint16_t*>(ib.ptr), int(ia.shape[1]), int(ia.shape[0]),
        PixelRect{rect[0], rect[1], rect[2], rect[3]}, int(it - sensor.channels.begin()),
        [&](int x, int y) { return sensor.channelAt(x, y); }, sensor.blackLevel_dn, Where{"", "rect"});
    py::dict d;
    d["mean_dn"] = p.mean_dn;
    d["variance_dn2"] = p.variance_dn2;
    d["snr"] = p.snr;
    d["pixels"] = p.sites;
    return d;
}

py::array deltaE2000Rows(const py::buffer& a, const py::buffer& b) {
    const std::vector<glm::dvec3> x = triples(a, "lab_a"), y = triples(b, "lab_b");
    if (x.size() != y.size()) failInput(Where{"", "lab_b"}, "expected as many colours as lab_a ({}); got {}", x.size(), y.size());
    std::vector<double> d;
    for (size_t i = 0; i < x.size(); ++i) d.push_back(deltaE2000(x[i], y[i]));
    return doubles(d);
}

}  // namespace

void bindCamera(py::module_& m) {
    m.def("delta_e2000", &deltaE2000Rows, py::arg("lab_a"), py::arg("lab_b"),
          "CIEDE2000 colour differences between two N × 3 arrays of CIELAB colours (the engine's color/delta_e)");
    m.def("developed_colour_error", &developedError, py::arg("developed"), py::arg("reference"), py::arg("white"),
          py::arg("adaptation"), py::arg("exposure_from"),
          "ΔE00 of developed colours (N × 3 linear sRGB) against the scene's (N × 3 CIE 1931 XYZ whose perfect white "
          "under the light is `white`: X, Y, Z or a library illuminant at Y = 100), the scene's adapted to D65; the "
          "developed exposure scaled so colour `exposure_from` has the reference's Y. Returns delta_e2000, "
          "developed_lab, reference_lab (CIELAB of D65) and exposure_scale");
    m.def("photon_transfer", &photonTransferOf, py::arg("a"), py::arg("b"), py::arg("sensor"), py::arg("rect"),
          py::arg("channel"),
          "EMVA 1288's photon transfer from two raw frames of one exposure, over the pixels of channel `channel` in "
          "rect = [x, y, width, height]: mean_dn (above black), variance_dn2 (temporal: var(a − b)/2), snr, pixels");
    m.def("develop", &developRaw, py::arg("raw"), py::arg("sensor"), py::kw_only(), py::arg("white_balance") = py::none(),
          py::arg("patch") = py::none(), py::arg("illuminant") = py::none(), py::arg("demosaic") = py::none(),
          py::arg("colour_correction") = py::none(), py::arg("exposure") = py::none(), py::arg("display") = py::none(),
          py::arg("bits") = py::none(),
          "A raw frame of an RGB Bayer sensor developed by its image processor (docs/camera.md): black and white "
          "levels, white balance (illuminant, grey-world or patch), demosaicing, the colour correction fitted on the "
          "ColorChecker under the illuminant, XYZ adapted to D65 → sRGB. Keywords override the sensor file's "
          "\"processor\". Returns xyz (rows × columns × 3, float64, adapted to the display's white), linear_rgb (the "
          "display's linear RGB), counts (uint8 or uint16, encoded for the display), display, neutral, gains, "
          "illuminant_neutral, dng_color_matrix (XYZ → camera), correction (3 × terms) and the fit's "
          "colorchecker_delta_e2000 per patch");
    m.def("fit_colour_correction", &fitCorrection, py::arg("rgb"), py::arg("xyz"), py::arg("form"),
          "The least-squares colour correction from white-balanced camera RGB (N × 3) to XYZ (N × 3): a 3 × 3 "
          "matrix (form 'linear') or Finlayson's root-polynomial of degree 2, 3 × 6 over the terms r, g, b, "
          "√(rg), √(gb), √(rb) ('root-polynomial'); XYZ = M · terms");
    m.def("demosaic", &demosaicArray, py::arg("mosaic"), py::arg("cfa"), py::arg("method"),
          "A Bayer mosaic (rows × columns, float64) to rows × columns × 3 (R, G, B): bilinear, or Malvar, He and "
          "Cutler's gradient-corrected interpolation (malvar2004); borders mirrored as scipy's 'reflect'");
    m.def("slanted_edge_sfr", &sfr, py::arg("image"),
          "ISO 12233's slanted-edge SFR of a region holding one near-vertical edge: frequency (cycles per pixel "
          "along the edge's normal, 0 … 1), mtf, mtf50 and the edge's angle_deg from the vertical");
}

}  // namespace metamer::python
