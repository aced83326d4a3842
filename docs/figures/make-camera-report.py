#!/usr/bin/env python3
"""docs/figures/camera-report.png: metamer.camera_report (docs/camera.md, "Metrics and the camera
report") for the bundled aps_c_rggb sensor under illuminant A, seed 3 — the page the function
writes, copied here. Needs a build and the project's venv (matplotlib):

    PYTHONPATH=build/python .venv/bin/python docs/figures/make-camera-report.py
"""
import shutil
import tempfile
from pathlib import Path

import metamer

HERE = Path(__file__).resolve().parent

with tempfile.TemporaryDirectory() as out:
    report = metamer.camera_report("aps_c_rggb", out, illuminant="illuminants/A", seed=3)
    shutil.copyfile(Path(out) / "report.png", HERE / "camera-report.png")
print(f"wrote {HERE / 'camera-report.png'}: ColorChecker mean ΔE00 {report['colorchecker']['mean_delta_e2000']:.2f}, "
      f"MTF50 G {report['mtf']['mtf50']['G']:.3f}, K {report['photon_transfer']['fitted_gain_dn_per_e']:.3f}, "
      f"pair ΔE00 observer {report['metamer_pair']['observer_delta_e2000']:.2f} camera "
      f"{report['metamer_pair']['camera_delta_e2000']:.2f}")
