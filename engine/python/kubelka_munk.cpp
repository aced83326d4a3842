// metamer._metamer._kubelka_munk: the engine's Kubelka–Munk functions, the ones the paints use
// (spectral/kubelka_munk.h; docs/physics.md, "Paints and coatings"), element-wise over numpy
// arrays, unchecked. metamer.kubelka_munk (python/metamer/kubelka_munk.py) is what users call: it
// types them, checks each argument's type and range against the scene reader's, broadcasts the
// mix's and the stack's arguments into the flat arrays `mix` and `stack` take here.
// Tests: tests/python/test_kubelka_munk.py, tests/python/test_paints.py.
#include "python/bindings.h"
#include "python/numpy_views.h"
#include "spectral/kubelka_munk.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string>
#include <vector>

namespace metamer::python {

namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The flat arrays metamer.kubelka_munk hands over; a mismatch is that module's mistake, not the
// user's, so the message names the shapes.
void requireShape(const Doubles& a, const char* name, std::vector<py::ssize_t> shape) {
    const std::vector<py::ssize_t> given(a.shape(), a.shape() + a.ndim());
    if (given != shape)
        throw py::value_error(fmt::format("{}: an array of shape ({}); expected ({})", name, fmt::join(given, ", "),
                                          fmt::join(shape, ", ")));
}

// The rows of a items × points array (items: pigments or films), the first dimension of `a`.
py::ssize_t rows(const Doubles& a) { return a.ndim() == 2 ? a.shape(0) : -1; }

// K and S at `n` points by the two-constant rule: concentrations, k and s (pigments × n), the
// film's own K and S (n).
py::tuple mix(const Doubles& concentrations, const Doubles& k, const Doubles& s, const Doubles& K0, const Doubles& S0) {
    const py::ssize_t items = rows(concentrations), n = K0.size();
    requireShape(concentrations, "concentrations", {items, n});
    requireShape(k, "k", {items, n});
    requireShape(s, "s", {items, n});
    requireShape(K0, "K", {n});
    requireShape(S0, "S", {n});
    std::vector<double> K(static_cast<size_t>(n)), S(static_cast<size_t>(n));
    std::vector<KubelkaMunkPigment> at(static_cast<size_t>(items));
    for (py::ssize_t j = 0; j < n; ++j) {
        for (py::ssize_t i = 0; i < items; ++i)
            at[size_t(i)] = {concentrations.data()[i * n + j], k.data()[i * n + j], s.data()[i * n + j]};
        const KubelkaMunkCoefficients mixed = kubelkaMunkMix(at, {K0.data()[j], S0.data()[j]});
        K[size_t(j)] = mixed.K;
        S[size_t(j)] = mixed.S;
    }
    return py::make_tuple(doubles(K), doubles(S));
}

// R at `n` points of films (K, S, X: films × n, bottom first) over a substrate (n).
py::array stack(const Doubles& K, const Doubles& S, const Doubles& X, const Doubles& substrate) {
    const py::ssize_t layers = rows(K), n = substrate.size();
    requireShape(K, "K", {layers, n});
    requireShape(S, "S", {layers, n});
    requireShape(X, "X", {layers, n});
    requireShape(substrate, "substrate", {n});
    std::vector<double> R(static_cast<size_t>(n));
    std::vector<KubelkaMunkFilm> films(static_cast<size_t>(layers));
    for (py::ssize_t j = 0; j < n; ++j) {
        for (py::ssize_t l = 0; l < layers; ++l)
            films[size_t(l)] = {K.data()[l * n + j], S.data()[l * n + j], X.data()[l * n + j]};
        R[size_t(j)] = kubelkaMunkStack(films, substrate.data()[j]);
    }
    return doubles(R);
}

}  // namespace

void bindKubelkaMunk(py::module_& m) {
    py::module_ km = m.def_submodule("_kubelka_munk", "The engine's Kubelka–Munk functions, unchecked: call them "
                                                      "through metamer.kubelka_munk");
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
    km.def("external_diffuse_reflectance", py::vectorize([](double n) { return externalDiffuseReflectance(n); }),
           py::arg("n"), "r_e: the diffuse reflectance of a surface of index n for light from the air");
    km.def("mix", &mix, py::arg("concentrations"), py::arg("k"), py::arg("s"), py::arg("K"), py::arg("S"),
           "(K, S) = (K₀ + Σ cᵢkᵢ, S₀ + Σ cᵢsᵢ): concentrations, k and s (pigments × points), K₀ and S₀ "
           "(points)");
    km.def("stack", &stack, py::arg("K"), py::arg("S"), py::arg("X"), py::arg("substrate"),
           "R of films applied bottom-up over a substrate: K, S, X (films × points, bottom first), substrate "
           "(points)");
}

}  // namespace metamer::python
