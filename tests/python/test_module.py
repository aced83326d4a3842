"""The Python module (`import metamer`, engine/python/; docs/python.md), tested
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
        assert f["cube"].attrs["units"] == "W sr-1 m-2 nm-1"  # UDUNITS, for CF readers
        assert f["cube"].attrs["units_readable"] == "W·sr⁻¹·m⁻²·nm⁻¹"
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
    assert len(blocks) == 4
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


# --- Hostile input (issue 30, class 7): memory, fork, paths, names, argument types.


def test_in_memory_outputs_are_refused_over_the_memory_budget_with_the_estimate():
    # 16384² on 89 bands: an 89 GiB cube kept in memory, over any default budget; refused before
    # anything is allocated (not a bare MemoryError).
    with pytest.raises(metamer.InputError) as e:
        metamer.render(white_quad(16384, 16384))
    message = str(e.value)
    assert "16384×16384" in message and "89 bands" in message and "memory budget" in message
    assert "memory_budget" in message and "camera.width" in message and "GiB" in message
    # Every kind of in-memory output counts: the display image alone over a tiny budget.
    with pytest.raises(metamer.InputError, match=r"over the memory budget of 0\.1 MiB"):
        metamer.render(white_quad(256, 256), write="xyz,display", memory_budget=0.0625)
    # The CLI's option, as a keyword: checked like the flag.
    for bad in [0, -1, math.nan, math.inf]:
        with pytest.raises(metamer.InputError, match="memory_budget"):
            metamer.render(white_quad(), memory_budget=bad)
    with pytest.raises(TypeError, match="memory_budget"):
        metamer.render(white_quad(), memory_budget="1G")


def test_a_render_over_the_budget_that_fits_in_strips_equals_the_whole_render():
    # The kept arrays fit, the render does not: it runs in strips into the arrays (GPU).
    whole = metamer.render(white_quad(64, 64, albedo=0.6), write="cube,xyz")
    strips = metamer.render(white_quad(64, 64, albedo=0.6), write="cube,xyz", memory_budget=4)
    assert any("strips" in note for note in strips.notes), strips.notes
    np.testing.assert_array_equal(strips.cube, whole.cube)
    np.testing.assert_array_equal(strips.xyz, whole.xyz)


def _render_mean(albedo):
    return float(metamer.render(white_quad(8, 8, albedo=albedo)).cube.mean())


def test_a_child_forked_after_a_render_renders_and_does_not_hang():
    import multiprocessing
    import signal
    import time

    expected = _render_mean(0.5)  # the parent has a device now
    # os.fork: the child renders on a fresh device and reports through a pipe; killed (and the
    # test failed) rather than waited for if it hangs.
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            os.close(read_end)
            os.write(write_end, repr((_render_mean(0.5), metamer._context_count())).encode())
            code = 0
        finally:
            os._exit(code)
    os.close(write_end)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        time.sleep(0.1)
    else:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        pytest.fail("a render in a child forked after a render hung")
    reply = os.read(read_end, 1000).decode()
    os.close(read_end)
    assert os.waitstatus_to_exitcode(status) == 0, reply
    mean, contexts = eval(reply)
    assert mean == expected and contexts == 1
    # multiprocessing's default start method on Linux, a pool of two.
    with multiprocessing.get_context("fork").Pool(2) as pool:
        means = pool.map_async(_render_mean, [0.25, 0.5, 0.75]).get(timeout=120)
    assert means[1] == expected and means[0] < means[1] < means[2]
    assert _render_mean(0.5) == expected  # and the parent's device still works


def test_paths_may_be_str_bytes_or_path_like_and_nothing_else(tmp_path):
    scene = REPO / "scenes" / "spheres.json"
    small = {"camera.width": 8, "camera.height": 6}
    by_bytes = metamer.render(os.fsencode(scene), grid="400:700:50", overrides=small)
    by_path = metamer.render(scene, grid="400:700:50", overrides=small)
    np.testing.assert_array_equal(by_bytes.cube, by_path.cube)
    saved = by_bytes.save(os.fsencode(tmp_path))
    assert saved == [str(tmp_path / "spheres.exr")]
    np.testing.assert_array_equal(metamer.load_cube(os.fsencode(saved[0]))["cube"], by_path.cube)
    assert metamer.compare(os.fsencode(saved[0]), Path(saved[0]))["max_abs"] == 0
    r = metamer.render(white_quad(), base_dir=os.fsencode(tmp_path), name="quad")
    assert [Path(p).name for p in r.save(tmp_path)] == ["quad.exr"]
    for call, argument in [(lambda: metamer.render(42), "scene"), (lambda: metamer.load_cube(3.5), "path"),
                           (lambda: metamer.compare(by_path, 7), "b"), (lambda: by_path.save(None), "dir"),
                           (lambda: metamer.render(white_quad(), base_dir=1), "base_dir"),
                           (lambda: metamer.compare(by_path, by_path, mask=[1]), "mask"),
                           (lambda: metamer.capture(7, "aps_c_rggb"), "source")]:
        with pytest.raises(TypeError, match=rf"^{argument}: expected a path \(str, bytes or os.PathLike\)"):
            call()
    with pytest.raises(metamer.InputError, match="path: the path holds a NUL byte"):
        metamer.load_cube(str(tmp_path / "x.exr") + "\0.h5")


def test_a_missing_file_is_a_file_not_found_error_with_the_cli_message(tmp_path):
    assert issubclass(metamer.NotFoundError, FileNotFoundError) and issubclass(metamer.NotFoundError, metamer.InputError)
    for call in [lambda: metamer.render(tmp_path / "no-such.json"), lambda: metamer.load_cube(tmp_path / "no.exr"),
                 lambda: metamer.compare(tmp_path / "no.exr", tmp_path / "no.exr")]:
        with pytest.raises(FileNotFoundError, match="not found"):
            call()
    cli = subprocess.run([BINARY, "render", str(tmp_path / "no-such.json"), "--out", str(tmp_path)],
                         capture_output=True, text=True)
    with pytest.raises(metamer.NotFoundError) as e:
        metamer.render(tmp_path / "no-such.json")
    assert cli.returncode == 2 and cli.stderr.strip() == "metamer: " + str(e.value)
    # A folder is there: an InputError, not "not found".
    with pytest.raises(metamer.InputError) as e:
        metamer.load_cube(tmp_path)
    assert not isinstance(e.value, FileNotFoundError)


@pytest.mark.parametrize("name", ["", ".hidden", "..", "../up", "a/b", "/abs", "nul\0byte", "line\nbreak", "x" * 201])
def test_names_that_would_make_hidden_or_outside_files_are_refused(tmp_path, name):
    with pytest.raises(metamer.InputError, match=r"^name: .*expected a file name without its extension"):
        metamer.render(white_quad(), name=name, base_dir=tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_output_names_follow_one_rule_in_the_cli_too(tmp_path):
    ok = metamer.render(white_quad(), name="quad 2 (a)")
    assert [Path(p).name for p in ok.save(tmp_path / "ok")] == ["quad 2 (a).exr"]
    hidden = tmp_path / ".json"
    hidden.write_text(json.dumps(white_quad()))
    cli = subprocess.run([BINARY, "render", str(hidden), "--out", str(tmp_path / "cli")], capture_output=True, text=True)
    assert cli.returncode == 2 and "'.json' starts with '.'" in cli.stderr
    assert not (tmp_path / "cli").exists() or list((tmp_path / "cli").iterdir()) == []
    with pytest.raises(metamer.InputError, match="'.json' starts with '.'"):
        metamer.render(hidden)


def test_hostile_arguments_are_errors_that_name_the_argument():
    r = metamer.render(white_quad())
    for call, kind, argument in [
            (lambda: metamer.render(white_quad(), ssaa="2"), TypeError, "ssaa"),
            (lambda: metamer.render(white_quad(), ssaa=2.0), TypeError, "ssaa"),
            (lambda: metamer.render(white_quad(), ssaa=2**70), metamer.InputError, "ssaa"),
            (lambda: metamer.render(white_quad(), ssaa=-3), metamer.InputError, "ssaa"),
            (lambda: metamer.render(white_quad(), bits=True), TypeError, "bits"),
            (lambda: metamer.render(white_quad(), bits=0), metamer.InputError, "bits"),
            (lambda: metamer.render(white_quad(), backend=3), TypeError, "backend"),
            (lambda: metamer.render(white_quad(), detector=b"cie1931"), TypeError, "detector"),
            (lambda: metamer.render(white_quad(), name=5), TypeError, "name"),
            (lambda: metamer.render(white_quad(), grid=b"400:700:10"), TypeError, "grid"),
            (lambda: metamer.render(white_quad(), grid=""), metamer.InputError, "grid"),
            (lambda: metamer.render(white_quad(), write=b"cube"), TypeError, "write"),
            (lambda: metamer.render(white_quad(), overrides={"camera.width": math.nan}), metamer.InputError,
             r"overrides\.camera\.width"),
            (lambda: metamer.compare(r, r, pixel_threshold="x"), TypeError, "pixel_threshold"),
            (lambda: metamer.compare(r, r, relative_floor=math.nan), metamer.InputError, "relative_floor"),
            (lambda: metamer.capture(r, "aps_c_rggb", seed=-1), metamer.InputError, "seed"),
            (lambda: metamer.capture(r, "aps_c_rggb", frames=1.5), TypeError, "frames"),
            (lambda: metamer.capture(r, "aps_c_rggb", exposure="1"), TypeError, "exposure"),
            (lambda: metamer.capture(r, "aps_c_rggb", exposure=math.inf), metamer.InputError, "exposure")]:
        with pytest.raises(kind, match=rf"^{argument}: "):
            call()
    # numpy integers are integers.
    assert metamer.render(white_quad(), ssaa=np.int64(2)).cube.shape == (6, 8, 89)


def test_scene_dicts_take_numpy_values_and_refuse_what_json_cannot_hold():
    wavelengths = np.arange(300.0, 741.0, 20.0)
    scene = white_quad()
    scene["materials"]["white"]["diffuse"] = {"wavelengths_nm": wavelengths, "values": np.full(len(wavelengths), 0.8,
                                                                                             np.float32)}
    scene["lights"][0]["scale"] = np.float64(2.0)
    scene["camera"]["width"] = np.int32(8)
    np.testing.assert_allclose(metamer.render(scene).cube, 0.8 * 2.0 / math.pi, rtol=1e-6)
    nan = white_quad()
    nan["materials"]["white"]["diffuse"] = {"wavelengths_nm": wavelengths, "values": np.full(len(wavelengths), np.nan)}
    with pytest.raises(metamer.InputError, match=r"^scene\.materials\.white\.diffuse\.values\.0: nan is not a number"):
        metamer.render(nan)
    odd = white_quad()
    odd["materials"]["white"]["diffuse"] = {0.8}
    with pytest.raises(TypeError, match=r"^scene\.materials\.white\.diffuse: a set is not something a scene holds"):
        metamer.render(odd)
    keyed = white_quad()
    keyed["materials"][1] = {"diffuse": 0.5}
    with pytest.raises(TypeError, match=r"^scene\.materials: a key must be a str"):
        metamer.render(keyed)
    looped = white_quad()
    looped["materials"]["white"]["self"] = looped
    with pytest.raises(metamer.InputError, match="nested deeper than 64 levels"):
        metamer.render(looped)


def test_a_render_shows_itself_in_a_notebook_as_its_display_image(tmp_path):
    """Jupyter calls _repr_png_: the PNG it gets, read by OpenImageIO, is the render's display counts."""
    oiio = pytest.importorskip("OpenImageIO")  # Debian's python3-openimageio, through the venv's system site
    r = metamer.render(REPO / "scenes" / "spheres.json", overrides={"camera.width": 48, "camera.height": 48},
                       write="cube,display")
    png = r._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    (tmp_path / "shown.png").write_bytes(png)
    shown = oiio.ImageBuf(str(tmp_path / "shown.png")).get_pixels(oiio.UINT8 if r.display.dtype == np.uint8 else oiio.UINT16)
    assert shown.shape == r.display.shape and np.array_equal(shown, r.display)
    assert len(np.unique(r.display.reshape(-1, 3), axis=0)) > 2  # an image, not a flat colour
    assert metamer.render(white_quad())._repr_png_() is None  # no display kept: the text repr


def test_a_pixel_is_a_colour_science_spectral_distribution():
    r = metamer.render(white_quad(albedo=0.5), grid="400:700:10")
    sd = r.sd(3, 2)
    assert isinstance(sd, colour.SpectralDistribution)
    assert np.array_equal(sd.wavelengths, r.wavelengths_nm) and np.array_equal(sd.values, r.cube[2, 3])
    assert sd.name == "pixel (3, 2)" and r.sd(np.int64(0), 0, name="corner").name == "corner"
    with pytest.raises(IndexError, match="x = 8 is outside the image"):
        r.sd(8, 0)
    with pytest.raises(TypeError, match="integer pixel index"):
        r.sd(1.5, 0)


def test_the_cube_is_an_xarray_data_array_with_its_wavelengths():
    xarray = pytest.importorskip("xarray")
    r = metamer.render(white_quad(albedo=0.5), grid="400:700:10")
    a = r.to_xarray()
    assert isinstance(a, xarray.DataArray) and a.dims == ("y", "x", "wavelength")
    assert np.array_equal(a.wavelength.values, r.wavelengths_nm) and a.wavelength.attrs["units"] == "nm"
    assert a.attrs["units"] == "W sr-1 m-2 nm-1"
    assert float(a.sel(wavelength=550, x=3, y=2)) == float(r.cube[2, 3, list(r.wavelengths_nm).index(550)])


# --- Issue 35: the objects users hold, a typed API, warnings as Python's, numbers as numbers, pickling.

class _Spectrum:
    """A colour-science SpectralDistribution as the package sees it: anything with .wavelengths and .values."""

    def __init__(self, wavelengths, values):
        self.wavelengths, self.values = np.asarray(wavelengths, float), np.asarray(values, float)


def test_a_keyword_typo_names_the_keyword_and_the_nearest_one():
    with pytest.raises(TypeError, match=r"^render\(\) got an unexpected keyword argument 'grids'; did you mean 'grid'\?$"):
        metamer.render(white_quad(), grids="400:700:10")
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'delta'; did you mean 'delta_e'\?"):
        metamer.compare("a.exr", "b.exr", delta=False)


def test_the_api_has_signatures_and_every_public_attribute_a_docstring():
    import inspect

    parameters = inspect.signature(metamer.render).parameters
    assert list(parameters)[:3] == ["scene", "grid", "overrides"] and parameters["half"].default is False
    for keyword in ("half", "compression", "strict_coverage", "readback", "memory_budget"):
        assert keyword in parameters and f"{keyword} (--" in metamer.render.__doc__
    for function in (metamer.render, metamer.compare, metamer.load_cube, metamer.capture):
        assert inspect.signature(function) and len(function.__doc__) > 80 and not function.__doc__.startswith(function.__name__ + "(")
    public = [n for n in dir(metamer.Render) if not n.startswith("_")]
    assert len(public) >= 24
    undocumented = [n for n in public if len((getattr(metamer.Render, n).__doc__ or "").strip()) < 10]
    assert undocumented == []


def test_numpy_numbers_and_spectrum_objects_in_overrides_and_scenes():
    w = np.arange(300.0, 741.0, 20.0)
    scene = white_quad()
    scene["materials"]["white"]["diffuse"] = _Spectrum(w, np.full(w.size, 0.5))
    r = metamer.render(scene, overrides={"lights.0.scale": np.int64(3), "camera.width": np.int32(4),
                                         "lights.0.spectrum": _Spectrum(w, np.full(w.size, 2.0))})
    assert r.cube.shape[1] == 4
    np.testing.assert_allclose(r.cube, 0.5 * 2.0 * 3 / math.pi, rtol=1e-6)
    with pytest.raises(metamer.InputError, match=r"overrides\.lights\.0\.spectrum: a spectrum with \(3, 2\) values"):
        metamer.render(white_quad(), overrides={"lights.0.spectrum": _Spectrum(w[:3], np.ones((3, 2)))})
    # Text where numbers go (issue 51, class 9): an input error naming the key, not numpy's bare ValueError.
    texty = _Spectrum(w, np.full(w.size, 0.5))
    texty.wavelengths = ["400 nm", "500 nm"]
    scene = white_quad()
    scene["materials"]["white"]["diffuse"] = texty
    with pytest.raises(metamer.InputError, match=r"scene\.materials\.white\.diffuse: the spectrum's wavelengths are not numbers"):
        metamer.render(scene)
    texty = _Spectrum(w, np.full(w.size, 0.5))
    texty.values = [object()] * w.size
    with pytest.raises(metamer.InputError, match=r"overrides\.lights\.0\.spectrum: the spectrum's values are not numbers"):
        metamer.render(white_quad(), overrides={"lights.0.spectrum": texty})


def test_grid_takes_a_spectral_shape_or_evenly_spaced_wavelengths():
    shape = colour.SpectralShape(400, 700, 10)
    assert metamer.render(white_quad(), grid=shape).grid == "400:700:10"
    assert metamer.render(white_quad(), grid=np.arange(420.0, 681.0, 20.0)).grid == "420:680:20"
    with pytest.raises(metamer.InputError, match="not evenly spaced"):
        metamer.render(white_quad(), grid=[400, 410, 430])
    with pytest.raises(TypeError, match="SpectralShape"):
        metamer.render(white_quad(), grid=object())


def test_a_detector_object_with_labels_is_a_detector():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ours = metamer.render(white_quad(), grid="380:780:5", detector=cmfs, write="responses")
    builtin = metamer.render(white_quad(), grid="380:780:5", detector="cie1931", write="responses")
    assert ours.response_channels == list(cmfs.labels)
    np.testing.assert_allclose(ours.responses, builtin.responses, rtol=2e-3)


def test_compare_takes_arrays_xarray_and_load_cube_dicts_and_gives_numbers(tmp_path):
    r = metamer.render(white_quad(), grid="400:700:10", format="exr")
    path = r.save(tmp_path)[0]
    for operand in (r.cube.copy(), r.to_xarray(), metamer.load_cube(path)):
        assert metamer.compare(operand, r, wavelengths=r.wavelengths_nm)["max_abs"] == 0
    stats = metamer.compare(r, np.zeros_like(r.cube), wavelengths=np.arange(400.0, 701.0, 10.0))
    assert isinstance(stats["rmse_relative"], float) and stats["rmse_relative"] == math.inf
    with pytest.raises(TypeError, match="an array needs its wavelengths"):
        metamer.compare(r.cube, r)
    with pytest.raises(metamer.InputError, match=r"^b: .*6×8×5 array on the grid 400:700:10 \(31 bands\)"):
        metamer.compare(r, r.cube[..., :5], wavelengths=r.wavelengths_nm)


def test_warnings_turned_into_errors_fail_the_render():
    import warnings

    args = dict(grid="300:740:20", overrides={"camera.width": 8, "camera.height": 8})
    with warnings.catch_warnings():
        warnings.simplefilter("error", metamer.Warning)
        with pytest.raises(metamer.Warning, match=r"materials\.floor\.diffuse"):
            metamer.render(REPO / "scenes" / "spheres.json", **args)
    with pytest.warns(metamer.Warning):  # the filter gone, the same render warns and returns
        assert metamer.render(REPO / "scenes" / "spheres.json", **args).cube is not None


def _render_in_worker(albedo):
    return metamer.render(white_quad(albedo=albedo), write="cube,xyz,display")


def test_renders_pickle_and_come_back_from_a_process_pool(tmp_path):
    import concurrent.futures
    import multiprocessing
    import pickle

    r = metamer.render(white_quad(), write="cube,xyz,display,responses")
    back = pickle.loads(pickle.dumps(r))
    for attribute in ("cube", "xyz", "display", "responses", "wavelengths_nm"):
        assert np.array_equal(getattr(back, attribute), getattr(r, attribute)), attribute
    for attribute in ("grid", "width", "height", "xyz_units", "response_channels", "backend", "display_description",
                      "timings_ms", "validation_errors"):
        assert getattr(back, attribute) == getattr(r, attribute), attribute
    with pytest.raises(metamer.InputError, match="unpickled"):
        back.save(tmp_path)
    # A forged state is refused when unpickled, not read out of bounds later (issue 51, class 9).
    version, fields = r.__getstate__()
    for key, value in (("width", -1), ("height", 0), ("width", 100000), ("bits", 12), ("cube_channels", 0)):
        forged = dict(fields, **{key: value})
        fresh = metamer.Render.__new__(metamer.Render)
        with pytest.raises(metamer.InputError, match="pickle"):
            fresh.__setstate__((version, forged))
    # −1 × −1 is one pixel: arrays of one pixel's size used to make it whole.
    one = dict(fields, width=-1, height=-1, cube=fields["cube"][: 4 * fields["cube_channels"]], counts=b"", xyz=b"",
               responses=b"", edges=b"")
    with pytest.raises(metamer.InputError, match=r"-1×-1 pixels"):
        metamer.Render.__new__(metamer.Render).__setstate__((version, one))
    # spawn: what docs/python.md recommends; the worker imports metamer afresh.
    with concurrent.futures.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        done = pool.submit(_render_in_worker, 0.5).result(timeout=300)
    assert isinstance(done, metamer.Render)
    np.testing.assert_allclose(done.cube, 0.5 * 2.0 / math.pi, rtol=1e-6)


def test_the_cli_render_flags_have_keywords(tmp_path):
    r = metamer.render(white_quad(), half=True, compression="zip", strict_coverage=True, readback="copy")
    written = r.save(tmp_path)
    oiio = pytest.importorskip("OpenImageIO")
    spec = oiio.ImageInput.open(written[0]).spec()
    assert str(spec.format) == "half" and spec.getattribute("compression") == "zip"
    with pytest.raises(metamer.InputError, match="readback"):
        metamer.render(white_quad(), readback="fast")


# --- Issue 35 item 1: renders you can stop and watch.

SPHERES = REPO / "scenes" / "spheres.json"


def test_progress_reaches_a_callable_and_a_tqdm_like_bar_and_strips_give_the_clis_values(tmp_path):
    calls = []
    args = dict(overrides={"camera.width": 640, "camera.height": 480}, grid="400:700:10")
    r = metamer.render(SPHERES, progress=lambda done, total: calls.append((done, total)), **args)
    total = calls[-1][1]
    assert calls[0] == (0, total) and calls[-1] == (total, total) and total >= 2  # 640×480 > 512²: strips
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)

    class Bar:  # what the package uses of a tqdm bar
        def __init__(self):
            self.total, self.n, self.unit = None, 0, "it"

        def reset(self, total=None):
            self.total, self.n = total, 0

        def update(self, n):
            self.n += n

    bar = Bar()
    metamer.render(SPHERES, progress=bar, **args)
    assert bar.total == total and bar.n == total and bar.unit == "strip"
    # The strips hold what the CLI's single frame holds (the CLI has no hook without a terminal) to
    # float rounding — a few edge pixels to 3·10⁻⁴ relative, as strips over the budget
    # (tests/strips_test.cpp); interruptible=False draws the single frame, bit for bit.
    cli = subprocess.run([BINARY, "render", str(SPHERES), "--grid", "400:700:10", "--set", "camera.width=640",
                          "--set", "camera.height=480", "--write", "cube", "--out", str(tmp_path)],
                         capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    whole = metamer.load_cube(tmp_path / "spheres.exr")["cube"]
    relative = np.abs(r.cube - whole) / np.maximum(np.abs(whole), 1e-3)
    assert relative.max() < 1e-3 and (relative.max(axis=2) > 1e-4).sum() < 100
    assert np.array_equal(metamer.render(SPHERES, interruptible=False, **args).cube, whole)
    with pytest.raises(TypeError, match="progress: expected a callable"):
        metamer.render(white_quad(), progress=3)


def test_an_exception_in_the_progress_callback_stops_the_render_and_the_next_one_works():
    def stop(done, total):
        if done >= 1:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="^enough$"):
        metamer.render(SPHERES, overrides={"camera.width": 640, "camera.height": 480}, progress=stop)
    np.testing.assert_allclose(metamer.render(white_quad()).cube, 0.8 * 2.0 / math.pi, rtol=1e-6)


def test_a_render_from_inside_a_progress_callback_is_refused_not_a_deadlock():
    """Issue 51, class 9: the callback runs on the render's thread, which holds the render lock; a
    render started there used to wait for itself. Now it raises, the outer render stops with that
    error, and the next render works."""
    def again(done, total):
        metamer.render(white_quad())

    with pytest.raises(RuntimeError, match="called from inside a render"):
        metamer.render(SPHERES, overrides={"camera.width": 64, "camera.height": 48}, progress=again)
    np.testing.assert_allclose(metamer.render(white_quad()).cube, 0.8 * 2.0 / math.pi, rtol=1e-6)


def _interrupt(tmp_path, script, ready, after_s, skip_why):
    """Runs `script` in a child Python, sends SIGINT `after_s` seconds after it prints `ready`, and
    returns its output's lines (split) and stderr once it has asserted that KeyboardInterrupt came
    within 0.5 s (the child prints "interrupted <time.monotonic()>" when it catches it, "finished"
    when there was nothing left to interrupt: then the test is skipped with `skip_why`)."""
    import signal
    import time

    child = tmp_path / "child.py"
    child.write_text(script)
    p = subprocess.Popen([sys.executable, str(child)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == ready
        time.sleep(after_s)
        sent = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=300)
    finally:
        p.kill()
    lines = [line.split() for line in out.splitlines()]
    if ["finished"] in lines:
        pytest.skip(skip_why)
    interrupted = [line for line in lines if line[:1] == ["interrupted"]]
    assert interrupted, (lines, err)
    latency = float(interrupted[0][1]) - sent
    print(f"Ctrl-C latency {latency * 1e3:.0f} ms")
    assert latency < 0.5, f"KeyboardInterrupt {latency:.2f} s after SIGINT"
    assert p.returncode == 0, (lines, err)
    return lines, err


def test_ctrl_c_stops_a_long_render_within_half_a_second(tmp_path):
    """SIGINT to a process 1.5 s into a render of many strips (a 1024² cube of 31 bands at 4×4
    supersampling, about 5 s on lavapipe), while a strip is being drawn: KeyboardInterrupt comes at the end of that
    strip, and the process renders again after it."""
    lines, err = _interrupt(tmp_path, f"""
import sys, time
import metamer
metamer.render({str(SPHERES)!r}, overrides={{"camera.width": 16, "camera.height": 16}}, write="xyz")  # the device
print("rendering", flush=True)
try:
    metamer.render({str(SPHERES)!r}, overrides={{"camera.width": 1024, "camera.height": 1024}}, ssaa=4,
                   grid="400:700:10")
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
r = metamer.render({str(SPHERES)!r}, overrides={{"camera.width": 16, "camera.height": 16}}, write="xyz")
print("after", r.xyz.shape, flush=True)
""", "rendering", 1.5,
                            "this device renders 1024² at ssaa 4 in under 1.5 s: nothing to interrupt")
    assert ["after", "(16,", "16,", "3)"] in lines, (lines, err)


def test_capture_checks_its_frames_memory_first_and_stops_between_frames_on_ctrl_c(tmp_path):
    """Issue 51, class 9: the frames are made once, straight into the array returned, which must fit
    the quarter of the machine's memory every decoded image is held to (checked before the first
    frame); and Ctrl-C stops a long capture between two frames."""
    big = metamer.render(white_quad(), overrides={"camera.width": 1024, "camera.height": 1024}, grid="400:700:50")
    with pytest.raises(metamer.InputError, match=r"100000 frames of 1024×1024"):  # 195 GiB of uint16
        metamer.capture(big, "aps_c_rggb", frames=100000)
    with pytest.raises(metamer.InputError, match="passes the last frame number"):
        metamer.capture(big, "aps_c_rggb", frame=2**64 - 1, frames=2)
    _interrupt(tmp_path, f"""
import time
import metamer
r = metamer.render({white_quad()!r}, overrides={{"camera.width": 64, "camera.height": 64}}, grid="400:700:50")
metamer.capture(r, "aps_c_rggb", frames=2)
print("capturing", flush=True)
try:
    metamer.capture(r, "aps_c_rggb", frames=100000)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
""", "capturing", 1.0, "100 000 frames of 64² in under a second: nothing to interrupt")
