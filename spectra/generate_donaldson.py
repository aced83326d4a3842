#!/usr/bin/env python3
"""Write the library's Donaldson (bispectral re-radiation) matrices: a measured-style model of a
paint holding two fluorophores, spectra/fluorescent/brightened_pink_{donaldson,base}.csv.

Run from anywhere with the project's Python (numpy; generate.py, whose band models this reuses,
also imports colour-science):

    .venv/bin/python spectra/generate_donaldson.py

The model, its parameters and sources are in spectra/README.md, "Donaldson matrices". Output is
deterministic (no randomness, fixed rounding, '\\n' line ends).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from generate import (  # noqa: E402
    BRIGHTENER_ABS, BRIGHTENER_EM, HC_EV_NM, PAINT_GROUND, PINK_ABS, PINK_EM, ROOT, absorbance, fmt_number,
    grid, peak_nm, write_csv,
)

KT_EV = 0.025693  # k·T at 298.15 K in eV

# The two fluorophores of the paint layer: (absorbance bands, emission bands, absorbance scale,
# quantum yield). Bands as in generate.py: (centre nm, FWHM eV, peak absorbance or weight).
FLUOROPHORES = {
    "brightener": (BRIGHTENER_ABS, BRIGHTENER_EM, 0.8, 0.80),
    "pink": (PINK_ABS, PINK_EM, 0.7, 0.85),
}

MATRIX_GRID = (300.0, 780.0, 5.0) # λin and λout samples, nm, as a bispectrometer might report them
FINE_GRID = (250, 900, 0.25)  # for the per-row normalization integrals


def emission_shape(wl, bands):
    """Relative emission: sum of Gaussian-in-energy bands (centre nm, FWHM eV, weight)."""
    e = HC_EV_NM / wl
    out = np.zeros(wl.shape)
    for centre, fwhm, weight in bands:
        s = fwhm / 2.3548200450309493
        out += weight * np.exp(-0.5 * ((e - HC_EV_NM / centre) / s) ** 2)
    return out


def model():
    wl = grid(*MATRIX_GRID)
    fine = grid(*FINE_GRID)
    per_dye = {name: scale * absorbance(wl, abs_bands) for name, (abs_bands, _, scale, _) in FLUOROPHORES.items()}
    total = sum(per_dye.values())
    a_total = 1.0 - 10.0 ** (-total)  # absorptance of the layer
    d = np.zeros((wl.size, wl.size))  # [λin][λout], nm⁻¹
    for name, (_, em_bands, _, yield_) in FLUOROPHORES.items():
        # Each fluorophore absorbs its share of what the layer absorbs.
        a = a_total * per_dye[name] / total
        shape = emission_shape(wl, em_bands)
        shape_fine = emission_shape(fine, em_bands)
        for i, li in enumerate(wl):
            # Kasha–Vavilov: the emission shape and yield do not depend on the exciting
            # wavelength, except that emitting a photon of more energy than the absorbed one
            # (anti-Stokes) needs thermal energy: a Boltzmann factor exp(−ΔE/kT) for ΔE > 0. Each
            # row is renormalized so the fluorophore still emits Φ photons per photon absorbed.
            boltz = np.minimum(1.0, np.exp(-(HC_EV_NM / wl - HC_EV_NM / li) / KT_EV))
            boltz_fine = np.minimum(1.0, np.exp(-(HC_EV_NM / fine - HC_EV_NM / li) / KT_EV))
            norm = np.trapezoid(shape_fine * boltz_fine, fine)  # nm
            photons = shape * boltz / norm  # nm⁻¹, unit area
            d[i, :] += yield_ * a[i] * photons * li / wl  # photons → energy: × λin/λout
    base = PAINT_GROUND * (1.0 - a_total)
    return wl, d, a_total, base, per_dye


def write_matrix(rel: str, wl, d, sig: int = 6, decimals: int = 9) -> None:
    path = ROOT / rel
    lines = ["excitation_nm/emission_nm," + ",".join(f"{w:g}" for w in wl)]
    for i, w in enumerate(wl):
        lines.append(f"{w:g}," + ",".join(fmt_number(v, sig, decimals) for v in d[i]))
    path.write_text("\n".join(lines) + "\n", encoding="ascii", newline="\n")
    print(f"wrote {rel:44s} {wl[0]:g}-{wl[-1]:g} nm step {wl[1] - wl[0]:g} nm on both axes, "
          f"{d.shape[0]}×{d.shape[1]} values")


def main() -> int:
    wl, d, a_total, base, per_dye = model()
    assert np.all(d >= 0) and np.all(np.isfinite(d))
    # Photons re-emitted per photon absorbed at λin, over the matrix's own λout range.
    step = wl[1] - wl[0]
    yield_in = (d * wl[None, :] / wl[:, None]).sum(axis=1) * step
    assert np.all(np.round(base, 6) + np.round(a_total, 6) <= 1.0 + 1e-12)
    assert np.all(base + yield_in <= 1.0), "reflects and re-emits more than it receives"
    s = np.linalg.svd(d, compute_uv=False)
    rank1 = np.sqrt(np.sum(s[1:] ** 2) / np.sum(s ** 2))
    print(f"  absorptance peak {a_total.max():.3f} at {peak_nm(wl, a_total):g} nm; brightener absorbance peak "
          f"{per_dye['brightener'].max():.3f}, pink {per_dye['pink'].max():.3f}")
    print(f"  photons re-emitted per photon received: max {yield_in.max():.3f} at {peak_nm(wl, yield_in):g} nm; "
          f"max(base + that) {np.max(base + yield_in):.3f}")
    print(f"  singular values / the first: {', '.join(f'{v / s[0]:.2e}' for v in s[1:5])}; the best rank-one "
          f"approximation leaves {rank1:.1%} of the matrix (Frobenius)")
    for li in (360, 450, 540):
        row = d[int(round((li - wl[0]) / step))]
        print(f"  excited at {li} nm: emission peak at {peak_nm(wl, row):g} nm, "
              f"share above 520 nm {row[wl > 520].sum() / row.sum():.1%}")
    write_matrix("fluorescent/brightened_pink_donaldson.csv", wl, d)
    fine = grid(300, 830, 1)
    per_fine = [scale * absorbance(fine, b) for (b, _, scale, _) in FLUOROPHORES.values()]
    base_fine = PAINT_GROUND * 10.0 ** (-sum(per_fine))
    write_csv("fluorescent/brightened_pink_base.csv", fine, {"value": base_fine}, sig=7, decimals=6)
    return 0


if __name__ == "__main__":
    sys.exit(main())
