"""Metamer: full-spectral rendering of spectral radiance cubes (docs/python.md).

render(), compare(), load_cube() and capture() are the engine's, a C++ extension (metamer._metamer,
engine/python/metamer_module.cpp). This file loads it, says what to install when Vulkan is missing,
and gives a Render what a notebook expects: its display image (``_repr_png_``), a pixel's spectrum
as a colour-science ``SpectralDistribution`` (``Render.sd``) and the cube as an ``xarray.DataArray``
(``Render.to_xarray``). colour-science and xarray are optional: imported only when asked for.
"""

import os as _os
import struct as _struct
import sys as _sys
import zlib as _zlib


class VulkanUnavailableError(ImportError):
    """Metamer renders with Vulkan, and this machine has no Vulkan loader, driver or usable device.

    The driver cannot ship in a wheel: it is the operating system's (on Debian or Ubuntu, Mesa's
    CPU driver lavapipe comes in ``mesa-vulkan-drivers``; a GPU's vendor driver works too)."""


_INSTALL = ("install the Vulkan loader and a driver: on Debian or Ubuntu, `apt-get install libvulkan1 "
            "mesa-vulkan-drivers` (lavapipe, Mesa's CPU driver; a GPU's own Vulkan driver works too)")

try:
    from . import _metamer
except ImportError as _e:
    # The extension links libvulkan.so.1; without it the dynamic loader's message names only the file.
    if "libvulkan" in str(_e):
        raise VulkanUnavailableError(f"metamer cannot load the Vulkan loader: {_e}; {_INSTALL}") from None
    raise


def _started_as_command():
    """True when this import only starts the command-line tool (`python -m metamer`, or the
    `metamer` console script): the tool reports a missing device itself, and `metamer --help` or
    `metamer compare` need none."""
    if _sys.argv[:1] == ["-m"]:  # runpy sets argv[0] to "-m" while it imports the package
        return True
    main = _sys.modules.get("__main__")
    return _os.path.basename(getattr(main, "__file__", "") or "") == "metamer"


if not _started_as_command() and not _os.environ.get("METAMER_SKIP_DEVICE_CHECK"):
    _problem = _metamer._vulkan_problem()
    if _problem:
        raise VulkanUnavailableError(
            f"metamer cannot render on this machine: {_problem}; {_INSTALL}. "
            "(METAMER_SKIP_DEVICE_CHECK=1 imports it anyway, for reading files and the cpu backend.)")

from ._metamer import (  # noqa: E402  (after the check, so a missing driver is one clear error)
    Error,
    InputError,
    NotFoundError,
    Render,
    Warning,
    __version__,
    capture,
    compare,
    kubelka_munk,
    load_cube,
    render,
    _context_count,
)

__all__ = ["Error", "InputError", "NotFoundError", "Render", "VulkanUnavailableError", "Warning", "__version__",
           "capture", "compare", "kubelka_munk", "load_cube", "render"]


# --- What a notebook expects of a Render ---

def _png(counts):
    """PNG bytes of rows × columns × 3 display counts (uint8 or uint16): truecolour, no filter."""
    import numpy as np

    rows, columns, _ = counts.shape
    depth = 8 if counts.dtype == np.uint8 else 16
    pixels = np.ascontiguousarray(counts, dtype=np.uint8 if depth == 8 else ">u2").reshape(rows, -1).view(np.uint8)
    scanlines = np.hstack([np.zeros((rows, 1), np.uint8), pixels])  # filter type 0 before each row

    def chunk(kind, data):
        return _struct.pack(">I", len(data)) + kind + data + _struct.pack(">I", _zlib.crc32(kind + data))

    header = _struct.pack(">IIBBBBB", columns, rows, depth, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", _zlib.compress(scanlines.tobytes(), 6))
            + chunk(b"IEND", b""))


def _repr_png_(self):
    """The display image as PNG bytes, for Jupyter; None (the text repr) unless write kept "display"."""
    counts = self.display
    return None if counts is None else _png(counts)


def _pixel(self, x, y):
    """The cube's spectrum at column x, row y (as an image viewer counts), checked."""
    if self.cube is None:
        raise InputError('this render kept no spectral cube (render with write="cube")')
    for name, value, size in (("x", x, self.width), ("y", y, self.height)):
        if not isinstance(value, int) and not hasattr(value, "__index__"):
            raise TypeError(f"{name} must be an integer pixel index, not {type(value).__name__}")
        if not 0 <= int(value) < size:
            raise IndexError(f"{name} = {int(value)} is outside the image (0 … {size - 1})")
    return self.cube[int(y), int(x)]


def sd(self, x, y, name=None):
    """The spectrum of pixel (x, y) — column x, row y — as a colour-science ``SpectralDistribution``
    of spectral radiance in W·sr⁻¹·m⁻²·nm⁻¹ on the render's wavelengths (needs colour-science)."""
    if self.wavelengths_nm is None:
        raise InputError(f"mode {self.channels} is not spectral: its channels are not a spectrum")
    values = _pixel(self, x, y)
    try:
        import colour
    except ImportError:
        raise ImportError("Render.sd needs colour-science: pip install colour-science") from None
    import numpy as np

    return colour.SpectralDistribution(np.asarray(values, dtype=np.float64), self.wavelengths_nm,
                                       name=name if name is not None else f"pixel ({x}, {y})")


def to_xarray(self):
    """The cube as an ``xarray.DataArray`` with dimensions (y, x, wavelength) — a wavelength
    coordinate in nm — or (y, x, channel) for a reduced mode (needs xarray). Shares the cube's
    memory (read-only)."""
    if self.cube is None:
        raise InputError('this render kept no spectral cube (render with write="cube")')
    try:
        import xarray
    except ImportError:
        raise ImportError("Render.to_xarray needs xarray: pip install xarray") from None
    import numpy as np

    coords = {"y": np.arange(self.height), "x": np.arange(self.width)}
    if self.wavelengths_nm is not None:
        last = "wavelength"
        coords[last] = ("wavelength", np.asarray(self.wavelengths_nm),
                        {"units": "nm", "long_name": "wavelength (band centre)"})
        attrs = {"units": "W sr-1 m-2 nm-1", "long_name": "spectral radiance", "grid": self.grid}
    else:
        last = "channel"
        coords[last] = list(self.channels)
        attrs = {"long_name": self.units}
    return xarray.DataArray(self.cube, dims=("y", "x", last), coords=coords, name="radiance", attrs=attrs)


Render._repr_png_ = _repr_png_
Render.sd = sd
Render.to_xarray = to_xarray
del sd, to_xarray, _repr_png_
