#!/usr/bin/env python3
"""Write tests/data/color/colorchecker_reference.csv: colour-science's colorimetry of the 24
ColorChecker patches under CIE D65, A and FL2, the oracle of engine/color/detector_colorimetry_test.cpp.

    .venv/bin/python tests/reference/make_colorchecker_table.py

Inputs are Metamer's own library files (spectra/colorchecker, spectra/illuminants,
spectra/observers/cie1931_2deg.csv), put on the grid 300:740:5 by colour-science's own linear
interpolation (the tabulated values at the band centres; 0 outside the data, as Metamer's coverage
policy), so the C++ test checks Metamer's resampling and colorimetry together. From there on
everything is colour-science 0.4.7:

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


def on_grid(w: np.ndarray, v: np.ndarray, grid=GRID) -> np.ndarray:
    """Data at the grid's band centres, resampled by colour-science: its LinearInterpolator (the
    tabulated value where a centre is a data point, linear between) and 0 outside the data. On
    the grids used here no library table is sampled more finely than the grid, so this is
    Metamer's rule (docs/physics.md, "Resampling") computed by colour-science, not by us."""
    start, end, step = grid
    centres = start + step * np.arange(int(round((end - start) / step)) + 1)
    if np.min(np.diff(w)) < step - 1e-9:  # finer data: every centre must be a data point or miss them
        inside = (centres >= w[0]) & (centres <= w[-1])
        assert np.all(np.isin(centres[inside], w)), "a band would take a band mean"
        assert np.all((centres[~inside] + step / 2 <= w[0]) | (centres[~inside] - step / 2 >= w[-1]))
    shape = colour.SpectralShape(start, end, step)
    sd = colour.SpectralDistribution(v, w)
    aligned = sd.copy().align(shape, interpolator=colour.LinearInterpolator,
                              extrapolator_kwargs={"method": "Constant", "left": 0, "right": 0})
    return aligned.values


def main() -> int:
    start, end, step = GRID
    shape = colour.SpectralShape(start, end, step)
    wl = shape.wavelengths

    cw, cv = read_table(SPECTRA / "observers" / "cie1931_2deg.csv")
    cmf_bands = np.stack([on_grid(cw, cv[:, i]) for i in range(3)], axis=1)
    cmfs = colour.MultiSpectralDistributions(cmf_bands, wl, labels=["x_bar", "y_bar", "z_bar"],
                                             name="CIE 1931 on the grid")
    reflectances = {}
    for p in PATCHES:
        w, v = read_table(SPECTRA / "colorchecker" / f"{p}.csv")
        reflectances[p] = colour.SpectralDistribution(on_grid(w, v[:, 0]), wl, name=p)
    perfect = colour.SpectralDistribution(np.ones(len(wl)), wl, name="perfect diffuser")

    rows = ["illuminant,patch,X,Y,Z,L,a,b,R8,G8,B8"]
    for name in ILLUMINANTS:
        w, v = read_table(SPECTRA / "illuminants" / f"{name}.csv")
        illuminant = colour.SpectralDistribution(on_grid(w, v[:, 0]), wl, name=name)
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
