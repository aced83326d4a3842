#!/usr/bin/env python3
"""Metamer's colorimetry against the standards, with colour-science 0.4.7 as the oracle
(issue 13; docs/color.md "Integration"):

    check_colorimetry_standards.py METAMER_BINARY WORK_DIR [--quick]

Renders the 24 ColorChecker patches of scenes/colorchecker.json head-on with `metamer render
--write xyz` (GPU path, validation layers on) under CIE D65, A and FL2, seen by the CIE 1931 and
1964 observers, and compares each patch's XYZ with colour-science's on the same library data
(spectra/ holds colour-science's tables):

* CIE 15 summation (--integration riemann, the default) on 380:780:5, against
  colour.sd_to_XYZ(method="Integration") on that shape: the data are already on it;
* the same on 360:830:1 against colour-science interpolating the 5 nm data to 1 nm by its own
  LinearInterpolator (Metamer's default rule) — and, with --resample sprague, by its
  SpragueInterpolator (its default, CIE 167) —, 0 outside the data (Metamer's coverage policy);
* ASTM E308 (--integration astm-e308) on 380:780:10 and 380:780:20 against
  colour.sd_to_XYZ(method="ASTM E308") of the patch sampled at 10 and 20 nm.

Each comparison is a CIELAB ΔE2000 relative to colour-science's perfect diffuser; the worst per
observer, illuminant and method is printed, and any over its bound (0.001 for the summations,
0.01 for E308) fails. --quick checks D65 only. --band-mean renders every case with
`--resample band-mean` (the rule before issue 13) and reports without failing: the "before"
figures of docs/color.md.
"""

from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore")
import colour  # noqa: E402
import OpenImageIO as oiio  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SPECTRA = REPO / "spectra"
SCENE = REPO / "scenes" / "colorchecker.json"
WIDTH, HEIGHT = 150, 100
OBSERVERS = {"cie1931": "cie1931_2deg", "cie1964": "cie1964_10deg"}


def table(rel: str):
    d = np.genfromtxt(SPECTRA / f"{rel}.csv", delimiter=",", skip_header=1)
    return d[:, 0], d[:, 1:]


def sd(rel: str) -> colour.SpectralDistribution:
    w, v = table(rel)
    return colour.SpectralDistribution(v[:, 0], w, name=rel)


def cmfs(observer: str) -> colour.MultiSpectralDistributions:
    w, v = table(f"observers/{OBSERVERS[observer]}")
    return colour.MultiSpectralDistributions(v, w, labels=["x_bar", "y_bar", "z_bar"], name=observer)


def on_shape(s: colour.SpectralDistribution, shape, interpolator) -> colour.SpectralDistribution:
    return s.copy().align(shape, interpolator=interpolator,
                          extrapolator_kwargs={"method": "Constant", "left": 0, "right": 0})


def patches() -> list[tuple[str, int, int]]:
    """(library name, pixel x, pixel y) of each patch centre at WIDTH × HEIGHT."""
    scene = json.loads(SCENE.read_text())
    height_m = scene["camera"]["height_m"]
    width_m = height_m * WIDTH / HEIGHT
    out = []
    for o in scene["objects"]:
        rel = scene["materials"][o["material"]]["diffuse"]
        if not isinstance(rel, str):
            continue
        cx, cy = o["center"][0], o["center"][1]
        out.append((rel, int((cx / width_m + 0.5) * WIDTH), int((0.5 - cy / height_m) * HEIGHT)))
    return out


def render(metamer: str, work: Path, tag: str, illuminant: str, observer: str, grid: str,
           integration: str, resample: str = "interpolate") -> np.ndarray:
    out = work / tag
    cmd = [metamer, "render", str(SCENE), "--out", str(out), "--grid", grid, "--resample", resample,
           "--detector", observer, "--integration", integration, "--write", "xyz", "--validation",
           "--set", f"lights.0.spectrum=illuminants/{illuminant}", "--set", f"camera.width={WIDTH}",
           "--set", f"camera.height={HEIGHT}"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"FAIL {' '.join(cmd)}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    image = oiio.ImageInput.open(str(out / "colorchecker.xyz.exr"))
    pixels = image.read_image(format="float")
    image.close()
    return np.asarray(pixels, dtype=float)


def main() -> int:
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    metamer, work = sys.argv[1], Path(sys.argv[2])
    work.mkdir(parents=True, exist_ok=True)
    quick = "--quick" in sys.argv
    before = "--band-mean" in sys.argv
    illuminants = ["D65"] if quick else ["D65", "A", "FL2"]
    where = patches()
    assert len(where) == 24
    reflectances = {rel: sd(rel) for rel, _, _ in where}
    perfect5 = colour.SpectralDistribution(np.ones(81), np.arange(380.0, 781.0, 5.0), name="perfect")
    methods = [
        # tag, grid, integration, resample, bound, oracle(patch sd, cmfs, illuminant) -> XYZ
        ("integration-5nm", "380:780:5", "riemann", "interpolate", 1e-3,
         lambda r, c, i: colour.sd_to_XYZ(r, c, i, method="Integration", shape=colour.SpectralShape(380, 780, 5))),
        ("integration-1nm-linear", "360:830:1", "riemann", "interpolate", 1e-3,
         lambda r, c, i: colour.sd_to_XYZ(on_shape(r, c.shape, colour.LinearInterpolator), c,
                                          on_shape(i, c.shape, colour.LinearInterpolator), method="Integration")),
        ("integration-1nm-sprague", "360:830:1", "riemann", "sprague", 1e-3,
         lambda r, c, i: colour.sd_to_XYZ(on_shape(r, c.shape, colour.SpragueInterpolator), c,
                                          on_shape(i, c.shape, colour.SpragueInterpolator), method="Integration")),
        ("astm-e308-10nm", "380:780:10", "astm-e308", "interpolate", 1e-2,
         lambda r, c, i: colour.sd_to_XYZ(subsampled(r, 10), c, i, method="ASTM E308")),
        ("astm-e308-20nm", "380:780:20", "astm-e308", "interpolate", 1e-2,
         lambda r, c, i: colour.sd_to_XYZ(subsampled(r, 20), c, i, method="ASTM E308")),
    ]
    failures = 0
    print(f"{'observer':8s} {'light':5s} {'method':24s} {'worst ΔE2000':>12s}  patch")
    for observer in OBSERVERS:
        c = cmfs(observer)
        for name in illuminants:
            illuminant = sd(f"illuminants/{name}")
            white = colour.sd_to_XYZ(perfect5, c, illuminant, method="Integration",
                                     shape=colour.SpectralShape(380, 780, 5))
            white_xy = colour.XYZ_to_xy(white)
            for tag, grid, integration, resample, bound, oracle in methods:
                xyz = render(metamer, work, f"{observer}-{name}-{tag}", name, observer, grid, integration,
                             "band-mean" if before else resample)
                worst, worst_patch = 0.0, ""
                for rel, x, y in where:
                    ours = xyz[y, x, :3]
                    theirs = oracle(reflectances[rel], c, illuminant)
                    de = float(colour.delta_E(colour.XYZ_to_Lab(ours / 100, white_xy),
                                              colour.XYZ_to_Lab(theirs / 100, white_xy), method="CIE 2000"))
                    if de > worst:
                        worst, worst_patch = de, rel.split("/")[1]
                ok = worst <= bound
                failures += not ok
                print(f"{observer:8s} {name:5s} {tag:24s} {worst:12.2e}  {worst_patch}{'' if ok else f'  FAIL > {bound:g}'}")
    if before:
        print(f"(band-mean resampling: {failures} comparisons over the bounds, reported only)")
        return 0
    if failures:
        print(f"FAIL: {failures} comparisons over their bound")
        return 1
    print("OK")
    return 0


def subsampled(s: colour.SpectralDistribution, step: int) -> colour.SpectralDistribution:
    w = np.arange(380.0, 781.0, float(step))
    return colour.SpectralDistribution(s[w], w, name=s.name)


if __name__ == "__main__":
    sys.exit(main())
