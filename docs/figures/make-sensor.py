#!/usr/bin/env python3
"""docs/figures/sensor.png: the metameric pair of scenes/metamers.json (a CIE 1931 match under D65)
captured by the simulated aps_c_rggb sensor (docs/sensor.md) at the automatic exposure and at 1/64
and 1/1024 of it, seed 1. Each raw is demosaiced by colour-demosaicing (bilinear), taken to CIE
XYZ with the inverse of the DNG colour matrix the capture computed (the sensor's own ColorChecker
characterization), scaled by the exposure ratio so the three are equally bright, and shown in
sRGB. The camera sees the pair differ (left patch against right) at full exposure; at 1/1024 the
noise is larger than the difference. Needs a build, the project's venv and oiiotool:

    .venv/bin/python docs/figures/make-sensor.py
"""
import json
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

warnings.filterwarnings("ignore")
import colour  # noqa: E402
from colour_demosaicing import demosaicing_CFA_Bayer_bilinear  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
BINARY = REPO / "build" / "metamer"
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"


def run(*args):
    p = subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True)
    if p.returncode:
        sys.exit(p.stderr)


def main():
    work = Path(tempfile.mkdtemp())
    run("render", REPO / "scenes" / "metamers.json", "--out", work, "--write", "cube")
    run("capture", work / "metamers.exr", "--sensor", "aps_c_rggb", "--out", work / "auto", "--no-noise")
    full = json.loads((work / "auto" / "metamers.raw.json").read_text())["exposure_s"]
    panels = []
    for i, (fraction, label) in enumerate([(1, "auto exposure"), (1 / 64, "1/64 of it"), (1 / 1024, "1/1024 of it")]):
        folder = work / f"f{i}"
        run("capture", work / "metamers.exr", "--sensor", "aps_c_rggb", "--out", folder, "--seed", 1,
            "--exposure", full * fraction)
        meta = json.loads((folder / "metamers.raw.json").read_text())
        raw = oiio.ImageBuf(str(folder / "metamers.raw.png")).get_pixels(oiio.UINT16)[..., 0].astype(float)
        camera = demosaicing_CFA_Bayer_bilinear((raw - meta["black_level_dn"]) / fraction, pattern="RGGB")
        to_xyz = np.linalg.inv(np.array(meta["xyz_to_camera_d65"]).reshape(3, 3))
        xyz = camera @ to_xyz.T
        xyz /= np.percentile(xyz[..., 1], 99.5) / 0.9
        rgb = colour.XYZ_to_sRGB(xyz)
        counts = (np.clip(rgb, 0, 1) * 255 + 0.5).astype(np.uint8)
        path = work / f"panel{i}.png"
        out = oiio.ImageOutput.create(str(path))
        out.open(str(path), oiio.ImageSpec(counts.shape[1], counts.shape[0], 3, oiio.UINT8))
        out.write_image(counts)
        out.close()
        panels += [str(path), "--resize", "384x192", "--fullsize", "384x222", "--croptofull",
                   f"--text:x=10:y=214:size=16:color=1,1,1:font={FONT}", f"{label}, seed 1"]
    subprocess.run(["oiiotool", *panels, "--mosaic:pad=8", "3x1", "-d", "uint8", "-o",
                    str(REPO / "docs" / "figures" / "sensor.png")], check=True)
    print("wrote docs/figures/sensor.png")


if __name__ == "__main__":
    main()
