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
import sys
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
    assert a.flags.c_contiguous and a.strides == (8 * 89 * 4, 89 * 4, 4)
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
    # CIE 1931 observer on the render grid, computed by colour-science from the module's cube
    # (colour-science takes an explicit k as absolute and divides its result by 100: undone here).
    r = metamer.render(REPO / "scenes" / "spheres.json", grid="380:780:5", xyz="absolute",
                       overrides={"camera.width": 32, "camera.height": 24}, write="cube,xyz")
    cmfs_table = np.genfromtxt(SPECTRA / "observers" / "cie1931_2deg.csv", delimiter=",", skip_header=1)
    cmfs = colour.MultiSpectralDistributions(cmfs_table[:, 1:], cmfs_table[:, 0], labels=["x_bar", "y_bar", "z_bar"])
    shape = colour.SpectralShape(380, 780, 5)
    cmfs = cmfs.copy().align(shape)
    ones = colour.sd_ones(shape)
    worst = 0.0
    lit = [(y, x) for y in range(24) for x in range(32) if r.xyz[y, x, 1] > 1.0]
    assert len(lit) > 100
    for y, x in lit:
        sd = colour.SpectralDistribution(r.cube[y, x].astype(float), r.wavelengths_nm)
        expected = 100.0 * colour.sd_to_XYZ(sd, cmfs, ones, k=683.0, method="Integration")
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


def test_engine_warnings_are_python_warnings():
    # ColorChecker data cover 380–780 nm: on a 300–740 nm grid the bands below are zero, with a warning.
    with pytest.warns(metamer.Warning, match=r"materials\.floor\.diffuse.*380.*780") as record:
        metamer.render(REPO / "scenes" / "spheres.json", grid="300:740:20",
                       overrides={"camera.width": 8, "camera.height": 8})
    assert not any(str(w.message).startswith("warning:") for w in record)


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


def test_saved_hdf5_and_envi_hold_the_render_for_h5py_and_spectral_python(tmp_path):
    import h5py
    import spectral

    r = metamer.render(REPO / "scenes" / "spheres.json", grid="400:700:10", format="exr,hdf5:gzip,envi:bil",
                       overrides={"camera.width": 24, "camera.height": 18}, write="cube")
    names = sorted(Path(p).name for p in r.save(tmp_path))
    assert names == ["spheres.exr", "spheres.h5", "spheres.hdr"]
    with h5py.File(tmp_path / "spheres.h5", "r") as f:
        np.testing.assert_array_equal(f["cube"][()], r.cube)
        np.testing.assert_array_equal(f["wavelength_nm"][()], r.wavelengths_nm)
        assert f["cube"].attrs["units"] == "W·sr⁻¹·m⁻²·nm⁻¹"
        assert f.attrs["metamer:overrides"] == "camera.width=24 camera.height=18"
    img = spectral.open_image(str(tmp_path / "spheres.hdr"))
    np.testing.assert_array_equal(np.asarray(img.load()), r.cube)
    assert [float(w) for w in img.metadata["wavelength"]] == list(r.wavelengths_nm)
    for name in names:
        c = metamer.load_cube(tmp_path / name)
        np.testing.assert_array_equal(c["cube"], r.cube)
    assert metamer.compare(tmp_path / "spheres.h5", tmp_path / "spheres.exr")["max_abs"] == 0


def write_envi(stem: Path, cube: np.ndarray, wavelengths, quantity="reflectance", byte_order="<"):
    """An ENVI BSQ reflectance cube written by hand, as another tool would (not by Metamer)."""
    lines, samples, bands = cube.shape
    stem.with_suffix(".img").write_bytes(np.ascontiguousarray(cube.transpose(2, 0, 1)).astype(byte_order + "f4").tobytes())
    stem.with_suffix(".hdr").write_text(
        "ENVI\n"
        f"samples = {samples}\nlines = {lines}\nbands = {bands}\nheader offset = 0\n"
        "file type = ENVI Standard\ndata type = 4\ninterleave = bsq\n"
        f"byte order = {0 if byte_order == '<' else 1}\nwavelength units = Nanometers\n"
        "wavelength = {" + ", ".join(f"{w:g}" for w in wavelengths) + "}\n"
        f"metamer quantity = {quantity}\n")


def textured_quad(texture: str):
    scene = white_quad(6, 6, albedo=1.0)
    scene["materials"]["white"] = {"textures": {"diffuse": texture}}
    scene["grid"] = {"start_nm": 400, "end_nm": 700, "step_nm": 50}
    return scene


def test_hdf5_and_envi_textures_written_by_other_tools_render_their_reflectance(tmp_path):
    import h5py

    wavelengths = np.arange(400.0, 701.0, 50.0)
    reflectance = np.linspace(0.1, 0.7, len(wavelengths))
    cube = np.broadcast_to(reflectance, (4, 4, len(wavelengths))).astype(np.float32)
    with h5py.File(tmp_path / "paint.h5", "w") as f:
        f["cube"] = cube
        f["wavelength_nm"] = wavelengths
        f["cube"].attrs["quantity"] = "reflectance"
    write_envi(tmp_path / "paint_le", cube, wavelengths)
    write_envi(tmp_path / "paint_be", cube, wavelengths, byte_order=">")
    expected = reflectance * 2.0 / math.pi  # ρ·E/π under the ambient light
    for texture in ["paint.h5", "paint_le.hdr", "paint_be.img"]:
        r = metamer.render(textured_quad(texture), base_dir=tmp_path, backend="cpu")
        np.testing.assert_allclose(r.cube[3, 3], expected, rtol=1e-6, err_msg=texture)


@pytest.mark.parametrize("case, damage, message", [
    ("envi-truncated", lambda p: p.with_suffix(".img").write_bytes(p.with_suffix(".img").read_bytes()[:-4]), "bytes"),
    ("envi-no-byte-order", lambda p: p.write_text(p.read_text().replace("byte order = 0\n", "")), "byte order"),
    ("envi-data-type", lambda p: p.write_text(p.read_text().replace("data type = 4", "data type = 12")), "data type"),
    ("envi-wavelengths", lambda p: p.write_text(p.read_text().replace("wavelength = {400, ", "wavelength = {")), "wavelength"),
    ("envi-emissive", lambda p: p.write_text(p.read_text().replace("= reflectance", "= spectral radiance")), "radiance"),
])
def test_damaged_envi_textures_are_input_errors_naming_the_file(tmp_path, case, damage, message):
    wavelengths = np.arange(400.0, 701.0, 50.0)
    write_envi(tmp_path / "t", np.full((2, 2, len(wavelengths)), 0.5, np.float32), wavelengths)
    damage(tmp_path / "t.hdr")
    with pytest.raises(metamer.InputError, match=message) as e:
        metamer.render(textured_quad("t.hdr"), base_dir=tmp_path)
    assert "materials.white.textures.diffuse" in str(e.value) and "t." in str(e.value)


CORPUS = REPO / "tests" / "bad-inputs" / "files" / "cubes"


@pytest.mark.parametrize("name, message", [
    ("truncated.hdr", "is 60 bytes; the header"), ("no-byte-order.hdr", "byte order: missing"),
    ("data-type-12.hdr", "data type: 12"), ("utf16.hdr", "UTF-16"), ("truncated.h5", "truncated or damaged"),
    ("no-wavelengths.h5", "/wavelength_nm: missing"), ("rank-2.h5", "/cube: has rank 2"),
])
def test_damaged_cubes_given_to_compare_are_input_errors_in_the_module_and_the_cli(tmp_path, name, message):
    reference = metamer.render(white_quad(2, 2), grid="400:700:50").save(tmp_path)[0]
    with pytest.raises(metamer.InputError, match=message):
        metamer.compare(CORPUS / name, reference)
    cli = subprocess.run([BINARY, "compare", str(CORPUS / name), reference], capture_output=True, text=True)
    assert cli.returncode == 2 and message in cli.stderr and name.split(".")[0] in cli.stderr
    assert len(cli.stderr.strip().splitlines()) == 1


def test_special_files_are_refused_by_load_cube_and_compare(tmp_path):
    fifo = tmp_path / "pipe.h5"
    os.mkfifo(fifo)
    with pytest.raises(metamer.InputError, match="not a regular file"):
        metamer.load_cube(fifo)
    with pytest.raises(metamer.InputError, match="not a regular file"):
        metamer.compare(fifo, fifo)
    with pytest.raises(metamer.InputError, match="not a regular file"):
        metamer.load_cube("/dev/zero")


def hostile_hdf5(tmp_path, name):
    """An HDF5 cube that would make HDF5 read another file (issue 30, class 6)."""
    import h5py

    path = tmp_path / (name + ".h5")
    fifo = tmp_path / "values.fifo"
    if not fifo.exists():
        os.mkfifo(fifo)
    with h5py.File(path, "w") as f:
        if name == "external-fifo":
            f.create_dataset("cube", shape=(2, 2, 7), dtype="<f4", external=[(str(fifo), 0, 2 * 2 * 7 * 4)])
        elif name == "external-link":
            f["cube"] = h5py.ExternalLink(str(fifo), "/cube")
        elif name == "soft-link":
            f["data"] = np.full((2, 2, 7), 0.5, np.float32)
            f["cube"] = h5py.SoftLink("/data")
        elif name == "virtual":
            layout = h5py.VirtualLayout(shape=(2, 2, 7), dtype="<f4")
            layout[:] = h5py.VirtualSource(str(fifo), "data", shape=(2, 2, 7))
            f.create_virtual_dataset("cube", layout)
        f["wavelength_nm"] = np.arange(400.0, 701.0, 50.0)
    return path


@pytest.mark.parametrize("name, message", [
    ("external-fifo", "/cube: keeps its values in 1 external file ('{fifo}')"),
    ("external-link", "/cube: is an external link to '{fifo}:/cube'"),
    ("soft-link", "/cube: is a soft link to '/data'"),
    ("virtual", "/cube: is a virtual dataset (1 source, the first in '{fifo}')"),
])
def test_hdf5_that_would_read_other_files_is_refused_at_once(tmp_path, name, message):
    # In child processes under a timeout: a reader that opens the FIFO fails instead of hanging.
    path = hostile_hdf5(tmp_path, name)
    message = message.format(fifo=tmp_path / "values.fifo")
    code = ("import metamer, sys\ntry:\n    metamer.load_cube(sys.argv[1])\nexcept metamer.InputError as e:\n"
            "    print(e)\n    sys.exit(2)\n")
    module = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True, timeout=60)
    assert module.returncode == 2 and str(path) in module.stdout and message in module.stdout, module
    assert "refused" in module.stdout
    cli = subprocess.run([BINARY, "compare", str(path), str(path)], capture_output=True, text=True, timeout=60)
    assert cli.returncode == 2 and message in cli.stderr and len(cli.stderr.strip().splitlines()) == 1, cli


def test_hdf5_with_a_user_block_reads_everywhere(tmp_path):
    import h5py

    wavelengths = np.arange(400.0, 701.0, 50.0)
    cube = np.broadcast_to(np.linspace(0.1, 0.7, len(wavelengths)), (4, 4, len(wavelengths))).astype(np.float32)
    with h5py.File(tmp_path / "block.h5", "w", userblock_size=512) as f:
        f["cube"] = cube
        f["wavelength_nm"] = wavelengths
        f["cube"].attrs["quantity"] = "reflectance"
    assert (tmp_path / "block.h5").read_bytes()[512:516] == b"\x89HDF"
    np.testing.assert_array_equal(metamer.load_cube(tmp_path / "block.h5")["cube"], cube)
    assert metamer.compare(tmp_path / "block.h5", tmp_path / "block.h5")["max_abs"] == 0
    r = metamer.render(textured_quad("block.h5"), base_dir=tmp_path, backend="cpu")
    np.testing.assert_allclose(r.cube[3, 3], cube[0, 0] * 2.0 / math.pi, rtol=1e-6)


def test_the_examples_in_docs_python_md_run(tmp_path, monkeypatch):
    import re

    blocks = re.findall(r"```python\n(.*?)```", (REPO / "docs" / "python.md").read_text(), re.S)
    assert len(blocks) == 3
    (tmp_path / "scenes").symlink_to(REPO / "scenes")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
    assert (tmp_path / "out" / "spheres.h5").exists()
    assert namespace["stats"]["max_abs"] == 0
    assert namespace["sd"].name == "the matte sphere" and float(namespace["sd"].values.max()) > 0


def test_render_keywords_carry_the_cli_help():
    # One help text per option (render/render_settings.h): the keyword's doc is the flag's.
    doc = metamer.render.__doc__
    assert "detector (--detector): cie1931, cie1964, camera:<name>, film:<name> or csv:<path>" in doc
    assert "overrides (--set): override a scene value" in doc
    cli = subprocess.run([os.environ["METAMER_BINARY"], "render", "--help"], capture_output=True, text=True).stdout
    assert "csv:<path> (default: the scene's output" in " ".join(cli.split())
