// metamer.compare and metamer.load_cube: `metamer compare` on paths, Renders' cubes or arrays with
// their grid (compare/compare.h, compare/tolerance.h), its statistics as a dict; a spectral cube
// from OpenEXR, HDF5 or ENVI (io/spectral_image.h) as numpy arrays that own it without a copy.
// Tests: tests/python/test_module.py (statistics, tolerance files, damaged and special files,
// HDF5 and ENVI read by h5py and Spectral Python).
#include "compare/compare.h"
#include "compare/tolerance.h"
#include "core/error.h"
#include "core/json.h"
#include "io/spectral_image.h"
#include "python/arguments.h"
#include "python/bindings.h"
#include "python/errors.h"
#include "python/numpy_views.h"
#include "python/render_class.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <memory>
#include <optional>

namespace metamer::python {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

void bindCompare(py::module_& m) {
    m.def("compare", &compare, py::arg("a"), py::arg("b"), py::kw_only(), py::arg("mask") = py::none(),
          py::arg("tolerance") = py::none(), py::arg("resample") = false, py::arg("detector") = "",
          py::arg("adapt") = "", py::arg("display") = "", py::arg("pixel_threshold") = py::none(),
          py::arg("relative_floor") = py::none(), py::arg("delta_e") = true,
          "Compares A against the reference B (paths, or Renders' cubes) as `metamer compare` does; the "
          "statistics as a dict (with \"passed\" and \"failures\" when a tolerance file is given)");
    m.def("load_cube", &loadCube, py::arg("path"),
          "Reads a spectral cube (OpenEXR, HDF5 or ENVI): a dict with cube (rows × columns × bands float32), "
          "wavelengths_nm, grid, quantity and units");
}

}  // namespace metamer::python
