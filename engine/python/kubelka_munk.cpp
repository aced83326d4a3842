// metamer.kubelka_munk: the Kubelka–Munk functions the paints use (spectral/kubelka_munk.h;
// docs/physics.md, "Paints and coatings"), element-wise over numpy arrays: to turn measured
// reflectances into K/S and back, and to check a paint before rendering it.
// Tests: tests/python/test_paints.py.
#include "python/bindings.h"
#include "spectral/kubelka_munk.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace metamer::python {

void bindKubelkaMunk(py::module_& m) {
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
}

}  // namespace metamer::python
