"""The image processor and the camera's metrics (issue 48) against independent implementations:
metamer.demosaic against colour-demosaicing's bilinear and Malvar (2004) demosaicing,
metamer.slanted_edge_sfr on an edge whose MTF numpy computes in closed form, a capture's developed
image against LibRaw's development of its DNG, and the developed ColorChecker's ΔE00 by colour-science.
Run by CTest (tests/CMakeLists.txt, test `python_isp`)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

warnings.filterwarnings("ignore")


@pytest.mark.parametrize("pattern", ["RGGB", "BGGR", "GRBG", "GBRG"])
def test_demosaicing_equals_colour_demosaicings(pattern):
    import metamer
    from colour_demosaicing import demosaicing_CFA_Bayer_bilinear, demosaicing_CFA_Bayer_Malvar2004
    rng = np.random.default_rng(7)
    mosaic = rng.random((37, 52))   # odd and even sizes: the mirrored borders of both phases
    for method, oracle in (("bilinear", demosaicing_CFA_Bayer_bilinear), ("malvar2004", demosaicing_CFA_Bayer_Malvar2004)):
        ours = metamer.demosaic(mosaic, cfa=pattern, method=method)
        theirs = oracle(mosaic, pattern)
        assert ours.shape == (37, 52, 3)
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12, err_msg=f"{method} {pattern}")


def test_demosaicing_names_its_mistakes():
    import metamer
    with pytest.raises(metamer.InputError, match="cfa: 'RGBG' is not a Bayer pattern"):
        metamer.demosaic(np.zeros((4, 4)), cfa="RGBG")
    with pytest.raises(metamer.InputError, match="method: 'ahd' is not a demosaicing method"):
        metamer.demosaic(np.zeros((4, 4)), method="ahd")
    with pytest.raises(metamer.InputError, match="mosaic: expected a C-ordered float64 array of rows × columns"):
        metamer.demosaic(np.zeros((4, 4, 3)))


def test_the_sfr_of_a_blurred_edge_is_its_gaussian_mtf():
    """A 4° edge blurred by a Gaussian of σ = 1 pixel, each pixel the exact mean of the blurred
    edge over its area (numpy and scipy's erf): MTF = exp(−2π²σ²f²)·sinc(f), to 0.02."""
    import metamer
    from scipy.special import erf
    sigma, angle = 1.0, np.radians(4.0)
    h, w, n = 96, 64, 16
    sub = (np.arange(n) + 0.5) / n
    y, x = np.mgrid[0:h, 0:w]
    xs = x[..., None, None] + sub[None, None, None, :]
    ys = y[..., None, None] + sub[None, None, :, None]
    distance = (xs - (w / 2 + np.tan(angle) * (ys - h / 2))) * np.cos(angle)
    image = (0.5 * (1 + erf(distance / (np.sqrt(2) * sigma)))).mean(axis=(2, 3))
    sfr = metamer.slanted_edge_sfr(image)
    assert sfr["angle_deg"] == pytest.approx(4.0, abs=0.05)
    f = sfr["frequency"]
    keep = f <= 0.5
    box = np.sinc(f * np.cos(angle)) * np.sinc(f * np.sin(angle))
    want = np.exp(-2 * np.pi ** 2 * sigma ** 2 * f ** 2) * box
    np.testing.assert_allclose(sfr["mtf"][keep], want[keep], atol=0.02)
    # MTF50 where the closed form falls to 0.5.
    fine = np.linspace(0, 0.5, 5001)
    closed = np.exp(-2 * np.pi ** 2 * sigma ** 2 * fine ** 2) * np.sinc(fine * np.cos(angle)) * np.sinc(fine * np.sin(angle))
    assert sfr["mtf50"] == pytest.approx(fine[np.argmax(closed <= 0.5)], abs=0.005)


@pytest.mark.parametrize("form,degree", [("linear", 1), ("root-polynomial", 2)])
def test_the_colour_correction_equals_colour_sciences_finlayson_fit(form, degree):
    import metamer
    from colour.characterisation import matrix_colour_correction_Finlayson2015
    rng = np.random.default_rng(3)
    rgb = rng.random((24, 3))
    xyz = rgb @ np.array([[0.6, 0.2, 0.1], [0.3, 0.7, 0.1], [0.05, 0.1, 0.9]]).T + 0.02 * rng.random((24, 3))
    ours = metamer.fit_colour_correction(rgb, xyz, form=form)
    theirs = matrix_colour_correction_Finlayson2015(rgb, xyz, degree=degree, root_polynomial_expansion=True)
    assert ours.shape == theirs.shape == (3, 3 if degree == 1 else 6)
    np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-12)
    with pytest.raises(metamer.InputError, match="form: 'cubic' is not a colour correction"):
        metamer.fit_colour_correction(rgb, xyz, form="cubic")


def test_the_bundled_slanted_edge_through_a_lens_measures_the_lenss_mtf(tmp_path):
    """End to end (issue 48): scenes/slanted-edge.json rendered, captured without noise by a
    monochrome sensor behind an f/16 lens (diffraction and the pixel aperture), and measured by
    metamer.slanted_edge_sfr on the electrons. The expected MTF along the edge's normal: the
    per-band diffraction OTFs averaged with the channel's weights QE·E·λ (the image is their sum),
    times the lens model's pixel square and the pixel aperture (sinc(f cos θ)·sinc(f sin θ) each)
    and the point-sampled edge's 1/4-pixel bins (sinc(f/4))."""
    import json
    import subprocess

    import metamer
    import OpenImageIO as oiio
    from pathlib import Path
    repo = Path(__file__).resolve().parents[2]
    binary = __import__("os").environ.get("METAMER_BINARY", str(repo / "build" / "metamer"))
    sensor = json.loads((repo / "spectra" / "sensors" / "mono_silicon.json").read_text())
    sensor["optics"] = {"f_number": 16, "transmittance": 1.0, "lens": {}}
    sensor["pixel"] = {"pitch_um": 5.0, "fill_factor": 1.0}
    (tmp_path / "lens.json").write_text(json.dumps(sensor))
    p = subprocess.run([binary, "render", str(repo / "scenes" / "slanted-edge.json"), "--out", str(tmp_path),
                        "--write", "cube"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    p = subprocess.run([binary, "capture", str(tmp_path / "slanted-edge.exr"), "--sensor", str(tmp_path / "lens.json"),
                        "--out", str(tmp_path), "--no-noise"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    electrons = oiio.ImageBuf(str(tmp_path / "slanted-edge.electrons.exr")).get_pixels(oiio.FLOAT)[..., 0]
    region = electrons[64:192, 48:144].astype(np.float64)   # the middle: the frame's edges stay out
    sfr = metamer.slanted_edge_sfr(region)
    angle = np.radians(sfr["angle_deg"])
    assert sfr["angle_deg"] == pytest.approx(5.0, abs=0.1)
    # The channel's weight per band: QE(λ)·E(λ)·λ on the render's grid (both sides of the edge are
    # grey, so the reflectance factors out).
    nm = np.arange(380.0, 781.0, 5.0)
    qe = np.loadtxt(repo / "spectra" / "sensors" / "silicon_qe.csv", delimiter=",", skiprows=1)
    d65 = np.loadtxt(repo / "spectra" / "illuminants" / "D65.csv", delimiter=",", skiprows=1)
    weight = np.interp(nm, qe[:, 0], qe[:, 1]) * np.interp(nm, d65[:, 0], d65[:, 1]) * nm
    f = sfr["frequency"]
    nu = f[:, None] / (1.0 / (nm[None, :] * 1e-6 * 16) * 0.005)       # f·λ·N in cycles per pixel
    otf = np.where(nu < 1, 2 / np.pi * (np.arccos(np.minimum(nu, 1)) - nu * np.sqrt(np.maximum(1 - nu ** 2, 0))), 0)
    box = np.sinc(f * np.cos(angle)) * np.sinc(f * np.sin(angle))
    want = (otf @ weight) / weight.sum() * box * box * np.sinc(f / 4)
    keep = f <= 0.5
    print(f"slanted edge end to end: worst |MTF − expected| {np.abs(sfr['mtf'][keep] - want[keep]).max():.4f}, MTF50 {sfr['mtf50']:.4f}")
    np.testing.assert_allclose(sfr["mtf"][keep], want[keep], atol=0.03)


# --- The image processor on a capture of the bundled ColorChecker (issue 48, items 2 and 3) ------

REPO = __import__("pathlib").Path(__file__).resolve().parents[2]


def _binary():
    import os
    return os.environ.get("METAMER_BINARY", str(REPO / "build" / "metamer"))


def _run(*args):
    import subprocess
    p = subprocess.run([_binary(), *map(str, args)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return p


def _colorchecker(tmp_path, light, scale=0.01):
    """scenes/colorchecker.json at 300 × 200 (1 mm per pixel: 40-pixel patches on a 45-pixel pitch)
    under `light`, its spectral cube written."""
    _run("render", REPO / "scenes" / "colorchecker.json", "--out", tmp_path, "--write", "cube",
         "--set", "camera.width=300", "--set", "camera.height=200",
         "--set", f"lights.0.spectrum={light}", "--set", f"lights.0.scale={scale}")
    return tmp_path / "colorchecker.exr"


def _patch_means(image, half=12):
    """The mean of each of the 24 patches' middles, in chart order (row by row)."""
    out = []
    for j in range(4):
        for i in range(6):
            cx, cy = int(150 + (i - 2.5) * 45), int(100 + (j - 1.5) * 45)
            out.append(image[cy - half:cy + half, cx - half:cx + half].reshape(-1, image.shape[-1]).mean(0))
    return np.array(out)


def _sensor(tmp_path, processor, name="sensor.json", **changes):
    import json
    s = json.loads((REPO / "spectra" / "sensors" / "aps_c_rggb.json").read_text())
    s["processor"] = processor
    s.update(changes)
    path = tmp_path / name
    path.write_text(json.dumps(s))
    return path


@pytest.mark.parametrize("white_balance", ["illuminant", "grey-world"])
def test_libraw_develops_metamers_dng_to_the_processors_image(tmp_path, white_balance):
    """The DNG's ColorMatrix1 and AsShotNeutral are the processor's own: LibRaw (rawpy), which builds its
    camera → sRGB matrix from them, develops a noisy capture under illuminant A — demosaicing bilinearly
    as the processor is told to, sRGB's curve, no auto-brightening — to the processor's 8-bit image,
    every pixel within rounding but the outermost ring."""
    import json

    import OpenImageIO as oiio
    import rawpy
    cube = _colorchecker(tmp_path, "illuminants/A")
    sensor = _sensor(tmp_path, {"illuminant": "illuminants/A", "demosaic": "bilinear", "white_balance": white_balance})
    _run("capture", cube, "--sensor", sensor, "--out", tmp_path / "cap", "--seed", 4)
    meta = json.loads((tmp_path / "cap" / "colorchecker.raw.json").read_text())
    ours = oiio.ImageBuf(str(tmp_path / "cap" / meta["developed"])).get_pixels(oiio.UINT8).astype(float)
    with rawpy.imread(str(tmp_path / "cap" / meta["dng"])) as r:
        theirs = r.postprocess(use_camera_wb=True, no_auto_bright=True, output_bps=16, gamma=(2.4, 12.92),
                               output_color=rawpy.ColorSpace.sRGB, adjust_maximum_thr=0.0, bright=1.0,
                               demosaic_algorithm=rawpy.DemosaicAlgorithm.LINEAR, user_flip=0,
                               highlight_mode=rawpy.HighlightMode.Clip).astype(float) / 257.0
    diff = np.abs(ours - theirs)
    # LibRaw fills the outermost ring of pixels by its own rule (border_interpolate); the processor
    # mirrors the mosaic in the CFA's phase there.
    diff = diff[1:-1, 1:-1]
    print(f"LibRaw vs the processor ({white_balance}): 8-bit |Δ| median {np.median(diff):.3f}, max {diff.max():.3f}")
    assert diff.max() <= 1.0      # LibRaw rounds to 16 bits at each step, the processor once to 8


def _reference_xyz(cube_path, light, scale):
    """CIE 1931 XYZ of the cube's patches by colour-science, relative to a perfect white diffuser under
    the library's light (its radiance E·scale/π), adapted to D65 by Bradford."""
    import colour

    import metamer
    c = metamer.load_cube(cube_path)
    nm = np.asarray(c["wavelengths_nm"])
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(colour.SpectralShape(nm[0], nm[-1], nm[1] - nm[0]))
    xyz = np.asarray(c["cube"]) @ cmfs.values
    table = np.loadtxt(REPO / "spectra" / "illuminants" / f"{light}.csv", delimiter=",", skiprows=1)
    illuminant = np.interp(nm, table[:, 0], table[:, 1]) * scale / np.pi   # the scene's light, as the render read it
    white = illuminant @ cmfs.values
    xyz, white = xyz / white[1], white / white[1]
    d65 = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"])
    return colour.adaptation.chromatic_adaptation_VonKries(_patch_means(xyz), white, d65, transform="Bradford"), d65


def _developed_delta_e(developed, reference, d65):
    import colour
    rgb = _patch_means(developed["linear_rgb"])
    xyz = colour.RGB_to_XYZ(rgb, colour.RGB_COLOURSPACES["sRGB"], apply_cctf_decoding=False)
    xyz *= reference[18, 1] / xyz[18, 1]   # the exposure: the white patch's luminance factor as the render's
    return colour.delta_E(colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(d65)), colour.XYZ_to_Lab(reference, colour.XYZ_to_xy(d65)),
                          method="CIE 2000")


@pytest.mark.parametrize("light,form", [("A", "linear"), ("D65", "linear"), ("A", "root-polynomial")])
def test_delta_e_per_patch_after_the_processor_is_the_fits_as_colour_science_measures_it(tmp_path, light, form):
    """ΔE00 per ColorChecker patch after the processor, measured on a noise-free capture by colour-science
    (the developed linear sRGB → XYZ against the cube's own XYZ, adapted to D65 by Bradford), equals the
    error the processor's ColorChecker fit reports for each patch."""
    import metamer
    cube = _colorchecker(tmp_path, f"illuminants/{light}")
    sensor = _sensor(tmp_path, {"illuminant": f"illuminants/{light}", "colour_correction": form})
    frame = metamer.capture(str(cube), str(sensor), noise=False)
    developed = metamer.develop(frame["raw"], str(sensor))
    reference, d65 = _reference_xyz(cube, light, 0.01)
    measured = _developed_delta_e(developed, reference, d65)
    fitted = np.array(developed["colorchecker_delta_e2000"])
    print(f"{light} {form}: ΔE00 after the processor, mean {measured.mean():.3f} max {measured.max():.3f}; "
          f"the fit's mean {fitted.mean():.3f}; worst disagreement {np.abs(measured - fitted).max():.3f}")
    np.testing.assert_allclose(measured, fitted, atol=0.1)
    assert 0.3 < fitted.mean() < 5            # a real camera is not colorimetric


def test_a_camera_that_is_a_linear_transform_of_the_cmfs_develops_with_no_colour_error(tmp_path):
    """Issue 48's known answer end to end: quantum efficiencies M·(x̄, ȳ, z̄)/λ captured without noise under
    illuminant A and developed by the 3 × 3 fit: every patch's ΔE00 is 0 but for the raw's rounding."""
    import colour

    import metamer
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(colour.SpectralShape(380, 780, 5))
    m = np.array([[0.9, 0.3, -0.05], [0.1, 0.8, 0.15], [0.02, 0.1, 0.95]])
    qe = cmfs.values @ m.T / cmfs.wavelengths[:, None]   # a photon counter: its response is Σ QE·λ·L
    table = np.column_stack([cmfs.wavelengths, qe / qe.max()])
    np.savetxt(tmp_path / "luther_qe.csv", table, delimiter=",", header="wavelength_nm,r,g,b", comments="", fmt="%.9g")
    # 16 bits and a deep well: the dark patches' raw rounding (0.13 % of dark skin's blue at 14 bits,
    # ΔE00 0.1 through the matrix's cross-talk) is the only error left, and small.
    sensor = _sensor(tmp_path, {"illuminant": "illuminants/A"},
                     quantum_efficiency={"table": "luther_qe.csv", "peak": 0.5},
                     adc_bits=16, full_well_e=200000, conversion_gain_dn_per_e=0.3)
    cube = _colorchecker(tmp_path, "illuminants/A")
    developed = metamer.develop(metamer.capture(str(cube), str(sensor), noise=False)["raw"], str(sensor))
    reference, d65 = _reference_xyz(cube, "A", 0.01)
    measured = _developed_delta_e(developed, reference, d65)
    print(f"Luther camera after the processor: ΔE00 max {measured.max():.4f}")
    assert measured.max() < 0.05
    assert max(developed["colorchecker_delta_e2000"]) < 1e-6


def test_develop_names_its_mistakes(tmp_path):
    import subprocess

    import metamer
    frame = np.full((8, 8), 500, np.uint16)
    for keywords, message in [
        ({"white_balance": "gray"}, "white_balance: unknown white balance 'gray'"),
        ({"white_balance": "patch"}, "patch: the patch white balance needs patch="),
        ({"white_balance": "patch", "patch": ["a", 1, 2, 3]}, "patch: expected \\[x, y, width, height\\]"),
        ({"white_balance": "patch", "patch": [0, 0, 9, 9]}, "patch: the patch \\[0, 0, 9, 9\\] .* inside the 8×8 frame"),
        ({"illuminant": "illuminants/D66"}, "illuminant"),
        ({"demosaic": "ahd"}, "demosaic: 'ahd' is not a demosaicing method"),
        ({"colour_correction": "cubic"}, "colour_correction"),
        ({"exposure": 0.0}, "exposure: expected a gain"),
        ({"display": "lcd"}, "^display: "),
        ({"bits": 12}, "bits: expected 8 or 16 bits per channel, got 12"),
    ]:
        with pytest.raises(metamer.InputError, match=message):
            metamer.develop(frame, "aps_c_rggb", **keywords)
    with pytest.raises(metamer.InputError, match="raw: a 5×1 frame cannot be developed"):
        metamer.develop(np.zeros((1, 5), np.uint16), "aps_c_rggb")
    with pytest.raises(metamer.InputError, match="raw: expected the sensor's digital numbers"):
        metamer.develop(frame.astype(float), "aps_c_rggb")
    with pytest.raises(metamer.InputError, match="not an RGB Bayer sensor"):
        metamer.develop(frame, "mono_silicon")
    # A capture too narrow to develop still writes its raw frame and DNG, and says why it has no sRGB.
    cube = _colorchecker(tmp_path, "illuminants/D65")
    one = tmp_path / "one"
    _run("render", REPO / "scenes" / "colorchecker.json", "--out", one, "--write", "cube",
         "--set", "camera.width=1", "--set", "camera.height=7")
    p = _run("capture", one / "colorchecker.exr", "--sensor", "aps_c_rggb", "--out", one)
    assert "too small to develop" in p.stdout
    import json
    meta = json.loads((one / "colorchecker.raw.json").read_text())
    assert meta["developed"] is None and (one / "colorchecker.raw.dng").exists()
    assert not (one / "colorchecker.raw.srgb.png").exists() and cube.exists()


def test_a_crt_processor_writes_its_counts_with_the_displays_icc_profile(tmp_path):
    """processor.display "crt", 16 bits: the developed frame is <stem>.raw.crt.png, 16-bit, carrying the
    CRT model's ICC profile (no sRGB chunk), its counts metamer.develop's for the same frame."""
    import json

    import OpenImageIO as oiio

    import metamer
    cube = _colorchecker(tmp_path, "illuminants/D65")
    sensor = _sensor(tmp_path, {"display": "crt", "bits": 16})
    _run("capture", cube, "--sensor", sensor, "--out", tmp_path / "cap", "--seed", 2)
    meta = json.loads((tmp_path / "cap" / "colorchecker.raw.json").read_text())
    assert meta["developed"] == "colorchecker.raw.crt.png" and meta["processor"]["display"] == "crt"
    png = tmp_path / "cap" / meta["developed"]
    data = png.read_bytes()
    assert b"iCCP" in data and b"sRGB" not in data[:data.index(b"IDAT")]
    buf = oiio.ImageBuf(str(png))
    assert buf.spec().format == oiio.UINT16 and buf.spec().nchannels == 3
    raw = oiio.ImageBuf(str(tmp_path / "cap" / "colorchecker.raw.png")).get_pixels(oiio.UINT16)[..., 0]
    developed = metamer.develop(raw, str(sensor))
    assert developed["display"] == "crt" and developed["counts"].dtype == np.uint16
    np.testing.assert_array_equal(buf.get_pixels(oiio.UINT16), developed["counts"])
