"""metamer.kubelka_munk (engine/python/metamer/kubelka_munk.py over spectral/kubelka_munk.h;
docs/python.md): r_e against Fresnel's equations integrated by scipy, the mix against the
two-constant rule in numpy, the stack against reflectance() applied film by film and against
Kubelka's closed form, both against a paint the engine renders, and the errors a user meets (a
wrong type, a value outside the physical domain, a keyword typo), each naming the argument. Run
by CTest (tests/CMakeLists.txt, test `python_kubelka_munk`) with validation layers on.
"""

from __future__ import annotations

import inspect
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import metamer
import metamer.kubelka_munk as km
from fresnel_oracle import diffuse_reflectance

REPO = Path(__file__).resolve().parents[2]
SPECTRA = REPO / "spectra"
GRID = np.arange(380.0, 780.0 + 1e-9, 5.0)   # every band centre a data point of the 1 nm pigment tables


def library(name):
    """A library spectrum at the grid's band centres, which the engine takes as tabulated
    (docs/physics.md, "Resampling", rule 1)."""
    data = np.loadtxt(SPECTRA / f"{name}.csv", delimiter=",", skiprows=1, comments="#")
    return np.interp(GRID, data[:, 0], data[:, 1])


def kubelka_closed_form(K, S, X, Rg):
    """Kubelka's closed form, a = 1 + K/S, b = √(a² − 1) (S > 0, finite X)."""
    a = 1 + K / S
    b = np.sqrt(a * a - 1)
    coth = 1 / np.tanh(b * S * X)
    return (1 - Rg * (a - b * coth)) / (a - Rg + b * coth)


# --- r_e

@pytest.mark.parametrize("n", [1.0, 1.2, 1.33, 1.5, 1.7, 2.4, 5.0])
def test_external_diffuse_reflectance_is_fresnel_integrated_over_the_hemisphere(n):
    assert km.external_diffuse_reflectance(n) == pytest.approx(diffuse_reflectance(1.0, n), abs=1e-11)
    assert km.k2(n) == pytest.approx(diffuse_reflectance(n, 1.0), abs=1e-11)


def test_external_and_internal_diffuse_reflectance_are_related_by_n_squared():
    n = np.linspace(1.0, 5.0, 41)
    r_e, r_i = km.external_diffuse_reflectance(n), km.k2(n)
    assert isinstance(r_e, np.ndarray) and r_e.shape == n.shape
    np.testing.assert_allclose(1 - r_i, (1 - r_e) / n**2, rtol=0, atol=1e-12)
    assert km.external_diffuse_reflectance(1.5) == pytest.approx(0.09178, abs=5e-6)
    assert km.external_diffuse_reflectance(1.5) != pytest.approx(km.k1(1.5), abs=1e-3)  # not the normal incidence value
    assert np.all(np.diff(r_e) > 0)   # a denser medium reflects more


# --- mix

def pigments():
    return [(0.1, library("pigments/titanium_white_k"), library("pigments/titanium_white_s")),
            (0.002, library("pigments/phthalo_blue_k"), library("pigments/phthalo_blue_s"))]


def test_mix_is_the_two_constant_rule_without_normalization():
    p = pigments()
    K, S = km.mix(p, K=50.0, S=100.0)
    np.testing.assert_allclose(K, 50.0 + sum(c * k for c, k, _ in p), rtol=1e-15)
    np.testing.assert_allclose(S, 100.0 + sum(c * s for c, _, s in p), rtol=1e-15)
    # The concentrations are amounts, not fractions: doubling them doubles K and S and keeps K/S.
    K2, S2 = km.mix([(2 * c, k, s) for c, k, s in p])
    K1, S1 = km.mix(p)
    np.testing.assert_allclose(K2, 2 * K1, rtol=1e-15)
    np.testing.assert_allclose(km.infinite(K2, S2), km.infinite(K1, S1), rtol=1e-12)
    # Numbers give floats; a sweep of concentrations broadcasts against the bands.
    assert km.mix([(0.1, 2.0, 3000.0), (0.002, 5e4, 400.0)]) == (pytest.approx(100.2), pytest.approx(300.8))
    assert type(km.mix([(0.1, 2.0, 3000.0)])[0]) is float
    c = np.linspace(0.0, 0.01, 11)[:, None]
    K, S = km.mix([(0.1, p[0][1], p[0][2]), (c, p[1][1], p[1][2])])
    assert K.shape == (11, GRID.size)
    np.testing.assert_allclose(K[7], 0.1 * p[0][1] + c[7] * p[1][1], rtol=1e-15)


def paint_quad(layers, substrate, irradiance=2.0):
    """A paint on a quad filling an orthographic view, under an ambient light of constant irradiance
    E: every pixel's radiance is ρ·E/π, ρ the paint's body reflectance (no surface, no specular)."""
    return {
        "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0],
                   "height_m": 1.0, "width": 4, "height": 4},
        "lights": [{"type": "ambient", "spectrum": 1.0, "scale": irradiance}],
        "materials": {"paint": {"layers": layers, "substrate": substrate}},
        "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [4, 4], "material": "paint"}],
    }


def test_mix_and_stack_are_what_a_rendered_paint_uses():
    # Two films over a grey: a white-and-blue paint in a binder with its own K and S, under a
    # scattering coat of constant K and S.
    layers = [{"K": 50.0, "S": 100.0, "thickness": 20e-6,
               "pigments": [{"pigment": "pigments/titanium_white", "concentration": 0.1},
                            {"pigment": "pigments/phthalo_blue", "concentration": 0.002}]},
              {"K": 2000.0, "S": 20000.0, "thickness": 10e-6}]
    r = metamer.render(paint_quad(layers, 0.5), grid="380:780:5")
    assert r.validation_errors == 0
    rendered = r.cube[2, 2].astype(float) / (2.0 / math.pi)

    K, S = km.mix(pigments(), K=50.0, S=100.0)
    expected = km.stack([(K, S, 20e-6), (2000.0, 20000.0, 10e-6)], substrate=0.5)
    np.testing.assert_allclose(rendered, expected, rtol=2e-6)   # float32 cube
    assert np.ptp(expected) > 0.1   # the paint is coloured: a test over the whole range
    # A mix normalized to fractions (cᵢ/Σc) is another paint: the test tells the two apart.
    total = 0.1 + 0.002
    Kn, Sn = km.mix([(c / total, k, s) for c, k, s in pigments()], K=50.0, S=100.0)
    normalized = km.stack([(Kn, Sn, 20e-6), (2000.0, 20000.0, 10e-6)], substrate=0.5)
    assert np.max(np.abs(rendered - normalized)) > 1e-2


# --- stack

def test_stack_is_reflectance_applied_film_by_film_bottom_up():
    rng = np.random.default_rng(46)
    films = [(rng.uniform(0, 500, 81), rng.uniform(100, 5e4, 81), X) for X in (30e-6, 5e-6, 12e-6)]
    substrate = rng.uniform(0, 1, 81)
    r = substrate
    for K, S, X in films:
        r = km.reflectance(K, S, X, r)
    stacked = km.stack(films, substrate)
    np.testing.assert_allclose(stacked, r, rtol=0, atol=1e-15)
    closed = substrate
    for K, S, X in films:
        closed = kubelka_closed_form(K, S, X, closed)
    np.testing.assert_allclose(stacked, closed, rtol=0, atol=1e-12)
    # Order matters: top-down is another stack.
    assert np.max(np.abs(km.stack(films[::-1], substrate) - stacked)) > 1e-3
    # An opaque bottom film hides the substrate; numbers give a float.
    opaque = km.stack([(1.0, 10.0, math.inf), (2.0, 30.0, 0.01)], substrate=0.9)
    assert type(opaque) is float
    assert opaque == km.reflectance(2.0, 30.0, 0.01, km.infinite(1.0, 10.0))
    assert opaque == km.stack([(1.0, 10.0, math.inf), (2.0, 30.0, 0.01)], substrate=0.0)


# --- The names that were there keep their values and forms.

def test_the_existing_functions_keep_their_values_and_return_floats_for_numbers():
    assert km.infinite(0.1, 1.0) == pytest.approx(0.6417424, abs=5e-8)
    assert km.reflectance(1, 10, 0.1) == pytest.approx(0.4610336, abs=5e-8)
    assert km.reflectance(1, 10, 0.1, 0.8) == pytest.approx(0.7123473, abs=5e-8)
    assert km.transmittance(1, 10, 0.1) == pytest.approx(0.4452842, abs=5e-8)
    assert km.saunderson(km.infinite(0.1, 1.0), 0.04, 0.6) == pytest.approx(0.4407273, abs=5e-8)
    assert km.k_over_s(km.infinite(0.1, 1.0)) == pytest.approx(0.1, rel=1e-12)
    assert km.saunderson_body(0.3, 0.04, 0.6) == pytest.approx(km.saunderson(0.3, 0.04, 0.6) - 0.04, abs=1e-16)
    assert km.saunderson_inverse(km.saunderson(0.3, 0.04, 0.6), 0.04, 0.6) == pytest.approx(0.3, abs=1e-15)
    assert km.k1(1.5) == pytest.approx(0.04, abs=1e-16)
    for value in (km.reflectance(1, 10, 0.1), km.k2(np.float32(1.5)), km.infinite(np.int64(1), 10)):
        assert type(value) is float
    assert isinstance(km.reflectance([1, 2], 10, 0.1), np.ndarray)
    # The domains' ends are inside: a film of no thickness is its substrate, R∞ = 1 has K/S = 0.
    assert km.reflectance(3.0, 5.0, 0.0, 0.4) == 0.4
    assert km.reflectance(0.0, 0.0, 1.0, 0.4) == pytest.approx(0.4, abs=1e-15)
    assert km.k_over_s(1.0) == 0.0
    assert km.k1(1.0) == 0.0 and km.external_diffuse_reflectance(1.0) == pytest.approx(0.0, abs=1e-15)
    assert "metamer.kubelka_munk" in sys.modules and metamer.kubelka_munk is km


# --- Errors a user meets.

WRONG_TYPES = [("a str", "0.5", "got str"), ("None", None, "got NoneType"), ("a list of str", ["0.5", "1"], "got list of str"),
               ("a dict", {"K": 1.0}, "got dict"), ("a bool", True, "got bool"), ("complex", 1j, "got complex"),
               ("a ragged list", [[1.0, 2.0], [3.0]], "rows of different lengths")]


@pytest.mark.parametrize("what,value,got", WRONG_TYPES, ids=[w[0] for w in WRONG_TYPES])
@pytest.mark.parametrize("call,name", [
    (lambda v: km.reflectance(v, 10.0, 0.1), "K"),
    (lambda v: km.reflectance(1.0, 10.0, 0.1, substrate=v), "substrate"),
    (lambda v: km.transmittance(1.0, v, 0.1), "S"),
    (lambda v: km.k_over_s(v), "r_infinite"),
    (lambda v: km.saunderson_inverse(0.5, v, 0.6), "k1"),
    (lambda v: km.external_diffuse_reflectance(v), "n"),
    (lambda v: km.mix([(0.1, 2.0, 3000.0)], S=v), "S"),
    (lambda v: km.mix([(0.1, 2.0, 3000.0), (v, 1.0, 1.0)]), r"pigments\[1\]\.concentration"),
    (lambda v: km.stack([(1.0, 10.0, 0.1), (1.0, 10.0, v)]), r"films\[1\]\.X"),
])
def test_a_wrong_type_is_a_type_error_naming_the_argument(call, name, what, value, got):
    with pytest.raises(TypeError, match=rf"^{name}: expected a number or an array of numbers, .*{got}") as e:
        call(value)
    assert "incompatible function arguments" not in str(e.value)


@pytest.mark.parametrize("call,message", [
    (lambda: km.mix("titanium_white"), r"^pigments: expected a list of \(concentration, k, s\) tuples, got str$"),
    (lambda: km.mix({"c": 0.1}), r"^pigments: expected a list of \(concentration, k, s\) tuples, got dict$"),
    (lambda: km.mix([(0.1, 2.0)]), r"^pigments\[0\]: expected a \(concentration, k, s\) tuple, got 2 values$"),
    (lambda: km.stack(None), r"^films: expected a list of \(K, S, X\) tuples, got NoneType$"),
    (lambda: km.stack([1.0, 2.0, 3.0]), r"^films\[0\]: expected a \(K, S, X\) tuple, got float$"),
])
def test_a_list_of_the_wrong_shape_is_a_type_error_naming_it(call, message):
    with pytest.raises(TypeError, match=message):
        call()


@pytest.mark.parametrize("call,message", [
    (lambda: km.reflectance(-1.0, 10.0, 0.1), r"^K: -1 is outside the allowed range \[0, ∞\); expected a Kubelka–Munk"),
    (lambda: km.reflectance(1.0, [10.0, 5.0, -2.0], 0.1), r"^S: -2 at index 2 is outside the allowed range \[0, ∞\)"),
    (lambda: km.infinite(1.0, math.inf), r"^S: inf is outside the allowed range \[0, ∞\)"),
    (lambda: km.reflectance(1.0, 10.0, -1e-6), r"^X: -1e-06 is outside the allowed range \[0, 1000\]; expected a "
                                              r"thickness in metres, or inf for an opaque film"),
    (lambda: km.transmittance(1.0, 10.0, 2e3), r"^X: 2000 is outside the allowed range \[0, 1000\]"),
    (lambda: km.reflectance(1.0, 10.0, 0.1, 1.5), r"^substrate: 1.5 is outside the allowed range \[0, 1\]"),
    (lambda: km.k_over_s(0.0), r"^r_infinite: 0 is outside the allowed range \(0, 1\]"),
    (lambda: km.k_over_s([0.5, 1.2]), r"^r_infinite: 1.2 at index 1 is outside the allowed range \(0, 1\]"),
    (lambda: km.k1(0.9), r"^n: 0.9 is outside the allowed range \[1, 5\]; expected a refractive index"),
    (lambda: km.k2(math.nan), r"^n: nan is not a number; expected a refractive index, in \[1, 5\]"),
    (lambda: km.external_diffuse_reflectance([[1.5, 1.6], [1.7, math.nan]]), r"^n: nan at index \[1, 1\] is not a number"),
    (lambda: km.saunderson(0.5, 1.0, 0.6), r"^k1: 1 is outside the allowed range \[0, 1\)"),
    (lambda: km.saunderson_body(-0.1, 0.04, 0.6), r"^R: -0.1 is outside the allowed range \[0, 1\]"),
    (lambda: km.saunderson_inverse([0.5, 0.03], 0.04, 0.6), r"^measured: 0.03 at index 1 is below k1 = 0.04"),
    (lambda: km.mix([(-0.1, 2.0, 3000.0)]), r"^pigments\[0\]\.concentration: -0.1 is outside the allowed range \[0, 1e6\]"),
    (lambda: km.mix([(0.1, 1e12, 3000.0)]), r"^pigments\[0\]\.k: 1e\+12 is outside the allowed range \[0, 1e12\)"),
    (lambda: km.mix([(0.1, 2.0, 3000.0)], K=-5.0), r"^K: -5 is outside the allowed range \[0, 1e12\)"),
    (lambda: km.mix([]), r"^pigments: 0 items; expected 1 … 64"),
    (lambda: km.stack([(1.0, 10.0, 0.1), (1.0, 10.0, math.inf)]),
     r"^films\[1\]\.X: inf is outside the allowed range \[0, 1000\]; .*only the bottom film may be opaque"),
    (lambda: km.stack([(1.0, 10.0, 0.1)] * 65), r"^films: 65 items; expected 1 … 64"),
    (lambda: km.reflectance([1.0, 2.0], [1.0, 2.0, 3.0], 0.1),
     r"^K, S: arrays of shapes \(2,\), \(3,\) do not broadcast together"),
])
def test_a_value_outside_the_physical_domain_is_an_input_error_naming_the_argument_and_range(call, message):
    with pytest.raises(metamer.InputError, match=message) as e:
        call()
    assert isinstance(e.value, ValueError)


def test_keywords_are_named_and_checked():
    with pytest.raises(TypeError, match=r"^reflectance\(\) got an unexpected keyword argument 'substrat'; did you mean "
                                        r"'substrate'\?$"):
        km.reflectance(1.0, 10.0, 0.1, substrat=0.5)
    with pytest.raises(TypeError, match=r"^mix\(\) got an unexpected keyword argument 's'; it takes pigments, K, S$"):
        km.mix([(0.1, 2.0, 3000.0)], s=1.0)
    assert list(inspect.signature(km.reflectance).parameters) == ["K", "S", "X", "substrate"]
    assert list(inspect.signature(km.mix).parameters) == ["pigments", "K", "S"]
    assert list(inspect.signature(km.stack).parameters) == ["films", "substrate"]
    assert km.reflectance(K=1, S=10, X=0.1, substrate=0.8) == km.reflectance(1, 10, 0.1, 0.8)
    for name in km.__all__:
        if callable(getattr(km, name)) and not name[0].isupper():
            assert len(getattr(km, name).__doc__ or "") > 60, name


def test_the_example_in_docs_python_md_runs(monkeypatch):
    import re
    import textwrap

    text = (REPO / "docs" / "python.md").read_text()
    blocks = [b for b in re.findall(r"\n\n((?:    .*\n|\n)+)", text) if "km.mix(" in b]
    assert len(blocks) == 1
    monkeypatch.chdir(REPO)
    namespace = {}
    exec(compile(textwrap.dedent(blocks[0]), "docs/python.md", "exec"), namespace)
    R, K, S = namespace["R"], namespace["K"], namespace["S"]
    assert R.shape == (81,) and np.all((0 < R) & (R < 1))
    np.testing.assert_array_equal(R, km.reflectance(K, S, 20e-6, 0.5))
