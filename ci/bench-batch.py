#!/usr/bin/env python3
"""metamer batch against a loop of metamer render (issue 16, item 3; docs/batch.md, "Speed").

The same 64 jobs — 8 light spectra × 4 detectors × 2 adaptations on one scene — rendered once by
one `metamer batch` process and once by 64 `metamer render` processes, at each size; prints the
wall time per job of each and their ratio. One run per figure; compare ratios taken in one run
(the machine is shared). A benchmark that prints figures: nothing is asserted.

  python3 ci/bench-batch.py [--metamer build/metamer] [--scene scenes/colorchecker.json]
                            [--sizes 64x64,512x512] [--write png,xyz] [--repeats 1]
"""
import argparse
import itertools
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
LIGHTS = ["illuminants/D65", "illuminants/A", "illuminants/FL2", "illuminants/D50", "illuminants/E",
          "illuminants/FL11", "illuminants/FL1", "illuminants/FL3"]
DETECTORS = ["cie1931", "cie1964", "camera:nikon_d5100", "film:reversal"]
ADAPTATIONS = ["bradford", "cat16"]


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True,
                       env=dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp")))
    if p.returncode != 0:
        sys.exit(f"bench-batch: {' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--metamer", default=os.path.join(ROOT, "build", "metamer"))
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "colorchecker.json"))
    ap.add_argument("--sizes", default="64x64,512x512")
    ap.add_argument("--write", default="png,xyz")
    ap.add_argument("--repeats", type=int, default=1, help="runs of each (median)")
    a = ap.parse_args()
    jobs = list(itertools.product(LIGHTS, DETECTORS, ADAPTATIONS))
    work = tempfile.mkdtemp(prefix="metamer-bench-batch-")
    print(f"{len(jobs)} jobs on {os.path.basename(a.scene)} ({len(LIGHTS)} lights × {len(DETECTORS)} detectors × "
          f"{len(ADAPTATIONS)} adaptations), --write {a.write}; {os.cpu_count()} CPUs; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"{'size':<10}{'batch s/job':>13}{'loop s/job':>12}{'loop / batch':>14}")
    for size in a.sizes.split(","):
        w, h = size.split("x")
        sweep = os.path.join(work, f"sweep-{size}.json")
        with open(sweep, "w") as f:
            json.dump({"scenes": [os.path.abspath(a.scene)], "render": {"write": a.write, "size": size},
                       "axes": [{"name": "light", "set": "lights.0.spectrum", "values": LIGHTS},
                                {"render": "detector", "values": DETECTORS},
                                {"render": "adapt", "values": ADAPTATIONS}]}, f)
        batch, loop = [], []
        for _ in range(a.repeats):
            out = os.path.join(work, "batch")
            shutil.rmtree(out, ignore_errors=True)
            t = time.perf_counter()
            run([a.metamer, "batch", sweep, "--out", out, "-q"])
            batch.append((time.perf_counter() - t) / len(jobs))
            out = os.path.join(work, "loop")
            shutil.rmtree(out, ignore_errors=True)
            t = time.perf_counter()
            for i, (light, detector, adapt) in enumerate(jobs):
                run([a.metamer, "render", a.scene, "--out", os.path.join(out, str(i)), "--write", a.write,
                     "--set", f"lights.0.spectrum={light}", "--set", f"camera.width={w}", "--set", f"camera.height={h}",
                     "--detector", detector, "--adapt", adapt])
            loop.append((time.perf_counter() - t) / len(jobs))
        b, l = statistics.median(batch), statistics.median(loop)
        print(f"{size:<10}{b:>13.3f}{l:>12.3f}{l / b:>14.1f}", flush=True)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
