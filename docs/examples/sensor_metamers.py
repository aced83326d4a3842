#!/usr/bin/env python3
"""When does sensor noise hide a camera's metameric mismatch? The metameric pair of the paper's
Figure 3 (scenes/metamers.json: a CIE 1931 match under D65) captured by the simulated RGGB sensor
(spectra/sensors/aps_c_rggb.json, docs/sensor.md) at a full exposure and at 1/64 and 1/1024 of it,
demosaiced by colour-demosaicing (bilinear), compared patch against patch.

The camera is not the CIE observer, so it sees the pair differently even under D65: the noise-free
capture's expected electrons give each channel's mismatch Δ. Noise gives each demosaiced pixel a standard
deviation σ. Δ/σ is the mismatch's signal-to-noise ratio per pixel (below 1 a single pixel cannot
tell the patches apart), and Δ/(σ·√(2/n)) that of two n-pixel patch means. Run from the
repository root after a build:

    .venv/bin/python docs/examples/sensor_metamers.py [LIGHT]      # LIGHT: illuminants/D65 (default), illuminants/A, …

`analyse()` returns the rows it prints.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

warnings.filterwarnings("ignore")
from colour_demosaicing import demosaicing_CFA_Bayer_bilinear  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
BINARY = os.environ.get("METAMER_BINARY", str(REPO / "build" / "metamer"))
# Two boxes well inside the 8 cm patches (256 × 128 pixels over 0.24 × 0.12 m).
BASE = (slice(44, 84), slice(65, 105))
METAMER = (slice(44, 84), slice(151, 191))


def metamer(*args):
    p = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    return p.stdout


def electrons(folder, name):
    """The demosaiced raw in electrons: (DN − black)/K, then bilinear demosaicing."""
    meta = json.loads((folder / f"{name}.json").read_text())
    raw = oiio.ImageBuf(str(folder / f"{name}.png")).get_pixels(oiio.UINT16)[..., 0].astype(float)
    e = (raw - meta["black_level_dn"]) / meta["conversion_gain_dn_per_e"]
    return demosaicing_CFA_Bayer_bilinear(e, pattern="RGGB"), meta


def analyse(light="illuminants/D65"):
    work = Path(tempfile.mkdtemp())
    metamer("render", REPO / "scenes" / "metamers.json", "--out", work, "--write", "cube",
            "--set", f"lights.0.spectrum={light}")
    cube = work / "metamers.exr"
    metamer("capture", cube, "--sensor", "aps_c_rggb", "--out", work / "auto", "--no-noise")
    full = json.loads((work / "auto" / "metamers.raw.json").read_text())["exposure_s"]
    rows = []
    for i, fraction in enumerate((1, 1 / 64, 1 / 1024)):
        t = full * fraction
        # A folder per capture: OpenImageIO caches images by name.
        folder = work / f"capture{i}"
        metamer("capture", cube, "--sensor", "aps_c_rggb", "--out", folder, "--seed", 1, "--exposure", t)
        noisy, _ = electrons(folder, "metamers.raw")
        # The truth: the expected electrons (no noise, no rounding), demosaiced the same way.
        truth = oiio.ImageBuf(str(folder / "metamers.electrons.exr")).get_pixels(oiio.FLOAT)[..., 0].astype(float)
        clean = demosaicing_CFA_Bayer_bilinear(truth, pattern="RGGB")
        n = clean[BASE][..., 0].size
        for c, channel in enumerate("RGB"):
            delta = clean[METAMER][..., c].mean() - clean[BASE][..., c].mean()
            sigma = 0.5 * (noisy[BASE][..., c].std() + noisy[METAMER][..., c].std())
            measured = noisy[METAMER][..., c].mean() - noisy[BASE][..., c].mean()
            rows.append({"exposure_s": t, "fraction": fraction, "channel": channel,
                         "signal_e": clean[BASE][..., c].mean(), "delta_e": delta, "sigma_e": sigma,
                         "snr_pixel": abs(delta) / sigma, "snr_patch": abs(delta) / (sigma * np.sqrt(2.0 / n)),
                         "measured_delta_e": measured})
    return rows


def main():
    light = sys.argv[1] if len(sys.argv) > 1 else "illuminants/D65"
    rows = analyse(light)
    print(f"scenes/metamers.json under {light}, aps_c_rggb, 40 × 40-pixel boxes, bilinear demosaicing")
    print(" exposure   channel  signal e⁻   Δ e⁻ (truth)  σ e⁻/pixel  Δ/σ pixel  Δ/σ patch  Δ measured")
    for r in rows:
        print(f" {r['exposure_s']:.3e}  {r['channel']:>5}  {r['signal_e']:10.1f}  {r['delta_e']:+12.2f}  "
              f"{r['sigma_e']:10.2f}  {r['snr_pixel']:9.2f}  {r['snr_patch']:9.1f}  {r['measured_delta_e']:+10.2f}")


if __name__ == "__main__":
    main()
