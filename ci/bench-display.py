#!/usr/bin/env python3
"""The display path's speed, measured from outside as a user sees it (issue 15; docs/performance.md).

Prints, in one run on this machine:
  1. display frame time: full spectral (the response pass) against --mode rgb, per scene, and the
     cube path (every band + the tonemap pass) for scale;
  2. the preview's frame time and frames per second at 512² × 89 bands on spheres: alone, with the
     probe and a pin, and in split view (needs xvfb-run);
  3. time to first image from process start: PNG, and the 89-band EXR (default compression);
  4. process start-up: `metamer --help`;
  5. the cube path's shading and readback at 512² × 89 bands and, with --ceiling, the lavapipe
     ceiling of ../shared/notes/lavapipe.md measured in the same run.
Medians over repeats; the machine is shared, so compare ratios taken in one run. This is a
benchmark that prints figures, not a test: nothing is asserted.

  python3 ci/bench-display.py [--metamer build/metamer] [--before OLD/metamer] [--repeats 5]
                              [--ceiling DIR] [--json FILE]

--before: a build of an earlier commit, measured in the same run beside it (display frame as that
build makes a PNG, time to first image, start-up, the cube path) — the before/after of
docs/performance.md.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
GRID89 = "300:740:5"


def run(cmd, env=None, check=True):
    e = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    if env:
        e.update(env)
    p = subprocess.run(cmd, capture_output=True, text=True, env=e)
    if p.returncode != 0:
        if not check:
            return None
        sys.exit(f"bench-display: {' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p.stdout + p.stderr


def wall(cmd, repeats):
    """Median seconds from process start to exit."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run(cmd)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def frame_ms(metamer, scene, out, extra, frames):
    """A render's median frame time: the response pass + tonemap, or shading + readback (cube; also
    what a build before the response pass reports for a PNG)."""
    text = run([metamer, "render", scene, "--out", out, "--frames", str(frames), "--timings"] + extra)
    m = re.search(r"median of the other \d+: shading ([\d.]+) ms, tonemap ([\d.]+) ms, frame ([\d.]+) ms", text)
    if m:
        return {"shading": float(m[1]), "tonemap": float(m[2]), "frame": float(m[3])}
    m = re.search(r"median of the other \d+: shading ([\d.]+) ms, readback ([\d.]+) ms", text)
    if m:
        return {"shading": float(m[1]), "readback": float(m[2]), "frame": float(m[1]) + float(m[2])}
    sys.exit(f"bench-display: no frame times in:\n{text}")


def preview_ms(metamer, scene, extra, frames):
    if not shutil.which("xvfb-run"):
        return None
    text = run(["xvfb-run", "-a", "-s", "-screen 0 1600x1024x24", metamer, "preview", scene, "--frames", str(frames),
                "--grid", GRID89, "--no-watch"] + extra)
    m = re.search(r"median of the other \d+: ([\d.]+) ms per frame \(shading ([\d.]+), tonemap ([\d.]+), "
                  r"probe ([\d.]+), present ([\d.]+)\)", text)
    if not m:
        sys.exit(f"bench-display: no preview frame times in:\n{text}")
    return {"frame": float(m[1]), "shading": float(m[2]), "tonemap": float(m[3]), "probe": float(m[4]),
            "present": float(m[5])}


def ceiling(folder):
    """The prototype's fragment-path rows (ms per 1024² × 89-band frame), built and run here."""
    work = tempfile.mkdtemp(prefix="metamer-ceiling-")
    shutil.copytree(folder, work, dirs_exist_ok=True)
    subprocess.run(["bash", "./build.sh"], cwd=work, check=True, capture_output=True)
    p = subprocess.run(["./proto"], cwd=work, capture_output=True, text=True,
                       env=dict(os.environ, MODES="bf", XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp")))
    shutil.rmtree(work, ignore_errors=True)
    return p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--metamer", default=os.path.join(ROOT, "build", "metamer"))
    ap.add_argument("--repeats", type=int, default=5, help="process runs per start-up figure (median)")
    ap.add_argument("--frames", type=int, default=30, help="frames per frame-time figure (median of 2..N)")
    ap.add_argument("--before", help="an earlier build of metamer to measure beside it")
    ap.add_argument("--ceiling", help="folder of the lavapipe-ceiling prototype (../shared/tools/lavapipe-ceiling)")
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    m = a.metamer
    out = tempfile.mkdtemp(prefix="metamer-bench-display-")
    figures = {"device": "", "scenes": {}}
    size = ["--set", "camera.width=512", "--set", "camera.height=512"]
    text = run([m, "render", os.path.join(ROOT, "scenes", "metamers.json"), "--out", out, "--write", "png", "-v",
                "--set", "camera.width=8", "--set", "camera.height=8"])
    dev = re.search(r"device \d+: (.*)", text)
    figures["device"] = dev[1] if dev else "?"
    print(f"device: {figures['device']}; {os.cpu_count()} CPUs; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")

    b = a.before
    print("\n1. Display frame, 512², ms (median of frames 2..N): full spectral through the response pass against "
          "--mode rgb")
    head = f"{'scene':<14}{'full 89':>9}{'full 81':>9}{'rgb':>8}{'ratio':>7}{'rgb cube path':>15}{'full cube path':>16}"
    if b:
        head += f"{'before: full 89':>17}{'rgb':>8}{'ratio':>7}"
    print(head)
    for name in ["spheres", "colorchecker", "textured"]:
        scene = os.path.join(ROOT, "scenes", name + ".json")
        full89 = frame_ms(m, scene, out, size + ["--grid", GRID89, "--write", "png"], a.frames)
        full = frame_ms(m, scene, out, size + ["--write", "png"], a.frames)
        rgb = frame_ms(m, scene, out, size + ["--mode", "rgb", "--write", "png"], a.frames)
        rgb_cube = frame_ms(m, scene, out, size + ["--mode", "rgb", "--write", "cube"], a.frames)
        full_cube = frame_ms(m, scene, out, size + ["--grid", GRID89, "--write", "cube"], a.frames)
        ratio = full89["frame"] / rgb["frame"]
        row = {"full89": full89, "full": full, "rgb": rgb, "rgb_cube": rgb_cube, "full_cube": full_cube,
               "ratio_full89_rgb": ratio}
        line = (f"{name:<14}{full89['frame']:>9.1f}{full['frame']:>9.1f}{rgb['frame']:>8.1f}{ratio:>7.2f}"
                f"{rgb_cube['frame']:>15.1f}{full_cube['frame']:>16.1f}")
        if b:
            bf = frame_ms(b, scene, out, size + ["--grid", GRID89, "--write", "png"], a.frames)
            br = frame_ms(b, scene, out, size + ["--mode", "rgb", "--write", "png"], a.frames)
            row["before"] = {"full89": bf, "rgb": br}
            line += f"{bf['shading']:>17.1f}{br['shading']:>8.1f}{bf['shading'] / br['shading']:>7.2f}"
        figures["scenes"][name] = row
        print(line)
    print("   (full 89: --grid 300:740:5; full 81: the scene's 380–780 nm grid; a frame is the response pass + the "
          "tonemap pass; cube paths: shading + readback, no tonemap" +
          ("; before: the older build's spectral pass alone (its PNG then adds the tonemap pass over the bands)"
           if b else "") + ")")

    print("\n2. Preview, spheres 512² × 89 bands (xvfb-run, lavapipe): ms per frame (fps)")
    spheres = os.path.join(ROOT, "scenes", "spheres.json")
    preview = {}
    for label, extra in [("alone", []), ("probe + pin", ["--probe", "256,300", "--pin", "100,400"]),
                         ("split view", ["--split", "lights.0.spectrum=illuminants/A"])]:
        p = preview_ms(m, spheres, extra, 60)
        if p is None:
            print("   xvfb-run not found: no preview figures")
            break
        preview[label] = p
        print(f"   {label:<12} {p['frame']:6.1f} ms ({1000 / p['frame']:5.1f} fps): shading {p['shading']:.1f}, "
              f"tonemap {p['tonemap']:.1f}, probe {p['probe']:.1f}, present {p['present']:.1f}")
    figures["preview"] = preview

    print(f"\n3. Time to first image from process start, spheres 512² (median of {a.repeats} runs), s")
    png = wall([m, "render", spheres, "--out", out, "--write", "png"], a.repeats)
    exr = wall([m, "render", spheres, "--out", out, "--write", "cube", "--grid", GRID89], a.repeats)
    both = wall([m, "render", spheres, "--out", out, "--grid", GRID89], a.repeats)
    figures["first_image_s"] = {"png": png, "exr89": exr, "exr89_and_png": both}
    print(f"   PNG {png:.2f}   89-band EXR (default compression) {exr:.2f}   EXR + PNG (the default --write) {both:.2f}")
    if b:
        bpng = wall([b, "render", spheres, "--out", out, "--write", "png"], a.repeats)
        bexr = wall([b, "render", spheres, "--out", out, "--write", "cube", "--grid", GRID89], a.repeats)
        bboth = wall([b, "render", spheres, "--out", out, "--grid", GRID89], a.repeats)
        figures["before_first_image_s"] = {"png": bpng, "exr89": bexr, "exr89_and_png": bboth}
        print(f"   before: PNG {bpng:.2f}   89-band EXR (its default compression) {bexr:.2f}   EXR + PNG {bboth:.2f}")

    print(f"\n4. Process start-up: metamer --help (median of {3 * a.repeats} runs)")
    helpS = wall([m, "--help"], 3 * a.repeats)
    libs = run(["ldd", m]).count("=>")
    figures["startup_s"] = helpS
    figures["shared_libraries"] = libs
    print(f"   {helpS * 1000:.1f} ms; {libs} shared libraries loaded at start")
    if b:
        bhelp = wall([b, "--help"], 3 * a.repeats)
        blibs = run(["ldd", b]).count("=>")
        figures["before_startup_s"] = bhelp
        figures["before_shared_libraries"] = blibs
        print(f"   before: {bhelp * 1000:.1f} ms; {blibs} shared libraries")

    print("\n5. The cube path, spheres 512² × 89 bands: shading and readback, ms")
    cube = frame_ms(m, spheres, out, ["--grid", GRID89, "--write", "cube"], a.frames)
    figures["cube_path"] = cube
    print(f"   shading {cube['shading']:.1f}   readback {cube['readback']:.1f}")
    if b:
        bcube = frame_ms(b, spheres, out, ["--grid", GRID89, "--write", "cube"], a.frames)
        figures["before_cube_path"] = bcube
        print(f"   before: shading {bcube['shading']:.1f}   readback {bcube['readback']:.1f}")
    for label, binary in [("", m)] + ([("before: ", b)] if b else []):
        big = frame_ms(binary, os.path.join(ROOT, "scenes", "colorchecker.json"), out,
                       ["--grid", GRID89, "--write", "cube", "--compression", "none", "--set", "camera.width=1024",
                        "--set", "camera.height=1024"], max(6, a.frames // 3))
        figures[label.replace(": ", "_") + "cube_path_colorchecker_1024"] = big
        print(f"   {label}colorchecker 1024² × 89: shading {big['shading']:.1f}   readback {big['readback']:.1f}")
    if a.ceiling:
        text = ceiling(a.ceiling)
        figures["ceiling"] = text
        print("   lavapipe ceiling (1024² × 89 bands; the prototype's rows):")
        for line in text.splitlines():
            if line.strip():
                print("     " + line)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(figures, f, indent=2)
    shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    main()
