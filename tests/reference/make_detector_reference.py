#!/usr/bin/env python3
"""Write the reference tables of the camera characterization and the film model, computed
independently of the C++ engine with numpy and colour-science 0.4.7:

    .venv/bin/python tests/reference/make_detector_reference.py

* tests/data/color/detectors/camera_reference.csv: for each camera, reference light (D65, A) and
  fit (white_preserving, least_squares): white-balance gains, the 3×3 raw → XYZ matrix row by row
  (numpy's lstsq for the plain fit; the constrained one from its KKT system, solved as one 4×4
  linear system per row, not the closed form the C++ uses), and rms / max ΔE2000 over the 24
  ColorChecker patches from colour.XYZ_to_Lab and colour.delta_E(method="CIE 2000").
* tests/data/color/detectors/film_reference.csv: the film model's projected XYZ (clear film
  Y = 1) of the 24 patches, the perfect white and a black under D65 and A, following the formulas
  of docs/color.md ("Detectors", "Film") from spectra/film/reversal.json and its tables.

All on the grid 300:740:5 with Riemann sums, spectra put on the grid by colour-science's linear
interpolation (tabulated values at the band centres, 0 outside the data; make_colorchecker_table.py).
"""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore", message=r".*related API features are not available.*")
import colour  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_colorchecker_table import PATCHES, REPO, SPECTRA, on_grid as values_on_grid, read_table  # noqa: E402

OUT = REPO / "tests" / "data" / "color" / "detectors"
STEP = 5.0
N = 89  # bands of 300:740:5
CAMERAS = ["nikon_d5100", "sigma_sd_merrill", "canon_eos_5d_mark_ii"]
LIGHTS = ["D65", "A"]


def on_grid(path: Path) -> np.ndarray:
    """Every value column of a library table on the grid (colour-science's resampling, as
    make_colorchecker_table.on_grid): [column][band]."""
    w, v = read_table(path)
    return np.stack([values_on_grid(w, v[:, i]) for i in range(v.shape[1])])


def number(x: float) -> str:
    return f"{x:.17g}"


def camera_table(cmf: np.ndarray, lights: dict, patches: np.ndarray) -> list[str]:
    rows = ["camera,illuminant,fit,g_r,g_g,g_b,m00,m01,m02,m10,m11,m12,m20,m21,m22,rms_de2000,max_de2000"]
    for cam in CAMERAS:
        sens = on_grid(SPECTRA / "cameras" / f"{cam}.csv") * STEP
        for light in LIGHTS:
            e = lights[light]
            raw_white = sens @ e
            gains = 1.0 / raw_white
            xyz_white = cmf @ e
            white = xyz_white / xyz_white[1]
            b = (patches * e) @ sens.T * gains  # [patch][channel], balanced raw
            t = (patches * e) @ cmf.T / xyz_white[1]  # [patch][XYZ]
            for fit in ["white_preserving", "least_squares"]:
                m = np.empty((3, 3))
                for i in range(3):
                    if fit == "least_squares":
                        m[i] = np.linalg.lstsq(b, t[:, i], rcond=None)[0]
                    else:
                        # KKT: [2BᵀB 1; 1ᵀ 0] [m; λ] = [2Bᵀt; white_i]
                        k = np.zeros((4, 4))
                        k[:3, :3] = 2.0 * b.T @ b
                        k[:3, 3] = 1.0
                        k[3, :3] = 1.0
                        rhs = np.concatenate([2.0 * b.T @ t[:, i], [white[i]]])
                        m[i] = np.linalg.solve(k, rhs)[:3]
                fitted = b @ m.T
                xy_w = colour.XYZ_to_xy(white)
                de = colour.delta_E(colour.XYZ_to_Lab(fitted, xy_w), colour.XYZ_to_Lab(t, xy_w), method="CIE 2000")
                rms = math.sqrt(float(np.mean(de**2)))
                rows.append(",".join([cam, light, fit] + [number(x) for x in (*gains, *m.ravel(), rms, de.max())]))
                print(f"  {cam:22s} {light:3s} {fit:16s} rms ΔE2000 {rms:.3f}, max {de.max():.3f}")
    return rows


def film_curve(x: float, c: dict) -> float:
    if x == -math.inf:
        return c["d_max"]
    r = c["d_max"] - c["d_min"]
    g = c["gamma"] / math.tanh(r / (4.0 * c["toe"]))
    u = g * (c["log_h0"] - x) + 0.5 * r
    b = c["toe"]
    return c["d_min"] + b * (np.logaddexp(0.0, u / b) - np.logaddexp(0.0, (u - r) / b))


def film_table(cmf: np.ndarray, lights: dict, patches: np.ndarray) -> list[str]:
    spec = json.loads((SPECTRA / "film" / "reversal.json").read_text())
    sens = on_grid(SPECTRA / f"{spec['sensitivity']}.csv") * STEP
    dyes_all = on_grid(SPECTRA / f"{spec['dye_density']}.csv")
    w, _ = read_table(SPECTRA / f"{spec['dye_density']}.csv")
    header = (SPECTRA / f"{spec['dye_density']}.csv").read_text().splitlines()[0].split(",")[1:]
    dyes = np.stack([dyes_all[header.index(layer["dye"])] for layer in spec["layers"]])
    base = on_grid(SPECTRA / f"{spec['base_density']}.csv")[0]
    lamp = on_grid(SPECTRA / f"{spec['lamp']}.csv")[0]
    balance = on_grid(SPECTRA / f"{spec['balance_illuminant']}.csv")[0]
    proj = cmf * lamp  # cmf already × Δλ

    def xyz_of(d_layers):
        t = 10.0 ** (-(d_layers @ dyes + base))
        return proj @ t

    d_min = np.array([layer["d_min"] for layer in spec["layers"]])
    y_clear = xyz_of(d_min)[1]
    rows = ["illuminant,patch,X,Y,Z"]
    for light in LIGHTS:
        white_radiance = lights[light] * 0.01 / math.pi
        h_bal = sens @ balance
        h_white = h_bal * (sens[1] @ white_radiance) / h_bal[1]
        samples = [(p, patches[i] * white_radiance) for i, p in enumerate(PATCHES)]
        samples += [("perfect_white", white_radiance), ("black", np.zeros(N))]
        for name, radiance in samples:
            h = sens @ radiance
            d = np.array([film_curve(math.log10(h[i] / h_white[i]) if h[i] > 0 else -math.inf, spec["layers"][i])
                          for i in range(3)])
            xyz = xyz_of(d) / y_clear
            rows.append(",".join([light, name] + [number(x) for x in xyz]))
    return rows


def main() -> int:
    cmf = on_grid(SPECTRA / "observers" / "cie1931_2deg.csv") * STEP
    lights = {k: on_grid(SPECTRA / "illuminants" / f"{k}.csv")[0] for k in LIGHTS}
    patches = np.stack([on_grid(SPECTRA / "colorchecker" / f"{p}.csv")[0] for p in PATCHES])
    assert cmf.shape == (3, N) and patches.shape == (24, N)
    OUT.mkdir(parents=True, exist_ok=True)
    for name, rows in [("camera_reference.csv", camera_table(cmf, lights, patches)),
                       ("film_reference.csv", film_table(cmf, lights, patches))]:
        (OUT / name).write_text("\n".join(rows) + "\n", encoding="ascii", newline="\n")
        print(f"wrote {(OUT / name).relative_to(REPO)}: {len(rows) - 1} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
