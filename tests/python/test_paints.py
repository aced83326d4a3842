"""Paints by Kubelka–Munk end to end (issue 28; docs/physics.md, "Paints and coatings"): the
bundled scenes/paints.json rendered through the Python module, against oracles written here —
numpy Kubelka–Munk closed forms on the library's own pigment, card and light data, Saunderson's
k2 by scipy quadrature of Fresnel's equations, colour-science for the colorimetry. Run by CTest
(tests/CMakeLists.txt, test `python_paints`) with validation layers on.
"""

from __future__ import annotations

import importlib.util
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import metamer

warnings.filterwarnings("ignore")
import colour  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SPECTRA = REPO / "spectra"
SCENE = REPO / "scenes" / "paints.json"
GRID = np.arange(380.0, 780.0 + 1e-9, 5.0)   # the scene's grid: band centres on every data point


def library(name):
    """A library spectrum at the grid's band centres (all of them data points, so the engine takes
    the tabulated values as they are: docs/physics.md, "Resampling")."""
    data = np.loadtxt(SPECTRA / f"{name}.csv", delimiter=",", skiprows=1, comments="#")
    return np.interp(GRID, data[:, 0], data[:, 1])


def k_and_s(pigments):
    K = sum(p["concentration"] * library(p["pigment"] + "_k") for p in pigments)
    S = sum(p["concentration"] * library(p["pigment"] + "_s") for p in pigments)
    return K, S


def km_over(K, S, X, Rg):
    """Kubelka's closed form, a = 1 + K/S, b = √(a² − 1)."""
    a = 1 + K / S
    b = np.sqrt(a * a - 1)
    coth = 1 / np.tanh(b * S * X)
    return (1 - Rg * (a - b * coth)) / (a - Rg + b * coth)


def internal_diffuse_reflectance(n):
    def fresnel(cos_i):
        sin_t = n * math.sqrt(max(0.0, 1 - cos_i * cos_i))
        if sin_t >= 1:
            return 1.0
        cos_t = math.sqrt(1 - sin_t * sin_t)
        rs = (n * cos_i - cos_t) / (n * cos_i + cos_t)
        rp = (n * cos_t - cos_i) / (n * cos_t + cos_i)
        return 0.5 * (rs * rs + rp * rp)
    f = lambda t: fresnel(math.cos(t)) * 2 * math.sin(t) * math.cos(t)
    return quad(f, 0, math.pi / 2, points=[math.asin(1 / n)], epsabs=1e-14, limit=200)[0]


K1, K2 = 0.04, internal_diffuse_reflectance(1.5)   # the scene's "surface": {"ior": 1.5}


def body(R):
    return (1 - K1) * (1 - K2) * R / (1 - K2 * R)


def test_hiding_thickness_from_the_rendered_drawdown_matches_the_oracle():
    spec = importlib.util.spec_from_file_location("paint_hiding", REPO / "docs" / "examples" / "paint_hiding.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    thickness, ratio, at98 = example.hiding(str(SCENE))

    scene = json.loads(SCENE.read_text())
    layer = scene["materials"]["drawdown_over_white"]["layers"][0]
    K, S = k_and_s(layer["pigments"])
    white, black = library("colorchecker/white_9_5"), library("colorchecker/black_2")
    light = library("illuminants/D65")
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(colour.SpectralShape(380, 780, 5))
    ybar = cmfs.values[:, 1]

    def contrast(X):
        if X <= 0:
            return float(np.sum(light * body(black) * ybar) / np.sum(light * body(white) * ybar))
        return float(np.sum(light * body(km_over(K, S, X, black)) * ybar) /
                     np.sum(light * body(km_over(K, S, X, white)) * ybar))

    want98 = brentq(lambda X: contrast(X) - 0.98, 1e-6, 1e-3, xtol=1e-12)
    print(f"98 % hiding: rendered {at98 * 1e6:.3f} µm, oracle {want98 * 1e6:.3f} µm")
    assert at98 == pytest.approx(want98, abs=0.3e-6)
    # Every column's contrast ratio; near X = 0 the texture's bilinear blend of reflectances (not
    # of thicknesses) between texels 0.59 µm apart departs most from the exact curve.
    errors = np.array([abs(r - contrast(x)) for x, r in zip(thickness, ratio)])
    for above, bound in ((10e-6, 2e-4), (30e-6, 2e-5)):
        assert errors[thickness > above].max() < bound, (above, errors[thickness > above].max())
    assert errors.max() < 3e-3


def xyz_and_white(r, x, y, light_name):
    """XYZ of pixel (x, y) and of a perfect white under the scene's light: a directional light of
    scale s along d gives the board the irradiance s·cos θ·E(λ), and a white radiance of that / π."""
    scene = json.loads(SCENE.read_text())
    light = scene["lights"][0]
    d = np.array(light["direction"], float)
    cos_theta = -d[2] / np.linalg.norm(d)
    E = library(light_name) * light["scale"] * cos_theta / math.pi
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(colour.SpectralShape(380, 780, 5)).values
    return r.cube[y, x].astype(float) @ cmfs, E @ cmfs


@pytest.mark.parametrize("light,lo,hi", [("illuminants/D65", 0.0, 0.01), ("illuminants/A", 1.5, 3.0)])
def test_the_metameric_greys_match_under_d65_and_not_under_a(light, lo, hi):
    r = metamer.render(str(SCENE), overrides={"lights.0.spectrum": light, "camera.width": 150, "camera.height": 100},
                       write="cube")
    # The pair: two 0.1 × 0.08 m patches centred at (∓0.05, −0.13) m; the camera at z = 1.2 looks
    # at the origin with a 20° field: pixel rows and columns by projection.
    f = 50.0 / math.tan(math.radians(10.0))   # 100 rows span 20°

    def pixel(x_m, y_m):
        return int(75 + f * x_m / 1.2), int(50 - f * y_m / 1.2)

    (xa, ya), (xb, yb) = pixel(-0.05, -0.13), pixel(0.05, -0.13)
    a, white = xyz_and_white(r, xa, ya, light)
    b, _ = xyz_and_white(r, xb, yb, light)
    wxy = colour.XYZ_to_xy(white)
    lab_a = colour.XYZ_to_Lab(a / white[1], wxy)
    lab_b = colour.XYZ_to_Lab(b / white[1], wxy)
    de = float(colour.delta_E(lab_a, lab_b, method="CIE 2000"))
    print(f"{light}: ΔE00 {de:.3f} (L* {lab_a[0]:.1f})")
    assert lo <= de <= hi
    assert 40 < lab_a[0] < 70   # a mid grey, and the pixel is on the patch


def test_the_kubelka_munk_functions_convert_measured_reflectances_both_ways():
    km = metamer.kubelka_munk
    # The known answers, through the module.
    assert km.infinite(0.1, 1.0) == pytest.approx(0.6417424, abs=5e-8)
    assert km.reflectance(1, 10, 0.1) == pytest.approx(0.4610336, abs=5e-8)
    assert km.reflectance(1, 10, 0.1, 0.8) == pytest.approx(0.7123473, abs=5e-8)
    assert km.transmittance(1, 10, 0.1) == pytest.approx(0.4452842, abs=5e-8)
    assert km.saunderson(km.infinite(0.1, 1.0), 0.04, 0.6) == pytest.approx(0.4407273, abs=5e-8)
    assert km.reflectance(1, 10, math.inf, 0.3) == km.infinite(1, 10)
    # Element-wise over arrays, against the oracles above.
    K, S, X, Rg = np.array([0.5, 2.0, 8.0]), np.array([10.0, 3.0, 60.0]), np.array([0.05, 0.2, 0.01]), 0.4
    assert np.allclose(km.reflectance(K, S, X, Rg), km_over(K, S, X, Rg), rtol=0, atol=1e-13)
    assert km.k2(1.5) == pytest.approx(internal_diffuse_reflectance(1.5), abs=1e-12)
    assert km.k1(1.5) == pytest.approx(0.04, abs=1e-16)
    # A measured masstone (specular included) → R → K/S → R∞ → measured again.
    measured = np.linspace(0.05, 0.9, 18)
    k1, k2 = km.k1(1.5), km.k2(1.5)
    R = km.saunderson_inverse(measured, k1, k2)
    q = km.k_over_s(R)
    again = km.saunderson(km.infinite(q, np.ones_like(q)), k1, k2)
    assert np.allclose(again, measured, rtol=0, atol=1e-14)
    assert np.allclose(km.saunderson(R, k1, k2) - km.saunderson_body(R, k1, k2), k1, atol=1e-15)
