"""A user's script with metamer.kubelka_munk, type-checked by mypy --strict against the package's
types (test_typing.py); never run."""

import math

import numpy as np
import numpy.typing as npt

import metamer
from metamer import kubelka_munk as km

wavelengths = np.arange(380.0, 781.0, 10.0)
k_white, s_white = np.full(wavelengths.shape, 2.0), np.full(wavelengths.shape, 3000.0)
k_black, s_black = np.full(wavelengths.shape, 5e4), np.full(wavelengths.shape, 400.0)

one: float = km.reflectance(1.0, 10.0, 0.1, substrate=0.8)
opaque: float = km.reflectance(1, 10, math.inf)
spectrum: npt.NDArray[np.float64] = km.reflectance(k_white, s_white, 20e-6, 0.5)
K, S = km.mix([(0.1, k_white, s_white), (0.002, k_black, s_black)], K=5.0)
bands: npt.NDArray[np.float64] = km.infinite(K, S)
K1, S1 = km.mix([(0.1, 2.0, 3000.0)])
ratio: float = K1 / S1
over_primer: npt.NDArray[np.float64] = km.stack([(K, S, 20e-6), (k_white, s_white, 5e-6)], substrate=0.8)
film: float = km.stack([(1.0, 10.0, 0.04), (1.0, 10.0, 0.06)], 0.8)
n = 1.5
r_e: float = km.external_diffuse_reflectance(n)
r_i: float = km.k2(n)
body: float = km.saunderson_body(km.infinite(0.1, 1.0), km.k1(n), r_i)
measured = np.linspace(0.05, 0.9, 18)
k_over_s: npt.NDArray[np.float64] = km.k_over_s(km.saunderson_inverse(measured, km.k1(n), r_i))
try:
    km.k_over_s(0.0)
except metamer.InputError as e:
    print(e)
print(one, opaque, spectrum.mean(), bands.max(), ratio, over_primer.min(), film, r_e, body, k_over_s.max(),
      km.transmittance(1.0, 10.0, 0.1) + km.saunderson(0.3, 0.04, 0.6))
