#!/usr/bin/env python3
"""Metamer's files as ordinary tools show them (docs/io.md; issue 35, item 6).

Renders tests/data/cli/small.json twice (sRGB and CRT displays) and checks, with the tools a user
has rather than Metamer's own readers:
- oiiotool: `oiiotool small.exr -o view.png` writes the cube's R, G, B, A preview, not its first
  bands; with `--ch R,G,B --colorconvert linear sRGB` it is the render's own PNG (within a count:
  oiiotool's conversion is float);
  `--ch` takes band channels by index, not by name (their names hold a comma, its separator).
- OpenImageIO: the XYZ EXR holds X, Y, Z in R, G, B with OpenEXR's XYZ chromaticities.
- xarray (h5netcdf): the HDF5 cube has dimensions y, x, wavelength and a wavelength coordinate.
- the PNG chunks: the sRGB display's PNG has an sRGB chunk; the CRT's an iCCP chunk holding an
  ICC display profile (RGB to XYZ) and no sRGB chunk.

Usage: check_ordinary_tools.py METAMER WORKDIR   (OIIOTOOL in the environment: oiiotool's path)
Exit codes: 0 pass, 1 fail, 77 skipped (no oiiotool).
"""

import os
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "tests" / "data" / "cli" / "small.json"
GRID = "400:700:10"


def run(cmd):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(map(str, cmd))}: exit {r.returncode}\n{r.stdout}{r.stderr}"
    return r.stdout + r.stderr


def read(path, channels=None):
    inp = oiio.ImageInput.open(str(path))
    assert inp, f"OpenImageIO cannot open {path}: {oiio.geterror()}"
    spec = inp.spec()
    n = spec.nchannels if channels is None else channels
    pixels = np.asarray(inp.read_image(0, 0, 0, n, "float"))
    inp.close()
    return spec, pixels


def srgb_encode(v):
    v = np.clip(v, 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)


def png_chunks(path):
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    chunks, at = {}, 8
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind = data[at + 4:at + 8].decode("latin-1")
        chunks.setdefault(kind, []).append(data[at + 8:at + 8 + length])
        at += 12 + length
    return chunks


def check_oiiotool(oiiotool, folder, work):
    cube = folder / "small.exr"
    spec, preview = read(cube, 4)
    names = list(spec.channelnames)
    assert names[:4] == ["R", "G", "B", "A"], f"{cube}: channels start {names[:6]}"
    # oiiotool's plain conversion: PNG holds at most 4 channels, and it keeps the first four.
    view = work / "view.png"
    run([oiiotool, cube, "-o", view])
    vspec, shown = read(view)
    assert vspec.nchannels == 4, f"{view}: {vspec.nchannels} channels"
    expected = np.round(np.clip(preview, 0, 1) * 255) / 255
    assert np.abs(shown - expected).max() <= 1 / 255 + 1e-6, "oiiotool's PNG is not the preview"
    band0 = names.index("S0.400,000000nm")
    _, all_channels = read(cube)
    first_band = np.round(np.clip(all_channels[:, :, band0], 0, 1) * 255) / 255
    assert np.abs(shown[:, :, 0] - first_band).max() > 0.05, "oiiotool's PNG looks like the first band"
    # Display-encoded: the render's own PNG, within one count.
    encoded = work / "view_srgb.png"
    run([oiiotool, cube, "--ch", "R,G,B", "--colorconvert", "linear", "sRGB", "-o", encoded])
    _, counts = read(encoded)
    _, png = read(folder / "small.png")
    worst = np.abs(counts - png).max() * 255
    assert worst <= 1.0 + 1e-6, f"preview encoded as sRGB differs from the render's PNG by {worst} counts"
    # --ch by index works; by a band's name it does not (the comma splits the name).
    bands = work / "bands.exr"
    run([oiiotool, cube, "--ch", f"{band0},{band0 + 1}", "-o", bands])
    bspec, bvalues = read(bands)
    assert list(bspec.channelnames) == names[band0:band0 + 2], bspec.channelnames
    assert np.array_equal(bvalues, all_channels[:, :, band0:band0 + 2]), "--ch by index: other values"
    by_name = run([oiiotool, cube, "--ch", "S0.400,000000nm", "-o", work / "by_name.exr"])
    assert "Unknown channel name" in by_name, f"oiiotool now takes a band by name; update docs/io.md:\n{by_name}"
    print(f"oiiotool: {cube.name} shows its preview (R, G, B, A of {len(names)} channels); "
          f"sRGB-encoded, the render's PNG within {worst:.0f} count; --ch takes bands by index")


def check_xyz(folder):
    spec, xyz = read(folder / "small.xyz.exr")
    assert list(spec.channelnames) == ["R", "G", "B"], spec.channelnames
    chroma = spec.getattribute("chromaticities")
    assert chroma is not None, "no chromaticities attribute"
    assert np.allclose(chroma, [1, 0, 0, 1, 0, 0, 1 / 3, 1 / 3], atol=1e-7), chroma
    assert xyz[:, :, 1].max() > 1.0, "Y (in G) looks empty"
    print(f"OpenImageIO: small.xyz.exr holds X, Y, Z in R, G, B with chromaticities {list(np.round(chroma, 4))}")


def check_hdf5(folder):
    import xarray

    with xarray.open_dataset(folder / "small.h5", engine="h5netcdf") as ds:
        cube = ds["cube"]
        assert cube.dims == ("y", "x", "wavelength"), cube.dims
        assert np.array_equal(ds["wavelength"].values, np.arange(400.0, 701.0, 10.0)), ds["wavelength"].values
        assert cube.attrs["units"] == "W sr-1 m-2 nm-1", cube.attrs["units"]
        _, exr = read(folder / "small.exr")
        spec, _ = read(folder / "small.exr", 4)
        band = list(spec.channelnames).index("S0.550,000000nm")
        assert np.array_equal(cube.sel(wavelength=550).values, exr[:, :, band]), "550 nm differs from the EXR's"
    print(f"xarray {xarray.__version__}: small.h5 dims {dict(cube.sizes)}, wavelength coordinate in nm")


def check_png_colour_spaces(srgb, crt):
    chunks = png_chunks(srgb / "small.png")
    assert "sRGB" in chunks and "iCCP" not in chunks, f"sRGB PNG chunks: {sorted(chunks)}"
    chunks = png_chunks(crt / "small.png")
    assert "iCCP" in chunks and "sRGB" not in chunks, f"CRT PNG chunks: {sorted(chunks)}"
    name, rest = chunks["iCCP"][0].split(b"\0", 1)
    assert rest[0] == 0, "iCCP: compression method"
    icc = zlib.decompress(rest[1:])
    (size,) = struct.unpack(">I", icc[:4])
    assert size == len(icc), f"ICC size {size} against {len(icc)} bytes"
    assert icc[36:40] == b"acsp", "not an ICC profile"
    assert icc[12:16] == b"mntr" and icc[16:20] == b"RGB " and icc[20:24] == b"XYZ ", icc[12:24]
    assert "crt".encode("utf-16-be") in icc, "the profile's description (ICC v4: UTF-16) does not name the display"
    print(f"PNG: sRGB display has an sRGB chunk; CRT display an iCCP chunk ({name.decode()}, {size} bytes, "
          "a display RGB profile)")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    metamer, work = Path(sys.argv[1]), Path(sys.argv[2])
    oiiotool = os.environ.get("OIIOTOOL", "")
    if not oiiotool or not Path(oiiotool).exists():
        print("SKIPPED: no oiiotool (Debian's openimageio-tools)")
        return 77
    work.mkdir(parents=True, exist_ok=True)
    srgb, crt = work / "srgb", work / "crt"
    base = [metamer, "render", SCENE, "--grid", GRID]
    try:
        run(base + ["--write", "cube,png,xyz", "--format", "exr,hdf5", "--out", srgb])
        run(base + ["--write", "png", "--display", "crt", "--out", crt])
        check_oiiotool(oiiotool, srgb, work)
        check_xyz(srgb)
        check_hdf5(srgb)
        check_png_colour_spaces(srgb, crt)
    except AssertionError as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
