#!/usr/bin/env python3
"""Regenerate the detector data of the Metamer spectra library: spectra/cameras/ and spectra/film/.

Run from anywhere with the project's Python (colour-science 0.4.7 and numpy):

    .venv/bin/python spectra/generate_detectors.py

Cameras are measured data copied unchanged from colour-science. The film is a parametric model
computed here; spectra/README.md ("Cameras", "Film") documents every parameter and where it comes
from, and docs/color.md ("Detectors") the formulas the engine applies to these files.

Separate from generate.py (the rest of the library) so that the two can be regenerated and
reviewed independently. Deterministic: no randomness, fixed rounding, "\\n" line endings.
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import numpy as np

# colour-science warns at import time about optional packages it does not need here.
warnings.filterwarnings("ignore", message=r".*related API features are not available.*")
import colour  # noqa: E402

ROOT = Path(__file__).resolve().parent
FWHM_TO_SIGMA = 1.0 / (2.0 * np.sqrt(2.0 * np.log(2.0)))
HC_EV_NM = 1239.841984  # photon energy E[eV] = HC_EV_NM / λ[nm]

written: list[Path] = []


# --------------------------------------------------------------------------------------------
# Output


def number(v: float, sig: int) -> str:
    v = float(v) + 0.0  # no "-0"
    return f"{v:.{sig}g}"


def write_table(rel: str, wl, columns: dict[str, np.ndarray], sig: int = 10) -> None:
    """`wavelength_nm,<names>` then one row per wavelength, `sig` significant digits."""
    wl = np.asarray(wl, dtype=float)
    cols = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
    assert np.all(np.diff(wl) > 0), rel
    for k, v in cols.items():
        assert v.shape == wl.shape and np.all(np.isfinite(v)), (rel, k)
    rows = ["wavelength_nm," + ",".join(cols)]
    for i, w in enumerate(wl):
        rows.append(",".join([f"{w:g}"] + [number(v[i], sig) for v in cols.values()]))
    path = ROOT / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(rows) + "\n", encoding="ascii", newline="\n")
    written.append(path)
    print(f"wrote {rel:34s} {wl[0]:g}-{wl[-1]:g} nm, {len(wl)} rows, columns {', '.join(cols)}")


def samples(start: float, end: float, step: float) -> np.ndarray:
    return start + step * np.arange(int(round((end - start) / step)) + 1, dtype=float)


# --------------------------------------------------------------------------------------------
# Cameras: measured relative RGB sensitivities, unchanged.

COLOUR_DATA = Path(colour.__file__).resolve().parent / "characterisation" / "datasets"


def cameras() -> None:
    npl = colour.characterisation.MSDS_CAMERA_SENSITIVITIES
    # The NPL set (Darrodi et al. 2015): colour-science names them "Nikon 5100" and "SDMerill".
    for key, name in [("Nikon 5100 (NPL)", "nikon_d5100"), ("Sigma SDMerill (NPL)", "sigma_sd_merrill")]:
        m = npl[key]
        assert list(m.labels) == ["red", "green", "blue"], m.labels
        v = m.values
        assert np.all(v >= 0), key
        write_table(f"cameras/{name}.csv", m.wavelengths, {"r": v[:, 0], "g": v[:, 1], "b": v[:, 2]})
    # Canon EOS 5D Mark II from the Academy's rawtoaces, as colour-science 0.4.7 ships it for its
    # ACES input-transform tests (not exported as a dataset, so read from the package folder).
    path = COLOUR_DATA / "rawtoaces" / "CANON_EOS_5DMark_II_RGB_Sensitivities.csv"
    d = np.genfromtxt(path, delimiter=",", names=True)
    assert d.dtype.names == ("wavelength", "R", "G", "B"), d.dtype.names
    write_table("cameras/canon_eos_5d_mark_ii.csv", d["wavelength"], {"r": d["R"], "g": d["G"], "b": d["B"]})


# --------------------------------------------------------------------------------------------
# Film: a parametric model of a daylight-balanced colour reversal (slide) film.
# spectra/README.md, "Film", explains each choice; the numbers below are that table.

FILM_GRID = (300, 830, 1)

# Layer spectral sensitivity: unit-peak Gaussian in wavelength with different widths on the
# short and long side (peak nm, σ short nm, σ long nm). Shapes read qualitatively from published
# spectral-sensitivity curves of E-6 slide films: blue layer ~400–500 nm (cut above ~500 nm by the
# yellow filter layer), green ~500–600 nm, red ~600–700 nm with a steep long-wavelength edge.
SENSITIVITY = {
    "blue": (445.0, 35.0, 22.0),
    "green": (545.0, 28.0, 22.0),
    "red": (645.0, 25.0, 14.0),
}

# Dye spectral density: Gaussian bands in photon energy (centre nm, FWHM eV, relative height),
# the main band first; the whole dye is scaled to peak 1. The secondary bands are the "unwanted
# absorptions" every real image dye has (magenta in the blue, cyan in the green and blue).
DYES = {
    "yellow": [(445.0, 0.45, 1.0)],
    "magenta": [(550.0, 0.40, 1.0), (430.0, 0.50, 0.18)],
    "cyan": [(660.0, 0.42, 1.0), (550.0, 0.40, 0.12), (440.0, 0.50, 0.08)],
}

# Base + residual stain density: neutral 0.05 plus a slight yellowish stain in the violet-blue.
BASE_NEUTRAL = 0.05
BASE_STAIN = (0.04, 420.0, 20.0)  # height, edge nm, edge width nm (logistic, falling to the red)

# Projection lamp: tungsten-halogen, a blackbody at 3200 K.
LAMP_CCT_K = 3200.0

# Characteristic curve of each layer in equivalent-neutral-density (END) units, the same for
# the three layers (a balanced film); converted below to each dye's own amount.
END_CURVE = {
    "d_min": 0.08,   # dye density left at full exposure (base is separate)
    "d_max": 3.30,   # dye density of an unexposed area
    "gamma": 1.60,   # |slope| at the middle of the curve, density per log10 exposure
    "toe": 0.20,     # softness of the toe and the shoulder, in density units
    "log_h0": -1.10, # log10(H / H_white) of the curve's middle density
}
# The film renders the white of this illuminant (x = 0 in every layer) as neutral.
BALANCE_ILLUMINANT = "illuminants/D65"


def skewed_gaussian(wl, peak, s_short, s_long):
    s = np.where(wl < peak, s_short, s_long)
    return np.exp(-0.5 * ((wl - peak) / s) ** 2)


def gaussian_ev(wl, centre_nm, fwhm_ev):
    e, e0 = HC_EV_NM / wl, HC_EV_NM / centre_nm
    return np.exp(-0.5 * ((e - e0) / (fwhm_ev * FWHM_TO_SIGMA)) ** 2)


def planck(wl_nm, t_k):
    c2 = 1.4387768775e7  # nm·K (CODATA 2018 second radiation constant)
    return wl_nm ** -5 / np.expm1(c2 / (wl_nm * t_k))


def softplus(z):
    return np.logaddexp(0.0, z)


def curve_density(x, c):
    """The characteristic curve (docs/color.md, "Film"): density of one layer at x = log10(H/H_white)."""
    r = c["d_max"] - c["d_min"]
    g = c["gamma"] / np.tanh(r / (4.0 * c["toe"]))
    u = g * (c["log_h0"] - x) + 0.5 * r
    b = c["toe"]
    return c["d_min"] + b * (softplus(u / b) - softplus((u - r) / b))


def load_library_csv(rel: str):
    d = np.genfromtxt(ROOT / rel, delimiter=",", skip_header=1)
    return d[:, 0], d[:, 1:]


def film() -> None:
    wl = samples(*FILM_GRID)
    sens = {k: skewed_gaussian(wl, *p) for k, p in SENSITIVITY.items()}
    dyes = {}
    for k, bands in DYES.items():
        v = sum(h * gaussian_ev(wl, c, f) for c, f, h in bands)
        dyes[k] = v / v.max()
    h, edge, width = BASE_STAIN
    base = BASE_NEUTRAL + h / (1.0 + np.exp((wl - edge) / width))
    lamp = planck(wl, LAMP_CCT_K)
    lamp = 100.0 * lamp / np.interp(560.0, wl, lamp)

    # CIE 1931 on the same 1 nm samples (zero outside 360–830 nm).
    cw, cv = load_library_csv("observers/cie1931_2deg.csv")
    cmf = np.stack([np.interp(wl, cw, cv[:, i], left=0.0, right=0.0) for i in range(3)])
    dye_m = np.stack([dyes["yellow"], dyes["magenta"], dyes["cyan"]])

    def projected(amounts):
        """XYZ of the lamp through dye amounts (3,) and no base, relative to the open gate Y."""
        t = 10.0 ** (-(amounts @ dye_m))
        xyz = cmf @ (lamp * t)
        return xyz / (cmf[1] @ lamp)

    def xy_y(xyz):
        return np.array([xyz[0] / xyz.sum(), xyz[1] / xyz.sum(), xyz[1]])

    lamp_xyz = cmf @ lamp
    lamp_xy = xy_y(lamp_xyz)[:2]

    # Equivalent neutral density: the dye amounts a_i per unit END are chosen so that END = 1 in
    # all three layers gives a grey of visual density 1 (Y = 0.1 of the open gate) with the
    # lamp's own chromaticity. Newton's method with a finite-difference Jacobian.
    target = np.array([lamp_xy[0], lamp_xy[1], 0.1])
    a = np.ones(3)
    for _ in range(50):
        f = xy_y(projected(a)) - target
        if np.max(np.abs(f)) < 1e-13:
            break
        jac = np.empty((3, 3))
        for j in range(3):
            da = np.zeros(3)
            da[j] = 1e-6
            jac[:, j] = (xy_y(projected(a + da)) - xy_y(projected(a - da))) / 2e-6
        a = a - np.linalg.solve(jac, f)
    assert np.max(np.abs(xy_y(projected(a)) - target)) < 1e-12, a
    print(f"  END balance: dye amounts per unit END yellow {a[0]:.4f}, magenta {a[1]:.4f}, cyan {a[2]:.4f}")

    layers = []
    for i, (channel, dye) in enumerate([("blue", "yellow"), ("green", "magenta"), ("red", "cyan")]):
        # Scaling a curve of this form by a keeps its form: densities and toe × a, gamma × a.
        layers.append({
            "channel": channel,
            "dye": dye,
            "d_min": round(a[i] * END_CURVE["d_min"], 6),
            "d_max": round(a[i] * END_CURVE["d_max"], 6),
            "log_h0": END_CURVE["log_h0"],
            "gamma": round(a[i] * END_CURVE["gamma"], 6),
            "toe": round(a[i] * END_CURVE["toe"], 6),
        })

    # Where the tone scale puts things (END units, printed for the README).
    for label, refl in [("white (x=0)", 1.0), ("18% grey of a 90% white", 0.18 / 0.9),
                        ("3% black of a 90% white", 0.03 / 0.9)]:
        x = np.log10(refl)
        print(f"  {label:26s} x = {x:+.3f}: END {curve_density(x, END_CURVE):.3f}")
    clear = projected(np.array([l["d_min"] for l in layers]))
    clear_base = cmf @ (lamp * 10.0 ** (-(np.array([l['d_min'] for l in layers]) @ dye_m + base)))
    print(f"  lamp xy {lamp_xy[0]:.4f},{lamp_xy[1]:.4f}; clear film (d_min + base) xy "
          f"{xy_y(clear_base)[0]:.4f},{xy_y(clear_base)[1]:.4f}, "
          f"Y/open gate {clear_base[1] / lamp_xyz[1]:.4f} (visual density {-np.log10(clear_base[1] / lamp_xyz[1]):.3f}); "
          f"d_min alone {-np.log10(clear[1]):.3f}")
    dmax = projected(np.array([l["d_max"] for l in layers]))
    print(f"  d_max visual density {-np.log10(dmax[1]):.3f}, xy {xy_y(dmax)[0]:.4f},{xy_y(dmax)[1]:.4f}")

    write_table("film/reversal_sensitivity.csv", wl, sens, sig=8)
    write_table("film/reversal_dye_density.csv", wl, dyes, sig=8)
    write_table("film/reversal_base_density.csv", wl, {"density": base}, sig=8)
    write_table("film/reversal_lamp.csv", wl, {"value": lamp}, sig=8)

    spec = {
        "description": "Parametric model of a daylight-balanced colour reversal (slide) film, "
                       "projected with a 3200 K tungsten-halogen lamp. Not measured data: "
                       "spectra/README.md (Film) gives the sources of every shape and number; "
                       "docs/color.md (Detectors) the formulas. Generated by spectra/generate_detectors.py.",
        "sensitivity": "film/reversal_sensitivity",
        "dye_density": "film/reversal_dye_density",
        "base_density": "film/reversal_base_density",
        "lamp": "film/reversal_lamp",
        "balance_illuminant": BALANCE_ILLUMINANT,
        "end_curve": END_CURVE,
        "end_dye_amounts": [round(float(v), 6) for v in a],
        "layers": layers,
    }
    path = ROOT / "film" / "reversal.json"
    path.write_text(json.dumps(spec, indent=2, ensure_ascii=True) + "\n", encoding="ascii", newline="\n")
    written.append(path)
    print("wrote film/reversal.json")


def main() -> int:
    print(f"colour-science {colour.__version__}, numpy {np.__version__}; writing under {ROOT}")
    cameras()
    film()
    print(f"{len(written)} files")
    return 0


if __name__ == "__main__":
    sys.exit(main())
