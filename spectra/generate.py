#!/usr/bin/env python3
"""Regenerate every CSV file of the Metamer spectra library.

Run from anywhere with the project's Python (colour-science 0.4.7 and numpy):

    .venv/bin/python spectra/generate.py

Tabulated data (CIE illuminants, CIE observers, ColorChecker) are taken from colour-science's
datasets unchanged. Everything else (blacklight, fluorescent dyes, metals, illuminant E) is a model
computed here; spectra/README.md documents each model's formula, parameters and sources.

The output is deterministic: no randomness, fixed rounding, fixed line endings. Each file is
`wavelength_nm,<columns>` followed by one sample per line.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

# colour-science warns at import time about optional packages it does not need here.
warnings.filterwarnings("ignore", message=r".*related API features are not available.*")
import colour  # noqa: E402

ROOT = Path(__file__).resolve().parent
HC_EV_NM = 1239.841984  # h·c in eV·nm: photon energy E[eV] = HC_EV_NM / λ[nm]
FWHM_TO_SIGMA = 1.0 / (2.0 * np.sqrt(2.0 * np.log(2.0)))  # σ = FWHM / 2.3548

written: list[Path] = []


# --------------------------------------------------------------------------------------------
# Output


def fmt_number(v: float, sig: int, decimals: int | None) -> str:
    """`sig` significant digits; with `decimals`, first round to that many decimal places (so
    model tails become a clean 0 instead of 1e-40)."""
    if decimals is not None:
        v = round(float(v), decimals)
    v = float(v) + 0.0  # turn -0.0 into 0.0
    return f"{v:.{sig}g}"


def write_csv(rel: str, wavelengths, columns: dict[str, np.ndarray], sig: int = 7,
              decimals: int | None = None) -> None:
    path = ROOT / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    wl = np.asarray(wavelengths, dtype=float)
    cols = [np.asarray(c, dtype=float) for c in columns.values()]
    assert all(c.shape == wl.shape for c in cols), rel
    assert np.all(np.diff(wl) > 0), rel
    assert all(np.all(np.isfinite(c)) for c in cols), rel
    lines = ["wavelength_nm," + ",".join(columns.keys())]
    for i, w in enumerate(wl):
        fields = [f"{w:g}"] + [fmt_number(c[i], sig, decimals) for c in cols]
        lines.append(",".join(fields))
    path.write_text("\n".join(lines) + "\n", encoding="ascii", newline="\n")
    written.append(path)
    step = np.unique(np.round(np.diff(wl), 6))
    step_text = f"{step[0]:g}" if len(step) == 1 else "variable"
    print(f"wrote {rel:36s} {wl[0]:g}-{wl[-1]:g} nm step {step_text:>4s}  "
          f"{len(wl):5d} rows  {len(cols)} column(s)")


def grid(start: float, end: float, step: float) -> np.ndarray:
    n = int(round((end - start) / step)) + 1
    return start + step * np.arange(n)


def write_sd(rel: str, sd, **kw) -> None:
    write_csv(rel, sd.wavelengths, {"value": sd.values}, **kw)


# --------------------------------------------------------------------------------------------
# Model building blocks


def gaussian_nm(wl, centre_nm, fwhm_nm):
    """Unit-peak Gaussian in wavelength."""
    s = fwhm_nm * FWHM_TO_SIGMA
    return np.exp(-0.5 * ((wl - centre_nm) / s) ** 2)


def gaussian_ev(wl, centre_nm, fwhm_ev):
    """Unit-peak Gaussian in photon energy (the natural shape of a broad molecular band),
    evaluated at wavelengths wl (nm)."""
    e = HC_EV_NM / wl
    e0 = HC_EV_NM / centre_nm
    s = fwhm_ev * FWHM_TO_SIGMA
    return np.exp(-0.5 * ((e - e0) / s) ** 2)


def absorbance(wl, bands):
    """Decadic absorbance: sum of Gaussian-in-energy bands (centre_nm, fwhm_ev, peak)."""
    return sum(peak * gaussian_ev(wl, c, f) for c, f, peak in bands)


def absorptance_from_absorbance(a_dec):
    """Fraction of the incident light the dye layer absorbs: 1 - 10^-A (saturates below 1)."""
    return 1.0 - 10.0 ** (-a_dec)


def emission(wl, bands):
    """Relative emission: sum of Gaussian-in-energy bands (centre_nm, fwhm_ev, weight),
    normalized to peak 1 on the output grid."""
    e = sum(w * gaussian_ev(wl, c, f) for c, f, w in bands)
    return e / e.max()


def peak_nm(wl, v):
    return float(wl[int(np.argmax(v))])


# --------------------------------------------------------------------------------------------
# Illuminants


def illuminants() -> None:
    cie = colour.SDS_ILLUMINANTS
    # CIE standard illuminant A from its defining Planck formula (T = 2848 K with c2 = 1.435e-2
    # m·K, i.e. 2856 K on the ITS-90 scale), normalized to 100 at 560 nm.
    a = colour.sd_CIE_standard_illuminant_A(colour.SpectralShape(300, 830, 1))
    assert abs(a[560] - 100.0) < 1e-9
    write_sd("illuminants/A.csv", a, sig=8)
    for key in ["D50", "D65"] + [f"FL{i}" for i in range(1, 13)]:
        write_sd(f"illuminants/{key}.csv", cie[key], sig=7)
    wl = grid(200, 2500, 10)
    write_csv("illuminants/E.csv", wl, {"value": np.full(wl.shape, 100.0)})
    # The CIE daylight components S0, S1, S2 (CIE 15:2004 Table T.2), from which a scene's
    # {"daylight_cct": T} is built (spectral/illuminant_models.h).
    from colour.colorimetry.datasets.illuminants import SDS_BASIS_FUNCTIONS_CIE_ILLUMINANT_D_SERIES as basis
    write_csv("illuminants/daylight_components.csv", basis["S0"].wavelengths,
              {"s0": basis["S0"].values, "s1": basis["S1"].values, "s2": basis["S2"].values}, sig=7)
    blacklight()


# Black-light-blue (BLB) fluorescent tube model. See README "blacklight".
BLB_PHOSPHOR = (368.0, 18.0)  # SrB4O7:Eu2+ band: centre nm, FWHM nm
BLB_LINE_FWHM = 1.5  # nm: spectrometer-like width given to the Hg lines
# Hg lines passed (partly) by the Wood's-glass envelope: wavelength nm, area relative to the
# phosphor band's area.
BLB_HG_LINES = [
    (334.15, 0.003),
    (365.02, 0.040),
    (404.66, 0.015),
    (435.83, 0.008),
]


def blacklight_model(wl):
    """The model's relative SPD at `wl` (nm): the phosphor band plus the Hg lines, scaled so that
    its peak (the 365 nm line) is 100."""
    c, fwhm = BLB_PHOSPHOR
    band_area = fwhm * FWHM_TO_SIGMA * np.sqrt(2 * np.pi)  # area of the unit-peak band
    line_area_1 = BLB_LINE_FWHM * FWHM_TO_SIGMA * np.sqrt(2 * np.pi)

    def raw(x):
        v = gaussian_nm(x, c, fwhm)
        for lam, rel_area in BLB_HG_LINES:
            v = v + (rel_area * band_area / line_area_1) * gaussian_nm(x, lam, BLB_LINE_FWHM)
        return v

    peak = raw(np.arange(300.0, 830.0, 0.001)).max()
    return 100.0 * raw(np.asarray(wl, dtype=float)) / peak


def blacklight() -> None:
    # Tabulated as the CIE tabulates its fluorescent lamps: every 5 nm, each value the lamp's mean
    # over the 5 nm band it centres, so a 1.5 nm line's energy is in the value of the band that
    # holds it (sampled at its own wavelengths, a line narrower than the step would be missed or
    # multiplied). To 830 nm (zeros past ~460 nm) so it covers every visible grid: the lamp is known
    # to emit nothing there, which is different from "not measured".
    wl = grid(300.0, 830.0, 5.0)
    fine = 0.01
    v = np.empty(len(wl))
    for i, c in enumerate(wl):
        x = c - 2.5 + fine * (np.arange(int(round(5 / fine))) + 0.5)  # midpoints of 0.01 nm pieces
        v[i] = blacklight_model(x).mean()
    dense = np.arange(295.0, 835.0, fine)
    model = blacklight_model(dense)
    uva = np.trapezoid(np.where((dense >= 315) & (dense <= 400), model, 0.0), dense) / np.trapezoid(model, dense)
    print(f"  blacklight: model peak 100 at {dense[np.argmax(model)]:.2f} nm, {100 * uva:.1f}% of the energy in "
          f"315-400 nm; 5 nm table peak {v.max():.3f} at {peak_nm(wl, v):g} nm, "
          f"table energy / model energy {5 * v.sum() / np.trapezoid(model, dense):.6f}")
    write_csv("illuminants/blacklight.csv", wl, {"value": v}, sig=8, decimals=6)


# --------------------------------------------------------------------------------------------
# ColorChecker


COLORCHECKER_NAMES = {
    "dark skin": "dark_skin",
    "light skin": "light_skin",
    "blue sky": "blue_sky",
    "foliage": "foliage",
    "blue flower": "blue_flower",
    "bluish green": "bluish_green",
    "orange": "orange",
    "purplish blue": "purplish_blue",
    "moderate red": "moderate_red",
    "purple": "purple",
    "yellow green": "yellow_green",
    "orange yellow": "orange_yellow",
    "blue": "blue",
    "green": "green",
    "red": "red",
    "yellow": "yellow",
    "magenta": "magenta",
    "cyan": "cyan",
    "white 9.5 (.05 D)": "white_9_5",
    "neutral 8 (.23 D)": "neutral_8",
    "neutral 6.5 (.44 D)": "neutral_6_5",
    "neutral 5 (.70 D)": "neutral_5",
    "neutral 3.5 (1.05 D)": "neutral_3_5",
    "black 2 (1.5 D)": "black_2",
}


def colorchecker() -> None:
    cc = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
    assert set(cc.keys()) == set(COLORCHECKER_NAMES), sorted(cc.keys())
    for key, name in COLORCHECKER_NAMES.items():
        sd = cc[key]
        assert np.all((sd.values >= 0) & (sd.values <= 1)), key
        write_sd(f"colorchecker/{name}.csv", sd, sig=7)


# --------------------------------------------------------------------------------------------
# Fluorescent materials. See README "fluorescent". Bands are (centre nm, FWHM eV, peak or weight).

FLUOR_GRID = (300, 830, 1)

# Stilbene-type fluorescent whitening agent (FWA) on paper.
BRIGHTENER_ABS = [(349.0, 0.46, 0.62), (375.0, 0.24, 0.12)]  # decadic absorbance bands
BRIGHTENER_EM = [(436.0, 0.34, 1.0), (468.0, 0.30, 0.30)]
# Paper substrate (unbrightened pulp, slightly yellowish): ρ = R_INF·(1 - DEPTH·exp(-(λ-300)/SCALE))
PAPER = (0.90, 0.35, 60.0)

# Daylight-fluorescent orange pigment: rhodamine-type dye plus a yellow donor dye in a resin.
ORANGE_ABS = [(530.0, 0.26, 1.00), (460.0, 0.45, 0.80), (375.0, 0.60, 0.50)]
ORANGE_EM = [(596.0, 0.17, 1.0), (640.0, 0.17, 0.25)]
# Daylight-fluorescent pink pigment: rhodamine-B-like dye in a resin.
PINK_ABS = [(552.0, 0.20, 1.00), (518.0, 0.22, 0.35), (355.0, 0.50, 0.22)]
PINK_EM = [(578.0, 0.15, 1.0), (620.0, 0.17, 0.28)]
# White ground / binder under the fluorescent paints: flat diffuse reflectance.
PAINT_GROUND = 0.90


def fluorescent() -> None:
    wl = grid(*FLUOR_GRID)

    def write_set(name, abs_bands, em_bands, substrate):
        a = absorptance_from_absorbance(absorbance(wl, abs_bands))
        em = emission(wl, em_bands)
        base = substrate * (1.0 - a)
        # Rounded values must still satisfy absorptance + base <= 1.
        a_r = np.round(a, 6)
        base_r = np.round(base, 6)
        assert np.all(a_r + base_r <= 1.0 + 1e-12), name
        print(f"  {name}: absorptance peak {a.max():.3f} at {peak_nm(wl, a):g} nm; "
              f"emission peak at {peak_nm(wl, em):g} nm; max(a+base) {np.max(a_r + base_r):.4f}")
        write_csv(f"fluorescent/{name}_ex.csv", wl, {"value": a}, sig=7, decimals=6)
        write_csv(f"fluorescent/{name}_em.csv", wl, {"value": em}, sig=7, decimals=6)
        write_csv(f"fluorescent/{name}_base.csv", wl, {"value": base}, sig=7, decimals=6)

    r_inf, depth, scale = PAPER
    paper = r_inf * (1.0 - depth * np.exp(-(wl - 300.0) / scale))
    write_set("brightener", BRIGHTENER_ABS, BRIGHTENER_EM, paper)
    write_set("orange_dye", ORANGE_ABS, ORANGE_EM, PAINT_GROUND)
    write_set("pink_dye", PINK_ABS, PINK_EM, PAINT_GROUND)


# --------------------------------------------------------------------------------------------
# Transparent materials. See README "Filters and dyes". Models, not measurements.

TRANSPARENT_GRID = (300, 830, 1)


def logistic(wl, edge_nm, width_nm):
    return 1.0 / (1.0 + np.exp(-(wl - edge_nm) / width_nm))


def transparent() -> None:
    wl = grid(*TRANSPARENT_GRID)
    # Lighting gels (thin sheets): transmittance per crossing, 0..1.
    orange = 0.02 + 0.86 * logistic(wl, 575.0, 12.0)  # long-pass: an amber/orange gel
    blue = 0.03 + 0.72 * gaussian_nm(wl, 465.0, 110.0) + 0.55 * logistic(wl, 705.0, 15.0)  # blue, with the red leak dyed gels have
    green = 0.02 + 0.68 * gaussian_nm(wl, 530.0, 85.0) + 0.40 * logistic(wl, 730.0, 15.0)
    for name, t in (("orange_gel", orange), ("blue_gel", blue), ("green_gel", green)):
        assert np.all((t >= 0) & (t <= 1)), name
        print(f"  filters/{name}: T {t.min():.3f}..{t.max():.3f}, at 450/550/650 nm "
              f"{t[150]:.3f}/{t[250]:.3f}/{t[350]:.3f}")
        write_csv(f"filters/{name}.csv", wl, {"value": t}, sig=7, decimals=6)
    # Rhodamine 6G in ethanol: molar absorptivity, L·mol⁻¹·cm⁻¹. The S0→S1 band and its vibronic
    # shoulder, and a weak near-UV band, as Gaussians in energy; scaled so that the peak is
    # 116 000 near 530 nm (the literature value, PhotochemCAD; the model's peak falls at 529 nm).
    r6g = absorbance(wl, [(530.0, 0.115, 1.0), (498.0, 0.20, 0.32), (348.0, 0.45, 0.09)])
    r6g *= 116000.0 / r6g.max()
    print(f"  dyes/rhodamine_6g_epsilon: peak {r6g.max():.0f} at {peak_nm(wl, r6g):g} nm")
    write_csv("dyes/rhodamine_6g_epsilon.csv", wl, {"value": r6g}, sig=7, decimals=2)
    # Tinted (blue-green) glass: decadic absorbance per metre, rising into the red (an Fe²⁺-like
    # band) with a UV edge. 6 mm of it transmits ~0.85 at 500 nm, ~0.70 at 700 nm (no reflection).
    glass = 12.0 + 45.0 * gaussian_ev(wl, 1050.0, 0.9) + 400.0 * logistic(wl, 320.0, -8.0)
    print(f"  media/tinted_glass_absorbance: {glass[200]:.1f} m⁻¹ at 500 nm, {glass[400]:.1f} at 700 nm")
    write_csv("media/tinted_glass_absorbance.csv", wl, {"value": glass}, sig=7, decimals=4)


# --------------------------------------------------------------------------------------------
# Pigments for Kubelka–Munk paints. See README "Pigments". Models, not measurements: absorption k
# and scattering s per unit volume concentration of pigment in the dry film, m⁻¹ (a layer's K = Σ
# cᵢkᵢ, S = Σ cᵢsᵢ; docs/physics.md, "Paints and coatings").

PIGMENT_GRID = (300, 830, 1)


def scattering(wl, s550, exponent):
    """Scattering falling with wavelength as (λ/550)^−exponent, s550 at 550 nm (m⁻¹)."""
    return s550 * (wl / 550.0) ** -exponent


PIGMENTS = {
    # name: (k(λ), s(λ)) as functions of the wavelength array
    # Rutile titanium white: absorbs below its ~410 nm band edge, scatters strongly.
    "titanium_white": (lambda wl: 2.0e3 + 4.0e7 * logistic(wl, 400.0, -5.0),
                       lambda wl: scattering(wl, 2.5e6, 1.2) * (0.3 + 0.7 * logistic(wl, 400.0, 5.0))),
    # Carbon black: absorbs everything, slightly less in the red; scatters little.
    "carbon_black": (lambda wl: 6.0e7 * (wl / 550.0) ** -0.3, lambda wl: scattering(wl, 6.0e5, 1.0)),
    # An arylide-like yellow: an absorption edge at 490 nm.
    "arylide_yellow": (lambda wl: 3.0e3 + 2.2e7 * logistic(wl, 488.0, -9.0) * (1.0 + 0.3 * gaussian_nm(wl, 430.0, 60.0)),
                       lambda wl: scattering(wl, 4.0e5, 1.0)),
    # A naphthol-like red: an edge at 585 nm, a shoulder in the green.
    "naphthol_red": (lambda wl: 4.0e3 + 1.8e7 * logistic(wl, 590.0, -6.0) + 4.0e6 * gaussian_nm(wl, 530.0, 60.0),
                     lambda wl: scattering(wl, 3.0e5, 1.0)),
    # A phthalocyanine-like blue: two absorption bands in the red, clear in the blue.
    "phthalo_blue": (lambda wl: 2.0e4 + 3.0e7 * gaussian_nm(wl, 610.0, 55.0) + 2.4e7 * gaussian_nm(wl, 680.0, 55.0)
                     + 8.0e6 * logistic(wl, 380.0, -8.0),
                     lambda wl: scattering(wl, 1.5e5, 1.0)),
    # A phthalocyanine-like green: absorbs the blue and the red, clear near 510 nm.
    "phthalo_green": (lambda wl: 2.0e4 + 2.6e7 * gaussian_nm(wl, 430.0, 70.0) + 3.2e7 * gaussian_nm(wl, 640.0, 90.0)
                      + 1.2e7 * logistic(wl, 720.0, 30.0),
                      lambda wl: scattering(wl, 1.5e5, 1.0)),
}


def km_infinite(k, s):
    q = k / s
    return 1.0 + q - np.sqrt(q * q + 2.0 * q)


def pigments() -> None:
    wl = grid(*PIGMENT_GRID)
    for name, (kf, sf) in PIGMENTS.items():
        k, s = kf(wl), sf(wl)
        assert np.all(k > 0) and np.all(s > 0), name
        # The masstone with a little white (c 0.1 of the pigment, 0.1 white), opaque: its R∞.
        kw, sw = PIGMENTS["titanium_white"][0](wl), PIGMENTS["titanium_white"][1](wl)
        tint = km_infinite(0.1 * k + 0.1 * kw, 0.1 * s + 0.1 * sw)
        print(f"  pigments/{name}: k {k.min():.3g}..{k.max():.3g} m⁻¹, s {s.min():.3g}..{s.max():.3g} m⁻¹; "
              f"1:1 with white, R∞ at 450/550/650 nm {tint[150]:.3f}/{tint[250]:.3f}/{tint[350]:.3f}")
        write_csv(f"pigments/{name}_k.csv", wl, {"value": k}, sig=6)
        write_csv(f"pigments/{name}_s.csv", wl, {"value": s}, sig=6)


def paint_reflectance(wl, recipe):
    """R∞ of an opaque paint {pigment: concentration}."""
    k = sum(c * PIGMENTS[n][0](wl) for n, c in recipe.items())
    s = sum(c * PIGMENTS[n][1](wl) for n, c in recipe.items())
    return km_infinite(k, s)


def metameric_paints() -> None:
    """Prints the recipes of scenes/paints.json's metameric pair: a grey of white and black, and a
    grey of white (the same 0.1), yellow, red and blue whose three concentrations are solved so
    that the two have the same CIE 1931 XYZ under D65 (R∞ depends only on the ratios, so white is
    held fixed), as the scene draws them: opaque (R∞) under a surface of n = 1.5 (Saunderson's body
    reflectance). Under A they differ (ΔE00 about 2)."""
    from scipy.optimize import least_squares

    wl = np.arange(380, 781, 5, dtype=float)
    shape = colour.SpectralShape(380, 780, 5)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)

    def xyz(r, illuminant):
        sd = colour.SpectralDistribution(dict(zip(wl, r)))
        ill = colour.SDS_ILLUMINANTS[illuminant].copy().align(shape)
        return colour.sd_to_XYZ(sd, cmfs, ill, method="Integration") / 100.0  # a Riemann sum, as Metamer integrates

    # The scene's paints have a surface of n = 1.5: Saunderson's body reflectance, with k1 = 0.04
    # and k2 the internal diffuse reflectance integrated from Fresnel's equations.
    from scipy.integrate import quad

    def fresnel_inside(theta, n=1.5):
        sin_t = n * np.sin(theta)
        if sin_t >= 1:
            return 1.0
        ci, ct = np.cos(theta), np.sqrt(1 - sin_t * sin_t)
        rs, rp = (n * ci - ct) / (n * ci + ct), (n * ct - ci) / (n * ct + ci)
        return 0.5 * (rs * rs + rp * rp)

    k1 = 0.04
    k2 = quad(lambda t: fresnel_inside(t) * 2 * np.sin(t) * np.cos(t), 0, np.pi / 2, points=[np.arcsin(1 / 1.5)])[0]

    def paint(recipe):
        r = paint_reflectance(wl, recipe)
        return (1 - k1) * (1 - k2) * r / (1 - k2 * r)

    first = {"titanium_white": 0.10, "carbon_black": 0.004}
    target = xyz(paint(first), "D65")

    def residual(logc):
        c = np.exp(logc)
        recipe = {"titanium_white": 0.1, "arylide_yellow": c[0], "phthalo_blue": c[1], "naphthol_red": c[2]}
        return (xyz(paint(recipe), "D65") - target) * 100.0

    fit = least_squares(residual, np.log([0.004, 0.004, 0.004]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    c = np.exp(fit.x)
    second = {"titanium_white": 0.1, "arylide_yellow": c[0], "phthalo_blue": c[1], "naphthol_red": c[2]}
    for ill in ("D65", "A"):
        a, b = xyz(paint(first), ill), xyz(paint(second), ill)
        white = xyz(np.ones_like(wl), ill)
        lab_a, lab_b = (colour.XYZ_to_Lab(v, colour.XYZ_to_xy(white)) for v in (a, b))
        print(f"  metameric paints under {ill}: ΔE00 {colour.delta_E(lab_a, lab_b, method='CIE 2000'):.3f}")
    print("  first:  " + ", ".join(f"{n} {v:.6g}" for n, v in first.items()))
    print("  second: " + ", ".join(f"{n} {v:.6g}" for n, v in second.items()))


# --------------------------------------------------------------------------------------------
# Sensors for `metamer capture` (docs/sensor.md). See README "Sensors". Models, not measurements.

def silicon_qe(wl):
    """A front-illuminated silicon photodiode's quantum efficiency: a broad hump (peak 0.62 near
    560 nm) that falls towards the UV (absorption in the surface layers) and the near infrared
    (photons passing through the thin epitaxial layer)."""
    return 0.62 * np.exp(-0.5 * ((wl - 560.0) / 150.0) ** 2) * logistic(wl, 380.0, 12.0)


def sensors() -> None:
    wl = grid(300, 1000, 1)
    si = silicon_qe(wl)
    write_csv("sensors/silicon_qe.csv", wl, {"value": si}, sig=6, decimals=6)
    # A four-band multispectral filter array on the same silicon: Gaussian filters (FWHM 40 nm).
    bands = {"b460": 460.0, "g530": 530.0, "y600": 600.0, "r670": 670.0}
    columns = {name: si * 0.85 * gaussian_nm(wl, centre, 40.0) for name, centre in bands.items()}
    write_csv("sensors/msfa_4band_qe.csv", wl, columns, sig=6, decimals=6)
    print(f"  sensors/silicon_qe: peak {si.max():.3f} at {peak_nm(wl, si):g} nm; msfa_4band_qe: 4 bands of FWHM 40 nm")


# --------------------------------------------------------------------------------------------
# Metals: Lorentz–Drude model of Rakić, Djurišić, Elazar & Majewski, Appl. Opt. 37(22), 5271
# (1998), Table 1 (LD model). ωp, Γ, ω in eV.
#   ε(ω) = 1 - f0 ωp² / (ω (ω + iΓ0)) + Σj fj ωp² / (ωj² - ω² - iωΓj)

RAKIC_LD = {
    # name: (ωp, f0, Γ0, [(fj, Γj, ωj), ...])
    "silver": (9.01, 0.845, 0.048, [(0.065, 3.886, 0.816), (0.124, 0.452, 4.481),
                                    (0.011, 0.065, 8.185), (0.840, 0.916, 9.083),
                                    (5.646, 2.419, 20.29)]),
    "gold": (9.03, 0.760, 0.053, [(0.024, 0.241, 0.415), (0.010, 0.345, 0.830),
                                  (0.071, 0.870, 2.969), (0.601, 2.494, 4.304),
                                  (4.384, 2.214, 13.32)]),
    "copper": (10.83, 0.575, 0.030, [(0.061, 0.378, 0.291), (0.104, 1.056, 2.957),
                                     (0.723, 3.213, 5.300), (0.638, 4.305, 11.18)]),
    "aluminium": (14.98, 0.523, 0.047, [(0.227, 0.333, 0.162), (0.050, 0.312, 1.544),
                                        (0.166, 1.351, 1.808), (0.030, 3.382, 3.473)]),
}


def lorentz_drude_eps(wl_nm, params):
    wp, f0, g0, osc = params
    w = HC_EV_NM / np.asarray(wl_nm, dtype=float)
    eps = 1.0 - f0 * wp**2 / (w * (w + 1j * g0))
    for fj, gj, wj in osc:
        eps = eps + fj * wp**2 / (wj**2 - w**2 - 1j * w * gj)
    return eps


def normal_reflectance(eps):
    nk = np.sqrt(eps)  # principal branch: n > 0, k >= 0 for Im ε >= 0
    n, k = nk.real, nk.imag
    return ((n - 1) ** 2 + k**2) / ((n + 1) ** 2 + k**2), n, k


def metals() -> None:
    wl = grid(300, 1000, 5)
    checks = {
        "gold": [(450, 0.30, 0.45), (650, 0.90, 1.0), (700, 0.93, 1.0)],
        "silver": [(450, 0.90, 1.0), (550, 0.93, 1.0), (700, 0.95, 1.0)],
        "copper": [(450, 0.45, 0.70), (700, 0.90, 1.0)],
        "aluminium": [(450, 0.88, 0.95), (550, 0.88, 0.95), (800, 0.83, 0.89)],
    }
    for name, params in RAKIC_LD.items():
        r, n, k = normal_reflectance(lorentz_drude_eps(wl, params))
        for lam, lo, hi in checks[name]:
            i = int(np.argmin(np.abs(wl - lam)))
            assert lo <= r[i] <= hi, f"{name} R({lam}) = {r[i]:.3f} outside [{lo}, {hi}]"
        i550 = int(np.argmin(np.abs(wl - 550)))
        print(f"  {name}: R(450)={r[np.argmin(np.abs(wl - 450))]:.3f} R(550)={r[i550]:.3f} "
              f"R(650)={r[np.argmin(np.abs(wl - 650))]:.3f} R(800)={r[np.argmin(np.abs(wl - 800))]:.3f}"
              f"  n,k(550)={n[i550]:.3f},{k[i550]:.3f}")
        write_csv(f"metals/{name}.csv", wl, {"value": r}, sig=7, decimals=6)


# --------------------------------------------------------------------------------------------
# Observers


def observers() -> None:
    for key, name in [("CIE 1931 2 Degree Standard Observer", "cie1931_2deg"),
                      ("CIE 1964 10 Degree Standard Observer", "cie1964_10deg")]:
        m = colour.MSDS_CMFS[key]
        assert m.shape.start == 360 and m.shape.end == 830 and m.shape.interval == 1, m.shape
        v = m.values
        print(f"  {name}: sum of y_bar (1 nm) = {v[:, 1].sum():.6f}")
        write_csv(f"observers/{name}.csv", m.wavelengths,
                  {"x_bar": v[:, 0], "y_bar": v[:, 1], "z_bar": v[:, 2]}, sig=7)


def main() -> int:
    print(f"colour-science {colour.__version__}, numpy {np.__version__}; writing under {ROOT}")
    illuminants()
    colorchecker()
    fluorescent()
    transparent()
    pigments()
    metameric_paints()
    sensors()
    metals()
    observers()
    print(f"{len(written)} files")
    return 0


if __name__ == "__main__":
    sys.exit(main())
