#!/usr/bin/env python3
"""The paper's Figure 6: scenes/fluorescent.json under CIE illuminant A, D65 and a black light, left
to right: plain paper, the same paper with an optical brightener, an orange and a pink
daylight-fluorescent paint. Each light is scaled to the same irradiance, 300–780 nm (the scene's
grid), as the scene's D65 (as lamps of one radiant output), and one exposure serves all three
panels — the luminance of a white diffuser under that D65 is display white — with no chromatic
adaptation, so the rooms differ as the lights do: A's is warm, and the black light's, whose output
is nearly all ultraviolet, is dark but for what fluoresces.

Each panel is CIE 1931 XYZ in cd/m² (metamer.render(..., xyz="absolute")), divided by that one
luminance, converted to sRGB by colour-science (D65 white, no adaptation), clipped and encoded;
oiiotool labels the panels and lays them side by side.

Needs the build's Python module and oiiotool: bash ci/build.sh, then
.venv/bin/python docs/figures/make-figure6.py   (writes docs/figures/figure6.png)"""

import os
import subprocess
import tempfile
import warnings

import colour
import numpy as np

import metamer

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(ROOT, "scenes", "fluorescent.json")
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
LIGHTS = [("illuminants/A", "CIE A"), ("illuminants/D65", "D65"), ("illuminants/blacklight", "black light")]


def irradiance(name):
    """∫ E(λ) dλ over 300–780 nm of a library spectrum (trapezoids on its own points), relative."""
    data = np.loadtxt(os.path.join(ROOT, "spectra", name + ".csv"), delimiter=",", skiprows=1)
    inside = (data[:, 0] >= 300) & (data[:, 0] <= 780)
    return float(np.trapezoid(data[inside, 1], data[inside, 0]))


def overrides(spectrum):
    """The scene's light with `spectrum`, scaled to D65's irradiance at the scene's scale (0.01)."""
    scale = 0.01 * irradiance("illuminants/D65") / irradiance(spectrum)
    return {"lights.0.spectrum": spectrum, "lights.0.scale": scale}


def white_luminance():
    """cd/m² of a perfect white diffuser under the D65 panel's light: the one exposure."""
    relative = metamer.render(SCENE, overrides=overrides("illuminants/D65"), write="xyz")
    absolute = metamer.render(SCENE, overrides=overrides("illuminants/D65"), write="xyz", xyz="absolute")
    y_rel, y_abs = relative.xyz[..., 1], absolute.xyz[..., 1]
    lit = y_rel > 1.0
    return float(np.median(y_abs[lit] / y_rel[lit]) * 100.0)


def write_ppm(path, rgb8):
    h, w, _ = rgb8.shape
    with open(path, "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (w, h))
        f.write(np.ascontiguousarray(rgb8, dtype=np.uint8).tobytes())


def main():
    warnings.simplefilter("ignore", metamer.Warning)  # the black light's data end at 500 nm
    y_white = white_luminance()
    with tempfile.TemporaryDirectory() as work:
        args = ["oiiotool"]
        for spectrum, label in LIGHTS:
            r = metamer.render(SCENE, overrides=overrides(spectrum), write="xyz", xyz="absolute")
            rgb = colour.XYZ_to_sRGB(np.asarray(r.xyz, dtype=np.float64) / y_white, apply_cctf_encoding=True)
            rgb8 = np.round(np.clip(rgb, 0.0, 1.0) * 255.0)
            panel = os.path.join(work, spectrum.split("/")[-1] + ".ppm")
            write_ppm(panel, rgb8)
            h, w, _ = rgb8.shape  # a black band of 40 px below each panel holds its label
            args += [panel, "--fullsize", f"{w}x{h + 40}", "--croptofull",
                     f"--text:x=14:y={h + 28}:size=24:color=1,1,1:font={FONT}", label]
        out = os.path.join(HERE, "figure6.png")
        args += ["--mosaic:pad=8", "3x1", "-d", "uint8", "-o", out]
        subprocess.run(args, check=True)
    print(f"wrote {os.path.relpath(out, ROOT)} (left to right: CIE A, D65, black light; white diffuser "
          f"under D65 = {y_white:.3g} cd/m² = display white)")


if __name__ == "__main__":
    main()
