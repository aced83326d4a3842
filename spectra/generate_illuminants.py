#!/usr/bin/env python3
"""Write the CIE's newer illuminant series into spectra/illuminants/: the LED series (CIE 015:2018
Table 11.4: LED-B1 … B5 phosphor-type, LED-BH1 hybrid, LED-RGB1 mixed, LED-V1, V2 violet-pumped),
the fluorescent lamp series FL3.1 … FL3.15 and the high-pressure discharge lamps HP1 … HP5 (CIE
015:2018 Tables 11.2 and 11.3), each as colour-science 0.4.7 ships it — light sources a random
scene draw chooses from (issue 49, item 2: `"choose_spectra": "illuminants/cie_led"`).

Run with the project's Python (colour-science 0.4.7, numpy 2.2.6):

    .venv/bin/python spectra/generate_illuminants.py

One CSV per lamp, `wavelength_nm,value` on colour-science's wavelengths (380–780 nm / 5 nm), values
as tabulated (relative SPD, 6 significant digits). Deterministic.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore")
import colour  # noqa: E402

assert colour.__version__ == "0.4.7", colour.__version__
OUT = Path(__file__).resolve().parent / "illuminants"
SERIES = {
    "cie_led": (r"LED-(.+)", lambda m: m.group(1)),          # LED-B1 → cie_led/B1
    "cie_fl3": (r"FL3\.(\d+)", lambda m: f"FL3_{int(m.group(1)):02d}"),  # FL3.1 → cie_fl3/FL3_01
    "cie_hp": (r"(HP\d+)", lambda m: m.group(1)),            # HP1 → cie_hp/HP1
}


def main() -> None:
    for folder, (pattern, name) in SERIES.items():
        out = OUT / folder
        out.mkdir(parents=True, exist_ok=True)
        for old in out.glob("*.csv"):
            old.unlink()
        count = 0
        for key, sd in colour.SDS_ILLUMINANTS.items():
            m = re.fullmatch(pattern, key)
            if not m:
                continue
            nm, values = np.asarray(sd.wavelengths), np.asarray(sd.values)
            assert np.all(values >= 0), key
            lines = ["wavelength_nm,value"] + [f"{w:g},{v:.6g}" for w, v in zip(nm, values)]
            (out / f"{name(m)}.csv").write_text("\n".join(lines) + "\n")
            count += 1
        print(f"{folder}: {count} lamps")


if __name__ == "__main__":
    main()
