#!/usr/bin/env python3
"""Renders the Cornell box's path-traced reference with Mitsuba 3, once: what tests/cornell_box_test
compares Metamer's interreflection with (docs/physics.md, "Interreflection"). CI does not run this;
it reads the stored result.

The scene is scenes/cornell-box.json's, built from the same sources: the geometry of
scenes/assets/make_cornell.py (flat faces, each front as wound there), the spectra of
spectra/cornell/ (piecewise linear, as Mitsuba's "irregular" spectrum takes them), diffuse BSDFs
(one-sided, as the box's surfaces are seen only from their fronts), the light a one-sided area
emitter of the measured spectrum, the perspective camera of the scene. Mitsuba's path tracer with
unlimited depth (Russian roulette from depth 5, unbiased) renders it spectrally; its film records one
channel per band of the scene's grid, the box [λ − 2.5, λ + 2.5] nm, divided by its width: the band
mean of the radiance, W·sr⁻¹·m⁻²·nm⁻¹, as Metamer's bands are (grid 400:700:5; the end bands,
half outside the data, are left out: 405–695 nm). A box pixel filter: each pixel the mean over its area.

Noise: the render is K independent renders (seeds 0..K−1) of S samples per pixel each; the stored
mean is their mean and the stored noise the standard error of that mean per pixel and band
(the sample standard deviation of the K renders over √K).

Writes tests/data/cornell/mitsuba.npz (mean and standard error, [y, x, band], float32; the band
centres) and tests/data/cornell/mitsuba.json (version, variant, spp, seeds, time, resolution, the
noise's median per band region).

    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba==3.6.4 numpy
    /tmp/mi/bin/python ci/mitsuba_cornell.py [--variant llvm_ad_spectral] [--size 128] [--spp 1024] [--renders 8]
"""
import argparse
import csv
import importlib.util
import json
import os
import platform
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "tests", "data", "cornell")


def spectrum(name):
    with open(os.path.join(ROOT, "spectra", "cornell", name + ".csv")) as f:
        rows = [r for r in csv.reader(f)][1:]
    return {"type": "irregular", "wavelengths": ", ".join(r[0] for r in rows), "values": ", ".join(r[1] for r in rows)}


def geometry():
    spec = importlib.util.spec_from_file_location("make_cornell", os.path.join(ROOT, "scenes", "assets", "make_cornell.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.groups()


def write_obj(path, quads):
    """Convex polygons (mm; 3 or 4 corners) as an OBJ (m), each its own vertices, wound as given."""
    with open(path, "w") as f:
        n = 0
        for q in quads:
            for p in q:
                f.write("v %.9g %.9g %.9g\n" % tuple(c / 1000.0 for c in p))
            for k in range(2, len(q)):
                f.write("f %d %d %d\n" % (n + 1, n + k, n + k + 1))
            n += len(q)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--variant", default="scalar_spectral")
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--renders", type=int, default=8)
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)

    with open(os.path.join(ROOT, "scenes", "cornell-box.json")) as f:
        cam = json.load(f)["camera"]
    bands = list(range(405, 700, 5))
    film = {"type": "specfilm", "width": args.size, "height": args.size, "rfilter": {"type": "box"}}
    for k, nm in enumerate(bands):
        lo, hi = nm - 2.5, nm + 2.5
        film["band%03d" % k] = {"type": "irregular", "wavelengths": f"{lo - 1e-4}, {lo}, {hi}, {hi + 1e-4}",
                                "values": "0, 1, 1, 0"}
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1, "rr_depth": 5},
        "sensor": {"type": "perspective", "fov": cam["fov_y_deg"], "fov_axis": "y",
                   "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["target"], up=cam["up"]),
                   "film": film, "sampler": {"type": "independent", "sample_count": args.spp}},
    }
    materials = {m: spectrum(m) for m in ("white", "red", "green")}
    tmp = tempfile.mkdtemp()
    for name, material, quads in geometry():
        path = os.path.join(tmp, name + ".obj")
        write_obj(path, quads)
        shape = {"type": "obj", "filename": path, "face_normals": True}
        if material == "light":
            shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.0}}
            shape["emitter"] = {"type": "area", "radiance": spectrum("light")}
        else:
            shape["bsdf"] = {"type": "diffuse", "reflectance": materials[material]}
        scene[name] = shape
    loaded = mi.load_dict(scene)

    renders, seconds = [], []
    for seed in range(args.renders):
        t = time.time()
        image = np.array(mi.render(loaded, seed=seed), dtype=np.float64) / 5.0  # ∫ over the 5 nm box → band mean
        seconds.append(time.time() - t)
        renders.append(image)
        print(f"render {seed + 1}/{args.renders}: {seconds[-1]:.1f} s", flush=True)
    stack = np.stack(renders)
    mean = stack.mean(axis=0)
    error = stack.std(axis=0, ddof=1) / np.sqrt(len(renders))
    os.makedirs(OUT, exist_ok=True)
    np.savez_compressed(os.path.join(OUT, "mitsuba.npz"), mean=mean.astype(np.float32), error=error.astype(np.float32),
                        wavelengths_nm=np.array(bands, dtype=np.float32))
    relative = error / np.maximum(mean, 1e-30)
    inside = mean.mean(axis=2) > 0
    regions = {}
    for lo, hi in ((405, 495), (500, 595), (600, 695)):
        sel = [k for k, nm in enumerate(bands) if lo <= nm <= hi]
        r = relative[..., sel][inside]
        regions[f"{lo}-{hi}"] = {"median": float(np.median(r)), "p99": float(np.percentile(r, 99))}
    info = {
        "renderer": "Mitsuba 3", "version": mi.__version__, "variant": args.variant, "integrator": "path, max_depth -1, rr_depth 5",
        "film": "specfilm, one box band of 5 nm per channel (405-695 nm), box pixel filter", "width": args.size,
        "height": args.size, "spp_per_render": args.spp, "renders": args.renders, "seeds": list(range(args.renders)),
        "spp_total": args.spp * args.renders, "seconds_per_render": seconds, "seconds": sum(seconds),
        "machine": f"{platform.node()} {platform.machine()}, {os.cpu_count()} CPUs",
        "noise": "standard error of the mean per pixel and band, relative to the mean, over the pixels that see the box",
        "relative_standard_error": regions,
    }
    with open(os.path.join(OUT, "mitsuba.json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    print(json.dumps(info["relative_standard_error"]), f"{info['seconds']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
