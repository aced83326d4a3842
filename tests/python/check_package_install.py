#!/usr/bin/env python3
"""The package as a user installs it (issue 32; docs/python.md "Getting it"): the wheel ci/build.sh
makes (build/dist/metamer-*.whl, the `pip wheel .` of this checkout) goes into a fresh venv outside
the checkout, and from another folder, with nothing pointing at the checkout or the build tree:

- `import metamer` loads the installed copy, which reads its own spectra (not the checkout's);
- a render of a white Lambertian quad under a known irradiance gives albedo·E/π in every band, its
  cube is saved and read back, and a pixel comes out as a colour-science SpectralDistribution when
  colour-science is there;
- `metamer.__version__`, `python -m metamer --version`, the `metamer` console script and the build
  tree's CLI say the same version, and the console script renders a bundled scene;
- without a Vulkan driver, or without the Vulkan loader, `import metamer` raises one
  VulkanUnavailableError naming the Debian packages to install;
- the wheel holds the package's files and no test programs; its size is printed.

Usage: check_package_install.py WHEEL_DIR BUILD_CLI SCENES_DIR
Exit codes: 0 pass, 1 fail.
"""

import glob
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile

failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        failures.append(what)


def run(argv, env, cwd, **kw):
    return subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True, timeout=600, **kw)


wheel_dir, build_cli, scenes = sys.argv[1:4]
wheels = sorted(glob.glob(os.path.join(wheel_dir, "metamer-*.whl")))
if len(wheels) != 1:
    sys.exit(f"FAIL expected one wheel in {wheel_dir} (ci/build.sh makes it), found {wheels}")
wheel = wheels[0]

# --- What the wheel holds.
with zipfile.ZipFile(wheel) as z:
    names = z.namelist()
size_mb = os.path.getsize(wheel) / 1e6
print(f"wheel {os.path.basename(wheel)}: {size_mb:.1f} MB, {len(names)} files")
for required in ["metamer/__init__.py", "metamer/__main__.py", "metamer/_api.py", "metamer/_notebook.py",
                 "metamer/_metamer.pyi", "metamer/py.typed", "metamer/bin/metamer",
                 "metamer/libmetamer_oiio.so", "metamer/spectra/README.md"]:
    check(required in names, f"the wheel holds {required}")
check(any(n.startswith("metamer/_metamer.") and n.endswith(".so") for n in names), "the wheel holds the extension")
check(sum(n.startswith("metamer/spectra/") for n in names) > 20, "the wheel holds the spectra library")
check(not any("_test" in n or "/tests/" in n for n in names), "the wheel holds no test programs")

root = tempfile.mkdtemp(prefix="metamer-install-")
try:
    venv = os.path.join(root, "venv")
    elsewhere = os.path.join(root, "elsewhere")
    os.makedirs(elsewhere)
    # Debian's python3-numpy (and colour-science if the system has it) from the system site; the
    # wheel itself from the file, no package index.
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "METAMER_SPECTRA", "VIRTUAL_ENV")}
    env["PATH"] = os.path.join(venv, "bin") + os.pathsep + env.get("PATH", "")
    install = run([os.path.join(venv, "bin", "pip"), "install", "--no-index", "--disable-pip-version-check", "-q",
                   wheel], env, elsewhere)
    check(install.returncode == 0, f"pip install {os.path.basename(wheel)} into a fresh venv: {install.stderr[-2000:]}")
    python = os.path.join(venv, "bin", "python")

    script = r"""
import json, math, os, sys
import numpy as np
import metamer
package = os.path.dirname(metamer.__file__)
print("file", metamer.__file__)
print("spectra", metamer._metamer._spectra_root())
scene = {
    "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0],
               "height_m": 1.0, "width": 8, "height": 6},
    "lights": [{"type": "ambient", "spectrum": 1.0, "scale": 2.0}],  # irradiance E = 2 W·m⁻²·nm⁻¹
    "materials": {"white": {"diffuse": 0.8}},
    "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [4, 4], "material": "white"}],
}
r = metamer.render(scene, name="quad", write="cube,display")
print("shape", r.cube.shape)
print("radiance", float(r.cube.min()), float(r.cube.max()))
r.save("out")
back = metamer.load_cube("out/quad.exr")
print("roundtrip", float(np.abs(back["cube"] - r.cube).max()))
print("png", (r._repr_png_() or b"")[:8] == b"\x89PNG\r\n\x1a\n")
print("version", metamer.__version__)
"""
    res = run([python, "-c", script], env, elsewhere)
    print(res.stdout, res.stderr[-3000:], sep="")
    check(res.returncode == 0, "import metamer and render from another folder")
    out = dict(line.split(" ", 1) for line in res.stdout.splitlines() if " " in line)
    check(out.get("file", "").startswith(venv + os.sep), "metamer is imported from the venv, not the checkout")
    check(out.get("spectra", "").startswith(os.path.join(venv, "lib")), "the installed package reads its own spectra")
    check(out.get("shape") == "(6, 8, 89)", "the cube is 6 × 8 × 89 bands (300–740 nm by 5)")
    if "radiance" in out:
        lo, hi = map(float, out["radiance"].split())
        expected = 0.8 * 2.0 / 3.141592653589793
        check(abs(lo - expected) < 1e-4 * expected and abs(hi - expected) < 1e-4 * expected,
              f"every band is albedo·E/π = {expected:.6f} (min {lo}, max {hi})")
    check(out.get("roundtrip") == "0.0", "the saved cube reads back bit for bit")
    check(out.get("png") == "True", "the render shows as a PNG in a notebook (_repr_png_)")

    cli_version = run([build_cli, "--version"], env, elsewhere).stdout.strip()
    module_version = run([python, "-m", "metamer", "--version"], env, elsewhere)
    script_version = run([os.path.join(venv, "bin", "metamer"), "--version"], env, elsewhere)
    check(cli_version == f"metamer {out.get('version')}",
          f"metamer.__version__ ({out.get('version')}) is the CLI's ({cli_version!r})")
    check(module_version.stdout.strip() == cli_version, f"python -m metamer --version: {module_version.stdout!r}")
    check(script_version.stdout.strip() == cli_version, f"the metamer console script --version: {script_version.stdout!r}")
    rendered = run([os.path.join(venv, "bin", "metamer"), "render", os.path.join(scenes, "metamers.json"),
                    "--set", "camera.width=32", "--set", "camera.height=16", "-o", "cli-out/"], env, elsewhere)
    check(rendered.returncode == 0 and os.path.exists(os.path.join(elsewhere, "cli-out", "metamers.exr")),
          f"the console script renders scenes/metamers.json: {rendered.stderr[-1500:]}")

    # --- No Vulkan: one clear exception, naming what to install.
    no_driver = dict(env, VK_ICD_FILENAMES="/nonexistent/icd.json", VK_DRIVER_FILES="/nonexistent/icd.json")
    res = run([python, "-c", "import metamer"], no_driver, elsewhere)
    check(res.returncode != 0 and "VulkanUnavailableError" in res.stderr and "mesa-vulkan-drivers" in res.stderr
          and "Segmentation" not in res.stderr, f"no Vulkan driver: {res.stderr.strip().splitlines()[-1:]}")
    res = run([python, "-c", "import metamer, sys; print(metamer.VulkanUnavailableError.__mro__[1].__name__)"],
              dict(no_driver, METAMER_SKIP_DEVICE_CHECK="1"), elsewhere)
    check(res.returncode == 0 and res.stdout.strip() == "ImportError",
          "METAMER_SKIP_DEVICE_CHECK=1 imports without a driver; VulkanUnavailableError is an ImportError")
    fake = os.path.join(root, "no-loader")
    os.makedirs(fake)
    open(os.path.join(fake, "libvulkan.so.1"), "wb").close()  # an unloadable loader stands for a missing one
    res = run([python, "-c", "import metamer"], dict(env, LD_LIBRARY_PATH=fake), elsewhere)
    check(res.returncode != 0 and "VulkanUnavailableError" in res.stderr and "libvulkan1" in res.stderr,
          f"no Vulkan loader: {res.stderr.strip().splitlines()[-1:]}")
finally:
    shutil.rmtree(root, ignore_errors=True)

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
