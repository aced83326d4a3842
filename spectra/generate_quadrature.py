#!/usr/bin/env python3
"""Generate the reduced colour representations of spectra/quadrature/ and their test data.

Run after generate_metamers.py (it reads spectra/metamers/), with the project's Python:

    .venv/bin/python spectra/generate_quadrature.py

Writes

* spectra/quadrature/ac1c2_N.csv (N = 3..8): `wavelength_nm,X,Y,Z`, N sample wavelengths and the
  weights that turn a spectrum's values there into CIE 1931 XYZ, XYZ ≈ Σ_k W[k]·L(λ_k), the
  shared-abscissa Gaussian rule for Meyer's (1988) opponent channels A, C1, C2;
* spectra/quadrature/ac1c2_4_quoted.csv: the 4 wavelengths quoted for Meyer (456, 490, 557,
  631 nm) with interpolatory weights, for comparison;
* spectra/quadrature/ac1c2.json: the cone and opponent matrices, every rule's wavelengths and
  its weights per XYZ and per A, C1, C2 channel;
* spectra/quadrature/rgb_weights.csv, rgb_light_weights.csv, rgb.json: the "rgb" mode's
  reduction of reflectances and lights to linear sRGB, and its matrices;
* tests/data/representations/ac1c2_weights.csv, ac1c2_accuracy.csv, representation_modes.csv,
  representation_modes_delta_e.csv, rgb_values.csv.

docs/representations.md derives every step. Deterministic; numpy only.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from generate_metamers import (  # noqa: E402
    REPO, ROOT, TESTDATA, Colorimeter, at, colour, de00, deab, fmt, lab, load_spectrum,
    load_table, write_csv, written)

QUAD = ROOT / "quadrature"

# 1 nm Riemann sums over the observer's whole table are "full integration" here.
LAM = np.arange(360.0, 831.0, 1.0)
T_MID, T_HALF = 595.0, 235.0  # polynomial variable t = (λ − 595)/235 maps 360..830 nm to −1..1

# Hunt–Pointer–Estévez cone fundamentals from CIE 1931 XYZ, equal-energy normalization (the
# CIECAM97s matrix; docs/color.md "Chromatic adaptation"): illuminant E gives L = M = S.
HPE_EE = np.array([[0.38971, 0.68898, -0.07868],
                   [-0.22981, 1.18340, 0.04641],
                   [0.0, 0.0, 1.0]])
# Relative weights of the L, M, S signals in the principal-axis analysis: equal (docs/
# representations.md shows how the rule moves under cone-number-like weights such as 32 : 16 : 1).
CONE_WEIGHTS = np.array([1.0, 1.0, 1.0])

QUOTED_4 = np.array([456.0, 490.0, 557.0, 631.0])  # nm, as quoted for Meyer (1988)
N_RANGE = range(3, 9)

# Linear sRGB (IEC 61966-2-1): BT.709 primaries and the D65 white of engine/color/srgb.h.
SRGB_PRIMARIES = np.array([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]])
SRGB_WHITE = np.array([0.95047, 1.0, 1.08883])


def tvar(lam):
    return (np.asarray(lam, dtype=float) - T_MID) / T_HALF


def cmfs() -> np.ndarray:
    ow, cmf = load_table("observers/cie1931_2deg")
    assert np.allclose(ow, LAM)
    return cmf.T.copy()  # 3 x 471


# --------------------------------------------------------------------------------------------
# A, C1, C2


def opponent_axes(cmf: np.ndarray, cone_weights=CONE_WEIGHTS):
    """Principal axes of the weighted cone fundamentals (Buchsbaum & Gottschalk's construction):
    eigenvectors of the Gram matrix G = Σ_λ c(λ)c(λ)ᵀ·1 nm, c = diag(w)·HPE·(x̄, ȳ, z̄).
    Returns (T: rows A, C1, C2 acting on the weighted cone signals; K = T·diag(w)·HPE acting on
    XYZ; relative eigenvalues)."""
    c = cone_weights[:, None] * (HPE_EE @ cmf)
    gram = c @ c.T
    ev, vec = np.linalg.eigh(gram)
    order = np.argsort(ev)[::-1]
    ev, vec = ev[order], vec[:, order]
    t = vec.T.copy()
    # Signs: A positive; the two opponent axes positive for L.
    if t[0].sum() < 0:
        t[0] = -t[0]
    for i in (1, 2):
        if t[i, 0] < 0:
            t[i] = -t[i]
    k = t @ np.diag(cone_weights) @ HPE_EE
    return t, k, ev / ev[0]


# --------------------------------------------------------------------------------------------
# Quadrature rules


def interpolatory_weights(nodes: np.ndarray, sens: np.ndarray) -> np.ndarray:
    """Weights W (N x channels) with Σ_k W[k, c]·p(λ_k) = Σ_λ p(λ)·s_c(λ)·1 nm for every
    polynomial p of degree < N (Legendre basis in t, for conditioning)."""
    n = len(nodes)
    vn = np.polynomial.legendre.legvander(tvar(nodes), n - 1).T  # N x N
    moments = np.polynomial.legendre.legvander(tvar(LAM), n - 1).T @ sens.T  # N x channels
    return np.linalg.solve(vn, moments)


def gauss_rule(weight: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Classical Gauss rule for the discrete measure weight(λ)·1 nm on LAM (Lanczos / Stieltjes
    recurrence in t, then the Golub–Welsch eigenvalue problem of the Jacobi matrix)."""
    assert weight.min() >= 0
    t = tvar(LAM)
    q = np.sqrt(weight)
    q = q / np.linalg.norm(q)
    basis, alpha, beta = [q], [], []
    prev, b = np.zeros_like(q), 0.0
    for _ in range(n):
        v = t * basis[-1] - b * prev
        a = basis[-1] @ v
        v = v - a * basis[-1]
        for u in basis:  # full re-orthogonalization
            v = v - (u @ v) * u
        alpha.append(a)
        b = np.linalg.norm(v)
        beta.append(b)
        prev = basis[-1]
        basis.append(v / b)
    jac = np.diag(alpha) + np.diag(beta[:-1], 1) + np.diag(beta[:-1], -1)
    ev, vec = np.linalg.eigh(jac)
    return T_MID + T_HALF * ev, vec[0] ** 2 * weight.sum()


def shared_conditions(n: int) -> list[tuple[int, int]]:
    """Extra moment conditions (channel, j) for the shared-abscissa rule, in priority order:
    every channel at j = 0, then A, C1, C2 at j = 1, and so on; the first n."""
    out, j = [], 0
    while len(out) < n:
        for ch in range(3):
            if len(out) < n:
                out.append((ch, j))
        j += 1
    return out


def shared_rule(opp: np.ndarray, n: int) -> np.ndarray:
    """Nodes of the shared-abscissa Gauss-type rule for the three opponent channels: the roots of
    the monic node polynomial ω(t) of degree n with Σ_λ ω(t)·t^j·s_c(λ) = 0 for the conditions
    (c, j) of shared_conditions(n). The interpolatory rule on these nodes is then exact for
    t^(n+j)·s_c as well: degree n − 1 for every channel plus the conditions' extra degrees."""
    t = tvar(LAM)
    conds = shared_conditions(n)
    m, r = np.zeros((n, n)), np.zeros(n)
    for row, (ch, j) in enumerate(conds):
        for i in range(n):
            m[row, i] = np.sum(t ** (i + j) * opp[ch])
        r[row] = -np.sum(t ** (n + j) * opp[ch])
    coef = np.linalg.solve(m, r)  # ω(t) = t^n + Σ coef[i] t^i
    roots = np.roots(np.concatenate(([1.0], coef[::-1])))
    assert np.abs(roots.imag).max() < 1e-12, roots
    nodes = np.sort(T_MID + T_HALF * roots.real)
    assert np.all(np.diff(nodes) > 0) and nodes[0] > LAM[0] and nodes[-1] < LAM[-1]
    return nodes


def check_exactness(nodes, w_opp, opp, conds) -> float:
    """Largest relative error of the rule on t^d·s_c for d < N and on the extra conditions."""
    t, tn, n = tvar(LAM), tvar(nodes), len(nodes)
    worst = 0.0
    tests = [(c, d) for c in range(3) for d in range(n)] + [(c, n + j) for c, j in conds]
    for c, d in tests:
        exact = np.sum(t ** d * opp[c])
        quad = np.sum(tn ** d * w_opp[:, c])
        worst = max(worst, abs(quad - exact) / np.sum(np.abs(opp[c])))
    return worst


# --------------------------------------------------------------------------------------------
# Evaluating a rule on reflectances


def colorchecker_names() -> list[str]:
    scene = json.loads((REPO / "scenes" / "colorchecker.json").read_text())
    return [m["diffuse"].split("/")[1] for m in scene["materials"].values()
            if isinstance(m["diffuse"], str)]


def light_1nm(name: str) -> tuple[np.ndarray, np.ndarray]:
    return load_spectrum(f"illuminants/{name}")


def reference_xyz(cmf, refl, light) -> tuple[np.ndarray, np.ndarray]:
    """Full integration: 1 nm Riemann sum over 360-830 nm of x̄·E·ρ (data linear between their
    samples, 0 outside), relative to the perfect white diffuser (Y = 100)."""
    e = at(*light, LAM)
    white = cmf @ e
    return 100 * (cmf @ (e * at(*refl, LAM))) / white[1], 100 * white / white[1]


def rule_xyz(nodes, w_xyz, refl, light) -> tuple[np.ndarray, np.ndarray]:
    """A rule's XYZ: radiance point-sampled at the nodes, L_k = ρ(λ_k)·E(λ_k), XYZ = Σ W[k]·L_k,
    relative to the rule's own white (Σ W[k]·E(λ_k), Y = 100)."""
    e = at(*light, nodes)
    white = w_xyz.T @ e
    return 100 * (w_xyz.T @ (e * at(*refl, nodes))) / white[1], 100 * white / white[1]


# --------------------------------------------------------------------------------------------
# RGB


def srgb_matrices() -> tuple[np.ndarray, np.ndarray]:
    """XYZ → linear sRGB and its inverse, from the primaries and the white (as srgb.cpp)."""
    x, y = SRGB_PRIMARIES[:, 0], SRGB_PRIMARIES[:, 1]
    p = np.stack([x / y, np.ones(3), (1 - x - y) / y])  # columns: primaries' XYZ at Y = 1
    s = np.linalg.solve(p, SRGB_WHITE)
    rgb_to_xyz = p * s
    return np.linalg.inv(rgb_to_xyz), rgb_to_xyz


class RgbMode:
    """A reflectance's RGB is the linear sRGB of its colour under D65, normalized per channel so
    that the perfect white diffuser is (1, 1, 1); a light's RGB is the linear sRGB of its own
    (radiometric) XYZ. The renderer multiplies them; the product goes back to XYZ with the sRGB
    RGB→XYZ matrix. Both reductions are 1 nm weight tables over 360-830 nm."""

    def __init__(self, cmf):
        self.m, self.minv = srgb_matrices()
        d65 = at(*light_1nm("D65"), LAM)
        self.light_w = (self.m @ cmf).T  # 471 x 3: RGB_light = Σ w·E(λ)·1 nm
        raw = (self.m @ (cmf * d65)).T
        self.norm = raw.sum(0)  # the white's linear sRGB under the D65 table
        self.refl_w = raw / self.norm  # 471 x 3: each column sums to 1

    def refl_rgb(self, refl):
        return self.refl_w.T @ at(*refl, LAM)

    def light_rgb(self, light):
        return self.light_w.T @ at(*light, LAM)

    def xyz(self, refl, light) -> tuple[np.ndarray, np.ndarray]:
        e = self.light_rgb(light)
        white = self.minv @ e
        return 100 * (self.minv @ (self.refl_rgb(refl) * e)) / white[1], 100 * white / white[1]


# --------------------------------------------------------------------------------------------
# Output helpers


def rounded(a, sig=12):
    if isinstance(a, (list, tuple, np.ndarray)):
        return [rounded(x, sig) for x in a]
    return float(fmt(a, sig))


def write_json(path: Path, obj) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(obj, indent=1, ensure_ascii=False) + "\n", encoding="utf-8",
                    newline="\n")
    written.append(path)
    print(f"wrote {path.relative_to(REPO)}")


def write_weights_csv(path: Path, wl, w, names=("X", "Y", "Z"), sig=10, wl_sig=10) -> None:
    rows = [[fmt(a, wl_sig), *row] for a, row in zip(wl, w)]
    write_csv(path, ["wavelength_nm", *names], rows, sig=sig)


def main() -> int:
    print(f"colour-science {colour.__version__}, numpy {np.__version__}")
    cmf = cmfs()
    t_mat, k_mat, ev = opponent_axes(cmf)
    opp = k_mat @ cmf  # A, C1, C2 sensitivities at 1 nm
    assert opp[0].min() > -1e-9, opp[0].min()
    a_weight = np.clip(opp[0], 0.0, None)
    print(f"  opponent axes (rows A, C1, C2) on weighted cones:\n{np.round(t_mat, 5)}\n"
          f"  relative eigenvalues {np.round(ev, 5)}\n  A, C1, C2 from XYZ:\n{np.round(k_mat, 5)}")

    # Rules.
    rules: dict[str, dict[int, dict]] = {"shared": {}, "gauss_A": {}, "quoted": {}}
    for n in N_RANGE:
        nodes = shared_rule(opp, n)
        w_xyz = interpolatory_weights(nodes, cmf)
        w_opp = w_xyz @ k_mat.T
        err = check_exactness(nodes, w_opp, opp, shared_conditions(n))
        assert err < 1e-9, err
        rules["shared"][n] = {"nodes": nodes, "xyz": w_xyz, "opp": w_opp}
        gn, gw = gauss_rule(a_weight, n)
        w_xyz_g = interpolatory_weights(gn, cmf)
        w_opp_g = w_xyz_g @ k_mat.T
        assert np.allclose(w_opp_g[:, 0], gw, rtol=1e-8, atol=1e-8 * gw.max()), (w_opp_g[:, 0], gw)
        rules["gauss_A"][n] = {"nodes": gn, "xyz": w_xyz_g, "opp": w_opp_g}
    w_q = interpolatory_weights(QUOTED_4, cmf)
    rules["quoted"][4] = {"nodes": QUOTED_4, "xyz": w_q, "opp": w_q @ k_mat.T}
    for kind, by_n in rules.items():
        for n, r in by_n.items():
            print(f"  {kind:8s} N={n}: " + ", ".join(f"{x:.2f}" for x in r["nodes"]) + " nm")

    # Sensitivity of the 4-point rules to the cone weights (docs).
    for cw in ([1, 1, 1], [1, 1, 0.5], [1, 1, 0.25], [1, 0.5, 1 / 32], [1, 0.25, 1 / 32]):
        _, k2, _ = opponent_axes(cmf, np.array(cw, dtype=float))
        try:
            shared = ", ".join(f"{x:.1f}" for x in shared_rule(k2 @ cmf, 4))
        except AssertionError:
            shared = "no rule (complex or out-of-range nodes)"
        gauss = ", ".join(f"{x:.1f}" for x in gauss_rule(np.clip((k2 @ cmf)[0], 0, None), 4)[0])
        print(f"  cone weights {cw[0]:g}:{cw[1]:g}:{cw[2]:.4g}: shared N=4 {shared}; "
              f"Gauss-A N=4 {gauss}")

    # Files for the engine.
    for n, r in rules["shared"].items():
        write_weights_csv(QUAD / f"ac1c2_{n}.csv", r["nodes"], r["xyz"])
    write_weights_csv(QUAD / "ac1c2_4_quoted.csv", QUOTED_4, rules["quoted"][4]["xyz"])
    write_json(QUAD / "ac1c2.json", {
        "description": "Meyer's (1988) AC1C2 opponent channels re-derived from CIE 1931 data, and "
                       "quadrature rules for them; see docs/representations.md. "
                       "XYZ ≈ Σ_k XYZ_weights[k]·L(λ_k), (A, C1, C2) ≈ Σ_k AC1C2_weights[k]·L(λ_k), "
                       "with the integrals taken as 1 nm sums over 360-830 nm.",
        "cones": "Hunt-Pointer-Estevez, equal-energy normalization: LMS = LMS_from_XYZ · XYZ",
        "LMS_from_XYZ": HPE_EE.tolist(),
        "cone_weights_LMS": CONE_WEIGHTS.tolist(),
        "AC1C2_from_weighted_LMS": rounded(t_mat),
        "AC1C2_from_XYZ": rounded(k_mat),
        "relative_eigenvalues": rounded(ev),
        "polynomial_variable": "t = (wavelength_nm - 595) / 235",
        "rules": {kind: {str(n): {"wavelength_nm": rounded(r["nodes"]),
                                  "XYZ_weights": rounded(r["xyz"]),
                                  "AC1C2_weights": rounded(r["opp"])}
                         for n, r in by_n.items()}
                  for kind, by_n in rules.items()},
    })

    rgb = RgbMode(cmf)
    write_weights_csv(QUAD / "rgb_weights.csv", LAM, rgb.refl_w, names=("R", "G", "B"), sig=10,
                      wl_sig=6)
    write_weights_csv(QUAD / "rgb_light_weights.csv", LAM, rgb.light_w, names=("R", "G", "B"),
                      sig=10, wl_sig=6)
    write_json(QUAD / "rgb.json", {
        "description": "The rgb mode's reduction (docs/representations.md, 'RGB'): reflectance RGB "
                       "= rgb_weights.csv · rho (1 nm, 360-830 nm), light RGB = "
                       "rgb_light_weights.csv · E; product RGB -> XYZ with "
                       "linear_sRGB_to_XYZ.",
        "XYZ_to_linear_sRGB": rounded(rgb.m, 15),
        "linear_sRGB_to_XYZ": rounded(rgb.minv, 15),
        "sRGB_white_XYZ": SRGB_WHITE.tolist(),
        "reflectance_normalization": rounded(rgb.norm, 15),
        "reflectance_normalization_note": "linear sRGB of the perfect white diffuser under the "
                                          "D65 table, sum of M·cmf·D65 over 1 nm; rgb_weights "
                                          "are M·cmf·D65 divided by it per channel",
    })

    # Test data: weights at full precision.
    rows = []
    for kind, by_n in rules.items():
        for n, r in by_n.items():
            for k in range(n):
                rows.append([kind, str(n), str(k), r["nodes"][k], *r["xyz"][k], *r["opp"][k]])
    write_csv(TESTDATA / "ac1c2_weights.csv",
              ["rule", "N", "k", "wavelength_nm", "X", "Y", "Z", "A", "C1", "C2"], rows, sig=17)

    # Accuracy on the ColorChecker.
    names = colorchecker_names()
    assert len(names) == 24
    acc_rows, summary = [], []
    methods = [(f"ac1c2", n, rules["shared"][n]) for n in N_RANGE] + \
              [(f"ac1c2_gauss_A", n, rules["gauss_A"][n]) for n in N_RANGE] + \
              [("ac1c2_quoted", 4, rules["quoted"][4]), ("rgb", 3, None)]
    for ill in ("D65", "A"):
        light = light_1nm(ill)
        for method, n, r in methods:
            des = []
            for name in names:
                refl = load_spectrum(f"colorchecker/{name}")
                ref, ref_w = reference_xyz(cmf, refl, light)
                if r is None:
                    q, q_w = rgb.xyz(refl, light)
                else:
                    q, q_w = rule_xyz(r["nodes"], r["xyz"], refl, light)
                d = de00(lab(ref, ref_w), lab(q, q_w))
                des.append(d)
                acc_rows.append([method, str(n), ill, name, *ref, *q, d])
            summary.append((method, n, ill, float(np.mean(des)), float(np.median(des)),
                            float(np.max(des)), names[int(np.argmax(des))]))
    write_csv(TESTDATA / "ac1c2_accuracy.csv",
              ["method", "N", "illuminant", "patch", "X_ref", "Y_ref", "Z_ref", "X", "Y", "Z",
               "dE00"], acc_rows, sig=12)
    print("  ColorChecker ΔE00 against 1 nm integration (method, N, illuminant: mean / median / "
          "max, worst patch)")
    for method, n, ill, mean, med, mx, worst in summary:
        print(f"    {method:14s} {n} {ill:3s}  {mean:6.2f} {med:6.2f} {mx:6.2f}  {worst}")

    # The metameric pair in every mode.
    pair = {n: load_spectrum(f"metamers/{n}") for n in ("base", "metamer")}
    white_refl = (np.array([300.0, 830.0]), np.array([1.0, 1.0]))
    mode_rows, de_rows = [], []
    modes = [("spectral_380_780_5", None)] + [(f"ac1c2_{n}", rules["shared"][n]) for n in N_RANGE] \
        + [("ac1c2_4_quoted", rules["quoted"][4]), ("ac1c2_gauss_A_4", rules["gauss_A"][4]),
           ("rgb", "rgb")]
    for ill in ("D65", "A"):
        light = light_1nm(ill)
        col = Colorimeter(ill, "380:780:5")
        for mode, r in modes:
            labs = {}
            for name, refl in [("white", white_refl), *pair.items()]:
                if r is None:
                    xyz, w = col.xyz(*refl), col.white
                elif r == "rgb":
                    xyz, w = rgb.xyz(refl, light)
                else:
                    xyz, w = rule_xyz(r["nodes"], r["xyz"], refl, light)
                labs[name] = lab(xyz, w)
                mode_rows.append([mode, ill, name, *xyz, *labs[name]])
            de_rows.append([mode, ill, de00(labs["base"], labs["metamer"]),
                            deab(labs["base"], labs["metamer"])])
    write_csv(TESTDATA / "representation_modes.csv",
              ["mode", "illuminant", "sample", "X", "Y", "Z", "L", "a", "b"], mode_rows, sig=17)
    write_csv(TESTDATA / "representation_modes_delta_e.csv",
              ["mode", "illuminant", "dE00", "dEab"], de_rows, sig=17)
    print("  the pair's ΔE00 (base vs metamer) by mode:")
    for ill in ("D65", "A"):
        print(f"    {ill:3s} " + "  ".join(f"{m}={d:.3g}" for m, i, d, _ in de_rows if i == ill))

    rgb_rows = [["reflectance", "base", *rgb.refl_rgb(pair["base"])],
                ["reflectance", "metamer", *rgb.refl_rgb(pair["metamer"])],
                ["reflectance", "white", *rgb.refl_rgb(white_refl)],
                ["light", "D65", *rgb.light_rgb(light_1nm("D65"))],
                ["light", "A", *rgb.light_rgb(light_1nm("A"))]]
    write_csv(TESTDATA / "rgb_values.csv", ["kind", "name", "R", "G", "B"], rgb_rows, sig=17)
    for r in rgb_rows:
        print(f"    rgb {r[0]:11s} {r[1]:8s} " + " ".join(f"{x:.6g}" for x in r[2:]))
    print(f"  XYZ→linear sRGB:\n{np.round(rgb.m, 7)}\n  reflectance normalization "
          f"{np.round(rgb.norm, 7)}")
    print(f"{len(written)} files")
    return 0


if __name__ == "__main__":
    sys.exit(main())
