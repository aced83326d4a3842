#!/usr/bin/env python3
"""HDF5 and ENVI texture files of the bad-input corpus (README.md, `cube-` cases), written the way
other tools write them (h5py; ENVI headers by hand), each damaged in one way: a truncated or
over-long .img, a header without `byte order`, `data type = 12`, a wavelength list one short, an
unterminated `{`, a header without its data file, radiance where a reflectance is needed, a NaN
texel, a file in UTF-16; HDF5 without /wavelength_nm, a rank-2 /cube, a truncated file, a radiance
cube, and HDF5 that would have the library read other files (issue 30, class 6): /cube's values in
external storage (/dev/zero), an external link to a file outside the scene's folder, a soft link, a
virtual dataset. Needs numpy and h5py (the venv): .venv/bin/python tests/bad-inputs/files/make_cube_files.py"""

import os

import h5py
import numpy as np

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cubes")
NM = [400.0, 500.0, 600.0, 700.0]


def header(lines=2, samples=2, bands=4, data_type=4, byte_order="byte order = 0\n", wavelengths=NM,
           quantity="reflectance", close="}"):
    return ("ENVI\n"
            f"samples = {samples}\nlines = {lines}\nbands = {bands}\nheader offset = 0\n"
            f"file type = ENVI Standard\ndata type = {data_type}\ninterleave = bsq\n{byte_order}"
            "wavelength units = Nanometers\n"
            "wavelength = {" + ", ".join(f"{w:g}" for w in wavelengths) + close + "\n"
            f"metamer quantity = {quantity}\n")


def envi(name, text, data=None, encoding="ascii"):
    with open(os.path.join(HERE, name + ".hdr"), "w", encoding=encoding) as f:
        f.write(text)
    if data is not None:
        with open(os.path.join(HERE, name + ".img"), "wb") as f:
            f.write(data)


def h5(name, **datasets):
    with h5py.File(os.path.join(HERE, name + ".h5"), "w") as f:
        attrs = datasets.pop("attrs", {})
        for k, v in datasets.items():
            f[k] = v
        for k, v in attrs.items():
            f["cube"].attrs[k] = v


def main():
    os.makedirs(HERE, exist_ok=True)
    good = np.full((4, 2, 2), 0.5, "<f4").tobytes()  # bands × lines × samples (BSQ)
    envi("truncated", header(), good[:-4])
    envi("too-long", header(), good + b"\0" * 8)
    envi("no-byte-order", header(byte_order=""), good)
    envi("data-type-12", header(data_type=12), good)
    envi("wavelength-short", header(wavelengths=NM[:3]), good)
    envi("unterminated", header(close=""), good)
    envi("no-data", header())
    envi("radiance", header(quantity="spectral radiance"), good)
    nan = np.full((4, 2, 2), 0.5, "<f4")
    nan[2, 1, 0] = np.nan
    envi("nan", header(), nan.tobytes())
    envi("utf16", header(), good, encoding="utf-16")
    cube = np.full((2, 2, 4), 0.5, np.float32)
    h5("no-wavelengths", cube=cube, attrs={"quantity": "reflectance"})
    h5("rank-2", cube=cube[0], wavelength_nm=np.array(NM), attrs={"quantity": "reflectance"})
    h5("radiance", cube=cube, wavelength_nm=np.array(NM), attrs={"quantity": "spectral radiance"})
    h5("whole", cube=cube, wavelength_nm=np.array(NM), attrs={"quantity": "reflectance"})
    # 16384 x 16384 x 4 texels that were never written: a chunked dataset holds no data for them,
    # so the file is small, but on the grid the texture would take 31 GiB.
    with h5py.File(os.path.join(HERE, "huge.h5"), "w") as f:
        f.create_dataset("cube", shape=(16384, 16384, 4), dtype="<f4", chunks=(1, 1024, 4), fillvalue=0.5)
        f["wavelength_nm"] = np.array(NM)
        f["cube"].attrs["quantity"] = "reflectance"
    with open(os.path.join(HERE, "whole.h5"), "rb") as f:
        whole = f.read()
    with open(os.path.join(HERE, "truncated.h5"), "wb") as f:
        f.write(whole[: len(whole) // 2])
    os.remove(os.path.join(HERE, "whole.h5"))
    hostile()


def hostile():
    """HDF5 indirection: each of these is refused before HDF5 opens any other file."""
    nm = np.array(NM)
    with h5py.File(os.path.join(HERE, "external-dev-zero.h5"), "w") as f:
        f.create_dataset("cube", shape=(2, 2, 4), dtype="<f4", external=[("/dev/zero", 0, 2 * 2 * 4 * 4)])
        f["wavelength_nm"] = nm
        f["cube"].attrs["quantity"] = "reflectance"
    with h5py.File(os.path.join(HERE, "external-link.h5"), "w") as f:
        f["cube"] = h5py.ExternalLink("../../../outside.h5", "/cube")
        f["wavelength_nm"] = nm
    with h5py.File(os.path.join(HERE, "soft-link.h5"), "w") as f:
        f["data"] = np.full((2, 2, 4), 0.5, np.float32)
        f["cube"] = h5py.SoftLink("/data")
        f["wavelength_nm"] = nm
    with h5py.File(os.path.join(HERE, "virtual.h5"), "w") as f:
        layout = h5py.VirtualLayout(shape=(2, 2, 4), dtype="<f4")
        layout[:] = h5py.VirtualSource("../../../outside.h5", "data", shape=(2, 2, 4))
        f.create_virtual_dataset("cube", layout)
        f["wavelength_nm"] = nm


if __name__ == "__main__":
    main()
