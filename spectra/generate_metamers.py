#!/usr/bin/env python3
"""Generate the metameric pair of spectra/metamers/ and its expected colorimetry.

Run from anywhere with the project's Python (colour-science 0.4.7 and numpy, no SciPy):

    .venv/bin/python spectra/generate_metamers.py

Writes

* spectra/metamers/base.csv, metamer.csv: the pair on 300-830 nm at 1 nm (what scenes use as
  `metamers/base` and `metamers/metamer`);
* spectra/metamers/base_380_780_5nm.csv, metamer_380_780_5nm.csv: the same two functions sampled
  at 5 nm over 380-780 nm, for tools that take the usual CIE 5 nm tables;
* tests/data/representations/metamers_colorimetry.csv and metamers_delta_e.csv: XYZ, CIELAB,
  ΔE and metamerism indices of the pair on three render grids, as the engine computes them.

Method (spectra/README.md, "Metameric pair"): base(λ) is a smooth analytic reflectance; a smooth
generator g(λ) is split, after Wyszecki & Stiles, into a "fundamental" part that carries all of
its tristimulus values and a metameric black b(λ) that carries none; metamer = base + a·b/max|b|.
The black is made exactly null on the engine's default grid (300:740:5, its default resampling —
here the 1 nm data's values at the band centres —, Riemann sums, CIE 1931 observer, D65) by
building the constraint with the engine's resampling operator, written again here from
engine/spectral/resampling.h.

Deterministic: no randomness, fixed rounding, fixed line endings. generate_quadrature.py imports
the spectrum helpers below.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore", message=r".*related API features are not available.*")
import colour  # noqa: E402

ROOT = Path(__file__).resolve().parent  # spectra/
REPO = ROOT.parent
TESTDATA = REPO / "tests" / "data" / "representations"

written: list[Path] = []

# --------------------------------------------------------------------------------------------
# Spectra as the engine sees them


def grid(start: float, end: float, step: float) -> np.ndarray:
    n = int(round((end - start) / step)) + 1
    return start + step * np.arange(n)


def parse_grid(spec: str) -> tuple[float, float, float]:
    a, b, c = (float(x) for x in spec.split(":"))
    return a, b, c


def load_table(rel: str) -> tuple[np.ndarray, np.ndarray]:
    """A library CSV (path below spectra/ without .csv): wavelengths and an (n, columns) array."""
    d = np.loadtxt(ROOT / f"{rel}.csv", delimiter=",", skiprows=1, ndmin=2)
    return d[:, 0], d[:, 1:]


def load_spectrum(rel: str) -> tuple[np.ndarray, np.ndarray]:
    w, v = load_table(rel)
    assert v.shape[1] == 1, rel
    return w, v[:, 0]


def at(w: np.ndarray, v: np.ndarray, x) -> np.ndarray:
    """Spectrum::at: linear between samples, 0 outside the data."""
    x = np.asarray(x, dtype=float)
    return np.where((x >= w[0]) & (x <= w[-1]), np.interp(x, w, v), 0.0)


def _interp_row(w: np.ndarray, x: float) -> dict[int, float]:
    """Weights of the samples in the linear interpolation at x (w[0] <= x <= w[-1])."""
    j = int(np.searchsorted(w, x, side="right")) - 1
    j = min(max(j, 0), len(w) - 2)
    t = (x - w[j]) / (w[j + 1] - w[j])
    return {j: 1.0 - t, j + 1: t}


def _band_mean_row(w: np.ndarray, c: float, step: float) -> np.ndarray:
    """The mean over [c - Δλ/2, c + Δλ/2] of the piecewise-linear data (0 outside), plus, when c
    lies inside the data, the end value held over the part of the band beyond the data's end."""
    row = np.zeros(len(w))
    lo, hi = c - step / 2, c + step / 2
    a, b = max(lo, w[0]), min(hi, w[-1])
    if b > a:
        xs = np.concatenate(([a], w[(w > a) & (w < b)], [b]))
        for k in range(len(xs) - 1):
            half = 0.5 * (xs[k + 1] - xs[k])
            for x in (xs[k], xs[k + 1]):
                for j, f in _interp_row(w, x).items():
                    row[j] += half * f
    if w[0] <= c <= w[-1]:
        if lo < w[0]:
            row[0] += w[0] - lo
        if hi > w[-1]:
            row[-1] += hi - w[-1]
    return row / step


def band_matrix(w: np.ndarray, grid_spec: str, rule: str = "interpolate") -> np.ndarray:
    """The engine's resampling (engine/spectral/resampling.h, docs/physics.md "Resampling") as a
    matrix, written again here: band values on the grid = band_matrix(w, grid) @ values, for data
    given at wavelengths w. Band i (centre c): the tabulated value when c is a data point; the band
    mean (_band_mean_row) when the grid step exceeds the spacing of the data interval around c
    (or of the nearest end interval outside the data); else the linear interpolant at c (0 outside
    the data). rule="band-mean" takes the band mean everywhere."""
    start, end, step = parse_grid(grid_spec)
    centres = grid(start, end, step)
    m = np.zeros((len(centres), len(w)))
    for i, c in enumerate(centres):
        if rule == "band-mean":
            m[i] = _band_mean_row(w, c, step)
            continue
        hit = np.nonzero(np.abs(w - c) <= 1e-9)[0]
        if len(hit):
            m[i, hit[0]] = 1.0
            continue
        j = min(max(int(np.searchsorted(w, c)) - 1, 0), len(w) - 2)
        if step > (w[j + 1] - w[j]) * (1 + 1e-9):
            m[i] = _band_mean_row(w, c, step)
        elif w[0] <= c <= w[-1]:
            for k, f in _interp_row(w, c).items():
                m[i, k] = f
    return m


def resample(w: np.ndarray, v: np.ndarray, grid_spec: str) -> np.ndarray:
    return band_matrix(w, grid_spec) @ v


class Colorimeter:
    """Relative CIE 1931 XYZ of reflectances under one light on one grid, as the engine's display
    path computes them for a surface lit head-on: light, reflectance and observer on the grid by
    the engine's rule (band_matrix), Riemann sum (q_b = Δλ), scaled so that the perfect white
    diffuser has Y = 100."""

    def __init__(self, light: str, grid_spec: str):
        self.grid = grid_spec
        self.step = parse_grid(grid_spec)[2]
        ow, cmf = load_table("observers/cie1931_2deg")
        bm = band_matrix(ow, grid_spec)
        self.cmf = np.stack([bm @ cmf[:, k] for k in range(3)])  # 3 x bands
        lw, lv = load_spectrum(f"illuminants/{light}")
        self.light = resample(lw, lv, grid_spec)
        self.k = 100.0 / (self.cmf[1] @ self.light * self.step)
        self.white = self.xyz_bands(np.ones_like(self.light))

    def xyz_bands(self, rho_bands: np.ndarray) -> np.ndarray:
        return self.k * self.step * (self.cmf @ (self.light * rho_bands))

    def xyz(self, w: np.ndarray, v: np.ndarray) -> np.ndarray:
        return self.xyz_bands(resample(w, v, self.grid))

    def constraint(self, w: np.ndarray) -> np.ndarray:
        """3 x len(w): the XYZ of data given at w is constraint(w) @ values."""
        return self.k * self.step * (self.cmf * self.light) @ band_matrix(w, self.grid)


def lab(xyz: np.ndarray, white: np.ndarray) -> np.ndarray:
    """CIELAB (colour-science) of XYZ relative to the white's XYZ (same scale)."""
    return colour.XYZ_to_Lab(np.asarray(xyz) / white[1], colour.XYZ_to_xy(white))


def de00(lab1, lab2) -> float:
    return float(colour.delta_E(lab1, lab2, method="CIE 2000"))


def deab(lab1, lab2) -> float:
    return float(colour.delta_E(lab1, lab2, method="CIE 1976"))


def fmt(v: float, sig: int) -> str:
    return f"{float(v) + 0.0:.{sig}g}"


def write_csv(path: Path, header: list[str], rows: list[list], sig: int = 8) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [",".join(header)]
    for r in rows:
        lines.append(",".join(x if isinstance(x, str) else fmt(x, sig) for x in r))
    path.write_text("\n".join(lines) + "\n", encoding="ascii", newline="\n")
    written.append(path)
    print(f"wrote {path.relative_to(REPO)}  ({len(rows)} rows)")


def write_spectrum(rel: str, w: np.ndarray, v: np.ndarray, sig: int = 8) -> None:
    write_csv(ROOT / f"{rel}.csv", ["wavelength_nm", "value"],
              [[f"{x:g}", y] for x, y in zip(w, v)], sig=sig)


# --------------------------------------------------------------------------------------------
# The pair

PAIR_WL = grid(300, 830, 1)  # nm: the library files' samples
DEFAULT_GRID = "300:740:5"  # the engine's default grid: the black is exactly null on it
GRIDS = ["300:740:5", "380:780:5", "360:830:1"]  # where the expected values are computed

BASE_MEAN, BASE_SWING, BASE_MID, BASE_WIDTH = 0.40, 0.10, 575.0, 50.0
GEN_CENTRE, GEN_SIGMA, GEN_PERIOD = 560.0, 90.0, 160.0
BLACK_AMPLITUDE = 0.15  # max |b(λ)| over 300-830 nm


def base_reflectance(wl: np.ndarray) -> np.ndarray:
    """A light warm grey (beige): 0.30 in the violet rising smoothly to 0.50 in the red."""
    return BASE_MEAN + BASE_SWING * np.tanh((wl - BASE_MID) / BASE_WIDTH)


def generator(wl: np.ndarray) -> np.ndarray:
    """The smooth spectrum whose metameric black we take: a cosine of period 160 nm under a
    Gaussian envelope (σ = 90 nm), both centred at 560 nm."""
    env = np.exp(-0.5 * ((wl - GEN_CENTRE) / GEN_SIGMA) ** 2)
    return env * np.cos(2.0 * np.pi * (wl - GEN_CENTRE) / GEN_PERIOD)


def cmf_on(wl: np.ndarray) -> np.ndarray:
    ow, cmf = load_table("observers/cie1931_2deg")
    return np.stack([at(ow, cmf[:, k], wl) for k in range(3)])


def metameric_black(wl: np.ndarray, col: Colorimeter) -> tuple[np.ndarray, np.ndarray]:
    """b = g − H·c with H = (x̄, ȳ, z̄) sampled at wl and c such that C·b = 0, C the 3 x N matrix
    that gives the XYZ (under the colorimeter's light, on its grid) of data sampled at wl.

    H·c is the combination of the colour-matching functions that has the same tristimulus values
    as g: g's "fundamental metamer" in the D65-weighted inner product Σ f·h·E (see the README).
    Returns (b normalized to max |b| = 1, c before normalization)."""
    C = col.constraint(wl)
    g = generator(wl)
    H = cmf_on(wl)
    c = np.linalg.solve(C @ H.T, C @ g)
    b = g - H.T @ c
    return b / np.abs(b).max(), c


def build_pair() -> dict:
    col = Colorimeter("D65", DEFAULT_GRID)
    bhat, c = metameric_black(PAIR_WL, col)
    base = base_reflectance(PAIR_WL)
    metamer = base + BLACK_AMPLITUDE * bhat
    # Round as written (8 significant digits), then check the rounded files.
    base = np.array([float(fmt(x, 8)) for x in base])
    metamer = np.array([float(fmt(x, 8)) for x in metamer])
    assert base.min() >= 0.01 and base.max() <= 0.99
    assert metamer.min() >= 0.01 and metamer.max() <= 0.99, (metamer.min(), metamer.max())
    write_spectrum("metamers/base", PAIR_WL, base)
    write_spectrum("metamers/metamer", PAIR_WL, metamer)
    sel = (PAIR_WL >= 380) & (PAIR_WL <= 780) & (np.mod(PAIR_WL, 5) == 0)
    write_spectrum("metamers/base_380_780_5nm", PAIR_WL[sel], base[sel])
    write_spectrum("metamers/metamer_380_780_5nm", PAIR_WL[sel], metamer[sel])
    black = metamer - base
    info = {
        "fundamental_coefficients": c,
        "base_range": (base.min(), base.max()),
        "metamer_range": (metamer.min(), metamer.max()),
        "black_range": (black.min(), black.max()),
        "black_zero_crossings": [float(PAIR_WL[i]) for i in range(len(black) - 1)
                                 if black[i] * black[i + 1] < 0],
        "black_rms_second_difference": float(np.sqrt(np.mean(np.diff(black, 2) ** 2))),
    }
    return info


# --------------------------------------------------------------------------------------------
# Colorimetry of the written pair


def metamerism_index(ref: Colorimeter, test: Colorimeter, s1, s2) -> tuple[float, float]:
    """CIE special metamerism index, change in illuminant, with the multiplicative correction:
    X'₂ₜ = X₂ₜ·X₁ᵣ/X₂ᵣ (and Y, Z alike), then ΔE between specimen 1 and the corrected specimen 2
    under the test illuminant. Returns (ΔE*ab, ΔE00)."""
    x1r, x2r = ref.xyz(*s1), ref.xyz(*s2)
    x1t, x2t = test.xyz(*s1), test.xyz(*s2)
    x2c = x2t * x1r / x2r
    l1, l2 = lab(x1t, test.white), lab(x2c, test.white)
    return deab(l1, l2), de00(l1, l2)


def colorimetry(info: dict) -> list[str]:
    pair = {name: load_spectrum(f"metamers/{name}") for name in ("base", "metamer")}
    pair5 = {name: load_spectrum(f"metamers/{name}_380_780_5nm") for name in ("base", "metamer")}
    summary = []
    rows_c, rows_d = [], []
    for g in GRIDS:
        cols = {ill: Colorimeter(ill, g) for ill in ("D65", "A", "FL2", "FL11")}
        for ill in ("D65", "A", "FL2", "FL11"):
            col = cols[ill]
            rows_c.append([g, ill, "white", *col.white, *lab(col.white, col.white)])
            labs = {}
            for name, (w, v) in pair.items():
                xyz = col.xyz(w, v)
                labs[name] = lab(xyz, col.white)
                rows_c.append([g, ill, name, *xyz, *labs[name]])
            d00, dab = de00(labs["base"], labs["metamer"]), deab(labs["base"], labs["metamer"])
            if ill == "D65":
                mi_ab, mi_00 = 0.0, 0.0
                mi_text = "reference"
            else:
                mi_ab, mi_00 = metamerism_index(cols["D65"], col, pair["base"], pair["metamer"])
                mi_text = f"MI ΔE*ab {mi_ab:.4f}, ΔE00 {mi_00:.4f}"
            w5 = [de00(lab(col.xyz(*pair5["base"]), col.white),
                       lab(col.xyz(*pair5["metamer"]), col.white))]
            rows_d.append([g, ill, d00, dab, mi_ab if ill != "D65" else "",
                           mi_00 if ill != "D65" else "", w5[0]])
            summary.append(f"{g:10s} {ill:5s} ΔE00 {d00:.3g}  ΔE*ab {dab:.3g}  {mi_text};"
                           f"  5 nm files ΔE00 {w5[0]:.3g}")
    header = ["grid", "illuminant", "sample", "X", "Y", "Z", "L", "a", "b"]
    write_csv(TESTDATA / "metamers_colorimetry.csv", header, rows_c, sig=17)
    write_csv(TESTDATA / "metamers_delta_e.csv",
              ["grid", "illuminant", "dE00", "dEab", "MI_dEab", "MI_dE00", "dE00_5nm_files"],
              rows_d, sig=17)
    return summary


def colour_science_check() -> list[str]:
    """Independent cross-check: colour-science's own integration (its D65 table and A at 1 nm,
    the pair as 1 nm SpectralDistributions)."""
    out = []
    pair = {n: load_spectrum(f"metamers/{n}") for n in ("base", "metamer")}
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    for ill in ("D65", "A"):
        sd_ill = colour.SDS_ILLUMINANTS[ill]
        labs = []
        for n, (w, v) in pair.items():
            sd = colour.SpectralDistribution(dict(zip(w, v)), name=n)
            xyz = colour.sd_to_XYZ(sd, cmfs, sd_ill, method="Integration",
                                   shape=colour.SpectralShape(360, 780, 1))
            white = colour.sd_to_XYZ(colour.SpectralDistribution(dict(zip(w, np.ones_like(v)))),
                                     cmfs, sd_ill, method="Integration",
                                     shape=colour.SpectralShape(360, 780, 1))
            labs.append(lab(xyz, white))
        out.append(f"colour-science sd_to_XYZ (Integration, 360-780 nm at 1 nm) {ill}: "
                   f"ΔE00 {de00(*labs):.3g}")
    return out


def main() -> int:
    print(f"colour-science {colour.__version__}, numpy {np.__version__}")
    info = build_pair()
    for k, v in info.items():
        print(f"  {k}: {v}")
    for line in colorimetry(info) + colour_science_check():
        print("  " + line)
    print(f"{len(written)} files")
    return 0


if __name__ == "__main__":
    sys.exit(main())
