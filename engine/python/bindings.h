// The Python module's areas, each registering its part of metamer._metamer (python/module.cpp
// calls them in this order: a type is registered before the functions that return it, so their
// docstrings name it). One file each under engine/python/.
// Tests: tests/python/ (test_module.py, test_paints.py, test_sensor.py, test_typing.py).
#pragma once

#include <pybind11/pybind11.h>

namespace metamer::python {

namespace py = pybind11;

void bindErrors(py::module_& m);        // python/errors.cpp: Error, InputError, NotFoundError, Warning
void bindRenderClass(py::module_& m);   // python/render_class.cpp: Render, its arrays, save, pickling
void bindRender(py::module_& m);        // python/render.cpp: render, the Vulkan contexts
void bindCompare(py::module_& m);       // python/compare.cpp: compare, load_cube
void bindCapture(py::module_& m);       // python/capture.cpp: capture
void bindCamera(py::module_& m);        // python/camera.cpp: demosaic, slanted_edge_sfr
void bindKubelkaMunk(py::module_& m);   // python/kubelka_munk.cpp: the kubelka_munk submodule

}  // namespace metamer::python
