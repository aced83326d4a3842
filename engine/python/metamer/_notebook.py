"""What a notebook expects of a Render: its display image (``_repr_png_``, which Jupyter shows), a
pixel's spectrum as a colour-science ``SpectralDistribution`` (``Render.sd``) and the cube as an
``xarray.DataArray`` with a wavelength coordinate (``Render.to_xarray``). colour-science and xarray
are optional: imported only when asked for.
"""

import importlib
from typing import Any, Optional
import struct as _struct
import zlib as _zlib

from ._metamer import InputError, Render


def _png(counts: Any) -> bytes:
    """PNG bytes of rows × columns × 3 display counts (uint8 or uint16): truecolour, no filter."""
    import numpy as np

    rows, columns, _ = counts.shape
    depth = 8 if counts.dtype == np.uint8 else 16
    pixels = np.ascontiguousarray(counts, dtype=np.uint8 if depth == 8 else ">u2").reshape(rows, -1).view(np.uint8)
    scanlines = np.hstack([np.zeros((rows, 1), np.uint8), pixels])  # filter type 0 before each row

    def chunk(kind: bytes, data: bytes) -> bytes:
        return _struct.pack(">I", len(data)) + kind + data + _struct.pack(">I", _zlib.crc32(kind + data))

    header = _struct.pack(">IIBBBBB", columns, rows, depth, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", _zlib.compress(scanlines.tobytes(), 6))
            + chunk(b"IEND", b""))


def _repr_png_(self: Render) -> Optional[bytes]:
    """The display image as PNG bytes, for Jupyter; None (the text repr) unless write kept "display"."""
    counts = self.display
    return None if counts is None else _png(counts)


def _pixel(self: Render, x: int, y: int) -> Any:
    """The cube's spectrum at column x, row y (as an image viewer counts), checked."""
    if self.cube is None:
        raise InputError('this render kept no spectral cube (render with write="cube")')
    for name, value, size in (("x", x, self.width), ("y", y, self.height)):
        if not isinstance(value, int) and not hasattr(value, "__index__"):
            raise TypeError(f"{name} must be an integer pixel index, not {type(value).__name__}")
        if not 0 <= int(value) < size:
            raise IndexError(f"{name} = {int(value)} is outside the image (0 … {size - 1})")
    return self.cube[int(y), int(x)]


def sd(self: Render, x: int, y: int, name: Optional[str] = None) -> Any:
    """The spectrum of pixel (x, y) — column x, row y — as a colour-science ``SpectralDistribution``
    of spectral radiance in W·sr⁻¹·m⁻²·nm⁻¹ on the render's wavelengths (needs colour-science)."""
    if self.wavelengths_nm is None:
        raise InputError(f"mode {self.channels} is not spectral: its channels are not a spectrum")
    values = _pixel(self, x, y)
    try:
        colour = importlib.import_module("colour")  # not `import`: type checkers need not read colour-science
    except ImportError:
        raise ImportError("Render.sd needs colour-science: pip install colour-science") from None
    import numpy as np

    return colour.SpectralDistribution(np.asarray(values, dtype=np.float64), self.wavelengths_nm,
                                       name=name if name is not None else f"pixel ({x}, {y})")


def to_xarray(self: Render) -> Any:
    """The cube as an ``xarray.DataArray`` with dimensions (y, x, wavelength) — a wavelength
    coordinate in nm — or (y, x, channel) for a reduced mode (needs xarray). Shares the cube's
    memory (read-only)."""
    if self.cube is None:
        raise InputError('this render kept no spectral cube (render with write="cube")')
    try:
        xarray = importlib.import_module("xarray")
    except ImportError:
        raise ImportError("Render.to_xarray needs xarray: pip install xarray") from None
    import numpy as np

    coords: dict[str, Any] = {"y": np.arange(self.height), "x": np.arange(self.width)}
    if self.wavelengths_nm is not None:
        last = "wavelength"
        coords[last] = ("wavelength", np.asarray(self.wavelengths_nm),
                        {"units": "nm", "long_name": "wavelength (band centre)"})
        attrs = {"units": "W sr-1 m-2 nm-1", "long_name": "spectral radiance", "grid": self.grid}
    else:
        last = "channel"
        coords[last] = list(self.channels or [])
        attrs = {"long_name": self.units}
    return xarray.DataArray(self.cube, dims=("y", "x", last), coords=coords, name="radiance", attrs=attrs)


# setattr, not assignment: the stub (_metamer.pyi) declares them as the class's own methods.
setattr(Render, "_repr_png_", _repr_png_)
setattr(Render, "sd", sd)
setattr(Render, "to_xarray", to_xarray)
del sd, to_xarray, _repr_png_
