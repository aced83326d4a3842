"""Kubelka–Munk films and Saunderson's correction, per wavelength: the functions the paints use
(docs/physics.md, "Paints and coatings"; docs/python.md), computed by the engine
(spectral/kubelka_munk.h, through metamer._metamer._kubelka_munk). Here they are typed and their
arguments checked, as render() and compare() are: a wrong type is a TypeError and a value outside
the physical domain a metamer.InputError, each naming the argument and what it takes; a keyword
typo names the nearest keyword. The domains are the scene reader's for the same quantities
(scene/scene_json.cpp, scene/scene_on_grid.cpp), but for one: a film may be 0 m thick here.

Element-wise over numpy arrays: any mix of arrays and numbers, broadcast together; a float when
every argument is a number. K and S are per metre (m⁻¹) and thicknesses in metres, as in a scene
(any unit pair whose product is a number works, within the domains).
"""

from __future__ import annotations

import math
import re
from typing import Any, Callable, Mapping, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

from . import _metamer
from ._api import _keywords_checked

_engine: Any = _metamer._kubelka_munk

Number = Union[float, np.floating[Any], np.integer[Any]]
"""A number: a Python int or float, or a numpy scalar."""
Values = Union[Number, Sequence[float], Sequence[Sequence[float]], npt.NDArray[np.floating[Any]],
               npt.NDArray[np.integer[Any]]]
"""A number or an array of numbers (a list, nested lists, a numpy array)."""
Result = npt.NDArray[np.float64]
# Each function has two overloads: numbers in, a float out; arrays (which include numbers) in, an
# array out. mypy calls such a pair an unsafe overlap, since the first returns a float where the
# second promises an array; the order resolves it (the first that matches wins), so each first
# overload says `type: ignore[overload-overlap]`.

__all__ = ["Number", "Values", "reflectance", "transmittance", "infinite", "k_over_s", "saunderson", "saunderson_body",
           "saunderson_inverse", "k1", "k2", "external_diffuse_reflectance", "mix", "stack"]

_WHAT = "a number or an array of numbers"
_MAX_ITEMS = 64  # a scene's paint takes 1 … 64 layers, and a layer 1 … 64 pigments


class _Domain:
    """The values an argument takes: lo … hi, each end open or closed, and optionally +inf (an
    opaque film's thickness). `says` is what the message says the argument is."""

    def __init__(self, lo: float, hi: float, says: str, *, lo_open: bool = False, hi_open: bool = False,
                 infinite: bool = False) -> None:
        self.lo, self.hi, self.lo_open, self.hi_open = lo, hi, lo_open, hi_open
        self.infinite, self.says = infinite, says

    def interval(self) -> str:
        def end(x: float) -> str:
            return "∞" if math.isinf(x) else re.sub(r"e\+0*", "e", f"{x:g}")  # 1e12, as the scene reader writes it
        return f"{'(' if self.lo_open else '['}{end(self.lo)}, {end(self.hi)}{')' if self.hi_open else ']'}"

    def holds(self, a: Result) -> npt.NDArray[np.bool_]:
        with np.errstate(invalid="ignore"):
            ok = (a > self.lo if self.lo_open else a >= self.lo) & (a < self.hi if self.hi_open else a <= self.hi)
            if self.infinite:
                ok |= a == math.inf
        return ok


# The domains, each where the scene reader draws the line for the same quantity. A film's K and S
# as scene/scene_on_grid.cpp checks a layer's once its pigments are mixed in (finite, ≥ 0); what
# goes into mix() as scene/scene_json.cpp checks a K, S, k or s spectrum (< 10¹²). A thickness may
# be 0 here, since the engine evaluates one where a thickness map scales a layer's down to 0 (a
# scene's own must be > 0).
_COEFFICIENT = _Domain(0.0, math.inf, "a Kubelka–Munk coefficient (m⁻¹), finite and ≥ 0", hi_open=True)
_MIXED = _Domain(0.0, 1e12, "a Kubelka–Munk coefficient (m⁻¹)", hi_open=True)
_THICKNESS = _Domain(0.0, 1e3, "a thickness in metres, or inf for an opaque film", infinite=True)
_THICKNESS_ABOVE = _Domain(0.0, 1e3, "a thickness in metres; only the bottom film may be opaque (inf): an opaque film "
                           "hides the films beneath it")
_REFLECTANCE = _Domain(0.0, 1.0, "a reflectance")
_R_INFINITE = _Domain(0.0, 1.0, "the reflectance of an opaque film (K/S is infinite at 0)", lo_open=True)
_SURFACE = _Domain(0.0, 1.0, "a surface's reflectance k1 or k2", hi_open=True)  # "surface": {"k1": …, "k2": …}
_INDEX = _Domain(1.0, 5.0, "a refractive index")  # "surface": {"ior": n}
_CONCENTRATION = _Domain(0.0, 1e6, "a pigment's concentration")


def _kind(x: Any, a: npt.NDArray[Any]) -> str:
    """What x is, for a TypeError: its type, and for a sequence or array what it holds."""
    if a.ndim == 0 or a.size == 0:
        return type(x).__name__
    if a.dtype.kind == "O":
        odd = next((v for v in a.flat if not isinstance(v, (int, float))), a.flat[0])
        return f"{type(x).__name__} holding {type(odd).__name__}"
    names = {"b": "bool", "U": "str", "S": "bytes", "c": "complex", "M": "datetime64", "m": "timedelta64"}
    return f"{type(x).__name__} of {names.get(a.dtype.kind, str(a.dtype))}"


def _numbers(x: Any, name: str) -> Result:
    """x as float64, if it is a number or an array of numbers (not a bool, a str, None, ...)."""
    if x is None or isinstance(x, (str, bytes, bool, Mapping, set, frozenset)):
        raise TypeError(f"{name}: expected {_WHAT}, got {type(x).__name__}")
    try:
        a = np.asarray(x)
    except (TypeError, ValueError):  # a ragged list
        raise TypeError(f"{name}: expected {_WHAT}, got a {type(x).__name__} of rows of different lengths") from None
    if a.dtype.kind == "O" and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in a.flat):
        a = a.astype(np.float64)  # ints beyond int64: numbers still (a domain then says if they are too large)
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{name}: expected {_WHAT}, got {_kind(x, a)}")
    return a.astype(np.float64, copy=False)


def _first(bad: npt.NDArray[np.bool_]) -> tuple[tuple[int, ...], str]:
    """The index of the first True in `bad`, and " at index i" (or [i, j]) for a message."""
    at = tuple(int(i) for i in np.argwhere(bad)[0])
    return at, (f" at index {at[0] if len(at) == 1 else list(at)}" if at else "")


def _checked(x: Any, name: str, domain: _Domain) -> Result:
    """x as float64, every value within `domain`; else an InputError naming the first one outside."""
    a = _numbers(x, name)
    ok = domain.holds(a)
    if not ok.all():
        at, where = _first(~ok)
        v = float(a[at])
        if math.isnan(v):
            raise _metamer.InputError(f"{name}: nan{where} is not a number; expected {domain.says}, in "
                                      f"{domain.interval()}")
        raise _metamer.InputError(f"{name}: {v:g}{where} is outside the allowed range {domain.interval()}; expected "
                                  f"{domain.says}")
    return a


def _shape(arrays: Mapping[str, Result]) -> tuple[int, ...]:
    """The shape the arrays broadcast to; an InputError naming them and their shapes if they do not."""
    try:
        return np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shaped = {n: a.shape for n, a in arrays.items() if a.ndim}
        shapes = ", ".join(map(str, shaped.values()))
        raise _metamer.InputError(f"{', '.join(shaped)}: arrays of shapes {shapes} do not broadcast together (numpy's "
                                  "rule: each dimension equal, or 1)") from None


def _elementwise(function: Callable[..., Any], **arrays: Result) -> Union[float, Result]:
    """The engine's vectorized function on checked arrays: a float when all are numbers."""
    _shape(arrays)
    result: Union[float, Result] = function(*arrays.values())
    return result


def _is_sequence(x: Any) -> bool:
    return (isinstance(x, Sequence) and not isinstance(x, (str, bytes))) or (isinstance(x, np.ndarray) and x.ndim > 0)


def _items(x: Any, name: str, item: str) -> list[Any]:
    """A list of 1 … 64 tuples (or lists, or array rows) of three, as mix() and stack() take them."""
    if not _is_sequence(x):
        raise TypeError(f"{name}: expected a list of {item} tuples, got {type(x).__name__}")
    if not 1 <= len(x) <= _MAX_ITEMS:
        raise _metamer.InputError(f"{name}: {len(x)} items; expected 1 … {_MAX_ITEMS} {item} tuples")
    for i, t in enumerate(x):
        if not _is_sequence(t) or len(t) != 3:
            got = f"{len(t)} values" if _is_sequence(t) else type(t).__name__
            raise TypeError(f"{name}[{i}]: expected a {item} tuple, got {got}")
    return list(x)


def _flat(arrays: list[Result], shape: tuple[int, ...]) -> Result:
    """Items × points: each array broadcast to `shape`, flattened, one row per item."""
    return np.stack([np.broadcast_to(a, shape).ravel() for a in arrays])


# --- One film.

@overload
def reflectance(K: Number, S: Number, X: Number,  # type: ignore[overload-overlap]
                substrate: Number = 0.0) -> float: ...
@overload
def reflectance(K: Values, S: Values, X: Values, substrate: Values = 0.0) -> Result: ...
@_keywords_checked
def reflectance(K: Values, S: Values, X: Values, substrate: Values = 0.0) -> Union[float, Result]:
    """R of a film of absorption K and scattering S (m⁻¹) and thickness X (m; math.inf for an opaque
    film) over a substrate of reflectance `substrate` (0: black): Kubelka's
    (1 − R_g(a − b·coth bSX))/(a − R_g + b·coth bSX), a = 1 + K/S, b = √(a² − 1).
    K, S: finite, ≥ 0; X: 0 … 1000 m or inf; substrate: 0 … 1."""
    return _elementwise(_engine.reflectance, K=_checked(K, "K", _COEFFICIENT), S=_checked(S, "S", _COEFFICIENT),
                        X=_checked(X, "X", _THICKNESS), substrate=_checked(substrate, "substrate", _REFLECTANCE))


@overload
def transmittance(K: Number, S: Number, X: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def transmittance(K: Values, S: Values, X: Values) -> Result: ...
@_keywords_checked
def transmittance(K: Values, S: Values, X: Values) -> Union[float, Result]:
    """T of a film for diffuse light: b/(a·sinh bSX + b·cosh bSX) (0 for an opaque film; e^(−KX) for
    S = 0). K, S: finite, ≥ 0; X: 0 … 1000 m or inf."""
    return _elementwise(_engine.transmittance, K=_checked(K, "K", _COEFFICIENT), S=_checked(S, "S", _COEFFICIENT),
                        X=_checked(X, "X", _THICKNESS))


@overload
def infinite(K: Number, S: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def infinite(K: Values, S: Values) -> Result: ...
@_keywords_checked
def infinite(K: Values, S: Values) -> Union[float, Result]:
    """R∞ = a − b of an opaque film, 1/(1 + K/S + √((K/S)² + 2K/S)); 0 when S = 0. K, S: finite, ≥ 0."""
    return _elementwise(_engine.infinite, K=_checked(K, "K", _COEFFICIENT), S=_checked(S, "S", _COEFFICIENT))


@overload
def k_over_s(r_infinite: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def k_over_s(r_infinite: Values) -> Result: ...
@_keywords_checked
def k_over_s(r_infinite: Values) -> Union[float, Result]:
    """K/S from R∞ (the inverse of infinite()): (1 − R∞)²/(2R∞). r_infinite: in (0, 1]."""
    return _elementwise(_engine.k_over_s, r_infinite=_checked(r_infinite, "r_infinite", _R_INFINITE))


# --- The surface (Saunderson).

@overload
def saunderson(R: Number, k1: Number, k2: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def saunderson(R: Values, k1: Values, k2: Values) -> Result: ...
@_keywords_checked
def saunderson(R: Values, k1: Values, k2: Values) -> Union[float, Result]:
    """The reflectance measured with the specular component included, of a film of reflectance R
    under a surface of external reflectance k1 and internal diffuse reflectance k2:
    k1 + (1 − k1)(1 − k2)R/(1 − k2R). R: 0 … 1; k1, k2: in [0, 1)."""
    return _elementwise(_engine.saunderson, R=_checked(R, "R", _REFLECTANCE), k1=_checked(k1, "k1", _SURFACE),
                        k2=_checked(k2, "k2", _SURFACE))


@overload
def saunderson_body(R: Number, k1: Number, k2: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def saunderson_body(R: Values, k1: Values, k2: Values) -> Result: ...
@_keywords_checked
def saunderson_body(R: Values, k1: Values, k2: Values) -> Union[float, Result]:
    """The body part of saunderson(), what Metamer draws as ρd (the surface's own k1 is the
    material's specular term): (1 − k1)(1 − k2)R/(1 − k2R). R: 0 … 1; k1, k2: in [0, 1)."""
    return _elementwise(_engine.saunderson_body, R=_checked(R, "R", _REFLECTANCE), k1=_checked(k1, "k1", _SURFACE),
                        k2=_checked(k2, "k2", _SURFACE))


@overload
def saunderson_inverse(measured: Number, k1: Number, k2: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def saunderson_inverse(measured: Values, k1: Values, k2: Values) -> Result: ...
@_keywords_checked
def saunderson_inverse(measured: Values, k1: Values, k2: Values) -> Union[float, Result]:
    """The film's R from a reflectance measured with the specular component included:
    (R_m − k1)/((1 − k1)(1 − k2) + k2(R_m − k1)). measured: k1 … 1 (the surface alone reflects k1);
    k1, k2: in [0, 1)."""
    m, a, b = (_checked(measured, "measured", _REFLECTANCE), _checked(k1, "k1", _SURFACE), _checked(k2, "k2", _SURFACE))
    _shape({"measured": m, "k1": a, "k2": b})
    mb, ab = np.broadcast_arrays(m, a)
    if (mb < ab).any():
        at, where = _first(mb < ab)
        raise _metamer.InputError(f"measured: {mb[at]:g}{where} is below k1 = {ab[at]:g}; expected a reflectance "
                                  "measured with the specular component included, at least the surface's own k1")
    return _elementwise(_engine.saunderson_inverse, measured=m, k1=a, k2=b)


@overload
def k1(n: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def k1(n: Values) -> Result: ...
@_keywords_checked
def k1(n: Values) -> Union[float, Result]:
    """Saunderson's k1: the Fresnel reflectance at normal incidence from air into index n,
    ((n − 1)/(n + 1))². n: 1 … 5."""
    return _elementwise(_engine.k1, n=_checked(n, "n", _INDEX))


@overload
def k2(n: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def k2(n: Values) -> Result: ...
@_keywords_checked
def k2(n: Values) -> Union[float, Result]:
    """Saunderson's k2, r_i: the internal diffuse reflectance of a surface of index n (light inside
    the medium, totally reflected beyond the critical angle), Fresnel's equations integrated over
    the hemisphere; 0.59635 at n = 1.5. n: 1 … 5."""
    return _elementwise(_engine.k2, n=_checked(n, "n", _INDEX))


@overload
def external_diffuse_reflectance(n: Number) -> float: ...  # type: ignore[overload-overlap]
@overload
def external_diffuse_reflectance(n: Values) -> Result: ...
@_keywords_checked
def external_diffuse_reflectance(n: Values) -> Union[float, Result]:
    """r_e: the diffuse reflectance of a surface of index n for Lambertian light from the air,
    ∫ R(θ)·2 sin θ cos θ dθ, Fresnel's equations integrated; 0.09178 at n = 1.5, and
    1 − k2(n) = (1 − r_e)/n². n: 1 … 5."""
    return _elementwise(_engine.external_diffuse_reflectance, n=_checked(n, "n", _INDEX))


# --- Mixtures and stacks.

@overload
def mix(pigments: Sequence[tuple[Number, Number, Number]],  # type: ignore[overload-overlap]
        *, K: Number = 0.0, S: Number = 0.0) -> tuple[float, float]: ...
@overload
def mix(pigments: Sequence[tuple[Values, Values, Values]], *, K: Values = 0.0,
        S: Values = 0.0) -> tuple[Result, Result]: ...
@_keywords_checked
def mix(pigments: Sequence[tuple[Values, Values, Values]], *, K: Values = 0.0,
        S: Values = 0.0) -> Union[tuple[float, float], tuple[Result, Result]]:
    """A film's (K, S) from its pigments by the two-constant rule, as a paint's layer has them:
    K = K₀ + Σ cᵢkᵢ, S = S₀ + Σ cᵢsᵢ. `pigments`: 1 … 64 (concentration, k, s) tuples — cᵢ
    (0 … 10⁶, not normalized: any unit the pigment data are per) and the pigment's k and s per unit
    concentration (m⁻¹, 0 … 10¹², per band: a library pigment's NAME_k and NAME_s); K, S: the
    film's own (a binder's), 0 … 10¹². Concentrations, k and s may be arrays (a sweep), broadcast
    together."""
    items = _items(pigments, "pigments", "(concentration, k, s)")
    c = [_checked(t[0], f"pigments[{i}].concentration", _CONCENTRATION) for i, t in enumerate(items)]
    k = [_checked(t[1], f"pigments[{i}].k", _MIXED) for i, t in enumerate(items)]
    s = [_checked(t[2], f"pigments[{i}].s", _MIXED) for i, t in enumerate(items)]
    own = {"K": _checked(K, "K", _MIXED), "S": _checked(S, "S", _MIXED)}
    arrays = {**own, **{f"pigments[{i}].concentration": a for i, a in enumerate(c)},
              **{f"pigments[{i}].k": a for i, a in enumerate(k)}, **{f"pigments[{i}].s": a for i, a in enumerate(s)}}
    shape = _shape(arrays)
    K_mixed, S_mixed = _engine.mix(_flat(c, shape), _flat(k, shape), _flat(s, shape), _flat([own["K"]], shape)[0],
                                   _flat([own["S"]], shape)[0])
    if shape == ():
        return float(K_mixed[0]), float(S_mixed[0])
    return K_mixed.reshape(shape), S_mixed.reshape(shape)


@overload
def stack(films: Sequence[tuple[Number, Number, Number]],  # type: ignore[overload-overlap]
          substrate: Number = 0.0) -> float: ...
@overload
def stack(films: Sequence[tuple[Values, Values, Values]], substrate: Values = 0.0) -> Result: ...
@_keywords_checked
def stack(films: Sequence[tuple[Values, Values, Values]], substrate: Values = 0.0) -> Union[float, Result]:
    """R of films applied bottom-up over a substrate, as a paint's layers: each film's reflectance()
    over what lies beneath is the next one's substrate. `films`: 1 … 64 (K, S, X) tuples, bottom
    first (K, S: finite, ≥ 0, m⁻¹; X: 0 … 1000 m, or inf for the bottom film alone: an opaque film
    hides what is beneath it); substrate: 0 … 1."""
    items = _items(films, "films", "(K, S, X)")
    K = [_checked(t[0], f"films[{i}].K", _COEFFICIENT) for i, t in enumerate(items)]
    S = [_checked(t[1], f"films[{i}].S", _COEFFICIENT) for i, t in enumerate(items)]
    X = [_checked(t[2], f"films[{i}].X", _THICKNESS if i == 0 else _THICKNESS_ABOVE) for i, t in enumerate(items)]
    under = _checked(substrate, "substrate", _REFLECTANCE)
    arrays = {"substrate": under, **{f"films[{i}].K": a for i, a in enumerate(K)},
              **{f"films[{i}].S": a for i, a in enumerate(S)}, **{f"films[{i}].X": a for i, a in enumerate(X)}}
    shape = _shape(arrays)
    R: Result = _engine.stack(_flat(K, shape), _flat(S, shape), _flat(X, shape), _flat([under], shape)[0])
    return float(R[0]) if shape == () else R.reshape(shape)
