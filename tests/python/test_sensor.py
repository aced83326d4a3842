"""The simulated sensor (issue 29; docs/sensor.md) end to end through `metamer capture`, against
oracles written here: numpy's own camera equation on the rendered cube (noise off: the raw is
round(K·μe) + black, exactly), colour-demosaicing's Bayer mosaic, and the files' determinism.
Run by CTest (tests/CMakeLists.txt, test `python_sensor`). The noise statistics themselves (Poisson
flat fields, photon transfer, χ²) are tested in engine/sensor/*_test.cpp and
tests/python/check_counter_rng.py.
"""

from __future__ import annotations

import json
import os
import subprocess
import warnings
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest

warnings.filterwarnings("ignore")

REPO = Path(__file__).resolve().parents[2]
BINARY = os.environ.get("METAMER_BINARY", str(REPO / "build" / "metamer"))
SENSOR = REPO / "spectra" / "sensors" / "aps_c_rggb.json"
H, C = 6.62607015e-34, 299792458.0


def run(*args):
    p = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return p.stdout


def read(path, dtype=oiio.FLOAT):
    buf = oiio.ImageBuf(str(path))
    return buf.get_pixels(dtype)


@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    out = tmp_path_factory.mktemp("sensor")
    run("render", REPO / "scenes" / "metamers.json", "--out", out, "--write", "cube",
        "--set", "camera.width=64", "--set", "camera.height=32")
    return out / "metamers.exr"


def expected_electrons(cube_path, sensor, exposure):
    """The camera equation in numpy: μe = t·A·π·T/(1 + 4N²)·Σ QE_c(λ)·λ/(hc)·Δλ·L(λ) (EMVA 1288 and ISETCam's
    form at magnification 0), the CFA's channel per pixel; A the whole pixel (the QE includes the fill factor)."""
    buf = oiio.ImageBuf(str(cube_path))
    spec = buf.spec()
    names = [spec.channelnames[i] for i in range(spec.nchannels)]
    nm = np.array([float(n.split(".", 1)[1][:-2].replace(",", ".")) for n in names])  # S0.380,000000nm
    L = buf.get_pixels(oiio.FLOAT).astype(np.float64)          # rows × columns × bands
    table = np.loadtxt(REPO / "spectra" / (sensor["quantum_efficiency"]["table"] + ".csv"), delimiter=",", skiprows=1)
    qe = np.stack([np.interp(nm, table[:, 0], table[:, c], left=0, right=0) for c in (1, 2, 3)])
    qe *= sensor["quantum_efficiency"]["peak"] / table[:, 1:].max()
    optics = sensor["optics"]
    area = (sensor["pixel"]["pitch_um"] * 1e-6) ** 2
    step = nm[1] - nm[0]
    w = area * np.pi * optics["transmittance"] / (1 + 4 * optics["f_number"] ** 2) * qe * (nm * 1e-9) / (H * C) * step
    rate = np.einsum("yxb,cb->yxc", L, w)                       # every channel at every pixel
    rows, cols = np.indices(rate.shape[:2])
    channel = np.array([[0, 1], [1, 2]])[rows % 2, cols % 2]    # RGGB
    signal = np.take_along_axis(rate, channel[..., None], axis=2)[..., 0]
    return exposure * (signal + sensor["dark_current_e_per_s"]), signal


def perfect_lens(folder):
    """The bundled sensor without its lens's blur (a perfect lens: the camera equation alone, pixel by
    pixel; the lens, which darkens a frame's borders, is tested in test_isp.py and lens_test.cpp)."""
    sensor = json.loads(SENSOR.read_text())
    del sensor["optics"]["lens"]
    (folder / "perfect_lens.json").write_text(json.dumps(sensor))
    return folder / "perfect_lens.json", sensor


def test_without_noise_the_raw_is_the_rounded_camera_equation(cube, tmp_path):
    path, sensor = perfect_lens(tmp_path)
    run("capture", cube, "--sensor", path, "--out", tmp_path, "--no-noise")
    meta = json.loads((tmp_path / "metamers.raw.json").read_text())
    raw = read(tmp_path / "metamers.raw.png", oiio.UINT16)[..., 0].astype(np.int64)
    mu, signal = expected_electrons(cube, sensor, meta["exposure_s"])
    # Auto-exposure: the 99th-percentile (nearest rank) signal reaches 0.7 of the full well.
    ranked = np.sort(signal.ravel())
    p99 = ranked[int(np.ceil(0.99 * ranked.size)) - 1]
    assert meta["exposure_s"] * p99 == pytest.approx(0.7 * sensor["full_well_e"], rel=1e-9)
    want = np.clip(np.rint(sensor["conversion_gain_dn_per_e"] * np.minimum(mu, sensor["full_well_e"]))
                   + sensor["black_level_dn"], 0, 2 ** sensor["adc_bits"] - 1)
    assert np.abs(raw - want).max() <= 1
    assert np.mean(raw == want) > 0.999
    truth = read(tmp_path / "metamers.electrons.exr")[..., 0]
    assert np.allclose(truth, mu, rtol=1e-6)


def test_a_flat_field_mosaic_is_colour_demosaicings_bayer_mosaic(tmp_path):
    from colour_demosaicing import mosaicing_CFA_Bayer
    scene = {"grid": {"start_nm": 380, "end_nm": 780, "step_nm": 5},
             "camera": {"projection": "orthographic", "position": [0, 0, 1], "target": [0, 0, 0],
                        "height_m": 1, "width": 16, "height": 12},
             "lights": [{"type": "ambient", "spectrum": "illuminants/D65", "scale": 0.05}],
             "materials": {"chart": {"diffuse": "colorchecker/orange"}},
             "objects": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [4, 4], "material": "chart"}]}
    (tmp_path / "flat.json").write_text(json.dumps(scene))
    run("render", tmp_path / "flat.json", "--out", tmp_path, "--write", "cube")
    run("capture", tmp_path / "flat.exr", "--sensor", perfect_lens(tmp_path)[0], "--out", tmp_path, "--no-noise")
    raw = read(tmp_path / "flat.raw.png", oiio.UINT16)[..., 0].astype(np.float64)
    rgb = np.empty(raw.shape + (3,))
    rgb[..., 0], rgb[..., 1], rgb[..., 2] = raw[0, 0], raw[0, 1], raw[1, 1]
    assert raw[0, 0] != raw[0, 1] != raw[1, 1]
    np.testing.assert_array_equal(mosaicing_CFA_Bayer(rgb, pattern="RGGB"), raw)


def test_frames_are_reproducible_and_differ_only_by_seed_and_frame(cube, tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    run("capture", cube, "--sensor", SENSOR, "--out", a, "--seed", 7, "--frames", 2)
    run("capture", cube, "--sensor", SENSOR, "--out", b, "--seed", 7, "--frame", 1)
    f0, f1 = (read(a / f"metamers.raw.{i}.png", oiio.UINT16) for i in (0, 1))
    again = read(b / "metamers.raw.png", oiio.UINT16)
    np.testing.assert_array_equal(f1, again)          # frame 1 alone = frame 1 of a run of two
    assert (f0 != f1).mean() > 0.5                    # another frame: other noise
    meta = json.loads((a / "metamers.raw.1.json").read_text())
    assert (meta["seed"], meta["frame"], meta["white_level_dn"], meta["cfa"]) == (7, 1, 16383, [["r", "g"], ["g", "b"]])


def test_the_worked_example_measures_the_camera_mismatch_within_its_noise():
    import importlib.util
    spec = importlib.util.spec_from_file_location("sensor_metamers", REPO / "docs" / "examples" / "sensor_metamers.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    rows = example.analyse("illuminants/D65")
    assert len(rows) == 9
    for r in rows:
        # The patch means' difference is the true Δ within 5 standard errors (n = 1600 per patch;
        # demosaicing correlates neighbours, so σ·√(2/n) is a lower bound: allow 5× that, and 2×).
        assert abs(r["measured_delta_e"] - r["delta_e"]) < 10 * r["sigma_e"] * np.sqrt(2 / 1600), r
    full = [r for r in rows if r["fraction"] == 1]
    dim = [r for r in rows if r["fraction"] == 1 / 1024]
    assert all(r["snr_pixel"] > 5 for r in full)     # the camera sees the pair differ, pixel by pixel
    assert all(r["snr_pixel"] < 1 for r in dim)      # at 1/1024 of the exposure, noise hides it per pixel
    assert all(r["snr_patch"] > 3 for r in dim)      # but 1600-pixel means still resolve it


def test_the_python_module_returns_the_same_arrays_as_the_files(cube, tmp_path):
    import metamer
    run("capture", cube, "--sensor", SENSOR, "--out", tmp_path, "--seed", 4, "--frame", 2)
    from_files = read(tmp_path / "metamers.raw.png", oiio.UINT16)[..., 0]
    c = metamer.capture(cube, str(SENSOR), seed=4, frame=2)
    np.testing.assert_array_equal(c["raw"], from_files)
    truth = read(tmp_path / "metamers.electrons.exr")[..., 0]
    np.testing.assert_allclose(c["electrons"], truth, rtol=1e-7)   # the file holds float32
    assert c["cfa"] == [["r", "g"], ["g", "b"]] and c["white_level_dn"] == 16383
    # A Render's cube, several frames: frame 2 of a run from 0 is the frame above.
    r = metamer.render(str(REPO / "scenes" / "metamers.json"), write="cube",
                       overrides={"camera.width": 64, "camera.height": 32})
    frames = metamer.capture(r, "aps_c_rggb", seed=4, frames=3)
    assert frames["raw"].shape == (3, 32, 64)
    np.testing.assert_array_equal(frames["raw"][2], from_files)
    with pytest.raises(metamer.InputError, match="library sensor"):
        metamer.capture(r, "no_such_sensor")


def test_the_dng_reads_back_through_rawpy_with_its_pattern_levels_and_colour(cube, tmp_path):
    import rawpy
    run("capture", cube, "--sensor", SENSOR, "--out", tmp_path, "--seed", 9)
    meta = json.loads((tmp_path / "metamers.raw.json").read_text())
    png = read(tmp_path / "metamers.raw.png", oiio.UINT16)[..., 0]
    with rawpy.imread(str(tmp_path / meta["dng"])) as r:
        np.testing.assert_array_equal(r.raw_image_visible, png)         # the same digital numbers
        assert r.color_desc == b"RGBG" and r.raw_pattern.tolist() == [[0, 1], [3, 2]]   # RGGB
        assert list(r.black_level_per_channel) == [0, 0, 0, 0] and r.white_level == 16383
        # LibRaw's white balance multipliers are the inverse of the as-shot neutral, green = 1.
        n = np.array(meta["as_shot_neutral"])
        np.testing.assert_allclose(np.array(r.camera_whitebalance[:3]), n[1] / n, rtol=1e-6)
        developed = r.postprocess(use_camera_wb=True, no_auto_bright=True, output_bps=16)
        assert developed.shape == (32, 64, 3)
    # The colour matrix maps the D65 white to the neutral.
    m = np.array(meta["xyz_to_camera_d65"]).reshape(3, 3)
    d65_white = np.array([0.95047, 1.0, 1.08883])
    np.testing.assert_allclose(m @ d65_white, n, atol=2e-3)
    assert meta["characterization_rms_delta_e2000"] < 5


def test_render_with_a_sensor_captures_its_cube_as_capture_does(tmp_path):
    args = ["--set", "camera.width=64", "--set", "camera.height=32"]
    run("render", REPO / "scenes" / "metamers.json", "--out", tmp_path / "one", "--write", "png",
        "--sensor", "aps_c_rggb", "--seed", 5, *args)
    assert (tmp_path / "one" / "metamers.exr").exists()            # the cube is written for the capture
    run("capture", tmp_path / "one" / "metamers.exr", "--sensor", "aps_c_rggb", "--seed", 5, "--out", tmp_path / "two")
    np.testing.assert_array_equal(read(tmp_path / "one" / "metamers.raw.png", oiio.UINT16),
                                  read(tmp_path / "two" / "metamers.raw.png", oiio.UINT16))
    p = subprocess.run([BINARY, "render", REPO / "scenes" / "metamers.json", "--out", tmp_path / "x", "--seed", "5"],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "--seed: goes with --sensor" in p.stderr


def files_in(folder):
    """Every entry, hidden ones included, with its bytes (None for a folder)."""
    return {p.name: (p.read_bytes() if p.is_file() else None) for p in sorted(Path(folder).iterdir())}


def test_a_render_whose_capture_fails_puts_none_of_its_files_in_place(tmp_path):
    """Issue 51, class 4: the capture runs on the cube before anything is renamed into place, so an
    unlit scene's auto-exposure failure leaves the previous run's files byte-identical."""
    scene = REPO / "tests" / "data" / "cli" / "small.json"
    run("render", scene, "--out", tmp_path, "--sensor", "aps_c_rggb", "--seed", 3)
    before = files_in(tmp_path)
    assert set(before) == {"small.exr", "small.png", "small.raw.png", "small.raw.dng", "small.raw.json",
                           "small.raw.srgb.png", "small.electrons.exr"}
    unlit = [a for i in range(3) for a in ("--set", f"lights.{i}.scale=0")]
    p = subprocess.run([BINARY, "render", scene, "--out", tmp_path, "--sensor", "aps_c_rggb", *unlit],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "auto-exposure needs light" in p.stderr, p.stderr
    assert "wrote" not in p.stdout
    assert files_in(tmp_path) == before                      # no new cube, no temporary, no staging folder


def test_a_capture_that_fails_at_a_later_frame_writes_no_frame(cube, tmp_path):
    """Every frame is staged, then all are put in place together: a frame that cannot be written
    (a folder where its metadata goes) leaves nothing of the frames before it, nor the electrons."""
    (tmp_path / "metamers.raw.2.json").mkdir()
    p = subprocess.run([BINARY, "capture", cube, "--sensor", SENSOR, "--out", tmp_path, "--frames", "4"],
                       capture_output=True, text=True)
    assert p.returncode == 1 and "metamers.raw.2.json': it is a folder" in p.stderr, p.stderr
    assert p.stdout == ""
    assert files_in(tmp_path) == {"metamers.raw.2.json": None}
    run("capture", cube, "--sensor", SENSOR, "--out", tmp_path / "ok", "--frames", "4")
    assert sorted(files_in(tmp_path / "ok")) == sorted(
        ["metamers.electrons.exr"] + [f"metamers.raw.{f}.{e}" for f in range(4) for e in ("png", "dng", "json", "srgb.png")])


def test_a_monochrome_sensors_frames_are_linear_raw_dngs_rawpy_reads(cube, tmp_path):
    """Issue 48, item 4: a monochrome sensor writes DNG too — LinearRaw, one sample per pixel."""
    import rawpy
    run("capture", cube, "--sensor", "mono_silicon", "--out", tmp_path, "--seed", 2)
    meta = json.loads((tmp_path / "metamers.raw.json").read_text())
    assert meta["dng"] == "metamers.raw.dng"
    png = read(tmp_path / "metamers.raw.png", oiio.UINT16)[..., 0]
    with rawpy.imread(str(tmp_path / "metamers.raw.dng")) as r:
        np.testing.assert_array_equal(r.raw_image_visible.reshape(png.shape), png)
        assert r.num_colors == 1 or r.raw_colors_visible.max() == 0
        assert r.white_level == 2 ** meta["adc_bits"] - 1


def test_python_capture_writes_the_clis_files_byte_for_byte(cube, tmp_path):
    """Issue 48, item 4: metamer.capture(..., out=FOLDER) writes what `metamer capture` does, DNG included."""
    import metamer
    run("capture", cube, "--sensor", SENSOR, "--out", tmp_path / "cli", "--seed", 6, "--frames", 2)
    c = metamer.capture(cube, str(SENSOR), seed=6, frames=2, out=tmp_path / "py")
    names = sorted(Path(f).name for f in c["files"])
    assert names == sorted(p.name for p in (tmp_path / "cli").iterdir())
    for name in names:
        if name.endswith(".json"):
            a, b = (json.loads((tmp_path / d / name).read_text()) for d in ("cli", "py"))
            assert a == b, name
        else:
            assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name
    np.testing.assert_array_equal(c["raw"][1], read(tmp_path / "py" / "metamers.raw.1.png", oiio.UINT16)[..., 0])


def test_capture_names_the_scenes_light_for_the_processor_and_the_dng(cube, tmp_path):
    """--illuminant (Python: illuminant=) replaces the sensor file's processor.illuminant: the frame is
    balanced for it, and its DNG's AsShotNeutral is the camera's response to it (tungsten: little blue)."""
    import metamer
    run("capture", cube, "--sensor", SENSOR, "--out", tmp_path, "--no-noise", "--illuminant", "illuminants/A")
    meta = json.loads((tmp_path / "metamers.raw.json").read_text())
    assert meta["processor"]["illuminant"] == "illuminants/A"
    neutral = np.array(meta["as_shot_neutral"])
    assert neutral.max() == 1.0 and neutral[2] < 0.6
    m = np.array(meta["xyz_to_camera_d65"]).reshape(3, 3)
    np.testing.assert_allclose(m @ np.array([0.95047, 1.0, 1.08883]), neutral, atol=1e-9)
    p = subprocess.run([BINARY, "capture", cube, "--sensor", SENSOR, "--out", tmp_path / "x", "--illuminant",
                        "illuminants/AA"], capture_output=True, text=True)
    assert p.returncode == 2 and "--illuminant" in p.stderr and "illuminants/A" in p.stderr, p.stderr
    with pytest.raises(metamer.InputError, match="illuminant"):
        metamer.capture(str(cube), str(SENSOR), illuminant="illuminants/AA")
    files = metamer.capture(str(cube), str(SENSOR), noise=False, illuminant="illuminants/A", out=tmp_path / "py")
    assert json.loads((tmp_path / "py" / "metamers.raw.json").read_text())["as_shot_neutral"] == meta["as_shot_neutral"]
    assert files["raw"].shape == (32, 64)
