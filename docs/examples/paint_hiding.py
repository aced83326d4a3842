#!/usr/bin/env python3
"""Hiding power from a rendered cube: the contrast ratio of scenes/paints.json's drawdown and the
film thickness at which it reaches 98 % (the hiding criterion of ISO 6504-1).

The drawdown is a wedge of one paint, 0 µm at its left end to 150 µm at its right
(materials.drawdown_over_*.layers.0: thickness 1.5e-4 m × assets/paint_wedge.png, a linear ramp
of 256 texels), over a white card stripe above a black one. The chart is rendered straight on by
an orthographic camera of one pixel per millimetre, so that column c sees u = (c + 0.5)/520 of
the wedge. The contrast ratio at each column is the luminance (CIE 1931 ȳ) over black divided by
the luminance over white — the same light falls on both, so this is R₀/R_w of the film's
luminance factors. Run from the repository root:

    .venv/bin/python docs/examples/paint_hiding.py

It prints the contrast ratio at a few thicknesses, the thickness at 98 % and the spreading rate
(m² of wall per litre of dry film) that gives it. `hiding()` returns the same numbers.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import metamer

WEDGE_M = 1.5e-4   # the layer's "thickness"; the map scales it by 0 … 1
TEXELS = 256       # paint_wedge.png's width; texel i holds i/255, centred at u = (i + 0.5)/256
COLUMNS = 520      # the chart is 0.52 m wide: one column per millimetre


def wedge_thickness_m(u):
    """The film thickness the bilinear texture lookup gives at u (texel centres hold i/255)."""
    return WEDGE_M * np.clip((u * TEXELS - 0.5) / (TEXELS - 1), 0.0, 1.0)


def hiding(scene="scenes/paints.json", criterion=0.98):
    # The chart straight on: y 0.06 … 0.16 m (black stripe below 0.11, white above), x ±0.26 m.
    doc = json.loads(Path(scene).read_text())
    doc["camera"] = {"projection": "orthographic", "position": [0, 0.11, 1], "target": [0, 0.11, 0],
                     "up": [0, 1, 0], "height_m": 0.1, "width": COLUMNS, "height": 100}
    r = metamer.render(doc, base_dir=str(Path(scene).parent), name="paints", write="cube")
    import warnings
    warnings.filterwarnings("ignore", module="colour")  # its note that matplotlib is absent
    import colour  # the observer, from colour-science (independent of the engine)
    shape = colour.SpectralShape(r.wavelengths_nm[0], r.wavelengths_nm[-1], r.wavelengths_nm[1] - r.wavelengths_nm[0])
    ybar = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape).values[:, 1]
    luminance = r.cube @ ybar                     # rows × columns, relative
    over_white, over_black = luminance[25], luminance[75]   # y = 0.135 and 0.085 m
    u = (np.arange(COLUMNS) + 0.5) / COLUMNS
    thickness = wedge_thickness_m(u)
    ratio = over_black / over_white
    # Leave out the half texel at each end, where the repeating texture blends its two ends.
    inside = (u > 1.0 / TEXELS) & (u < 1.0 - 1.0 / TEXELS)
    thickness, ratio = thickness[inside], ratio[inside]
    above = np.nonzero(ratio >= criterion)[0]
    if above.size == 0:
        return thickness, ratio, None
    i = above[0]
    # Linear interpolation between the two columns that straddle the criterion.
    t = (criterion - ratio[i - 1]) / (ratio[i] - ratio[i - 1])
    return thickness, ratio, thickness[i - 1] + t * (thickness[i] - thickness[i - 1])


def main():
    thickness, ratio, at_criterion = hiding()
    for um in (5, 10, 20, 40, 80, 120):
        i = int(np.argmin(np.abs(thickness - um * 1e-6)))
        print(f"{thickness[i] * 1e6:6.1f} µm: contrast ratio {ratio[i]:.4f}")
    if at_criterion is None:
        print("the film does not reach 98 % on this wedge")
        return
    print(f"98 % hiding at {at_criterion * 1e6:.1f} µm of dry film: a spreading rate of "
          f"{1e-3 / at_criterion:.1f} m²/L")


if __name__ == "__main__":
    main()
