"""The Python module (`import metamer`, engine/python/metamer_module.cpp; docs/python.md), tested
with pytest through the project's venv: known answers, the CLI's files, colour-science as the
colorimetry oracle, h5py and Spectral Python as the readers of the cube formats, errors, memory
and the GIL. Run by CTest (tests/CMakeLists.txt, test `python_module`) with validation layers on.
"""

from __future__ import annotations

import json
import math
import os
import resource
import subprocess
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest

import metamer

warnings.filterwarnings("ignore")
import colour  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SPECTRA = REPO / "spectra"
BINARY = os.environ.get("METAMER_BINARY", str(REPO / "build" / "metamer"))


def white_quad(width=8, height=6, albedo=0.8, irradiance=2.0, grid=None):
    """A Lambertian quad of constant reflectance filling an orthographic view, under an ambient
    light of constant irradiance E: every pixel's radiance is albedo·E/π in every band."""
    scene = {
        "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0],
                   "height_m": 1.0, "width": width, "height": height},
        "lights": [{"type": "ambient", "spectrum": 1.0, "scale": irradiance}],
        "materials": {"white": {"diffuse": albedo}},
        "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [4, 4],
                     "material": "white"}],
    }
    if grid:
        scene["grid"] = grid
    return scene


def test_import_and_errors_are_exceptions_of_their_own():
    assert metamer.__version__
    assert issubclass(metamer.InputError, metamer.Error)
    assert issubclass(metamer.InputError, ValueError)
    assert issubclass(metamer.Error, RuntimeError)


@pytest.mark.parametrize("backend", ["gpu", "cpu"])
def test_known_answer_white_lambertian_quad(backend):
    r = metamer.render(white_quad(), backend=backend)
    assert r.validation_errors == 0
    cube = r.cube
    assert cube.dtype == np.float32 and cube.shape == (6, 8, 89)
    assert r.units == "W·sr⁻¹·m⁻²·nm⁻¹"
    np.testing.assert_array_equal(r.wavelengths_nm, np.arange(300, 741, 5, dtype=float))
    expected = 0.8 * 2.0 / math.pi
    np.testing.assert_allclose(cube, expected, rtol=1e-6)


def test_cube_is_a_read_only_view_of_the_render():
    r = metamer.render(white_quad())
    a, b = r.cube, r.cube
    assert not a.flags.owndata and np.shares_memory(a, b)  # no copy per access
    with pytest.raises(ValueError):
        a[0, 0, 0] = 1.0
    del r  # the array keeps the render alive
    assert float(a[0, 0, 0]) == pytest.approx(0.8 * 2.0 / math.pi, rel=1e-6)


def test_scene_file_with_overrides_grid_and_outputs_equals_the_cli(tmp_path):
    scene = REPO / "scenes" / "spheres.json"
    args = dict(grid="400:700:10", overrides=["camera.width=48", "camera.height=40"])
    r = metamer.render(scene, write=("cube", "png", "xyz", "responses"), **args)
    assert r.cube.shape == (40, 48, 31)
    assert r.xyz.shape == (40, 48, 3) and r.xyz.dtype == np.float32
    assert r.display.shape == (40, 48, 3) and r.display.dtype == np.uint8
    assert r.responses.shape == (40, 48, 3) and r.response_channels == ["X", "Y", "Z"]
    saved = {Path(p).name for p in r.save(tmp_path / "py")}
    assert saved == {"spheres.exr", "spheres.png", "spheres.xyz.exr", "spheres.cie1931.exr"}

    cli = tmp_path / "cli"
    subprocess.run([BINARY, "render", str(scene), "--out", str(cli), "--grid", "400:700:10", "--set",
                    "camera.width=48", "--set", "camera.height=40", "--write", "cube,png,xyz,responses"],
                   check=True, capture_output=True)
    for name in saved:
        stats = metamer.compare(tmp_path / "py" / name, cli / name, delta_e=False)
        assert stats["max_abs"] == 0, name
    np.testing.assert_array_equal(metamer.load_cube(cli / "spheres.exr")["cube"], r.cube)


def test_xyz_agrees_with_colour_science():
    # Absolute XYZ (cd/m²) of a pixel: 683 lm/W × CIE 15's summation of its radiance against the
    # CIE 1931 observer on the render grid, computed by colour-science from the module's cube.
    r = metamer.render(REPO / "scenes" / "spheres.json", grid="380:780:5", xyz="absolute",
                       overrides={"camera.width": 32, "camera.height": 24}, write="cube,xyz")
    cmfs_table = np.genfromtxt(SPECTRA / "observers" / "cie1931_2deg.csv", delimiter=",", skip_header=1)
    cmfs = colour.MultiSpectralDistributions(cmfs_table[:, 1:], cmfs_table[:, 0], labels=["x_bar", "y_bar", "z_bar"])
    shape = colour.SpectralShape(380, 780, 5)
    cmfs = cmfs.copy().align(shape)
    ones = colour.sd_ones(shape)
    worst = 0.0
    for y, x in [(12, 16), (20, 4), (3, 30), (15, 10)]:
        sd = colour.SpectralDistribution(r.cube[y, x].astype(float), r.wavelengths_nm)
        expected = colour.sd_to_XYZ(sd, cmfs, ones, k=683.0, method="Integration")
        got = r.xyz[y, x].astype(float)
        worst = max(worst, float(np.max(np.abs(got - expected) / np.maximum(np.abs(expected), 1e-6))))
    assert worst < 1e-4, worst


def test_sweep_over_illuminants_in_a_loop_keeps_one_device_and_bounded_memory():
    scene = white_quad(32, 32)
    ys = []
    for name in ["illuminants/A", "illuminants/D65", "illuminants/FL2"] * 2:
        scene["lights"][0]["spectrum"] = name
        ys.append(metamer.render(scene, write="xyz", xyz="absolute").xyz[..., 1].mean())
    assert ys[0] == ys[3] and ys[1] == ys[4]
    assert len(set(ys[:3])) == 3
    assert metamer._context_count() == 1

    def rss_kib():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") // 1024

    for _ in range(5):
        metamer.render(white_quad(128, 128))
    before = rss_kib()
    for _ in range(30):
        metamer.render(white_quad(128, 128))  # 128² × 89 bands: 5.6 MiB a cube
    grown = rss_kib() - before
    assert grown < 16 * 1024, f"RSS grew by {grown} KiB over 30 renders"


def test_the_gil_is_released_while_rendering():
    counter = 0
    done = threading.Event()

    def work():
        metamer.render(white_quad(256, 256), backend="cpu")
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        counter += 1
    t.join()
    assert counter > 10000, counter


def test_input_errors_carry_the_cli_message(tmp_path):
    with pytest.raises(metamer.InputError, match="no-such.json"):
        metamer.render(tmp_path / "no-such.json")
    bad = white_quad()
    bad["materials"]["white"]["diffuse"] = "colorchecker/dark_skn"
    with pytest.raises(metamer.InputError, match=r"materials\.white\.diffuse.*did you mean 'colorchecker/dark_skin'"):
        metamer.render(bad)
    with pytest.raises(metamer.InputError, match="grid"):
        metamer.render(white_quad(), grid="400-700")
    with pytest.raises(metamer.InputError, match="backend"):
        metamer.render(white_quad(), backend="opengl")
    with pytest.raises(metamer.InputError, match="--mode|mode"):
        metamer.render(white_quad(), mode="spectral")
    # The CLI says the same about the same file.
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(bad))
    cli = subprocess.run([BINARY, "render", str(p), "--out", str(tmp_path)], capture_output=True, text=True)
    assert cli.returncode == 2
    with pytest.raises(metamer.InputError) as e:
        metamer.render(p)
    assert cli.stderr.strip() == "metamer: " + str(e.value)


def test_compare_returns_the_statistics(tmp_path):
    a = metamer.render(white_quad(albedo=0.8))
    b = metamer.render(white_quad(albedo=0.4))
    same = metamer.compare(a, a)
    assert same["max_abs"] == 0 and same["max_rel"] == 0
    diff = metamer.compare(a, b, delta_e=False)
    assert diff["max_rel"] == pytest.approx(1.0, rel=1e-5)
    tol = tmp_path / "tol.json"
    tol.write_text('{"max_rel": 0.5}')
    verdict = metamer.compare(a, b, tolerance=tol, delta_e=False)
    assert verdict["passed"] is False and verdict["failures"]


def test_cube_formats_round_trip_through_load_cube_and_the_readers(tmp_path):
    import h5py
    import spectral

    r = metamer.render(white_quad(9, 7), grid="400:700:20", write="cube")
    written = r.save(tmp_path)
    exr = metamer.load_cube(written[0])
    np.testing.assert_array_equal(exr["cube"], r.cube)
    assert exr["units"] == "W·sr⁻¹·m⁻²·nm⁻¹" and exr["grid"] == "400:700:20"
