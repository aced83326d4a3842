"""metamer.camera_report (issue 48, item 5) for the bundled APS-C sensor under illuminant A: the files
a person opens, and numbers that must hold — the photon transfer's slope is the sensor's gain K, the
grey patches' SNR is EMVA 1288's model of the sensor's noise, the ColorChecker's ΔE00 on the capture is
the processor's fit per patch, and the metameric pair's observer ΔE00 is colour-science's from the cube.
Run by CTest (tests/CMakeLists.txt, test `python_camera_report`)."""

from __future__ import annotations

import csv
import json
import warnings

import numpy as np
import pytest

warnings.filterwarnings("ignore")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    import metamer
    out = tmp_path_factory.mktemp("report")
    r = metamer.camera_report("aps_c_rggb", out, illuminant="illuminants/A", seed=3, exposures=10)
    return out, r


def test_the_report_writes_its_page_and_its_numbers(report):
    out, r = report
    for name in ("report.png", "report.svg", "report.json", "patches.csv", "photon_transfer.csv", "mtf.csv"):
        assert (out / name).stat().st_size > 0, name
    assert json.loads((out / "report.json").read_text()) == json.loads(json.dumps(r))
    assert (out / "report.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (out / "report.svg").read_bytes()[:500]
    rows = list(csv.reader((out / "patches.csv").open()))
    assert len(rows) == 25 and rows[1][0] == "dark_skin"
    assert len(list(csv.reader((out / "photon_transfer.csv").open()))) == 11
    assert not [p for p in out.iterdir() if p.name.startswith(".")]     # no temporary left behind


def test_the_photon_transfer_slope_is_the_sensors_gain(report):
    _, r = report
    ptc = r["photon_transfer"]
    print(f"fitted K {ptc['fitted_gain_dn_per_e']:.4f} DN/e⁻, the sensor's {ptc['sensor_gain_dn_per_e']}")
    # Each point's σ² from ~2600 pixels is good to ±2.8 % (1σ); the fitted slope over six or seven of them
    # to about ±1.5 %.
    assert ptc["fitted_gain_dn_per_e"] == pytest.approx(ptc["sensor_gain_dn_per_e"], rel=0.04)
    # Past the full well (twice the auto exposure, which puts the brightest pixels at 0.7 of it) the
    # white patch saturates and its variance collapses.
    assert ptc["points"][0]["variance_dn2"] < 0.2 * ptc["points"][1]["variance_dn2"]


def test_the_grey_patches_snr_is_the_sensors_noise_model(report):
    """EMVA 1288's linear model: σ²_y = K²(μ_e + σ_d²) with σ_d² = σ_r² + the dark current's, plus the
    quantization's 1/12 DN²; the PRNU and DSNU cancel in the two frames' difference."""
    _, r = report
    sensor = json.loads((__import__("pathlib").Path(__file__).resolve().parents[2] / "spectra" / "sensors" /
                         "aps_c_rggb.json").read_text())
    k, read = sensor["conversion_gain_dn_per_e"], sensor["read_noise_e"]
    for g in r["grey_patch_snr"]["patches"]:
        mu_e = g["mean_dn"] / k
        want = g["mean_dn"] / np.sqrt(k * k * (mu_e + read ** 2) + 1 / 12)
        print(f"{g['name']:<12} SNR {g['snr']:6.1f}, model {want:6.1f} ({g['pixels']} pixels)")
        assert g["snr"] == pytest.approx(want, rel=0.12)     # σ² from ~1150 pixels: ±4 % (1σ) each


def test_the_colorcheckers_delta_e_on_the_capture_is_the_processors_fit(report):
    _, r = report
    patches = r["colorchecker"]["patches"]
    worst = max(abs(p["delta_e2000"] - p["fit_delta_e2000"]) for p in patches)
    print(f"ΔE00 mean {r['colorchecker']['mean_delta_e2000']:.3f}; worst |capture − fit| {worst:.3f}")
    assert worst < 0.3          # noise over ~2300 pixels per patch, the lens's blur far from the middles
    assert 0.3 < r["colorchecker"]["mean_delta_e2000"] < 5


def test_the_metameric_pairs_observer_delta_e_is_colour_sciences(report, tmp_path):
    """The observer's ΔE00 between the pair under A, adapted to D65 by Bradford, from the spectra
    themselves by colour-science; the camera's differs (it is not colorimetric)."""
    import colour
    from pathlib import Path
    repo = Path(__file__).resolve().parents[2]
    _, r = report
    shape = colour.SpectralShape(380, 780, 5)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)

    def spectrum(name):
        t = np.loadtxt(repo / "spectra" / f"{name}.csv", delimiter=",", skiprows=1)
        return np.interp(shape.wavelengths, t[:, 0], t[:, 1])

    light = spectrum("illuminants/A")
    white = light @ cmfs.values
    d65 = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"])
    lab = []
    for name in ("metamers/base", "metamers/metamer"):
        xyz = (spectrum(name) * light) @ cmfs.values / white[1]
        adapted = colour.adaptation.chromatic_adaptation_VonKries(xyz, white / white[1], d65, transform="Bradford")
        lab.append(colour.XYZ_to_Lab(adapted, colour.XYZ_to_xy(d65)))
    want = colour.delta_E(lab[0], lab[1], method="CIE 2000")
    pair = r["metamer_pair"]
    print(f"metameric pair under A: observer ΔE00 {pair['observer_delta_e2000']:.3f} (colour-science {want:.3f}), "
          f"camera {pair['camera_delta_e2000']:.3f}")
    assert pair["observer_delta_e2000"] == pytest.approx(want, abs=0.05)
    assert abs(pair["camera_delta_e2000"] - pair["observer_delta_e2000"]) > 1


def test_the_mtf_per_channel_falls_from_one(report):
    _, r = report
    f = np.array(r["mtf"]["frequency"])
    for c in "RGB":
        mtf = np.array(r["mtf"]["curves"][c])
        assert mtf[0] == pytest.approx(1.0, abs=0.02)
        assert 0.1 < r["mtf"]["mtf50"][c] < 0.5
        assert mtf[np.searchsorted(f, 0.5)] < 0.5      # the lens's diffraction, OLPF and pixel aperture
    assert r["mtf"]["edge_angle_deg"] == pytest.approx(5.0, abs=0.2)


def test_mistakes_are_named():
    import metamer
    with pytest.raises(metamer.InputError, match="exposures"):
        metamer.camera_report("aps_c_rggb", "/nonexistent-never", exposures=2)
    with pytest.raises(metamer.InputError, match="RGB Bayer"):
        metamer.camera_report("mono_silicon", __import__("tempfile").mkdtemp(), exposures=4)
