"""metamer.camera_report (this module, metamer.report): the one-page report a camera engineer reads (issue 48, item 5;
docs/camera.md, "The camera report"). It renders the package's charts — the ColorChecker, the
slanted edge and the metameric pair — under one light, captures them with a sensor, develops them
with the sensor's image processor, and measures them with the engine's functions:

- the MTF per developed channel (ISO 12233 e-SFR, metamer.slanted_edge_sfr) and MTF50;
- the ColorChecker as rendered beside the camera's developed image, ΔE00 per patch
  (metamer.developed_colour_error: the scene's own XYZ adapted to D65 against the developed sRGB);
- the photon transfer curve and SNR against signal (metamer.photon_transfer on two frames per
  exposure, EMVA 1288), with the overall system gain K fitted from its slope; SNR per grey patch;
- the metameric pair's ΔE00 as the camera develops it beside the CIE 1931 observer's.

Plots by matplotlib (report.png, report.svg); the numbers in report.json and three CSV files. Each
file is written whole or not at all (a temporary beside it, renamed). Only the plotting and the
orchestration are here: every measurement is the engine's.
`metamer camera-report --sensor S --out DIR` (the package's command, metamer/__main__.py) and
`python -m metamer.report …` run main().
Tests: tests/python/test_camera_report.py."""

from __future__ import annotations

import csv
import io
import json
import os
import tempfile
from pathlib import Path
from typing import Any, Optional, Union

PathLike = Union[str, "os.PathLike[str]"]

# Chart order, row by row from dark skin (as color/camera_characterization's colorCheckerPatchNames).
PATCHES = ["dark_skin", "light_skin", "blue_sky", "foliage", "blue_flower", "bluish_green",
           "orange", "purplish_blue", "moderate_red", "purple", "yellow_green", "orange_yellow",
           "blue", "green", "red", "yellow", "magenta", "cyan",
           "white_9_5", "neutral_8", "neutral_6_5", "neutral_5", "neutral_3_5", "black_2"]
WHITE_PATCH = PATCHES.index("white_9_5")
GREYS = PATCHES[WHITE_PATCH:]


def _scene(name: str) -> Path:
    return Path(__file__).resolve().parent / "scenes" / name


def _object_rects(scene: dict[str, Any], fraction: float = 0.6) -> dict[str, list[int]]:
    """The middle `fraction` of each object's square, in pixels, by material name: the charts are flat
    quads seen head-on by an orthographic camera at x = y = 0 looking down −z with +y up."""
    cam = scene["camera"]
    w, h, height_m = cam["width"], cam["height"], cam["height_m"]
    per_m = h / height_m
    rects = {}
    for o in scene["objects"]:
        (cx, cy, _), (sx, sy) = o["center"], o["size"]
        half_x, half_y = sx * fraction / 2 * per_m, sy * fraction / 2 * per_m
        px, py = w / 2 + cx * per_m, h / 2 - cy * per_m
        rects[o["material"]] = [int(round(px - half_x)), int(round(py - half_y)),
                                int(round(2 * half_x)), int(round(2 * half_y))]
    return rects


def _mean(image: Any, rect: list[int]) -> Any:
    x, y, w, h = rect
    return image[y:y + h, x:x + w].reshape(-1, image.shape[-1]).mean(0)


def _write_atomically(path: Path, data: bytes) -> None:
    fd, temp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(temp, path)
    except BaseException:
        Path(temp).unlink(missing_ok=True)
        raise


def _csv(rows: list[list[Any]]) -> bytes:
    text = io.StringIO()
    csv.writer(text, lineterminator="\n").writerows(rows)
    return text.getvalue().encode()


def _green(channels: list[str]) -> str:
    for c in channels:
        if c.lower().startswith("g"):
            return c
    return channels[0]


def camera_report(sensor: PathLike, out: PathLike, *, illuminant: str = "illuminants/D65", seed: int = 0,
                  backend: str = "gpu", exposures: int = 16) -> dict[str, Any]:
    """Renders the charts under `illuminant`, captures and develops them with `sensor` (an RGB Bayer
    sensor file or library name), and writes report.png, report.svg, report.json, patches.csv,
    photon_transfer.csv and mtf.csv into `out`. Returns what report.json holds."""
    import numpy as np

    from . import _api
    if not isinstance(exposures, int) or not 4 <= exposures <= 64:
        raise _api._metamer.InputError(f"exposures: expected 4 … 64 exposures for the photon transfer curve, got {exposures!r}")
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    light = {"lights.0.spectrum": illuminant}
    sensor = str(sensor)
    # Developed for the sRGB display, 8 bits, whatever the sensor file's processor says: the report's
    # colour is measured in D65's CIELAB.
    srgb = {"illuminant": illuminant, "display": "srgb", "bits": 8}

    # The ColorChecker: rendered (cube and XYZ), two noisy frames, the first developed.
    chart_scene = json.loads(_scene("colorchecker.json").read_text())
    rects = _object_rects(chart_scene)
    chart = _api.render(str(_scene("colorchecker.json")), overrides=light, write=["cube", "xyz", "png"], backend=backend)
    frames = _api.capture(chart, sensor, frames=2, seed=seed)
    channels, raw = frames["channels"], frames["raw"]
    if len(channels) != 3:
        raise _api._metamer.InputError(f"sensor: the report develops an RGB Bayer sensor; {sensor} has "
                                       f"{len(channels)} channel(s)")
    developed = _api.develop(raw[0], sensor, **srgb)
    dev_means = np.array([_mean(developed["linear_rgb"], rects[p]) for p in PATCHES])
    chart_xyz = np.asarray(chart.xyz, dtype=np.float64)
    ref_means = np.array([_mean(chart_xyz, rects[p]) for p in PATCHES])
    colour_error = _api.developed_colour_error(dev_means, ref_means, white=illuminant, exposure_from=WHITE_PATCH)
    green = _green(channels)
    grey_snr = {p: _api.photon_transfer(raw[0], raw[1], sensor, rect=rects[p], channel=green) for p in GREYS}

    # The photon transfer: the white patch's green pixels at exposures from twice the auto exposure
    # (which puts the brightest pixels at 0.7 of the full well: twice is past it) down by factors of
    # √2, two frames each.
    auto = frames["exposure_s"]
    whole_white = _object_rects(chart_scene, 0.9)["white_9_5"]   # the most pixels: σ² to ±3 % per point
    ptc = []
    for k in range(exposures):
        t = auto * 2.0 * 2.0 ** (-k / 2)
        pair = _api.capture(chart, sensor, frames=2, seed=seed + 1 + k, exposure=t)["raw"]
        p = _api.photon_transfer(pair[0], pair[1], sensor, rect=whole_white, channel=green)
        ptc.append({"exposure_s": t, **p})
    white_level = frames["white_level_dn"] - frames["black_level_dn"]
    linear = [p for p in ptc if 0.002 * white_level < p["mean_dn"] < 0.6 * white_level]
    gain_fit = float(np.polyfit([p["mean_dn"] for p in linear], [p["variance_dn2"] for p in linear], 1)[0]) if len(linear) >= 2 else None

    # The slanted edge, noise-free, developed; the SFR of each channel in the middle of the frame.
    edge = _api.render(str(_scene("slanted-edge.json")), overrides=light, write=["cube"], backend=backend)
    edge_dev = _api.develop(_api.capture(edge, sensor, noise=False)["raw"], sensor, **srgb)
    h, w = edge_dev["linear_rgb"].shape[:2]
    region = edge_dev["linear_rgb"][h // 4:3 * h // 4, w // 4:3 * w // 4]
    sfr = {c: _api.slanted_edge_sfr(np.ascontiguousarray(region[..., i])) for i, c in enumerate("RGB")}

    # The metameric pair: the camera's ΔE00 between the developed squares beside the observer's.
    pair_scene = json.loads(_scene("metamers.json").read_text())
    pair_rects = _object_rects(pair_scene)
    pair = _api.render(str(_scene("metamers.json")), overrides=light, write=["cube", "xyz"], backend=backend)
    pair_xyz = np.asarray(pair.xyz, dtype=np.float64)
    pair_dev = _api.develop(_api.capture(pair, sensor, noise=False)["raw"], sensor, **srgb)
    pair_error = _api.developed_colour_error(
        np.array([_mean(pair_dev["linear_rgb"], pair_rects[m]) for m in ("base", "metamer")]),
        np.array([_mean(pair_xyz, pair_rects[m]) for m in ("base", "metamer")]),
        white=illuminant, exposure_from=0)
    camera_de = float(_api.delta_e2000(pair_error["developed_lab"][0], pair_error["developed_lab"][1])[0])
    observer_de = float(_api.delta_e2000(pair_error["reference_lab"][0], pair_error["reference_lab"][1])[0])

    report: dict[str, Any] = {
        "sensor": sensor,
        "illuminant": illuminant,
        "exposure_s": auto,
        "processor": {"white_balance": developed["white_balance"], "illuminant": developed["illuminant"],
                      "neutral": developed["neutral"]},
        "colorchecker": {
            "units": "ΔE00 between the developed image and the rendered scene's XYZ adapted to D65 by Bradford, "
                     "CIELAB of D65; the developed exposure scaled so the white patch has the scene's luminance",
            "mean_delta_e2000": float(np.mean(colour_error["delta_e2000"])),
            "max_delta_e2000": float(np.max(colour_error["delta_e2000"])),
            "patches": [{"name": p, "delta_e2000": float(colour_error["delta_e2000"][i]),
                         "developed_lab": colour_error["developed_lab"][i].tolist(),
                         "reference_lab": colour_error["reference_lab"][i].tolist(),
                         "fit_delta_e2000": developed["colorchecker_delta_e2000"][i]} for i, p in enumerate(PATCHES)],
        },
        "grey_patch_snr": {"channel": green, "units": "mean DN above black / temporal σ (two frames, EMVA 1288)",
                           "patches": [{"name": p, **v} for p, v in grey_snr.items()]},
        "photon_transfer": {"channel": green, "patch": "white_9_5", "points": ptc,
                            "fitted_gain_dn_per_e": gain_fit,
                            "sensor_gain_dn_per_e": frames["conversion_gain_dn_per_e"]},
        "mtf": {"units": "cycles per pixel along the edge's normal; developed linear sRGB channels",
                "mtf50": {c: sfr[c]["mtf50"] for c in "RGB"},
                "edge_angle_deg": sfr["G"]["angle_deg"],
                "frequency": sfr["G"]["frequency"].tolist(),
                "curves": {c: sfr[c]["mtf"].tolist() for c in "RGB"}},
        "metamer_pair": {"camera_delta_e2000": camera_de, "observer_delta_e2000": observer_de,
                         "units": "ΔE00 between the pair's two squares, CIELAB of D65 after Bradford from the light"},
    }

    _write_atomically(folder / "patches.csv", _csv(
        [["patch", "delta_e2000", "fit_delta_e2000", "L_developed", "a_developed", "b_developed",
          "L_reference", "a_reference", "b_reference"]]
        + [[p["name"], p["delta_e2000"], p["fit_delta_e2000"], *p["developed_lab"], *p["reference_lab"]]
           for p in report["colorchecker"]["patches"]]))
    _write_atomically(folder / "photon_transfer.csv", _csv(
        [["exposure_s", "mean_dn", "variance_dn2", "snr", "pixels"]]
        + [[p["exposure_s"], p["mean_dn"], p["variance_dn2"], p["snr"], p["pixels"]] for p in ptc]))
    _write_atomically(folder / "mtf.csv", _csv(
        [["frequency_cycles_per_pixel", "mtf_R", "mtf_G", "mtf_B"]]
        + [[f, *(sfr[c]["mtf"][i] for c in "RGB")] for i, f in enumerate(sfr["G"]["frequency"])]))
    _write_atomically(folder / "report.json", (json.dumps(report, indent=2) + "\n").encode())
    figure = _figure(report, np.asarray(chart.display), developed["counts"], rects, colour_error["delta_e2000"], sfr, ptc)
    for ext in ("png", "svg"):
        buffer = io.BytesIO()
        figure.savefig(buffer, format=ext, dpi=100)
        _write_atomically(folder / f"report.{ext}", buffer.getvalue())
    import matplotlib.pyplot as plt
    plt.close(figure)
    return report


def _figure(report: dict[str, Any], rendered: Any, developed: Any, rects: dict[str, list[int]], delta_e: Any,
            sfr: dict[str, Any], ptc: list[dict[str, Any]]) -> Any:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(2, 3, figsize=(16, 9.5))
    fig.suptitle(f"Metamer camera report — {Path(report['sensor']).stem} under {report['illuminant']}", fontsize=14)

    ax = axes[0, 0]
    for c, colour in zip("RGB", ("tab:red", "tab:green", "tab:blue")):
        ax.plot(sfr[c]["frequency"], sfr[c]["mtf"], color=colour, label=f"{c}: MTF50 {sfr[c]['mtf50']:.3f}")
    ax.axhline(0.5, color="grey", lw=0.5)
    ax.axvline(0.5, color="grey", lw=0.5, ls="--")
    ax.set(xlim=(0, 1), ylim=(0, 1.05), xlabel="cycles per pixel", ylabel="MTF",
           title=f"Slanted-edge SFR (ISO 12233), edge {report['mtf']['edge_angle_deg']:.1f}°")
    ax.legend()

    ax = axes[0, 1]
    both = np.concatenate([rendered[..., :3].astype(np.uint8), np.full((rendered.shape[0], 8, 3), 255, np.uint8),
                           developed], axis=1)
    ax.imshow(both)
    offset = rendered.shape[1] + 8
    for i, name in enumerate(PATCHES):
        x, y, w, h = rects[name]
        ax.text(offset + x + w / 2, y + h / 2, f"{delta_e[i]:.1f}", ha="center", va="center", fontsize=7,
                color="white" if i in (0, 3, 7, 9, 12, 22, 23) else "black")
    ax.set(title="ColorChecker: the render's sRGB | the camera's, ΔE00 per patch", xticks=[], yticks=[])

    ax = axes[0, 2]
    ax.bar(range(24), delta_e, color="tab:purple", label="on the developed capture")
    ax.plot(range(24), [p["fit_delta_e2000"] for p in report["colorchecker"]["patches"]], "k.", label="the processor's fit")
    ax.set(xticks=range(24), ylabel="ΔE00",
           title=f"ΔE00 per patch: mean {report['colorchecker']['mean_delta_e2000']:.2f}, "
                 f"max {report['colorchecker']['max_delta_e2000']:.2f}")
    ax.set_xticklabels(PATCHES, rotation=90, fontsize=7)
    ax.legend()

    signal = np.array([p["mean_dn"] for p in ptc])
    variance = np.array([p["variance_dn2"] for p in ptc])
    gain = report["photon_transfer"]["fitted_gain_dn_per_e"]
    # Past the full well the variance collapses: those points are marked, not joined.
    saturated = variance < 0.25 * (gain or 0) * signal
    keep = (signal > 0) & ~saturated
    ax = axes[1, 0]
    ax.loglog(signal[keep], variance[keep], "o", color="tab:green")
    if saturated.any():
        ax.loglog(signal[saturated], np.maximum(variance[saturated], 1e-3), "x", color="tab:red", label="saturated")
    if gain:
        xs = np.geomspace(signal[keep].min(), signal[keep].max(), 50)
        ax.loglog(xs, gain * xs, "k--", lw=0.8, label=f"K = {gain:.3f} DN/e⁻ (sensor {report['photon_transfer']['sensor_gain_dn_per_e']:g})")
        ax.legend()
    ax.set(xlabel="mean signal μ − black, DN", ylabel="temporal variance σ², DN²",
           title="Photon transfer (white patch, green pixels)")

    ax = axes[1, 1]
    ax.loglog(signal[keep], [p["snr"] for p, k in zip(ptc, keep) if k], "o-", color="tab:green",
              label="white patch, exposure series (unsaturated)")
    greys = report["grey_patch_snr"]["patches"]
    ax.loglog([g["mean_dn"] for g in greys], [g["snr"] for g in greys], "s", color="k", label="grey patches, one exposure")
    ax.set(xlabel="mean signal μ − black, DN", ylabel="SNR", title="SNR against signal")
    ax.legend()

    ax = axes[1, 2]
    ax.axis("off")
    pair = report["metamer_pair"]
    lines = [
        "Metameric pair (spectra/metamers)",
        f"  observer (CIE 1931) ΔE00: {pair['observer_delta_e2000']:.2f}",
        f"  camera after its processor ΔE00: {pair['camera_delta_e2000']:.2f}",
        "",
        "SNR per grey patch (green pixels)",
        *[f"  {g['name']:<12} μ {g['mean_dn']:8.1f} DN   SNR {g['snr']:6.1f}" for g in greys],
        "",
        f"auto exposure {report['exposure_s']:.4g} s",
        f"white balance {report['processor']['white_balance']} ({report['processor']['illuminant']})",
    ]
    ax.text(0, 1, "\n".join(lines), va="top", family="monospace", fontsize=10)
    fig.tight_layout()
    return fig


def main(argv: Optional[list[str]] = None) -> None:
    import argparse
    parser = argparse.ArgumentParser(prog="metamer camera-report", description=camera_report.__doc__)
    parser.add_argument("--sensor", required=True, help="an RGB Bayer sensor file or library sensor")
    parser.add_argument("--out", required=True, help="the folder the report goes to")
    parser.add_argument("--illuminant", default="illuminants/D65", help="the charts' light (default illuminants/D65)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--backend", choices=["gpu", "cpu"], default="gpu")
    a = parser.parse_args(argv)
    r = camera_report(a.sensor, a.out, illuminant=a.illuminant, seed=a.seed, backend=a.backend)
    print(f"wrote {a.out}/report.png, report.svg, report.json, patches.csv, photon_transfer.csv, mtf.csv "
          f"(ColorChecker mean ΔE00 {r['colorchecker']['mean_delta_e2000']:.2f}, MTF50 G {r['mtf']['mtf50']['G']:.3f})")


if __name__ == "__main__":
    main()
