#!/usr/bin/env python3
"""Write spectra/reflectances/: the measured surface reflectances colour-science 0.4.7 ships, one CSV
per sample, for scenes and for random scene draws (issue 49, item 3; spectra/README.md,
"Reflectances").

Run with the project's Python (colour-science 0.4.7, numpy 2.2.6):

    .venv/bin/python spectra/generate_reflectances.py

Each set is a folder; each sample `wavelength_nm,value` on the set's own wavelengths (the library
resamples onto a render's grid), values as published (reflectance factor, 0..1) but for measurements that dip a hair below 0
(down to −0.01: noise at the ends of a range), set to 0 — nothing in the library is negative. A
sample whose factor passes 1 is a fluorescent one's radiance factor, not a reflectance, and is
left out.
`spectra/reflectances/index.tsv` (tab-separated; not .csv, which the library would read as a
spectrum) lists every sample: set, name, the library name a scene uses,
its source's own label, and its range and step. Deterministic: fixed rounding (6 significant
digits), fixed line endings.
"""

from __future__ import annotations

import csv
import re
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore")
import colour  # noqa: E402
from colour.characterisation import SDS_COLOURCHECKERS, read_training_data_rawtoaces_v1  # noqa: E402
from colour.quality.cfi2017 import load_TCS_CIE2017  # noqa: E402
from colour.quality.datasets import SDS_TCS, SDS_VS  # noqa: E402

assert colour.__version__ == "0.4.7", colour.__version__
OUT = Path(__file__).resolve().parent / "reflectances"


def snake(label: str) -> str:
    """'white 9.5 (.05 D)' → 'white_9_5', 'Gray-80' → 'gray_80', 'TCS01' → 'tcs01'."""
    label = re.sub(r"\(.*?\)", "", label).strip().lower()
    return re.sub(r"[^a-z0-9]+", "_", label).strip("_")


def sets() -> dict[str, list[tuple[str, np.ndarray, np.ndarray]]]:
    """set → [(source label, wavelengths, values)], in the source's order."""
    out: dict[str, list[tuple[str, np.ndarray, np.ndarray]]] = {}

    def from_dict(d):
        return [(label, sd.wavelengths, sd.values) for label, sd in d.items()]

    out["babelcolor_average"] = from_dict(SDS_COLOURCHECKERS["BabelColor Average"])
    out["pmc"] = from_dict(SDS_COLOURCHECKERS["PMC"])
    # CIE 13.3's fourteen test colour samples and the fifteenth (Japanese skin) the CIE published in
    # 2024: the CIE 2024 set holds all fifteen.
    out["cie_tcs"] = from_dict(SDS_TCS["CIE 2024"])
    out["nist_cqs_vs"] = from_dict(SDS_VS["NIST CQS 9.0"])
    ces = load_TCS_CIE2017(colour.SpectralShape(380, 780, 5))
    out["cie_2017_ces"] = [(label, ces.wavelengths, ces.values[:, i]) for i, label in enumerate(ces.labels)]
    # colour-science labels them "TCS0 (CIE 2017)" … "TCS98 (CIE 2017)"; CIE 224 numbers them CES1 … CES99.
    assert [str(label) for label, _, _ in out["cie_2017_ces"]] == [f"TCS{i} (CIE 2017)" for i in range(99)]
    aces = read_training_data_rawtoaces_v1()
    out["aces_training"] = [(label, aces.wavelengths, aces.values[:, i]) for i, label in enumerate(aces.labels)]
    return out


def write_csv(path: Path, nm: np.ndarray, values: np.ndarray) -> None:
    lines = ["wavelength_nm,value"] + [f"{w:g},{v:.6g}" for w, v in zip(nm, values)]
    path.write_text("\n".join(lines) + "\n")


def main() -> None:
    index = [["set", "name", "library_name", "source_label", "start_nm", "end_nm", "step_nm"]]
    for name, samples in sets().items():
        folder = OUT / name
        folder.mkdir(parents=True, exist_ok=True)
        for old in folder.glob("*.csv"):
            old.unlink()
        seen = set()
        kept = 0
        for label, nm, values in samples:
            if np.max(values) > 1.0:
                # A radiance factor above 1 is a fluorescent sample's under the measuring light, not a
                # reflectance (five of the ACES training patches): left out, and listed in the README.
                print(f"  left out {name} {label}: its factor reaches {np.max(values):.3f}")
                continue
            kept += 1
            stem = f"ces{int(str(label)[3:].split()[0]) + 1:02d}" if name == "cie_2017_ces" else snake(str(label))
            assert stem and stem not in seen, (name, label)
            seen.add(stem)
            nm = np.asarray(nm, dtype=float)
            values = np.asarray(values, dtype=float)
            assert np.all(np.isfinite(values)) and values.min() > -0.01, (name, label)
            write_csv(folder / f"{stem}.csv", nm, np.maximum(values, 0.0))
            step = float(np.round(nm[1] - nm[0], 6))
            index.append([name, stem, f"reflectances/{name}/{stem}", str(label), f"{nm[0]:g}", f"{nm[-1]:g}", f"{step:g}"])
        print(f"{name}: {kept} samples, {nm[0]:g}-{nm[-1]:g} nm")
    (OUT / "index.csv").unlink(missing_ok=True)
    with (OUT / "index.tsv").open("w", newline="") as f:
        csv.writer(f, delimiter="\t", lineterminator="\n").writerows(index)
    print(f"{len(index) - 1} reflectances; index in {OUT / 'index.tsv'}")


if __name__ == "__main__":
    main()
