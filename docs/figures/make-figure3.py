#!/usr/bin/env python3
"""The paper's Figure 3: a metameric pair (scenes/metamers.json) rendered with the RGB, AC1C2 and
full-spectral representations (rows) under CIE D65 and A (columns), each cell labelled with the
ΔE2000 between the pair as that mode predicts it, plus the CIE metamerism index of the pair.

The renders come from `metamer render` (the engine); the ΔE2000 in the labels are computed here
with colour-science from the XYZ EXRs the engine writes — an independent check of the numbers.
Run with the project's venv: .venv/bin/python docs/figures/make-figure3.py (needs a build).
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
import colour
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
METAMER = os.environ.get("METAMER", os.path.join(ROOT, "build", "metamer"))
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
MODES = [("rgb", "RGB"), ("ac1c2:4", "AC1C2 (4 samples)"), ("full", "full spectral (5 nm)")]
LIGHTS = ["D65", "A"]


def render(mode, light, out):
    subprocess.run([METAMER, "render", os.path.join(ROOT, "scenes", "metamers.json"), "--out", out,
                    "--mode", mode, "--set", f"lights.0.spectrum=illuminants/{light}",
                    "--write", "png,xyz", "--adapt", "bradford"], check=True, stdout=subprocess.DEVNULL)
    xyz = oiio.ImageBuf(os.path.join(out, "metamers.xyz.exr")).get_pixels(oiio.FLOAT)
    h, w, _ = xyz.shape
    # The two patches' centres (the scene puts base left, metamer right).
    return xyz[h // 2, w // 4].astype(float), xyz[h // 2, 3 * w // 4].astype(float)


def lab(xyz, white):
    return colour.XYZ_to_Lab(xyz / 100.0, colour.XYZ_to_xy(white / 100.0))


def main():
    work = tempfile.mkdtemp()
    cells, labels = {}, {}
    white = {l: colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"][l]) * 100
             for l in LIGHTS}
    measured = {}
    for mode, _ in MODES:
        for light in LIGHTS:
            out = os.path.join(work, f"{mode.replace(':', '-')}-{light}")
            a, b = render(mode, light, out)
            de = float(colour.delta_E(lab(a, white[light]), lab(b, white[light]), method="CIE 2000"))
            measured[(mode, light)] = (a, b, de)
            cells[(mode, light)] = oiio.ImageBuf(os.path.join(out, "metamers.png"))
            labels[(mode, light)] = f"dE2000 {de:.2f}"  # the text renderer takes ASCII
    # CIE metamerism index (full spectral): ΔE2000 under A after the multiplicative correction that
    # makes the pair match under the reference D65 (X'₂ = X₂·X₁,D65/X₂,D65, and Y, Z alike).
    a65, b65, _ = measured[("full", "D65")]
    aA, bA, _ = measured[("full", "A")]
    corrected = bA * (a65 / b65)
    mi = float(colour.delta_E(lab(aA, white["A"]), lab(corrected, white["A"]), method="CIE 2000"))

    cw, ch = cells[(MODES[0][0], LIGHTS[0])].spec().width, cells[(MODES[0][0], LIGHTS[0])].spec().height
    left, top, pad, band = 230, 40, 8, 28
    W = left + len(LIGHTS) * (cw + pad)
    H = top + len(MODES) * (ch + band + pad) + 40
    fig = oiio.ImageBuf(oiio.ImageSpec(W, H, 3, oiio.UINT8))
    oiio.ImageBufAlgo.fill(fig, (1, 1, 1))
    text = dict(fontname=FONT, textcolor=(0, 0, 0))
    for j, light in enumerate(LIGHTS):
        oiio.ImageBufAlgo.render_text(fig, left + j * (cw + pad) + cw // 2 - 40, 28, f"CIE {light}", 22, **text)
    for i, (mode, name) in enumerate(MODES):
        y = top + i * (ch + band + pad)
        oiio.ImageBufAlgo.render_text(fig, 10, y + ch // 2 + 8, name, 18, **text)
        for j, light in enumerate(LIGHTS):
            x = left + j * (cw + pad)
            oiio.ImageBufAlgo.paste(fig, x, y, 0, 0, cells[(mode, light)])
            oiio.ImageBufAlgo.render_text(fig, x + 8, y + ch + 21, labels[(mode, light)], 18, **text)
    oiio.ImageBufAlgo.render_text(fig, 10, H - 14,
                                  f"CIE metamerism index (A, reference D65, full spectral): dE2000 {mi:.2f}", 18, **text)
    path = os.path.join(HERE, "figure3.png")
    fig.write(path)
    print(f"wrote {os.path.relpath(path, ROOT)}")
    print("| mode | D65 | A |\n|---|---|---|")
    for mode, name in MODES:
        print(f"| {name} | {measured[(mode, 'D65')][2]:.4f} | {measured[(mode, 'A')][2]:.4f} |")
    print(f"metamerism index (A vs D65, ΔE2000): {mi:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
