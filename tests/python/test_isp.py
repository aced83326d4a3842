"""The image processor and the camera's metrics (issue 48) against independent implementations:
metamer.demosaic against colour-demosaicing's bilinear and Malvar (2004) demosaicing, and
metamer.slanted_edge_sfr on an edge whose MTF numpy computes in closed form.
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
