// metamer.demosaic and metamer.slanted_edge_sfr: the image processor's demosaicing (isp/demosaic.h)
// and the slanted-edge SFR (sensor/slanted_edge.h) on numpy arrays; metamer/_api.py converts its
// arguments to C-ordered float64 first.
// Tests: tests/python/test_isp.py.
#include "core/error.h"
#include "isp/colour_correction.h"
#include "isp/demosaic.h"
#include "python/bindings.h"
#include "python/numpy_views.h"
#include "sensor/slanted_edge.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

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

}  // namespace

void bindCamera(py::module_& m) {
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
