#!/usr/bin/env python3
"""Write tests/data/color/colorchecker_reference.csv: colour-science's colorimetry of the 24
ColorChecker patches under CIE D65, A and FL2, the oracle of engine/color/detector_colorimetry_test.cpp.

    .venv/bin/python tests/reference/make_colorchecker_table.py

Inputs are Metamer's own library files (spectra/colorchecker, spectra/illuminants,
spectra/observers/cie1931_2deg.csv), band-averaged onto the grid 300:740:5 exactly as
engine/spectral/spectrum.cpp does (implemented again below), so that the C++ test compares
colorimetry, not resampling. From there on everything is colour-science 0.4.7:

* XYZ: colour.sd_to_XYZ_integration (a Riemann sum Σ x̄·S·R·Δλ, k so that the perfect reflecting
  diffuser has Y = 100), on spectral distributions that already share the grid's shape.
* L*a*b*: colour.XYZ_to_Lab relative to that perfect diffuser (its xy; Y = 100 ↔ 1).
* sRGB counts: XYZ / 100 (white Y = 1) → colour.chromatic_adaptation_VonKries with the Bradford
  transform from the illuminant's white to the sRGB display white (X, Y, Z) = (0.95047, 1,
  1.08883) of engine/color/srgb.h → colour.XYZ_to_sRGB with no further adaptation (sRGB
  encoding) → × 255, rounded, clipped to 0..255.

Columns: illuminant,patch,X,Y,Z,L,a,b,R8,G8,B8; floats with 17 significant digits.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore", message=r".*related API features are not available.*")
import colour  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SPECTRA = REPO / "spectra"
OUT = REPO / "tests" / "data" / "color" / "colorchecker_reference.csv"

GRID = (300.0, 740.0, 5.0)
ILLUMINANTS = ["D65", "A", "FL2"]
# Chart order, as engine/color/camera_characterization.cpp's colorCheckerPatchNames().
PATCHES = [
    "dark_skin", "light_skin", "blue_sky", "foliage", "blue_flower", "bluish_green",
    "orange", "purplish_blue", "moderate_red", "purple", "yellow_green", "orange_yellow",
    "blue", "green", "red", "yellow", "magenta", "cyan",
    "white_9_5", "neutral_8", "neutral_6_5", "neutral_5", "neutral_3_5", "black_2",
]
SRGB_DISPLAY_WHITE = np.array([0.95047, 1.0, 1.08883])  # engine/color/srgb.h kD65WhiteXyz


def read_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """wavelength_nm,<columns> with a header line; returns wavelengths and values[row][column]."""
    d = np.genfromtxt(path, delimiter=",", skip_header=1, comments="#")
    return d[:, 0], d[:, 1:]


def integrate_linear(w: np.ndarray, v: np.ndarray, a: float, b: float) -> float:
    """∫ over [a, b] of the piecewise-linear function through (w, v), 0 outside [w0, wN]."""
    a, b = max(a, w[0]), min(b, w[-1])
    if b <= a:
        return 0.0
    total = 0.0
    for j in range(len(w) - 1):
        lo, hi = max(a, w[j]), min(b, w[j + 1])
        if hi <= lo:
            continue
        f_lo = np.interp(lo, w, v)
        f_hi = np.interp(hi, w, v)
        total += 0.5 * (f_lo + f_hi) * (hi - lo)
    return total


def band_average(w: np.ndarray, v: np.ndarray, grid=GRID) -> np.ndarray:
    """Metamer's resampling (docs/physics.md, "Resampling"): the mean of the piecewise-linear data
    over each band [c − Δ/2, c + Δ/2], 0 outside the data, except that a band whose centre lies
    inside the data holds the end value over the part the data do not reach."""
    start, end, step = grid
    centres = start + step * np.arange(int(round((end - start) / step)) + 1)
    out = np.empty(len(centres))
    for i, c in enumerate(centres):
        lo, hi = c - step / 2, c + step / 2
        s = integrate_linear(w, v, lo, hi)
        if w[0] <= c <= w[-1]:
            if lo < w[0]:
                s += v[0] * (w[0] - lo)
            if hi > w[-1]:
                s += v[-1] * (hi - w[-1])
        out[i] = s / step
    return out


def main() -> int:
    start, end, step = GRID
    shape = colour.SpectralShape(start, end, step)
    wl = shape.wavelengths

    cw, cv = read_table(SPECTRA / "observers" / "cie1931_2deg.csv")
    cmf_bands = np.stack([band_average(cw, cv[:, i]) for i in range(3)], axis=1)
    cmfs = colour.MultiSpectralDistributions(cmf_bands, wl, labels=["x_bar", "y_bar", "z_bar"],
                                             name="CIE 1931 band-averaged")
    reflectances = {}
    for p in PATCHES:
        w, v = read_table(SPECTRA / "colorchecker" / f"{p}.csv")
        reflectances[p] = colour.SpectralDistribution(band_average(w, v[:, 0]), wl, name=p)
    perfect = colour.SpectralDistribution(np.ones(len(wl)), wl, name="perfect diffuser")

    rows = ["illuminant,patch,X,Y,Z,L,a,b,R8,G8,B8"]
    for name in ILLUMINANTS:
        w, v = read_table(SPECTRA / "illuminants" / f"{name}.csv")
        illuminant = colour.SpectralDistribution(band_average(w, v[:, 0]), wl, name=name)
        for sd in [perfect, *reflectances.values(), cmfs]:
            assert sd.shape == shape, sd.name  # no realignment by colour-science
        white = colour.colorimetry.sd_to_XYZ_integration(perfect, cmfs, illuminant)
        assert abs(white[1] - 100.0) < 1e-12, white
        white_xy = colour.XYZ_to_xy(white / 100.0)
        for p in PATCHES:
            xyz = colour.colorimetry.sd_to_XYZ_integration(reflectances[p], cmfs, illuminant)
            lab = colour.XYZ_to_Lab(xyz / 100.0, white_xy)
            adapted = colour.adaptation.chromatic_adaptation_VonKries(
                xyz / 100.0, white / 100.0, SRGB_DISPLAY_WHITE, transform="Bradford")
            encoded = colour.XYZ_to_sRGB(adapted, chromatic_adaptation_transform=None)
            counts = np.clip(np.round(encoded * 255.0), 0, 255).astype(int)
            fields = [name, p] + [f"{x:.17g}" for x in (*xyz, *lab)] + [str(c) for c in counts]
            rows.append(",".join(fields))
        print(f"{name}: white XYZ {white[0]:.4f} {white[1]:.4f} {white[2]:.4f}")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(rows) + "\n", encoding="ascii", newline="\n")
    print(f"wrote {OUT.relative_to(REPO)}: {len(rows) - 1} rows (colour-science {colour.__version__})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
