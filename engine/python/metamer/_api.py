"""The package's functions as a Python user calls them: typed signatures (inspect.signature, IDEs,
mypy), keyword typos named with a suggestion, and the objects users already hold taken as they
are — colour-science's SpectralDistribution and SpectralShape (duck-typed, never imported), numpy
scalars and arrays, xarray cubes. Each function converts its arguments and calls the engine
(metamer._metamer); nothing is computed here.
"""

from __future__ import annotations

import contextlib
import difflib
import functools
import inspect
import json
import os
import tempfile
from typing import Any, Callable, Literal, Mapping, Optional, Sequence, TypeVar, Union

from . import _metamer

PathLike = Union[str, bytes, "os.PathLike[str]", "os.PathLike[bytes]"]
F = TypeVar("F", bound=Callable[..., Any])


def _keywords_checked(function: F) -> F:
    """A keyword the function does not take is a TypeError that names it and the nearest one it
    does take (`grids=` → "did you mean 'grid'?"), not a list of signatures."""
    parameters = inspect.signature(function).parameters
    names = [n for n, p in parameters.items() if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)]

    @functools.wraps(function)
    def call(*args: Any, **keywords: Any) -> Any:
        for keyword in keywords:
            if keyword not in parameters:
                near = difflib.get_close_matches(keyword, names, n=1, cutoff=0.6)
                hint = f"; did you mean {near[0]!r}?" if near else f"; it takes {', '.join(names)}"
                raise TypeError(f"{function.__name__}() got an unexpected keyword argument {keyword!r}{hint}")
        return function(*args, **keywords)

    return call  # type: ignore[return-value]


# --- Objects users hold, as the engine takes them.

def _is_spectrum(x: Any) -> bool:
    """A SpectralDistribution, duck-typed: .wavelengths and .values, one value per wavelength."""
    return hasattr(x, "wavelengths") and hasattr(x, "values") and not isinstance(x, (str, bytes, Mapping))


def _float_array(x: Any, what: str, where: str) -> Any:
    """x as float64 numbers, or an InputError naming where and what they are (numpy's own error
    says neither: "could not convert string to float: 'a'")."""
    import numpy as np

    try:
        return np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise _metamer.InputError(f"{where}: the {what} are not numbers ({e})") from None


def _spectrum_json(x: Any, where: str) -> dict[str, list[float]]:
    """A spectrum object as the scene format's inline spectrum (docs/scene-format.md)."""
    wavelengths = _float_array(x.wavelengths, "spectrum's wavelengths", where).ravel()
    values = _float_array(x.values, "spectrum's values", where)
    if values.ndim != 1 or values.shape != wavelengths.shape:
        raise _metamer.InputError(f"{where}: a spectrum with {values.shape} values on {wavelengths.size} wavelengths; "
                                  "expected one value per wavelength (a multi-channel object is a detector)")
    return {"wavelengths_nm": wavelengths.tolist(), "values": values.tolist()}


def _scene_values(x: Any, where: str, depth: int = 0) -> Any:
    """A scene dict or an override's value with every spectrum object made inline JSON. Past the
    parser's depth the value is passed on as it is, for the engine to refuse at its key path."""
    if depth > 64:
        return x
    if _is_spectrum(x):
        return _spectrum_json(x, where)
    if isinstance(x, Mapping):
        return {k: _scene_values(v, f"{where}.{k}", depth + 1) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_scene_values(v, f"{where}.{i}", depth + 1) for i, v in enumerate(x)]
    return x


def _number_text(v: float) -> str:
    return repr(float(v)).removesuffix(".0") if float(v) == float(v) else str(v)


def _grid_text(grid: Any, keyword: str = "grid") -> Optional[str]:
    """A grid as "START:END:STEP": the text itself; a SpectralShape-like object (.start, .end,
    .interval); or evenly spaced wavelengths (a list or array)."""
    if grid is None or isinstance(grid, str):
        return grid
    if all(hasattr(grid, a) for a in ("start", "end", "interval")):
        return f"{_number_text(grid.start)}:{_number_text(grid.end)}:{_number_text(grid.interval)}"
    import numpy as np

    try:
        w = np.asarray(grid, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{keyword}: expected \"START:END:STEP\", an object with .start, .end and .interval (a "
                        f"colour SpectralShape) or evenly spaced wavelengths, got {type(grid).__name__}") from None
    if w.ndim != 1 or w.size < 2:
        raise _metamer.InputError(f"{keyword}: {w.size} wavelength(s); expected at least two, evenly spaced")
    steps = np.diff(w)
    if not np.all(np.isfinite(w)) or not np.allclose(steps, steps[0], rtol=0, atol=1e-9 * max(1.0, abs(w).max())):
        raise _metamer.InputError(f"{keyword}: the wavelengths are not evenly spaced (steps {steps.min():g} … "
                                  f"{steps.max():g} nm); a grid has one step")
    return f"{_number_text(w[0])}:{_number_text(w[-1])}:{_number_text(steps[0])}"


def _detector_file(detector: Any, folder: str) -> Optional[str]:
    """A detector given as an object with .wavelengths, .values (wavelengths × channels) and
    .labels (a colour MultiSpectralDistributions) written as the user table `csv:PATH` reads."""
    if detector is None or isinstance(detector, str):
        return detector
    if not all(hasattr(detector, a) for a in ("wavelengths", "values", "labels")):
        raise TypeError("detector: expected a name (cie1931, camera:<name>, csv:<path>, …) or an object with "
                        f".wavelengths, .values and .labels (a colour MultiSpectralDistributions), got "
                        f"{type(detector).__name__}")
    wavelengths = _float_array(detector.wavelengths, "detector's wavelengths", "detector").ravel()
    values = _float_array(detector.values, "detector's values", "detector")
    labels = [str(label) for label in detector.labels]
    if values.ndim == 1:
        values = values[:, None]
    if values.shape != (wavelengths.size, len(labels)):
        raise _metamer.InputError(f"detector: {values.shape} values for {wavelengths.size} wavelengths and "
                                  f"{len(labels)} labels; expected wavelengths × channels")
    for label in labels:
        if not label or any(c in label for c in ",\n\r\""):
            raise _metamer.InputError(f"detector: channel label {label!r}; expected a non-empty name without "
                                      "commas, quotes or line breaks")
    path = os.path.join(folder, "detector.csv")
    with open(path, "w", encoding="utf-8") as f:
        f.write(",".join(["wavelength_nm", *labels]) + "\n")
        for w, row in zip(wavelengths.tolist(), values.tolist()):
            f.write(",".join(repr(float(v)) for v in [w, *row]) + "\n")
    return "csv:" + path


def _cube_operand(x: Any, wavelengths: Any, which: str) -> Any:
    """A compare operand: a path or a Render as they are; an xarray DataArray with a wavelength
    coordinate, a dict as load_cube returns, or an array with `wavelengths`, as (cube, grid)."""
    import numpy as np

    is_array = isinstance(x, np.ndarray) or hasattr(x, "__array__") or hasattr(x, "__array_interface__")
    if not (is_array or isinstance(x, Mapping)) or isinstance(x, (str, bytes, os.PathLike, _metamer.Render)):
        return x  # a path, a Render or a (cube, grid) pair; anything else is refused by the engine, by name

    if hasattr(x, "dims") and hasattr(x, "coords"):  # xarray
        if "wavelength" not in x.dims:
            raise _metamer.InputError(f"{which}: an xarray object without a 'wavelength' dimension (dims {x.dims})")
        x = x.transpose(..., "wavelength")
        return (np.asarray(x.values, dtype=np.float32), _grid_text(x["wavelength"].values, which))
    if isinstance(x, Mapping) and "cube" in x and "grid" in x:  # load_cube's dict
        return (x["cube"], x["grid"])
    if wavelengths is None:
        raise TypeError(f"{which}: an array needs its wavelengths: compare(a, b, wavelengths=...) (or pass a path, "
                        "a Render, an xarray DataArray or load_cube's dict)")
    return (np.asarray(x, dtype=np.float32), _grid_text(wavelengths, "wavelengths"))


def _progress_call(progress: Any) -> Optional[Callable[[str, int, int, float], None]]:
    """What the engine calls between units of work, (unit, done, total, seconds), from a
    user's `progress`: a callable progress(done, total), or a tqdm bar (anything with .update and
    .total), reset to the render's total and advanced by each unit."""
    if progress is None:
        return None
    if hasattr(progress, "update") and hasattr(progress, "total"):
        bar, last = progress, [0]

        def advance(unit: str, done: int, total: int, seconds: float) -> None:
            if done == 0 or bar.total != total:
                if hasattr(bar, "reset"):
                    bar.reset(total=total)
                else:
                    bar.total = total
                if hasattr(bar, "unit"):
                    bar.unit = unit
                last[0] = 0
            bar.update(done - last[0])
            last[0] = done

        return advance
    if callable(progress):
        def call(unit: str, done: int, total: int, seconds: float) -> None:
            progress(done, total)

        return call
    raise TypeError(f"progress: expected a callable progress(done, total) or a tqdm bar, got {type(progress).__name__}")


def _numbers(x: Any) -> Any:
    """The statistics as numbers: JSON's "inf", "-inf" and "nan" strings become floats."""
    if isinstance(x, dict):
        return {k: _numbers(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_numbers(v) for v in x]
    if isinstance(x, str) and x in ("inf", "-inf", "nan", "Infinity", "-Infinity", "NaN"):
        return float(x.replace("Infinity", "inf").replace("NaN", "nan"))
    return x


# --- The functions.

@_keywords_checked
def render(
    scene: Union[PathLike, Mapping[str, Any]],
    *,
    grid: Any = None,
    overrides: Union[Mapping[str, Any], Sequence[str], str, None] = None,
    backend: Literal["gpu", "cpu"] = "gpu",
    detector: Any = None,
    adapt: Optional[Literal["none", "vonkries-xyz", "vonkries", "bradford", "cat02", "cat16"]] = None,
    display: Optional[Literal["srgb", "crt"]] = None,
    bits: Optional[Literal[8, 16]] = None,
    integration: Optional[Literal["riemann", "trapezoid", "astm-e308"]] = None,
    xyz: Optional[Literal["relative", "absolute"]] = None,
    mode: str = "full",
    write: Union[str, Sequence[str], None] = None,
    resample: Optional[Literal["interpolate", "sprague", "band-mean"]] = None,
    ssaa: int = 1,
    validation: bool = False,
    device: str = "",
    allow_outside_paths: bool = False,
    name: str = "scene",
    base_dir: Optional[PathLike] = None,
    format: Union[str, Sequence[str], None] = None,
    memory_budget: Optional[float] = None,
    half: bool = False,
    compression: str = "piz",
    strict_coverage: bool = False,
    readback: Literal["auto", "map", "copy"] = "auto",
    progress: Union[Callable[[int, int], Any], Any, None] = None,
    interruptible: bool = True,
    interreflection: Union[bool, Mapping[str, Any], None] = None,
) -> _metamer.Render:
    if interreflection is not None:
        # The scene's "interreflection" key, set after the other overrides (so it wins).
        value = dict(interreflection) if isinstance(interreflection, Mapping) else interreflection
        if not isinstance(value, (bool, dict)):
            raise TypeError(f"interreflection: expected True, False or a dict of its settings, got {value!r}")
        if overrides is None or isinstance(overrides, Mapping):
            overrides = {**(overrides or {}), "interreflection": value}
        else:
            overrides = ([overrides] if isinstance(overrides, str) else list(overrides)) + [
                "interreflection=" + json.dumps(value)]
    if isinstance(scene, Mapping):
        scene = _scene_values(dict(scene), "scene")
    if isinstance(overrides, Mapping):
        overrides = {k: _scene_values(v, f"overrides.{k}") for k, v in overrides.items()}
    # A detector object is written as a table for the render to read, then removed.
    folder = None if detector is None or isinstance(detector, str) else tempfile.TemporaryDirectory(prefix="metamer-")
    with folder if folder is not None else contextlib.nullcontext():
        return _metamer.render(
            scene, grid=_grid_text(grid), overrides=overrides, backend=backend,
            detector=_detector_file(detector, folder.name if folder else ""), adapt=adapt, display=display, bits=bits,
            integration=integration, xyz=xyz, mode=mode, write=write, resample=resample, ssaa=ssaa,
            validation=validation, device=device, allow_outside_paths=allow_outside_paths, name=name,
            base_dir=base_dir, format=format, memory_budget=memory_budget, half=half, compression=compression,
            strict_coverage=strict_coverage, readback=readback, progress=_progress_call(progress),
            interruptible=interruptible)


@_keywords_checked
def compare(
    a: Any,
    b: Any,
    *,
    wavelengths: Any = None,
    mask: Optional[PathLike] = None,
    tolerance: Optional[PathLike] = None,
    resample: bool = False,
    detector: str = "",
    adapt: str = "",
    display: str = "",
    pixel_threshold: Optional[float] = None,
    relative_floor: Optional[float] = None,
    delta_e: bool = True,
) -> dict[str, Any]:
    stats = _metamer.compare(
        _cube_operand(a, wavelengths, "a"), _cube_operand(b, wavelengths, "b"), mask=mask, tolerance=tolerance,
        resample=resample, detector=detector, adapt=adapt, display=display, pixel_threshold=pixel_threshold,
        relative_floor=relative_floor, delta_e=delta_e)
    numbers: dict[str, Any] = _numbers(stats)
    return numbers


@_keywords_checked
def load_cube(path: PathLike) -> dict[str, Any]:
    return _metamer.load_cube(path)


@_keywords_checked
def capture(
    source: Union[PathLike, _metamer.Render],
    sensor: PathLike,
    *,
    seed: int = 0,
    frame: int = 0,
    frames: int = 1,
    exposure: Optional[float] = None,
    noise: bool = True,
    out: Optional[PathLike] = None,
    illuminant: Optional[str] = None,
) -> dict[str, Any]:
    return _metamer.capture(source, sensor, seed=seed, frame=frame, frames=frames, exposure=exposure, noise=noise,
                            out=out, illuminant=illuminant)


@_keywords_checked
def demosaic(mosaic: Any, *, cfa: str = "RGGB", method: str = "bilinear") -> Any:
    import numpy
    return _metamer.demosaic(numpy.ascontiguousarray(mosaic, dtype=numpy.float64), cfa, method)


@_keywords_checked
def develop(
    raw: Any,
    sensor: PathLike,
    *,
    white_balance: Optional[str] = None,
    patch: Optional[Any] = None,
    illuminant: Optional[str] = None,
    demosaic: Optional[str] = None,
    colour_correction: Optional[str] = None,
    exposure: Optional[float] = None,
    display: Optional[Literal["srgb", "crt"]] = None,
    bits: Optional[Literal[8, 16]] = None,
) -> dict[str, Any]:
    import numpy
    frame = numpy.asarray(raw)
    if frame.dtype.kind not in "ui":
        raise _metamer.InputError(f"raw: expected the sensor's digital numbers (an integer array, as metamer.capture's raw); "
                         f"got {frame.dtype}")
    if frame.size and (frame.min() < 0 or frame.max() > 65535):
        raise _metamer.InputError("raw: digital numbers must lie in 0 … 65535")
    if patch is not None:
        values = list(patch) if isinstance(patch, (list, tuple, numpy.ndarray)) else None
        if values is None or len(values) != 4 or not all(isinstance(v, (int, numpy.integer)) for v in values):
            raise _metamer.InputError(f"patch: expected [x, y, width, height], four whole numbers of pixels; got {patch!r}")
        patch = [int(v) for v in values]
    result: dict[str, Any] = _metamer.develop(numpy.ascontiguousarray(frame, dtype=numpy.uint16), sensor,
                                              white_balance=white_balance, patch=patch, illuminant=illuminant,
                                              demosaic=demosaic, colour_correction=colour_correction,
                                              exposure=exposure, display=display, bits=bits)
    return result


@_keywords_checked
def developed_colour_error(
    developed: Any,
    reference: Any,
    *,
    white: Union[str, Sequence[float]],
    adaptation: str = "bradford",
    exposure_from: int = 0,
) -> dict[str, Any]:
    import numpy
    result: dict[str, Any] = _metamer.developed_colour_error(
        numpy.ascontiguousarray(numpy.atleast_2d(developed), dtype=numpy.float64),
        numpy.ascontiguousarray(numpy.atleast_2d(reference), dtype=numpy.float64),
        white if isinstance(white, str) else [float(v) for v in white], adaptation, exposure_from)
    return result


@_keywords_checked
def delta_e2000(lab_a: Any, lab_b: Any) -> Any:
    import numpy
    return _metamer.delta_e2000(numpy.ascontiguousarray(numpy.atleast_2d(lab_a), dtype=numpy.float64),
                                numpy.ascontiguousarray(numpy.atleast_2d(lab_b), dtype=numpy.float64))


@_keywords_checked
def photon_transfer(a: Any, b: Any, sensor: PathLike, *, rect: Sequence[int], channel: str) -> dict[str, Any]:
    import numpy
    frames = []
    for name, frame in (("a", a), ("b", b)):
        f = numpy.asarray(frame)
        if f.dtype.kind not in "ui":
            raise _metamer.InputError(f"{name}: expected a raw frame's digital numbers (integers); got {f.dtype}")
        frames.append(numpy.ascontiguousarray(f, dtype=numpy.uint16))
    result: dict[str, Any] = _metamer.photon_transfer(frames[0], frames[1], sensor, [int(v) for v in rect], channel)
    return result


@_keywords_checked
def slanted_edge_sfr(image: Any) -> dict[str, Any]:
    import numpy
    result: dict[str, Any] = _metamer.slanted_edge_sfr(numpy.ascontiguousarray(image, dtype=numpy.float64))
    return result


@_keywords_checked
def fit_colour_correction(rgb: Any, xyz: Any, *, form: str = "linear") -> Any:
    import numpy
    return _metamer.fit_colour_correction(numpy.ascontiguousarray(rgb, dtype=numpy.float64),
                                          numpy.ascontiguousarray(xyz, dtype=numpy.float64), form)


def _engine_doc(function: Any) -> str:
    """The extension's docstring without pybind11's signature line (the signature is this module's)."""
    doc = function.__doc__ or ""
    return doc.split("\n\n", 1)[1] if doc.startswith(function.__name__ + "(") else doc


render.__doc__ = _engine_doc(_metamer.render) + (
    "\nprogress: a callable progress(done, total), or a tqdm bar, told how far the render is between its "
    "strips, passes or rows; Ctrl-C (or a notebook's interrupt) stops a render between them with "
    "KeyboardInterrupt, within one strip of at most 512² samples (pixels × ssaa²): larger images render in "
    "strips, equal to one frame to float rounding; interruptible=False draws one frame (the CLI's values bit for "
    "bit) and a stop waits for it.\n"
    "In Python also: `grid` may be a colour SpectralShape (.start, .end, .interval) or evenly spaced "
    "wavelengths; any object with .wavelengths and .values (a colour SpectralDistribution) is a spectrum in a "
    "scene dict or an override; `detector` may be an object with .wavelengths, .values (wavelengths × channels) "
    "and .labels (a colour MultiSpectralDistributions). Returns a Render.")
compare.__doc__ = _engine_doc(_metamer.compare) + (
    "\n\nA and B may also be an xarray DataArray with a 'wavelength' dimension, the dict load_cube returns, or a "
    "rows × columns × bands array with `wavelengths` (evenly spaced, nm). Infinite and undefined statistics are "
    "floats (inf, nan).")
load_cube.__doc__ = _engine_doc(_metamer.load_cube)
capture.__doc__ = _engine_doc(_metamer.capture)
demosaic.__doc__ = _engine_doc(_metamer.demosaic)
slanted_edge_sfr.__doc__ = _engine_doc(_metamer.slanted_edge_sfr)
fit_colour_correction.__doc__ = _engine_doc(_metamer.fit_colour_correction)
develop.__doc__ = _engine_doc(_metamer.develop)
developed_colour_error.__doc__ = _engine_doc(_metamer.developed_colour_error)
photon_transfer.__doc__ = _engine_doc(_metamer.photon_transfer)
delta_e2000.__doc__ = _engine_doc(_metamer.delta_e2000)
