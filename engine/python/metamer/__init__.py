"""Metamer: full-spectral rendering of spectral radiance cubes (docs/python.md).

render(), compare(), load_cube() and capture() are the engine's, a C++ extension (metamer._metamer,
engine/python/*.cpp), called through _api.py, which types them and takes the objects
users hold (colour-science spectra and shapes, numpy, xarray); kubelka_munk.py does the same for
the Kubelka–Munk functions. This file loads the extension and
says what to install when Vulkan is missing; _notebook.py gives a Render what a notebook expects.
"""

import os as _os
import sys as _sys


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


def _started_as_command() -> bool:
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
    _context_count,
)
from typing import Any as _Any, Dict as _Dict  # noqa: E402
from ._api import PathLike as _PathLike  # noqa: E402
from ._api import capture, compare, delta_e2000, demosaic, develop, developed_colour_error, fit_colour_correction, load_cube, photon_transfer, render, slanted_edge_sfr  # noqa: E402


def camera_report(sensor: _PathLike, out: _PathLike, *, illuminant: str = "illuminants/D65", seed: int = 0,
                  backend: str = "gpu", exposures: int = 16) -> _Dict[str, _Any]:
    """The camera report (metamer/report.py, docs/camera.md): renders the charts under `illuminant`,
    captures and develops them with `sensor`, writes report.png, report.svg, report.json and CSVs
    into `out`, and returns what report.json holds. Imported on first use (matplotlib is heavy)."""
    from . import report
    return report.camera_report(sensor, out, illuminant=illuminant, seed=seed, backend=backend, exposures=exposures)


from . import kubelka_munk  # noqa: E402  (the engine's Kubelka–Munk functions, typed and checked)
from . import _notebook  # noqa: E402,F401  (gives Render its notebook methods)

__all__ = ["Error", "InputError", "NotFoundError", "Render", "VulkanUnavailableError", "Warning", "__version__",
           "camera_report", "capture", "compare", "delta_e2000", "demosaic", "develop", "developed_colour_error", "fit_colour_correction", "kubelka_munk", "load_cube", "photon_transfer", "render", "slanted_edge_sfr"]
