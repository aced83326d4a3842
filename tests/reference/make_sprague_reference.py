#!/usr/bin/env python3
"""Write tests/data/spectral/sprague_reference.csv: colour-science 0.4.7's Sprague (1880)
interpolation (CIE 167:2005), the oracle of engine/spectral/resampling_test.cpp
(Resample.SpragueMatchesColourScience).

    .venv/bin/python tests/reference/make_sprague_reference.py

Two data sets: the library's CIE D65 (300–780 nm, 5 nm) and a short synthetic set of 7 values at
10 nm (so the standard's extrapolated end points enter every interval). For each, the data rows
(kind "data") and colour.algebra.SpragueInterpolator at every whole nm and at offset points
(kind "at"). Floats with 17 significant digits.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore", message=r".*related API features are not available.*")
from colour.algebra import SpragueInterpolator  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
OUT = REPO / "tests" / "data" / "spectral" / "sprague_reference.csv"


def main() -> None:
    d65 = np.genfromtxt(REPO / "spectra" / "illuminants" / "D65.csv", delimiter=",", skip_header=1)
    sets = {
        "D65": (d65[:, 0], d65[:, 1]),
        "short10nm": (np.arange(400.0, 461.0, 10.0), np.array([0.12, 0.55, 0.31, 0.87, 0.44, 0.61, 0.29])),
    }
    rows = ["set,kind,wavelength_nm,value"]
    for name, (w, v) in sets.items():
        for x, y in zip(w, v):
            rows.append(f"{name},data,{x:.17g},{y:.17g}")
        interp = SpragueInterpolator(w, v)
        at = np.concatenate([np.arange(w[0], w[-1] + 1e-9, 1.0), w[:-1] + 2.3, w[:-1] + 0.25 * (w[1] - w[0])])
        for x in at:
            rows.append(f"{name},at,{x:.17g},{float(interp(x)):.17g}")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(rows) + "\n", encoding="ascii", newline="\n")
    print(f"wrote {OUT.relative_to(REPO)} ({len(rows) - 1} rows)")


if __name__ == "__main__":
    main()
