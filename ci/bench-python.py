#!/usr/bin/env python3
"""What a call of `metamer.render` costs against a run of the CLI, on a small scene (docs/python.md,
"Speed"). One run, interleaved, medians: the machine is shared and noisy.

    .venv/bin/python ci/bench-python.py [--scene scenes/spheres.json] [--size 64x48] [--runs 7]

Prints, per case: the module's first call (device, pipelines), the median of the later calls, the
CLI's median wall time (a process per render: driver load, device, pipeline cache, files), and
their ratio. The CLI writes its files into a temporary folder; the module keeps the arrays (and,
in the `+ save` case, writes the same files).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "build" / "python"))  # this checkout's build, not an installed copy
import metamer  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(REPO / "scenes" / "spheres.json"))
    ap.add_argument("--size", default="64x48")
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--binary", default=str(REPO / "build" / "metamer"))
    args = ap.parse_args()
    w, h = args.size.split("x")
    sets = [f"camera.width={w}", f"camera.height={h}"]
    os.environ.setdefault("XDG_RUNTIME_DIR", "/tmp")

    cases = {"cube,png": "cube,png", "png,xyz": "png,xyz"}
    print(f"scene {args.scene} at {w}×{h}, {args.runs} runs each, interleaved")
    print(f"{'outputs':<10} {'module 1st':>11} {'module':>9} {'module+save':>12} {'CLI':>9} {'CLI/module':>11}")
    with tempfile.TemporaryDirectory() as tmp:
        for label, write in cases.items():
            t = time.perf_counter()
            metamer.render(args.scene, overrides=sets, write=write)
            first = time.perf_counter() - t
            module, saved, cli = [], [], []
            for i in range(args.runs):
                t = time.perf_counter()
                metamer.render(args.scene, overrides=sets, write=write)
                module.append(time.perf_counter() - t)
                t = time.perf_counter()
                metamer.render(args.scene, overrides=sets, write=write).save(Path(tmp) / "py")
                saved.append(time.perf_counter() - t)
                cmd = [args.binary, "render", args.scene, "--out", str(Path(tmp) / "cli"), "--write", write]
                for s in sets:
                    cmd += ["--set", s]
                t = time.perf_counter()
                subprocess.run(cmd, check=True, capture_output=True)
                cli.append(time.perf_counter() - t)
            m, s, c = statistics.median(module), statistics.median(saved), statistics.median(cli)
            print(f"{label:<10} {first * 1e3:>9.0f}ms {m * 1e3:>7.0f}ms {s * 1e3:>10.0f}ms {c * 1e3:>7.0f}ms "
                  f"{c / m:>10.1f}×")
    sweep(args.scene, args.runs)
    return 0


def sweep(scene: str, runs: int) -> None:
    """A sweep over illuminants at the scene's own size (docs/python.md, "Speed"): the light's
    spectrum changes each call, which leaves the shadow maps as they were (drawn once, reused);
    beside it, the same calls with the point light moved a millimetre each time, which redraws
    them — the cost a spectrum change no longer pays."""
    spectra = ["illuminants/A", "illuminants/D65", "illuminants/FL2"]
    print(f"\nsweep over lights.1.spectrum, {scene} at its own size, write=xyz, {runs} calls each, interleaved")
    metamer.render(scene, write="xyz")  # the device, the pipelines, the maps
    changed, moved, upload_changed, upload_moved = [], [], [], []
    for i in range(runs):
        t = time.perf_counter()
        r = metamer.render(scene, write="xyz", overrides={"lights.1.spectrum": spectra[i % 3]})
        changed.append(time.perf_counter() - t)
        upload_changed.append(r.timings_ms["upload"])
        t = time.perf_counter()
        r = metamer.render(scene, write="xyz", overrides={"lights.1.spectrum": spectra[i % 3],
                                                          "lights.1.position": [1.5 + 0.001 * (i + 1), 3, 2.5]})
        moved.append(time.perf_counter() - t)
        upload_moved.append(r.timings_ms["upload"])
    c, m = statistics.median(changed), statistics.median(moved)
    print(f"{'call':<34} {'median':>8} {'upload (incl. shadow maps)':>28}")
    print(f"{'spectrum changed (maps reused)':<34} {c * 1e3:>6.0f}ms {statistics.median(upload_changed):>26.0f}ms")
    print(f"{'light moved (maps redrawn)':<34} {m * 1e3:>6.0f}ms {statistics.median(upload_moved):>26.0f}ms")
    print(f"reuse saves {(m - c) * 1e3:.0f} ms a call ({m / c:.1f}×)")


if __name__ == "__main__":
    sys.exit(main())
