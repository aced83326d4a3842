#!/usr/bin/env python3
"""Writes spectra/cornell/: the measured spectra of the Cornell box (README, "Cornell box").

The numbers are the Cornell University Program of Computer Graphics' published measurements of the
box's surfaces and light ("Cornell Box Data", www.graphics.cornell.edu/online/box/data.html): the
diffuse reflectance of its white, green and red surfaces at 76 wavelengths (400–700 nm, 4 nm) and
the relative emission of its light at four (400, 500, 600, 700 nm). They are transcribed here as
facts of that dataset; the script only writes them in the library's format. Deterministic.

    .venv/bin/python spectra/generate_cornell.py
"""
import os
import sys

ROOT = os.path.dirname(os.path.abspath(__file__))

WAVELENGTHS = list(range(400, 701, 4))  # 76 samples

WHITE = [0.343, 0.445, 0.551, 0.624, 0.665, 0.687, 0.708, 0.723, 0.715, 0.710, 0.745, 0.758, 0.739, 0.767, 0.777,
         0.765, 0.751, 0.745, 0.748, 0.729, 0.745, 0.757, 0.753, 0.750, 0.746, 0.747, 0.735, 0.732, 0.739, 0.734,
         0.725, 0.721, 0.733, 0.725, 0.732, 0.743, 0.744, 0.748, 0.728, 0.716, 0.733, 0.726, 0.713, 0.740, 0.754,
         0.764, 0.752, 0.736, 0.734, 0.741, 0.740, 0.732, 0.745, 0.755, 0.751, 0.744, 0.731, 0.733, 0.744, 0.731,
         0.712, 0.708, 0.729, 0.730, 0.727, 0.707, 0.703, 0.729, 0.750, 0.760, 0.751, 0.739, 0.724, 0.730, 0.740,
         0.737]
GREEN = [0.092, 0.096, 0.098, 0.097, 0.098, 0.095, 0.095, 0.097, 0.095, 0.094, 0.097, 0.098, 0.096, 0.101, 0.103,
         0.104, 0.107, 0.109, 0.112, 0.115, 0.125, 0.140, 0.160, 0.187, 0.229, 0.285, 0.343, 0.390, 0.435, 0.464,
         0.472, 0.476, 0.481, 0.462, 0.447, 0.441, 0.426, 0.406, 0.373, 0.347, 0.337, 0.314, 0.285, 0.277, 0.266,
         0.250, 0.230, 0.207, 0.186, 0.171, 0.160, 0.148, 0.141, 0.136, 0.130, 0.126, 0.123, 0.121, 0.122, 0.119,
         0.114, 0.115, 0.117, 0.117, 0.118, 0.120, 0.122, 0.128, 0.132, 0.139, 0.144, 0.146, 0.150, 0.152, 0.157,
         0.159]
RED = [0.040, 0.046, 0.048, 0.053, 0.049, 0.050, 0.053, 0.055, 0.057, 0.056, 0.059, 0.057, 0.061, 0.061, 0.060,
       0.062, 0.062, 0.062, 0.061, 0.062, 0.060, 0.059, 0.057, 0.058, 0.058, 0.058, 0.056, 0.055, 0.056, 0.059,
       0.057, 0.055, 0.059, 0.059, 0.058, 0.059, 0.061, 0.061, 0.063, 0.063, 0.067, 0.068, 0.072, 0.080, 0.090,
       0.099, 0.124, 0.154, 0.192, 0.255, 0.287, 0.349, 0.402, 0.443, 0.487, 0.513, 0.558, 0.584, 0.620, 0.606,
       0.609, 0.651, 0.612, 0.610, 0.650, 0.638, 0.627, 0.620, 0.630, 0.628, 0.642, 0.639, 0.657, 0.639, 0.635,
       0.642]
LIGHT_WAVELENGTHS = [400, 500, 600, 700]
LIGHT = [0.0, 8.0, 15.6, 18.4]


def write(rel, wavelengths, values):
    assert len(wavelengths) == len(values), rel
    path = os.path.join(ROOT, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="\n") as f:
        f.write("wavelength_nm,value\n")
        for w, v in zip(wavelengths, values):
            f.write(f"{w},{v:g}\n")
    print(f"  {rel}: {wavelengths[0]}–{wavelengths[-1]} nm, {len(values)} samples")


def main():
    assert len(WAVELENGTHS) == 76
    for name, values in [("white", WHITE), ("green", GREEN), ("red", RED)]:
        assert all(0.0 <= v <= 1.0 for v in values), name
        write(f"cornell/{name}.csv", WAVELENGTHS, values)
    write("cornell/light.csv", LIGHT_WAVELENGTHS, LIGHT)
    return 0


if __name__ == "__main__":
    sys.exit(main())
