#!/usr/bin/env python3
"""Independent check of the RGB up-sampling (engine/color/rgb_upsampling.h) with colour-science.

Reads the file written by tests/python/write_upsampled_spectra and, for every colour:

* evaluates the Jakob & Hanika (2019) model with colour-science's own `sd_Jakob2019` from the
  engine's coefficients (nm units) and compares it with the engine's ρ(λ) at 1 nm;
* integrates that spectrum under D65 with the CIE 1931 observer (colour's observer table and
  `sd_to_XYZ`, "Integration"), converts to linear sRGB with a matrix colour derives from the sRGB
  primaries and white, normalized per channel
  so that the perfect white diffuser is (1, 1, 1) (docs/representations.md "RGB"), and compares it
  with the input colour: ΔE2000 in colour's CIELAB, and with the engine's own figure.

D65 is the library's table (spectra/illuminants/D65.csv, the CIE's 5 nm values) made linear
between its samples and 0 past 780 nm, as the engine reads it (spectra/README.md): colour's own
default would interpolate it with Sprague's method and hold it past 780 nm, a different definition
that moves saturated colours by up to 0.01 ΔE00. With the same definition the spectra's colour
is within 2e-4 ΔE00 of the input (the fit stops at ΔE*ab 1e-4) and within 1e-5 of the engine's own
figure (measured: 6.6e-5 and 8.7e-7 over 74 colours).

Usage: check_upsampling_colour.py FILE.csv
Exit codes: 0 pass, 1 fail.
"""

import os
import sys
import warnings

import numpy as np


SPECTRA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "spectra")


def main(path):
    warnings.filterwarnings("ignore")  # colour warns that SciPy is missing; nothing here needs it
    import colour
    from colour.recovery import sd_Jakob2019

    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    rgb_in, coefficients, rgb_engine, rho_engine = data[:, 0:3], data[:, 3:6], data[:, 6:9], data[:, 9:]
    shape = colour.SpectralShape(360, 830, 1)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)
    table = np.loadtxt(os.path.join(SPECTRA, "illuminants", "D65.csv"), delimiter=",", skiprows=1)
    d65 = colour.SpectralDistribution(
        np.interp(shape.wavelengths, table[:, 0], table[:, 1], left=0.0, right=0.0), shape.wavelengths)
    # The sRGB matrix derived from the primaries and the white XYZ (0.95047, 1, 1.08883), as
    # color/srgb.h does; colour's RGB_COLOURSPACES["sRGB"] carries the standard's 4-decimal matrix
    # instead, which moves saturated colours by up to 0.01 ΔE00.
    primaries = colour.RGB_COLOURSPACES["sRGB"].primaries
    to_xyz = colour.normalised_primary_matrix(primaries, colour.XYZ_to_xy(np.array([0.95047, 1.0, 1.08883])))
    to_rgb = np.linalg.inv(to_xyz)

    def linear_srgb(sd):
        return to_rgb @ colour.sd_to_XYZ(sd, cmfs, d65, method="Integration")

    white = linear_srgb(colour.SpectralDistribution(np.ones(len(shape)), shape.wavelengths))
    white_xyz = to_xyz @ np.ones(3)

    def lab(rgb):
        return colour.XYZ_to_Lab(to_xyz @ rgb, colour.XYZ_to_xy(white_xyz))

    failures = 0
    worst_model = worst_oracle = worst_engine = 0.0
    for i in range(len(data)):
        sd = sd_Jakob2019(coefficients[i], shape)
        model = np.max(np.abs(sd.values - rho_engine[i]))
        rgb = linear_srgb(sd) / white
        de_oracle = float(colour.delta_E(lab(rgb), lab(rgb_in[i]), method="CIE 2000"))
        de_engine = float(colour.delta_E(lab(rgb), lab(rgb_engine[i]), method="CIE 2000"))
        worst_model, worst_oracle, worst_engine = (
            max(worst_model, model), max(worst_oracle, de_oracle), max(worst_engine, de_engine))
        if model > 1e-12 or de_oracle > 2e-4 or de_engine > 1e-5:
            failures += 1
            print(f"FAIL colour {rgb_in[i]}: |Δρ| {model:.2e}, ΔE00 to the input {de_oracle:.2e}, "
                  f"to the engine's colour {de_engine:.2e}")
    print(f"{len(data)} colours: model |Δρ| ≤ {worst_model:.2e}; colour-science's colour of the "
          f"up-sampled spectrum vs the input: ΔE00 ≤ {worst_oracle:.2e}; vs the engine's: ≤ {worst_engine:.2e}")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
