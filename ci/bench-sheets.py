#!/usr/bin/env python3
"""The cost of many transparent objects under a shadow-casting light (issue 50; docs/numerics.md,
"Scale of transparent scenes"), measured from outside as a user runs it: N filter sheets stacked
over a grey card under a directional light that casts coloured shadows, rendered by
`metamer render --write png --timings` (81 bands, 256 x 256). Prints per N the shadow maps' time
(the transmittance maps, drawn once per scene), the upload, the first frame's shading and the
process's wall time, and the estimate `metamer` says before drawing (render/transmittance_map_cost.h)
when it is above 10 s. A benchmark that prints figures, not a test: nothing is asserted.

  python3 ci/bench-sheets.py [--metamer build/metamer] [--counts 1000 10000 100000] [--side 0.5]
                             [--materials 1]

--side: each sheet's side in metres; the light's view spans the 2 m card, so 0.5 is 1/16 of it.
--materials: the sheets cycle through this many filter materials (one optical-depth channel each).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time


def scene(count, side, materials):
    objects = [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [2, 2], "material": "card"}]
    for i in range(count):
        objects.append({"shape": "quad", "center": [0.3, 0.2, 0.1 + 0.5 * i / count], "normal": [0, 0, 1],
                        "size": [side, side], "material": f"gel{i % materials}"})
    mats = {"card": {"diffuse": 0.5}}
    for m in range(materials):
        mats[f"gel{m}"] = {"transmittance": round(0.999 - 0.0001 * m, 6)}
    return {"grid": {"start_nm": 380, "end_nm": 780, "step_nm": 5},
            "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 35,
                       "width": 256, "height": 256},
            "lights": [{"type": "directional", "direction": [0.2, 0.1, -1], "spectrum": "illuminants/D65", "scale": 0.01}],
            "materials": mats, "objects": objects}


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--metamer", default=os.path.join(here, "build", "metamer"))
    ap.add_argument("--counts", type=int, nargs="+", default=[1000, 10000, 100000])
    ap.add_argument("--side", type=float, default=0.5)
    ap.add_argument("--materials", type=int, default=1)
    args = ap.parse_args()
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", tempfile.gettempdir()))
    print(f"{'sheets':>8} {'shadow maps s':>14} {'upload s':>9} {'shading s':>10} {'wall s':>7}  estimate said")
    with tempfile.TemporaryDirectory() as work:
        for n in args.counts:
            path = os.path.join(work, f"sheets{n}.json")
            with open(path, "w") as f:
                json.dump(scene(n, args.side, args.materials), f)
            t0 = time.monotonic()
            r = subprocess.run([args.metamer, "render", path, "--out", os.path.join(work, f"out{n}"), "--write", "png",
                                "--timings"], capture_output=True, text=True, env=env)
            wall = time.monotonic() - t0
            text = r.stdout + r.stderr
            if r.returncode != 0:
                print(f"{n:>8} exit {r.returncode}: {text.strip().splitlines()[-1] if text.strip() else ''}")
                continue
            shadow = re.search(r"shadow maps: ([0-9.]+) ms", text)
            upload = re.search(r"upload ([0-9.]+)", text)
            shading = re.search(r"shading ([0-9.]+)", text)
            said = re.search(r"about ([0-9.e+]+) s with lavapipe", text)
            fmt = lambda m: f"{float(m.group(1)) / 1000:.2f}" if m else "?"
            print(f"{n:>8} {fmt(shadow):>14} {fmt(upload):>9} {fmt(shading):>10} {wall:>7.1f}  "
                  f"{said.group(1) + ' s' if said else '(below 10 s: not said)'}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
