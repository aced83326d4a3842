#!/usr/bin/env python3
"""Independent check of our HDF5 and ENVI cubes with the readers their users have.

Reads the files tests/python/write_cube_formats writes (value = band + 0.25*x + 0.5*y on the grid
380:1020:20, 7x5 pixels): h5py reads pattern.h5, Spectral Python reads pattern_bsq.hdr and
pattern_bil.hdr, and each must hold exactly the values OpenImageIO reads from pattern.exr (and the
pattern itself), with the wavelengths, band widths and metadata the writers promise. xarray, through
h5netcdf, opens pattern.h5 as netCDF: dimensions y, x, wavelength and a wavelength coordinate in nm.

Usage: check_cube_formats.py DIR
Exit codes: 0 pass, 1 fail.
"""

import math
import os
import sys

import numpy as np

GRID = (380.0, 1020.0, 20.0)
WIDTH, HEIGHT = 7, 5
RADIANCE_UNITS = "W sr-1 m-2 nm-1"  # UDUNITS grammar
RADIANCE_UNITS_READABLE = "W·sr⁻¹·m⁻²·nm⁻¹"


def expected_cube():
    start, end, step = GRID
    wavelengths = np.arange(start, end + step / 2, step)
    y, x, band = np.meshgrid(np.arange(HEIGHT), np.arange(WIDTH), np.arange(len(wavelengths)), indexing="ij")
    return wavelengths, (band + 0.25 * x + 0.5 * y).astype(np.float32)


def nearest_band(wavelengths, nm):
    """1-based, as the writer chooses ENVI's default bands (round half away from zero, clamped)."""
    start, step = wavelengths[0], wavelengths[1] - wavelengths[0]
    i = math.floor((nm - start) / step + 0.5)
    return min(max(i, 0), len(wavelengths) - 1) + 1


def read_exr(path):
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(path)
    assert inp, f"OpenImageIO cannot open {path}: {oiio.geterror()}"
    spec = inp.spec()
    pixels = inp.read_image("float")
    inp.close()
    assert pixels is not None, f"OpenImageIO cannot read {path}"

    def nm(name):  # "S0.1000,000000nm" -> 1000.0
        return float(name[3:-2].replace(",", "."))

    names = list(spec.channelnames)
    order = sorted(range(len(names)), key=lambda c: nm(names[c]))
    return np.array([nm(names[c]) for c in order]), np.asarray(pixels)[:, :, order]


def check_hdf5(path, exr_values, wavelengths):
    import h5py

    with h5py.File(path, "r") as f:
        cube = f["cube"]
        assert cube.shape == (HEIGHT, WIDTH, len(wavelengths)), f"/cube shape {cube.shape}"
        assert cube.dtype == np.float32, f"/cube dtype {cube.dtype}"
        assert cube.compression == "gzip" and cube.shuffle, f"/cube filters {cube.compression}, {cube.shuffle}"
        values = cube[()]
        wl = f["wavelength_nm"][()]
        fwhm = f["fwhm_nm"][()]
        assert wl.dtype == np.float64, f"/wavelength_nm dtype {wl.dtype}"
        assert np.array_equal(wl, wavelengths), f"/wavelength_nm {wl.tolist()}"
        assert np.array_equal(fwhm, np.full(len(wavelengths), GRID[2])), f"/fwhm_nm {fwhm.tolist()}"
        attrs = dict(cube.attrs)
        assert attrs.get("units") == RADIANCE_UNITS, f"units {attrs.get('units')!r}"
        assert attrs.get("units_readable") == RADIANCE_UNITS_READABLE, f"units_readable {attrs.get('units_readable')!r}"
        assert attrs.get("quantity") == "spectral radiance", f"quantity {attrs.get('quantity')!r}"
        assert attrs.get("grid") == "380:1020:20", f"grid {attrs.get('grid')!r}"
        assert float(attrs.get("band_width_nm")) == GRID[2], f"band_width_nm {attrs.get('band_width_nm')!r}"
        assert f.attrs.get("metamer:scene") == "pattern", f"metamer:scene {f.attrs.get('metamer:scene')!r}"
    assert np.array_equal(values, exr_values), f"HDF5 and EXR differ by up to {np.abs(values - exr_values).max()}"
    print(f"h5py {__import__('h5py').__version__}: {path}: {values.shape} float32, values equal the EXR's")


def check_xarray(path, exr_values, wavelengths):
    """netCDF readers name the cube's dimensions from its dimension scales, not phony_dim_N."""
    import h5netcdf
    import xarray

    with xarray.open_dataset(path, engine="h5netcdf") as ds:
        cube = ds["cube"]
        assert cube.dims == ("y", "x", "wavelength"), f"dims {cube.dims}"
        assert not any(d.startswith("phony_dim") for d in ds.dims), f"dataset dims {dict(ds.sizes)}"
        assert "wavelength" in ds.coords, f"coords {list(ds.coords)}"
        assert np.array_equal(ds["wavelength"].values, wavelengths), ds["wavelength"].values.tolist()
        assert ds["wavelength"].attrs.get("units") == "nm", ds["wavelength"].attrs
        assert cube.attrs.get("units") == RADIANCE_UNITS, cube.attrs.get("units")
        assert ds["wavelength_nm"].dims == ("wavelength",), ds["wavelength_nm"].dims
        assert np.array_equal(ds["x"].values, np.arange(WIDTH)), ds["x"].values.tolist()
        assert np.array_equal(ds["y"].values, np.arange(HEIGHT)), ds["y"].values.tolist()
        # A spectrum by wavelength, the way an xarray user asks for one.
        spectrum = cube.sel(y=2, x=3, wavelength=slice(400, 460)).values
        band = [int(i) for i in np.flatnonzero((wavelengths >= 400) & (wavelengths <= 460))]
        assert np.array_equal(spectrum, exr_values[2, 3, band]), spectrum.tolist()
        values = cube.values
    assert np.array_equal(values, exr_values), f"xarray and EXR differ by up to {np.abs(values - exr_values).max()}"
    print(f"xarray {xarray.__version__} (h5netcdf {h5netcdf.__version__}): {path}: dims {dict(cube.sizes)}, "
          "a wavelength coordinate in nm, values equal the EXR's")


def check_envi(path, exr_values, wavelengths):
    import spectral

    img = spectral.open_image(path)
    values = np.asarray(img.load())
    assert values.shape == (HEIGHT, WIDTH, len(wavelengths)), f"shape {values.shape} (lines, samples, bands)"
    meta = img.metadata
    assert np.array_equal(np.array(meta["wavelength"], dtype=float), wavelengths), meta["wavelength"]
    assert np.array_equal(np.array(img.bands.centers), wavelengths), img.bands.centers
    assert np.array_equal(np.array(meta["fwhm"], dtype=float), np.full(len(wavelengths), GRID[2])), meta["fwhm"]
    expected_default = [nearest_band(wavelengths, nm) for nm in (610, 550, 465)]
    assert [int(b) for b in meta["default bands"]] == expected_default, meta["default bands"]
    assert meta.get("metamer quantity") == "spectral radiance", meta.get("metamer quantity")
    assert meta.get("metamer scene") == "pattern", meta.get("metamer scene")
    assert meta.get("band names", [None])[0] == "380 nm", meta.get("band names")
    assert np.array_equal(values.astype(np.float32), exr_values), (
        f"ENVI and EXR differ by up to {np.abs(values - exr_values).max()}"
    )
    print(f"Spectral Python {spectral.__version__}: {path}: {values.shape}, interleave {meta['interleave']}, "
          "values equal the EXR's")


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    folder = sys.argv[1]
    try:
        wavelengths, pattern = expected_cube()
        exr_wavelengths, exr_values = read_exr(os.path.join(folder, "pattern.exr"))
        assert np.allclose(exr_wavelengths, wavelengths, rtol=0, atol=1e-6), exr_wavelengths.tolist()
        assert np.array_equal(exr_values, pattern), "the EXR does not hold the pattern"
        check_hdf5(os.path.join(folder, "pattern.h5"), exr_values, wavelengths)
        check_xarray(os.path.join(folder, "pattern.h5"), exr_values, wavelengths)
        for name in ("pattern_bsq.hdr", "pattern_bil.hdr"):
            check_envi(os.path.join(folder, name), exr_values, wavelengths)
    except AssertionError as e:
        print(f"FAIL {folder}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
