#!/usr/bin/env python3
"""The slabs of write_dielectric_slabs (engine/spectral/dielectric) against an independent
package: `tmm`'s incoherent transfer-matrix solver (Byrnes), air | slab | air with the slab
incoherent, s and p averaged. An absorbance A (decadic, per metre) is the extinction coefficient
k = A·ln(10)·λ/(4π); k is ~1e-5 at most here, so the interfaces' Fresnel terms it adds are below
1e-9. Prints the worst differences; exits 1 beyond 1e-9.

    check_dielectric_tmm.py SLABS.csv"""
import csv
import math
import sys

import numpy as np
import tmm

rows = list(csv.DictReader(open(sys.argv[1])))
worst_r = worst_t = 0.0
for r in rows:
    n, nm, deg = float(r["n"]), float(r["wavelength_nm"]), float(r["incidence_deg"])
    d, a = float(r["thickness_m"]), float(r["absorbance_per_m"])
    k = a * math.log(10.0) * (nm * 1e-9) / (4.0 * math.pi)
    lam = nm * 1e-9
    rt = []
    for pol in ("s", "p"):
        out = tmm.inc_tmm(pol, [1.0, n + 1j * k, 1.0], [np.inf, d, np.inf], ["i", "i", "i"], math.radians(deg), lam)
        rt.append((out["R"], out["T"]))
    R = 0.5 * (rt[0][0] + rt[1][0])
    T = 0.5 * (rt[0][1] + rt[1][1])
    worst_r = max(worst_r, abs(R - float(r["R"])))
    worst_t = max(worst_t, abs(T - float(r["T"])))
print(f"{len(rows)} slabs (n = 1.5 and N-BK7, 0-85 degrees, clear and absorbing) against tmm.inc_tmm: "
      f"largest |dR| {worst_r:.2e}, |dT| {worst_t:.2e}")
sys.exit(0 if worst_r <= 1e-9 and worst_t <= 1e-9 else 1)
