#!/usr/bin/env python3
"""What a Kubelka–Munk paint costs against a plain diffuse material (docs/performance.md, "Paints").
One process, the cases interleaved, medians of the module's own phase timings (`timings_ms`): the
machine is shared and noisy.

    .venv/bin/python ci/bench-paints.py [--runs 9] [--size 600x400]

Cases, all scenes/paints.json's geometry and light:
  plain     every paint replaced by {"diffuse": 0.5}: no Kubelka–Munk, no texture;
  paints    the scene as bundled: Kubelka–Munk once per material at load, the drawdown's thickness
            map (256 texels) turned into a spectral texture;
  no-map    the paints without the thickness map (a uniform 150 µm film): Kubelka–Munk, no texture;
  map 1024² a 1024 × 1024 float thickness map of distinct values (the worst case for the per-texel
            spectra: no two texels share a thickness), instead of the 256-texel ramp.
Prints load (scene, spectra, Kubelka–Munk), shading and total per case, and the ratios to plain.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "build" / "python"))
import metamer  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=9)
    ap.add_argument("--size", default="600x400")
    args = ap.parse_args()
    os.environ.setdefault("XDG_RUNTIME_DIR", "/tmp")
    w, h = (int(v) for v in args.size.split("x"))
    scene = json.loads((REPO / "scenes" / "paints.json").read_text())
    scene["camera"].update({"width": w, "height": h})
    plain, nomap, big = copy.deepcopy(scene), copy.deepcopy(scene), copy.deepcopy(scene)
    for m in plain["materials"].values():
        if "layers" in m:
            for k in ("layers", "substrate", "surface"):
                m.pop(k, None)
            m["diffuse"] = 0.5
    for m in nomap["materials"].values():
        for layer in m.get("layers", []):
            layer.pop("thickness_map", None)
    folder = Path(tempfile.mkdtemp())
    (folder / "assets").symlink_to(REPO / "scenes" / "assets")
    import OpenImageIO as oiio
    ramp = np.linspace(0.0, 1.0, 1024 * 1024, dtype=np.float32).reshape(1024, 1024, 1)
    out = oiio.ImageOutput.create(str(folder / "wedge1024.exr"))
    out.open(str(folder / "wedge1024.exr"), oiio.ImageSpec(1024, 1024, 1, oiio.FLOAT))
    out.write_image(ramp)
    out.close()
    for m in big["materials"].values():
        for layer in m.get("layers", []):
            if "thickness_map" in layer:
                layer["thickness_map"] = "wedge1024.exr"
    cases = {"plain": plain, "paints": scene, "no-map": nomap, "map 1024²": big}
    times = {name: {"load": [], "shading": [], "total": []} for name in cases}
    for name, doc in cases.items():  # warm-up: pipelines, caches
        metamer.render(doc, base_dir=str(REPO / "scenes" if name != "map 1024²" else folder), name="paints", write="cube")
    for _ in range(args.runs):
        for name, doc in cases.items():
            r = metamer.render(doc, base_dir=str(REPO / "scenes" if name != "map 1024²" else folder), name="paints",
                               write="cube")
            for k in times[name]:
                times[name][k].append(r.timings_ms[k])
    print(f"scenes/paints.json at {w}×{h}, 81 bands, {args.runs} runs each (medians, ms; ratio to plain):")
    base = {k: statistics.median(v) for k, v in times["plain"].items()}
    for name, t in times.items():
        med = {k: statistics.median(v) for k, v in t.items()}
        print(f"  {name:10s} load {med['load']:8.1f} ({med['load'] / base['load']:5.2f}×)   shading {med['shading']:7.1f} "
              f"({med['shading'] / base['shading']:4.2f}×)   total {med['total']:7.1f} ({med['total'] / base['total']:4.2f}×)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
