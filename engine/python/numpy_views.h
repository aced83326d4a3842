// numpy arrays of the engine's results: read-only views of a render's or a cube's own memory (no
// copy of a cube that may be GiBs) and float64 copies of short vectors (wavelengths). Used by the
// Render class (python/render_class) and load_cube (python/compare).
// Tests: tests/python/test_module.py (views, strides, memory, load_cube).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <vector>

namespace metamer::python {

namespace py = pybind11;

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
inline py::array doubles(const std::vector<double>& v) {
    const std::vector<py::ssize_t> shape{py::ssize_t(v.size())};
    py::array a(py::dtype::of<double>(), shape, cStrides<double>(shape));
    std::copy(v.begin(), v.end(), static_cast<double*>(a.mutable_data()));
    return a;
}

}  // namespace metamer::python
