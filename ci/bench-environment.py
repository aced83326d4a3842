#!/usr/bin/env python3
"""The cost of the environment (hemisphere lights) and the preview's frame rate, measured from
outside as a user sees it (issue 26; docs/performance.md, "The environment"). Prints, in one run:

  1. the lavapipe ceiling of ../shared/notes/lavapipe.md (row (b): 3 passes x 8/8/7 attachments at
     1024² x 89 bands), the yardstick every other figure is divided by;
  2. scenes/spheres.json as shipped against the same scene without its two hemisphere lights:
     shading of the response pass (--write png) and of the cube path (--write cube), 512² and 1024²,
     and their ratio;
  3. every bundled scene at 512²: the response pass's and the cube path's shading;
  4. `metamer preview` at 512² on every bundled scene: ms per frame, fps, and the frame over row (b)
     (25 fps on a machine whose row (b) takes 86 ms is a frame <= 0.47 x row (b));
  5. time to first image for spheres.json as shipped at 512²: process start to exit for the PNG
     (--write png) and the 89-band EXR (--write cube --grid 300:740:5), the lobe tables already on
     disk; and once with an empty lobe cache (the tables built).
Medians; runs of the variants alternate so that the machine's drift falls on both. A benchmark that
prints figures, not a test: nothing is asserted.

  python3 ci/bench-environment.py [--metamer build/metamer] [--before OLD/metamer]
                                  [--ceiling ../shared/tools/lavapipe-ceiling] [--repeats 3] [--json FILE]

--before: an earlier build measured beside it in the same run (every figure but the empty cache).
"""
import argparse
import glob
import importlib.util
import json
import os
import statistics
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
# The helpers of ci/bench-display.py (a render's frame times, the preview's, the ceiling).
_spec = importlib.util.spec_from_file_location("bench_display", os.path.join(HERE, "bench-display.py"))
bd = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bd)

SIZES = [512, 1024]


def ceiling_row_b(folder):
    text = bd.ceiling(folder)
    for line in text.splitlines():
        if line.startswith("(b)"):
            return float(line.split()[6]), text
    sys.exit(f"bench-environment: no row (b) in the ceiling's output:\n{text}")


def shading(metamer, scene, out, write, size, frames):
    extra = ["--write", write, "--set", f"camera.width={size}", "--set", f"camera.height={size}"]
    if write == "cube":
        extra += ["--compression", "none"]
    return bd.frame_ms(metamer, scene, out, extra, frames)["shading"]


def reads(metamer, scene, work):
    """Whether this build renders the scene at all (an earlier build refuses keys added since)."""
    out = os.path.join(work, "probe")
    return bd.run([metamer, "render", scene, "--out", out, "--write", "png", "--set", "camera.width=16",
                   "--set", "camera.height=16"], check=False) is not None


def alternate(measures, repeats):
    """Runs each (name, function) `repeats` times, alternating; the median of each."""
    values = {name: [] for name, _ in measures}
    for _ in range(repeats):
        for name, f in measures:
            values[name].append(f())
    return {name: statistics.median(v) for name, v in values.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--metamer", default=os.path.join(ROOT, "build", "metamer"))
    ap.add_argument("--before", help="an earlier build of metamer to measure beside it")
    ap.add_argument("--ceiling", default=os.path.join(ROOT, "..", "shared", "tools", "lavapipe-ceiling"))
    ap.add_argument("--repeats", type=int, default=3, help="alternating runs per figure (median)")
    ap.add_argument("--frames", type=int, default=12, help="frames per render (median of 2..N)")
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    builds = [("now", a.metamer)] + ([("before", a.before)] if a.before else [])
    work = tempfile.mkdtemp(prefix="metamer-bench-env-")
    figures = {}

    row_b, ceiling_text = ceiling_row_b(a.ceiling)
    figures["ceiling_row_b_ms"] = row_b
    print("lavapipe ceiling (1024² x 89 bands, ms per frame), this run:")
    print("\n".join("  " + line for line in ceiling_text.splitlines() if line.strip()))
    print(f"row (b): {row_b:.1f} ms; targets: preview frame <= {0.47 * row_b:.1f} ms, "
          f"PNG <= {5.8 * row_b / 1000:.2f} s, EXR <= {11.6 * row_b / 1000:.2f} s\n")

    # 2. The environment's cost: spheres.json with and without its hemisphere lights.
    spheres = os.path.join(ROOT, "scenes", "spheres.json")
    scene = json.load(open(spheres))
    scene["lights"] = [l for l in scene["lights"] if l["type"] != "hemisphere"]
    plain = os.path.join(work, "spheres-without-environment.json")
    json.dump(scene, open(plain, "w"))
    print("environment: spheres.json as shipped vs without its hemisphere lights, shading ms (median)")
    print(f"{'build':8} {'path':14} {'size':>6} {'with':>8} {'without':>8} {'ratio':>6}")
    figures["environment"] = []
    for label, metamer in builds:
        for write, path in [("png", "response pass"), ("cube", "cube path")]:
            for size in SIZES:
                out = os.path.join(work, "out")
                m = alternate([("with", lambda: shading(metamer, spheres, out, write, size, a.frames)),
                               ("without", lambda: shading(metamer, plain, out, write, size, a.frames))], a.repeats)
                ratio = m["with"] / m["without"]
                print(f"{label:8} {path:14} {size:>5}² {m['with']:8.1f} {m['without']:8.1f} {ratio:6.2f}")
                figures["environment"].append({"build": label, "path": path, "size": size, **m, "ratio": ratio})
    print()

    # 3. Every bundled scene at 512²: the response pass's and the cube path's shading.
    scenes = sorted(p for p in glob.glob(os.path.join(ROOT, "scenes", "*.json")))
    print("every bundled scene at 512²: shading ms (median), response pass (--write png) and cube path (--write cube)")
    figures["scenes"] = []
    for path in scenes:
        name = os.path.splitext(os.path.basename(path))[0]
        out = os.path.join(work, "out")
        measures = []
        for label, metamer in builds:
            if label != "now" and not reads(metamer, path, work):
                print(f"  ({label} cannot read {name}: skipped for it)")
                continue
            for write in ["png", "cube"]:
                measures.append((f"{label} {write}",
                                 lambda metamer=metamer, write=write: shading(metamer, path, out, write, 512, a.frames)))
        m = alternate(measures, a.repeats)
        line = "  ".join(f"{k} {v:7.1f}" for k, v in m.items())
        print(f"  {name:20} {line}")
        figures["scenes"].append({"scene": name, **m})
    print()

    # 4. The preview at 512² on every bundled scene.
    print("preview, 512², ms per frame (median of frames 2..30): frame, fps, frame / row (b)")
    figures["preview"] = []
    for path in scenes:
        name = os.path.splitext(os.path.basename(path))[0]
        for label, metamer in builds:
            if label != "now" and not reads(metamer, path, work):
                continue
            values = []
            for _ in range(a.repeats):
                p = bd.preview_ms(metamer, path, ["--set", "camera.width=512", "--set", "camera.height=512"], 30)
                if p is None:
                    print("  (no xvfb-run: preview skipped)")
                    break
                values.append(p)
            if not values:
                continue
            frame = statistics.median(v["frame"] for v in values)
            shade = statistics.median(v["shading"] for v in values)
            print(f"  {label:7} {name:20} {frame:7.1f} ms {1000 / frame:6.1f} fps  shading {shade:6.1f}  "
                  f"{frame / row_b:5.2f} x row (b)")
            figures["preview"].append({"build": label, "scene": name, "frame": frame, "shading": shade,
                                       "over_row_b": frame / row_b})
    print()

    # 5. Time to first image (spheres.json as shipped, 512²).
    print("time to first image, spheres.json at 512², s (median), and / row (b)")
    figures["first_image"] = []
    out = os.path.join(work, "first")
    for label, metamer in builds:
        bd.run([metamer, "render", spheres, "--out", out, "--write", "png"])  # tables and shaders on disk
        bd.run([metamer, "render", spheres, "--out", out, "--write", "cube", "--grid", bd.GRID89])
        png = bd.wall([metamer, "render", spheres, "--out", out, "--write", "png"], max(5, a.repeats))
        exr = bd.wall([metamer, "render", spheres, "--out", out, "--write", "cube", "--grid", bd.GRID89],
                      max(5, a.repeats))
        print(f"  {label:7} PNG {png:.2f} s ({png * 1000 / row_b:.1f} x)   EXR {exr:.2f} s ({exr * 1000 / row_b:.1f} x)")
        figures["first_image"].append({"build": label, "png_s": png, "exr_s": exr})
    empty = os.path.join(work, "empty-lobe-cache")
    os.makedirs(empty)
    t0 = time.perf_counter()
    bd.run([a.metamer, "render", spheres, "--out", out, "--write", "png"], env={"METAMER_LOBE_CACHE": empty})
    cold = time.perf_counter() - t0
    print(f"  now     PNG with an empty lobe cache (both gloss values' tables built): {cold:.2f} s")
    figures["first_image_empty_cache_s"] = cold

    if a.json:
        json.dump(figures, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
