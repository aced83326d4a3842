#!/usr/bin/env python3
"""The bundled training-set sweep's cost per job (issue 49, item 5; docs/batch.md, "Random draws").

`metamer batch scenes/dataset/sweep.json --shard I/N`: N shards of its 10 000 draws, each job at
512 × 482 (ARAD's size) on 31 bands, written as OpenEXR and the ARAD layout with its ground truth
(reflectance, illumination, ids, depth, normal, mask), as shipped; and the same jobs without the
ground truth (the sweep's "render": {"write": "cube,png"}), the two runs alternating. Prints, in one
run: the lavapipe ceiling's row (b) (../shared/notes/lavapipe.md: the yardstick for this machine's
day), the median per job of every stage the job records hold (timings_ms), the wall time per job of
the whole batch, the bytes a job writes, and the ratios. A benchmark that prints figures: nothing is
asserted.

  python3 ci/bench-dataset.py [--metamer build/metamer] [--shard 0/2000] [--repeats 1]
                              [--ceiling ../shared/tools/lavapipe-ceiling] [--json FILE]
"""
import argparse
import glob
import importlib.util
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
_spec = importlib.util.spec_from_file_location("bench_display", os.path.join(HERE, "bench-display.py"))
bd = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bd)


def batch(metamer, sweep, shard, out):
    shutil.rmtree(out, ignore_errors=True)
    start = time.monotonic()
    p = subprocess.run([metamer, "batch", sweep, "--shard", shard, "--out", out, "-q"], capture_output=True, text=True,
                       env=dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp")))
    wall = time.monotonic() - start
    if p.returncode != 0:
        sys.exit(f"bench-dataset: batch {sweep} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    records = [json.load(open(f)) for f in glob.glob(os.path.join(out, "*", "job.json"))]
    if not records:
        sys.exit(f"bench-dataset: no job records under {out}")
    sizes = [sum(os.path.getsize(f) for f in glob.glob(os.path.join(os.path.dirname(r), "*")))
             for r in glob.glob(os.path.join(out, "*", "job.json"))]
    return wall, records, sizes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--metamer", default=os.path.join(ROOT, "build", "metamer"))
    ap.add_argument("--shard", default="0/2000", help="the shard of the 10 000 jobs to render (0/2000: 5 jobs)")
    ap.add_argument("--repeats", type=int, default=1, help="runs of each variant, alternating")
    ap.add_argument("--ceiling", help="folder of the lavapipe-ceiling prototype (../shared/tools/lavapipe-ceiling)")
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="metamer-bench-dataset-")
    bundled = os.path.join(ROOT, "scenes", "dataset", "sweep.json")
    sweep = json.load(open(bundled))
    sweep["scenes"] = [os.path.join(ROOT, "scenes", "dataset", s) for s in sweep["scenes"]]
    plain = os.path.join(work, "sweep-without-ground-truth.json")
    json.dump({**sweep, "render": {**sweep.get("render", {}), "write": "cube,png"}}, open(plain, "w"))
    shipped = os.path.join(work, "sweep.json")
    json.dump(sweep, open(shipped, "w"))
    print(f"scenes/dataset/sweep.json, shard {a.shard}; {os.cpu_count()} CPUs; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    figures = {"shard": a.shard, "variants": {}}
    if a.ceiling:
        text = bd.ceiling(a.ceiling)
        row_b = next((float(l.split()[6]) for l in text.splitlines() if l.startswith("(b)")), None)
        figures["row_b_ms"] = row_b
        print(f"lavapipe ceiling row (b): {row_b} ms per 1024² × 89-band frame (this machine, this run)")
    runs = {"with ground truth (as shipped)": shipped, "without ground truth": plain}
    results = {name: [] for name in runs}
    for _ in range(a.repeats):
        for name, path in runs.items():
            results[name].append(batch(a.metamer, path, a.shard, os.path.join(work, "out")))
    for name, rs in results.items():
        records = [r for _, recs, _ in rs for r in recs]
        stages = {}
        for r in records:
            for stage, ms in r.get("timings_ms", {}).items():
                stages.setdefault(stage, []).append(ms)
        wall = statistics.median(w / len(recs) for w, recs, _ in rs)
        size = statistics.median(s for _, _, sizes in rs for s in sizes)
        med = {s: statistics.median(v) for s, v in stages.items()}
        figures["variants"][name] = {"jobs": len(records), "wall_s_per_job": wall, "bytes_per_job": size,
                                     "median_ms": med}
        print(f"\n{name}: {len(records)} jobs, wall {wall:.2f} s a job (the batch's process included), "
              f"{size / 2**20:.1f} MiB a job")
        print("  median ms per job: " + "  ".join(f"{s} {v:.0f}" for s, v in med.items()))
        if figures.get("row_b_ms"):
            print(f"  a job's render (job) / row (b): {med.get('job', med.get('total', 0)) / figures['row_b_ms']:.1f}")
    names = list(runs)
    w0, w1 = (figures["variants"][n]["wall_s_per_job"] for n in names)
    print(f"\nthe ground truth's share: {w0 / w1:.2f} × the job without it (wall per job)")
    print(f"10 000 jobs at this rate: {w0 * 10000 / 3600:.1f} h on one such machine "
          f"({figures['variants'][names[0]]['bytes_per_job'] * 10000 / 2**40:.2f} TiB)")
    if a.json:
        json.dump(figures, open(a.json, "w"), indent=2)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
