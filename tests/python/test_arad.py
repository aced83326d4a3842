"""The ARAD / NTIRE layout (issue 49, item 4): `--format arad` writes a MATLAB v7.3 MAT-file that the
challenge's readers open — h5py (the HDF5 inside, MATLAB's array order) and the mat73 package (MATLAB's
own view: cube rows × columns × 31) — with cube · norm_factor the render's radiance at 400, 410, …,
700 nm. Run by CTest (tests/CMakeLists.txt, test `python_arad`)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
BINARY = os.environ.get("METAMER_BINARY", str(REPO / "build" / "metamer"))


def render(tmp_path, *args):
    p = subprocess.run([BINARY, "render", str(REPO / "scenes" / "colorchecker.json"), "--out", str(tmp_path),
                        "--set", "camera.width=120", "--set", "camera.height=80", "--write", "cube", *args],
                       capture_output=True, text=True)
    return p


def test_h5py_and_mat73_read_the_cube_bands_and_norm_factor(tmp_path):
    import h5py
    import mat73

    import metamer
    p = render(tmp_path, "--format", "exr,arad")
    assert p.returncode == 0, p.stderr
    mat = tmp_path / "colorchecker.mat"
    head = mat.read_bytes()[:128]
    assert head.startswith(b"MATLAB 7.3 MAT-file") and head[124:128] == b"\x00\x02IM"
    with h5py.File(mat, "r") as f:                      # HDF5's order: MATLAB's reversed
        assert f["cube"].shape == (31, 120, 80) and f["cube"].dtype == np.float32
        assert f["cube"].attrs["MATLAB_class"] == b"single"
        assert f["bands"].shape == (31, 1) and f["bands"].attrs["MATLAB_class"] == b"double"
        assert f["norm_factor"].shape == (1, 1)
        via_h5py = np.transpose(f["cube"][()], (2, 1, 0))
    m = mat73.loadmat(str(mat))                          # MATLAB's view
    cube, bands, norm = m["cube"], np.ravel(m["bands"]), float(m["norm_factor"])
    assert cube.shape == (80, 120, 31) and cube.dtype == np.float32
    np.testing.assert_array_equal(cube, via_h5py)
    np.testing.assert_array_equal(bands, np.arange(400.0, 701.0, 10.0))
    assert cube.max() == pytest.approx(1.0, abs=1e-7) and cube.min() >= 0
    # The render's grid (380:780:5) holds every ARAD centre: its bands, scaled back, are the cube's.
    exr = metamer.load_cube(tmp_path / "colorchecker.exr")
    nm = list(np.asarray(exr["wavelengths_nm"]))
    radiance = np.asarray(exr["cube"])[..., [nm.index(w) for w in bands]]
    np.testing.assert_allclose(cube * norm, radiance, rtol=2e-7, atol=1e-12)


def test_a_grid_that_misses_400_to_700_nm_is_refused_naming_the_format(tmp_path):
    p = render(tmp_path, "--format", "arad", "--grid", "420:720:10")
    assert p.returncode == 2 and "--format" in p.stderr and "400–700 nm" in p.stderr, p.stderr
    assert not list(tmp_path.glob("*.mat"))


def test_a_coarser_render_grid_is_averaged_onto_the_arad_bands(tmp_path):
    """A 20 nm render: the 10 nm bands between its centres are its interpolant (the engine's one rule)."""
    import mat73
    p = render(tmp_path, "--format", "exr,arad", "--grid", "400:700:20")
    assert p.returncode == 0, p.stderr
    m = mat73.loadmat(str(tmp_path / "colorchecker.mat"))
    import metamer
    exr = np.asarray(metamer.load_cube(tmp_path / "colorchecker.exr")["cube"])
    arad = m["cube"] * float(m["norm_factor"])
    np.testing.assert_allclose(arad[..., 0::2], exr, rtol=2e-7, atol=1e-12)            # 400, 420, …: its bands
    np.testing.assert_allclose(arad[..., 1], (exr[..., 0] + exr[..., 1]) / 2, rtol=1e-6, atol=1e-12)  # 410: midway
