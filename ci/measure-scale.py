#!/usr/bin/env python3
"""Scale and position, measured through the CLI as a user runs it (docs/numerics.md, "Scale and
position"): a white Lambertian quad (rho = 0.5, 2 m) under a point light, rendered by `metamer
render` on both backends moved 10^3 ... 10^7 m from the world origin and scaled 10^-6 ... 10^6,
each against the analytic answer rho*I*cos(theta)/(pi d^2) computed here in double; and point
lights placed exactly on pixel centres of a lit quad (d = 0), counting NaN.

    python3 ci/measure-scale.py [--metamer build/metamer] [--label now]

Run it with two binaries (before and after a change) to get the table in docs/numerics.md. It
asserts nothing: it prints one row per case. Needs numpy."""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

LIGHT = np.array([0.375, 0.25, 0.625])  # m, in the quad's frame (the quad: z = 0, 2 m x 2 m)
DIRECTION = np.array([1.0, -0.75, 0.5])  # the translations' direction


def quad_scene(perspective, k, t):
    """The point-lit quad scaled by k and moved by t (the light k^2 brighter: same radiance)."""
    t = np.asarray(t, dtype=float)
    if perspective:
        camera = {"position": list(t + k * np.array([0, 0, 2.5])), "target": list(t), "fov_y_deg": 40}
    else:
        camera = {"projection": "orthographic", "position": list(t + k * np.array([0.5, -1.0, 2.0])),
                  "target": list(t), "height_m": 1.25 * k}
    camera.update({"up": [0, 1, 0], "width": 24, "height": 24})
    return {
        "grid": {"start_nm": 400, "end_nm": 700, "step_nm": 50},
        "camera": camera,
        # illuminants/E is 100 at every wavelength: I = 100 x 0.01 x k^2 W/sr/nm.
        "lights": [{"type": "point", "position": list(t + k * LIGHT), "spectrum": "illuminants/E",
                    "scale": 0.01 * k * k, "shadows": False}],
        "materials": {"white": {"diffuse": 0.5}},
        "objects": [{"shape": "quad", "center": list(t), "normal": [0, 0, 1], "size": [2 * k, 2 * k],
                     "material": "white"}],
    }


def known_answer(perspective, w=24, h=24):
    """rho*I*cos/(pi d^2) per pixel centre (the unscaled, unmoved scene; docs/physics.md "Camera"),
    and whether the pixel's 3x3 neighbourhood lies on the quad."""
    if perspective:
        pos, fov = np.array([0, 0, 2.5]), 40.0
    else:
        pos, height = np.array([0.5, -1.0, 2.0]), 1.25
    f = -pos / np.linalg.norm(pos)
    r = np.cross(f, [0, 1, 0]); r /= np.linalg.norm(r)
    u = np.cross(r, f)
    out = np.zeros((h, w)); inside = np.zeros((h, w), bool)
    for y in range(h):
        for x in range(w):
            nx, ny = 2 * (x + 0.5) / w - 1, 1 - 2 * (y + 0.5) / h
            if perspective:
                t = math.tan(math.radians(fov) / 2)
                o, d = pos, f + nx * t * r + ny * t * u
                d = d / np.linalg.norm(d)
            else:
                o, d = pos + 0.5 * height * (nx * r + ny * u), f
            p = o - (o[2] / d[2]) * d
            to = LIGHT - p
            d2 = to @ to
            out[y, x] = 0.5 * 1.0 * (to[2] / math.sqrt(d2)) / (math.pi * d2)
            inside[y, x] = abs(p[0]) < 1 and abs(p[1]) < 1
    interior = inside.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            interior &= np.roll(np.roll(inside, dy, 0), dx, 1)
    interior[[0, -1], :] = False
    interior[:, [0, -1]] = False
    return out, interior


def read_envi(header):
    keys = {}
    for line in open(header):
        if "=" in line:
            k, v = line.split("=", 1)
            keys[k.strip()] = v.strip()
    w, h, b = int(keys["samples"]), int(keys["lines"]), int(keys["bands"])
    data = np.fromfile(header[:-4] + ".img", dtype="<f4").reshape(b, h, w)  # bsq
    return data


def render(metamer, scene, folder, backend):
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    out = os.path.join(folder, "out-" + backend)
    p = subprocess.run([metamer, "render", path, "--backend", backend, "--out", out, "--write", "cube",
                        "--format", "envi", "--no-png"], capture_output=True, text=True)
    if p.returncode != 0:
        return None, p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"
    return read_envi(os.path.join(out, "scene.hdr")), None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--metamer", default="build/metamer")
    ap.add_argument("--label", default="")
    a = ap.parse_args()
    metamer = os.path.abspath(a.metamer)
    print(f"# {a.label or metamer}: relative error against rho*I*cos/(pi d^2), worst over interior pixels and bands")
    print(f"{'case':<44} {'GPU':>10} {'CPU':>10}  black/NaN px (GPU)")
    cases = [("at the origin", 1.0, 0.0)]
    cases += [(f"moved {d:.0e} m", 1.0, d) for d in (1e3, 1e5, 1e7)]
    cases += [(f"scale {k:g}", k, 0.0) for k in (1e-6, 1e-3, 1e3, 1e6)]
    with tempfile.TemporaryDirectory() as folder:
        for perspective in (True, False):
            expected, interior = known_answer(perspective)
            for name, k, d in cases:
                scene = quad_scene(perspective, k, d * DIRECTION)
                row = []
                bad = ""
                for backend in ("gpu", "cpu"):
                    cube, error = render(metamer, scene, folder, backend)
                    if cube is None:
                        row.append("error")
                        bad = error
                        continue
                    ratio = cube[:, interior] / expected[interior]
                    err = np.abs(ratio - 1)
                    worst = float(np.nanmax(np.where(np.isfinite(err), err, np.inf)))
                    row.append(f"{worst:10.2e}")
                    if backend == "gpu":
                        bad = f"{int(np.sum(np.any(~np.isfinite(cube) | (cube == 0), axis=0) & interior))} of {int(interior.sum())}"
                label = ("perspective head-on, " if perspective else "orthographic, ") + name
                print(f"{label:<44} {row[0]:>10} {row[1]:>10}  {bad}")
        # The grazing point light of tests/numerics_test.cpp on its own: a glossy quad 20 m long
        # seen at 89.9 degrees, lit by a point light 1 cm above it; GPU against the reference.
        a = math.radians(89.9)
        eye = [0, -20 * math.sin(a), 20 * math.cos(a)]
        for perspective in (False, True):
            camera = {"position": eye, "target": [0, 0, 0], "up": [0, 0, 1], "width": 24, "height": 24}
            camera.update({"fov_y_deg": 0.03} if perspective else {"projection": "orthographic", "height_m": 0.01})
            scene = {
                "grid": {"start_nm": 400, "end_nm": 700, "step_nm": 10},
                "camera": camera,
                "lights": [{"type": "point", "position": [0.3, 0.5, 0.01], "spectrum": "illuminants/E",
                            "scale": 0.01, "shadows": False}],
                "materials": {"paint": {"diffuse": 0.5, "specular": 0.5, "gloss": 50}},
                "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1, 20],
                             "material": "paint"}],
            }
            cubes = [render(metamer, scene, folder, backend)[0] for backend in ("gpu", "cpu")]
            label = "grazing 89.9°, point light alone, " + ("perspective" if perspective else "orthographic")
            if any(c is None for c in cubes):
                print(f"{label:<44} error")
                continue
            gpu, cpu = cubes[0][:, 1:-1, 1:-1], cubes[1][:, 1:-1, 1:-1]
            floor = 1e-4 * np.max(np.abs(cpu), axis=(1, 2), keepdims=True)
            err = float(np.max(np.abs(gpu - cpu) / np.maximum(np.abs(cpu), floor)))
            print(f"{label:<44} {err:10.2e} {'(GPU vs CPU)':>10}")
        # d = 0: point lights exactly on pixel centres of a quad lit by a directional light.
        scene = {
            "grid": {"start_nm": 400, "end_nm": 700, "step_nm": 50},
            "camera": {"projection": "orthographic", "position": [0, 0, 2], "target": [0, 0, 0], "up": [0, 1, 0],
                       "height_m": 17 / 16, "width": 17, "height": 17},
            "lights": [{"type": "directional", "direction": [0.25, -0.5, -1], "spectrum": "illuminants/E", "scale": 0.01}]
            + [{"type": "point", "position": p, "spectrum": "illuminants/E", "scale": 0.01, "shadows": False}
               for p in ([0, 0, 0], [0.5, 0.5, 0], [-0.5, -0.5, 0], [0.5, 0, 0], [0, -0.5, 0], [0.0625, 0.0625, 0],
                         [-0.25, 0.3125, 0], [0.4375, -0.125, 0], [-0.1875, -0.375, 0])],
            "materials": {"white": {"diffuse": 0.5}},
            "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1, 1], "material": "white"}],
        }
        for backend in ("gpu", "cpu"):
            cube, error = render(metamer, scene, folder, backend)
            nan = "error: " + error if cube is None else f"{int(np.sum(np.any(~np.isfinite(cube), axis=0)))} px non-finite"
            print(f"{'9 point lights on pixel centres (d = 0), ' + backend:<44} {nan}")


if __name__ == "__main__":
    sys.exit(main())
