#!/usr/bin/env python3
"""The Kubelka–Munk layers of write_kubelka_munk (engine/spectral/kubelka_munk) against two
independent oracles, which must first agree with each other:

(a) numpy: Kubelka's closed forms in the textbook variables a = 1 + K/S, b = sqrt(a^2 - 1):
    R = (1 - Rg (a - b coth bSX)) / (a - Rg + b coth bSX), T = b / (a sinh bSX + b cosh bSX),
    R_inf = a - b, Saunderson R_m = k1 + (1 - k1)(1 - k2) R / (1 - k2 R);
(b) scipy: solve_bvp on the two-flux equations, x down into the layer, i the downward and j the
    upward diffuse flux: di/dx = -(K + S) i + S j, dj/dx = (K + S) j - S i, with i(0) = 1 and
    j(X) = Rg i(X); R = j(0), T = i(X) over black.

Then the diffuse Fresnel reflectances (Saunderson's k2 is the internal one) by scipy.integrate.quad
of Fresnel's equations written here, and the issue's known answers. Exits 1 beyond 1e-9 (layers) /
1e-10 (interfaces), or when the oracles disagree beyond 1e-7 (the ODE solve's tolerance).

    check_kubelka_munk.py PREFIX   (reads PREFIX_layers.csv and PREFIX_interfaces.csv)"""
import csv
import math
import sys

import numpy as np
from scipy.integrate import solve_bvp

from fresnel_oracle import diffuse_reflectance

prefix = sys.argv[1]
failures = []


def closed_form(K, S, X, Rg):
    a = 1.0 + K / S
    b = math.sqrt(a * a - 1.0)
    bsx = b * S * X
    coth = 1.0 / math.tanh(bsx)
    R = (1.0 - Rg * (a - b * coth)) / (a - Rg + b * coth)
    T = b / (a * math.sinh(bsx) + b * math.cosh(bsx))
    return R, T, a - b


def two_flux(K, S, X, Rg):
    def rhs(x, y):
        i, j = y
        return np.vstack((-(K + S) * i + S * j, (K + S) * j - S * i))

    def bc(y0, yX):
        return np.array([y0[0] - 1.0, yX[1] - Rg * yX[0]])

    x = np.linspace(0.0, X, 200)
    guess = np.vstack((np.exp(-K * x), 0.5 * np.exp(-K * x)))
    sol = solve_bvp(rhs, bc, x, guess, tol=1e-10, max_nodes=200000)
    if not sol.success:
        raise RuntimeError(f"solve_bvp failed for K={K} S={S} X={X} Rg={Rg}: {sol.message}")
    return sol.sol(0.0)[1], sol.sol(X)[0]


def saunderson(R, k1, k2):
    return k1 + (1 - k1) * (1 - k2) * R / (1 - k2 * R)


# 1. The oracles agree: closed form against the ODE solve on cases that span thin to opaque.
worst_oracles = 0.0
for K, S, X, Rg in [(1, 10, 0.1, 0.0), (1, 10, 0.1, 0.8), (0.05, 1, 0.5, 0.3), (8, 60, 0.02, 1.0), (0.2, 3, 1.0, 0.5)]:
    R, T, _ = closed_form(K, S, X, Rg)
    Rode, _ = two_flux(K, S, X, Rg)
    _, Tode = two_flux(K, S, X, 0.0)
    if Rg == 0.0:
        worst_oracles = max(worst_oracles, abs(T - Tode))
    worst_oracles = max(worst_oracles, abs(R - Rode))
print(f"numpy closed forms against scipy's two-flux solve: largest difference {worst_oracles:.1e}")
if worst_oracles > 1e-7:
    failures.append("the two oracles disagree")

# 2. The known answers, from the oracles.
R_inf = closed_form(0.1, 1.0, 1.0, 0.0)[2]
known = {
    "R_inf(K/S = 0.1) = 0.6417424": (R_inf, 0.6417424),
    "R(K 1, S 10, X 0.1) over black = 0.4610336": (two_flux(1, 10, 0.1, 0.0)[0], 0.4610336),
    "R over Rg 0.8 = 0.7123473": (two_flux(1, 10, 0.1, 0.8)[0], 0.7123473),
    "T = 0.4452842": (two_flux(1, 10, 0.1, 0.0)[1], 0.4452842),
    "Saunderson(k1 0.04, k2 0.6) of R_inf = 0.4407273": (saunderson(R_inf, 0.04, 0.6), 0.4407273),
}
for what, (got, want) in known.items():
    if abs(got - want) > 5e-8:
        failures.append(f"oracle: {what}, got {got:.9f}")

# 3. The engine's layers against the closed forms.
rows = list(csv.DictReader(open(prefix + "_layers.csv")))
worst = {"R": 0.0, "R_black": 0.0, "T": 0.0, "R_inf": 0.0, "R_saunderson": 0.0}
for r in rows:
    K, S, X, Rg = (float(r[k]) for k in ("K", "S", "X", "Rg"))
    if K > 0.0:
        R, T, Rinf = closed_form(K, S, X, Rg)
        want = {"R": R, "R_black": closed_form(K, S, X, 0.0)[0], "T": T, "R_inf": Rinf,
                "R_saunderson": saunderson(Rinf, 0.04, 0.6)}
    else:  # a = 1, b = 0: the limits of the closed forms, written out
        want = {"R": (Rg + S * X * (1 - Rg)) / (1 + S * X * (1 - Rg)), "R_black": S * X / (1 + S * X),
                "T": 1 / (1 + S * X), "R_inf": 1.0, "R_saunderson": saunderson(1.0, 0.04, 0.6)}
    for k in worst:
        worst[k] = max(worst[k], abs(float(r[k]) - want[k]))
print(f"{len(rows)} layers (K 0-8, S 0.1-60, X 0.001-3, Rg 0-1) against the closed forms: " +
      ", ".join(f"|d{k}| {v:.1e}" for k, v in worst.items()))
if max(worst.values()) > 1e-9:
    failures.append("the engine's layers differ from the closed forms beyond 1e-9")


# 4. Diffuse Fresnel reflectance: unpolarized Fresnel integrated over a Lambertian hemisphere
# (tests/python/fresnel_oracle.py).
worst_i = worst_e = 0.0
for r in csv.DictReader(open(prefix + "_interfaces.csv")):
    n = float(r["n"])
    ri = diffuse_reflectance(n, 1.0) if n > 1 else 0.0
    re = diffuse_reflectance(1.0, n)
    worst_i = max(worst_i, abs(ri - float(r["internal"])))
    worst_e = max(worst_e, abs(re - float(r["external"])))
    if abs(float(r["k1"]) - ((n - 1) / (n + 1)) ** 2) > 1e-15:
        failures.append(f"k1 at n = {n}")
print(f"diffuse Fresnel reflectance, n 1-3, against scipy.integrate.quad: internal (k2) |d| {worst_i:.1e}, "
      f"external |d| {worst_e:.1e}; at n = 1.5: internal {diffuse_reflectance(1.5, 1.0):.5f}, external {diffuse_reflectance(1.0, 1.5):.5f}")
if worst_i > 1e-10 or worst_e > 1e-10:
    failures.append("the diffuse Fresnel reflectances differ beyond 1e-10")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
