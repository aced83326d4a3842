#!/usr/bin/env python3
"""Independent check of our spectral EXR layout.

Reads a file written by tests/python/write_exr_pattern (value = band + 0.25*x + 0.5*y on the grid
380:1020:20, 5x3 pixels) with colour-science's reader of the Fichet et al. (2021) layout, and checks
that `oiiotool --info -v` lists the channels and header attributes.

Usage: check_exr_colour.py FILE.exr float|half
Exit codes: 0 pass, 1 fail, 77 skipped (oiiotool not found; the colour-science part still ran).
"""

import os
import shutil
import subprocess
import sys
import warnings

import numpy as np

GRID = (380.0, 1020.0, 20.0)
WIDTH, HEIGHT = 5, 3
ATTRIBUTES = {
    "spectralLayoutVersion": "1.0",
    "emissiveUnits": "W.m^-2.sr^-1",
    "metamer:grid": "380:1020:20",
    "metamer:quantity": "spectral radiance per band (docs/physics.md), W·sr⁻¹·m⁻²·nm⁻¹",
}


def channel_name(nm):
    return "S0." + f"{nm:.6f}".replace(".", ",") + "nm"


def expected_cube():
    start, end, step = GRID
    wavelengths = np.arange(start, end + step / 2, step)
    y, x, band = np.meshgrid(
        np.arange(HEIGHT), np.arange(WIDTH), np.arange(len(wavelengths)), indexing="ij"
    )
    return wavelengths, band + 0.25 * x + 0.5 * y


def check_colour(path, depth):
    # colour warns that SciPy is missing; the reader does not need it.
    warnings.filterwarnings("ignore", module="colour")
    from colour.io import read_spectral_image_Fichet2021

    components, specification = read_spectral_image_Fichet2021(
        path, bit_depth="float16" if depth == "half" else "float32", additional_data=True
    )
    assert specification.is_emissive, "colour does not see an emissive image"
    assert not specification.is_polarised, "colour sees a polarised image"
    assert set(components) == {"S0"}, f"components {sorted(components)}, expected only S0"

    wavelengths, values = components["S0"]
    # colour keeps the file's channel order, which is alphabetical: sort by wavelength.
    order = np.argsort(wavelengths)
    wavelengths, values = wavelengths[order], values[..., order]
    expected_wl, expected_values = expected_cube()
    assert np.allclose(wavelengths, expected_wl, rtol=0, atol=1e-6), (
        f"wavelengths {wavelengths.tolist()} != {expected_wl.tolist()}"
    )
    assert values.shape == expected_values.shape, f"shape {values.shape} != {expected_values.shape}"
    # The pattern is exact in float32 and in half.
    assert np.array_equal(values.astype(np.float64), expected_values), (
        f"max |difference| {np.abs(values - expected_values).max()}"
    )

    attributes = {a.name: a.value for a in specification.attributes}
    for name, value in ATTRIBUTES.items():
        assert attributes.get(name) == value, f"attribute {name} = {attributes.get(name)!r}, expected {value!r}"
    print(f"colour-science {__import__('colour').__version__}: {len(wavelengths)} bands, values match")


def find_oiiotool():
    configured = os.environ.get("OIIOTOOL", "")
    if configured and not configured.endswith("NOTFOUND") and os.path.exists(configured):
        return configured
    return shutil.which("oiiotool")


def check_oiiotool(path, depth):
    tool = find_oiiotool()
    if tool is None:
        return False
    out = subprocess.run([tool, "--info", "-v", path], capture_output=True, text=True, check=True).stdout
    kind = "half" if depth == "half" else "float"
    assert f"{WIDTH} x    {HEIGHT}, 33 channel, {kind} openexr" in out, out
    wavelengths, _ = expected_cube()
    listed = next(line for line in out.splitlines() if "channel list:" in line)
    names = [n.strip() for n in listed.split(":", 1)[1].split(",") if n.strip()]
    # The names contain commas themselves; rebuild them in pairs "S0.380" + "000000nm".
    names = [names[i] + "," + names[i + 1] for i in range(0, len(names), 2)]
    assert sorted(names) == sorted(channel_name(w) for w in wavelengths), names
    for name, value in ATTRIBUTES.items():
        assert f'{name}: "{value}"' in out, f"oiiotool does not list {name}: {value!r}\n{out}"
    assert 'compression: "piz"' in out, out
    print(f"oiiotool: {len(names)} channels and {len(ATTRIBUTES)} attributes listed")
    return True


def main():
    if len(sys.argv) != 3 or sys.argv[2] not in ("float", "half"):
        print(__doc__, file=sys.stderr)
        return 2
    path, depth = sys.argv[1], sys.argv[2]
    try:
        check_colour(path, depth)
        if not check_oiiotool(path, depth):
            print("SKIPPED: oiiotool not found (set OIIOTOOL); the colour-science check passed")
            return 77
    except AssertionError as e:
        print(f"FAIL {path}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
