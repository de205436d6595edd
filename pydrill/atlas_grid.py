"""Where a coordinate given to an atlas query lies on its grid: the value as a float (units
allowed), on a grid point or not, near enough to the grid for "nearest"."""

from __future__ import annotations

import math
import numbers
import reprlib
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np


class CoordinateError(ValueError, KeyError):
    """A coordinate, start or axis name that an atlas query cannot take: an axis the atlas has
    not, a value off its grid or outside it, a start it was not swept from. Both a ValueError
    (a bad value, as the figures and the commands have it) and a KeyError (a name not found,
    what ``Atlas.index``, ``value``, ``regimes`` and ``sel`` raised before): either
    ``except`` catches it."""

    def __str__(self) -> str:
        # KeyError's own str() is the repr of its message, quotes and all
        return str(self.args[0]) if len(self.args) == 1 else super().__str__()


def not_an_axis(name: str, names: Any) -> CoordinateError:
    """The error for ``name``, which is none of the axes ``names``."""
    from .suggest import did_you_mean

    names = list(names)
    return CoordinateError(
        f"{name} is not an axis of this atlas{did_you_mean(name, names)}; axes: {', '.join(names)}"
    )


def spec_holds(spec: Any) -> dict[str, float]:
    """What an atlas's spec holds at every point without sweeping it (SI): a W_ob, torque or
    depth in [model], a string parameter it sets there (mu_static = 0.9), its dof."""
    held = {**spec.fixed}
    for name, value in spec.overrides.items():  # not the lists (inertias), tally or lump
        if isinstance(value, int | float) and not isinstance(value, bool) and name != "lump":
            held[name] = float(value)
    if spec.dof is not None:
        held["dof"] = float(spec.dof)
    return held


def leave_out_held(
    values: dict[str, float], axes: Any, held: dict[str, float], option: Callable[[str], str]
) -> dict[str, float]:
    """``values`` asked of an atlas (NAME: SI value) without those of what its spec holds at
    every point (``held``, no axis): torque = 9 kN·m asked of a sweep at 9 kN·m adds nothing
    and is left out (equal to 6 digits, as printed, so that 6638 ft·lbf is the same as 9 kN·m);
    another value is refused (a CoordinateError), ``option(name)`` naming the option that gave
    it (it said "torque is not an axis of this atlas", as if the atlas knew nothing of the
    torque)."""
    out = {}
    for name, value in values.items():
        if name in axes or name not in held:
            out[name] = value  # an axis's value, or one the atlas refuses as no axis
        elif not math.isclose(value, held[name], rel_tol=1e-6):
            shown, given = with_unit(name, held[name]), with_unit(name, value)
            if shown == given:  # 9 kN·m against 9.000001 kN·m: in full
                given, shown = distinct(value, held[name], name)
            raise CoordinateError(
                f"{option(name)}: its spec holds {name} = {shown} at every point, not {given}; "
                "leave it out"
            )
    return out


def without_held(atlas: Any, coords: dict[str, Any]) -> dict[str, Any]:
    """``coords`` given to ``atlas`` without what the spec holds at every point, at
    its value: torque = 8.3 of a sweep at 8.3 N·m was "not an axis" to ``Atlas.value``, though
    ``atlas query --torque 8.3`` took it; another value is a CoordinateError naming the one
    held (``leave_out_held``)."""
    held = spec_holds(atlas.spec)
    given = {n: coordinate(n, v) for n, v in coords.items() if n in held and n not in atlas.axes}
    leave_out_held(given, atlas.axes, held, lambda n: f"{n} is not an axis of this atlas")
    return {n: v for n, v in coords.items() if n not in given}


def on_grid(values: np.ndarray, i: int, v: float) -> bool:
    """Whether ``v`` is the grid value ``values[i]`` (its nearest): equal within 1e-6 of it,
    float32's resolution (``np.float32(8.3)`` is 8.30000019), but never nearer than a quarter
    of the step to its neighbours, so that no value names two grid points."""
    g = float(values[i])
    tol = max(1e-6 * abs(g), 1e-12)
    if len(values) > 1:
        others = np.delete(values, i).astype(float)
        tol = min(tol, float(np.min(np.abs(others - g))) / 4)
    return abs(v - g) <= tol


def grid_index(name: str, values: np.ndarray, v: float, method: str = "exact") -> int:
    """The index of the grid value of axis ``name`` that ``v`` (SI) names: exactly (as
    ``on_grid`` has it), or with ``method="nearest"`` the nearest. A CoordinateError beyond
    half a grid step past either end, whatever the method (``near_enough``: no advice to ask
    for the nearest, which would be refused too), or off the grid when exact."""
    near_enough(name, values, v)
    i = int(np.argmin(np.abs(values - v)))
    if method == "exact" and not on_grid(values, i, v):
        shown, near = distinct(v, values[i], name, values)
        raise CoordinateError(
            f"{name} = {shown} is not on the grid (nearest {near}); "
            "use method='nearest' (--nearest)"
        )
    return i


def grid_value(name: str, values: np.ndarray, value: Any) -> float:
    """The grid value of axis ``name`` that ``value`` names exactly (as ``Atlas.index`` takes
    it: float32's 8.3 is 8.3); a CoordinateError, worded as index()'s, if it names none."""
    return values[grid_index(name, values, coordinate(name, value))].item()


def axis_unit(name: str) -> str:
    """The SI unit of a sweep axis's values ("1": a count or a plain number)."""
    from .model import _UNITS

    known = {"wob": "N", "torque": "N·m", "depth": "m", "dof": "1", "pipes": "1"}
    unit = known.get(name) or _UNITS.get(name, "1")
    return "1" if unit == "friction coefficient" else unit


def shown_unit(name: str, *values: float) -> tuple[str, float]:
    """The unit a sweep axis's values are printed in, and its size in SI: a real string's
    weights on bit (1e5 N) and torques (8000 N·m) read as kN and kN·m, the reduced-scale rig's
    (100 N, 8.3 N·m) as N and N·m."""
    from .cli_options import KILO  # the figures' threshold, and the other commands' text

    unit = axis_unit(name)
    if unit in ("N", "N·m") and max(abs(float(v)) for v in values) > KILO:
        return "k" + unit, 1e3
    return unit, 1.0


def grid_unit(name: str, values: Any) -> tuple[str, float]:
    """The unit a whole axis reads in (``shown_unit`` of its extremes): a value on it is printed
    in that unit too, so that 9 kN·m on an axis of 6 ... 12 kN·m does not read 9000 N·m."""
    values = np.asarray(values, dtype=float)
    return shown_unit(name, float(np.min(values)), float(np.max(values)))


def with_unit(name: str, value: float, unit: tuple[str, float] | None = None) -> str:
    """A sweep axis's SI value as text with its unit ("80 N", "120 kN", "4" for a count)."""
    text, factor = unit or shown_unit(name, value)
    number = f"{value / factor:g}"
    return number if text == "1" else f"{number} {text}"


def distinct(a: float, b: Any, name: str | None = None, axis: Any = None) -> tuple[str, str]:
    """``a`` and ``b`` printed briefly (``:g``), or in full when that shows them equal; with
    the unit of axis ``name`` when it is given, the one its grid values ``axis`` read in (else
    its grid value ``b``), both in it: 70 kN, 60 kN."""
    if not name:
        text, factor = "1", 1.0
    else:
        text, factor = grid_unit(name, [b] if axis is None else axis)
    x, y = float(a) / factor, float(b) / factor
    short = f"{x:g}", f"{y:g}"
    pair = short if short[0] != short[1] else (repr(x), repr(y))
    return pair if text == "1" else (f"{pair[0]} {text}", f"{pair[1]} {text}")


def near_enough(name: str, values: np.ndarray, v: float) -> None:
    """Refuse (CoordinateError) a value whose nearest grid point would answer for a place the sweep
    never went: beyond half a grid step past either end, or off a one-value axis."""
    if len(values) == 1:
        if not on_grid(values, 0, v):
            shown, only = distinct(v, values[0], name, values)
            raise CoordinateError(f"{name} = {shown} is outside the atlas (only {only})")
        return
    ends = np.sort(values)
    lo = ends[0] - 0.5 * (ends[1] - ends[0])
    hi = ends[-1] + 0.5 * (ends[-1] - ends[-2])
    if not lo <= v <= hi:
        unit = shown_unit(name, ends[0], ends[-1])  # the grid's unit, whatever was asked
        first, last = (with_unit(name, e, unit) for e in (ends[0], ends[-1]))
        # the value and the end it is past in full where they print alike (100.00004 N
        # past 100.0000004 N read "100 N is outside the atlas (40 N ... 100 N)")
        shown, end = distinct(v, ends[0] if v < lo else ends[-1], name, ends)
        first, last = (end, last) if v < lo else (first, end)
        raise CoordinateError(f"{name} = {shown} is outside the atlas ({first} ... {last})")


def listed(name: str, value: Any) -> tuple[bool, list[Any]]:
    """What ``Atlas.sel`` was given for ``name``: whether a list (a tuple, a 1-D array) and its
    entries, else the one value. An empty list selects nothing: a ValueError, not an empty
    slice that reads as an atlas without points."""
    if isinstance(value, list | tuple | np.ndarray) and np.ndim(value) > 0:
        if len(value) == 0:
            raise ValueError(f"{name} = {value!r} selects nothing: give at least one value")
        return True, list(value)
    return False, [value]


def coordinate(name: str, value: Any) -> float:
    """A coordinate as a float: a number, or a string with a unit where the axis measures
    something (``"20 kN"`` for wob; a bare ``"80"`` is SI). TypeError or CoordinateError name
    it; NaN is refused as such (it is no place on a grid, nearest or not)."""
    v = _as_float(name, value)
    if math.isnan(v):
        raise CoordinateError(f"{name} = {value!r} is not a number: give a grid value")
    return v


def _as_float(name: str, value: Any) -> float:
    """``coordinate``'s float, NaN and all."""
    from . import units
    from .spec_rules import KINDS

    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    if isinstance(value, str):
        if name not in KINDS:
            try:
                return float(value)
            except ValueError:
                raise CoordinateError(f"{name} = {value!r} is not a number") from None
        try:
            return units.parse(value, KINDS[name])
        except ValueError as exc:  # the message starts with the value
            raise CoordinateError(f"{name} = {exc}") from None
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(
            f"{name} = {value!r} is not allowed: a number, or a string with a unit (e.g. '20 kN')"
        )
    try:
        return float(value)
    except OverflowError:  # an integer beyond any float: an OverflowError from float() it was
        raise CoordinateError(
            f"{name} = {reprlib.repr(value)} is not allowed: beyond the range of a float"
        ) from None


def selection(
    axes: Mapping[str, np.ndarray], initials: Sequence[str], method: Any, coords: dict[str, Any]
) -> dict[str, Any]:
    """What ``Atlas.sel`` selects (see there): each axis's grid value(s) as floats, initial's
    name(s), ready for ``xarray.Dataset.sel``; refused, saying why, what is none of them."""
    unknown = sorted(set(coords) - set(axes) - {"initial"})
    if unknown:
        raise not_an_axis(unknown[0], [*axes, "initial"])
    # xarray's own fill methods ("pad", "backfill") answered 1e9 N with the last grid
    # value's data: only the grid's values, or the nearest within the grid's reach.
    if not (method is None or (isinstance(method, str) and method in ("exact", "nearest"))):
        raise ValueError(
            f"method = {method!r} is not allowed: None (or 'exact') for grid values only, "
            "or 'nearest'"
        )
    chosen: dict[str, Any] = {}
    for name, v in coords.items():
        if isinstance(v, slice):
            if name == "initial" or method == "nearest":
                why = (
                    "initial takes names, not a slice"
                    if name == "initial"
                    else "a slice keeps the grid values between its ends: 'nearest' has no "
                    "meaning for it (leave method out)"
                )
                raise ValueError(
                    f"{name} = {v!r}: {why}; or give a list of values, or use "
                    "atlas.to_xarray().sel(...) for xarray's own selection"
                )
            chosen[name] = _within(name, axes[name], v)
            continue
        # numbers, or strings with a unit ("20 kN"), as index() takes them
        many, given = listed(name, v)
        if name == "initial":  # a name, chosen exactly: "nearest" has no meaning for it
            for one in given:  # (xarray's KeyError named neither it nor the starts)
                if not isinstance(one, str) or one not in initials:
                    raise CoordinateError(
                        f"initial = {one!r} is not in this atlas: {list(initials)}"
                    )
            chosen[name] = given if many else given[0]
            continue
        # each on the grid (exact) or within its reach (nearest), as index() has it
        mode = "nearest" if method == "nearest" else "exact"
        asked = [coordinate(name, one) for one in given]
        for k, one in enumerate(asked):
            # the grid value itself, nearest too: at a tie (6.5 between 6 and 7) xarray's
            # nearest took the larger, grid_index (value, index) the first
            asked[k] = axes[name][grid_index(name, axes[name], one, mode)].item()
        chosen[name] = asked if many else asked[0]
    return chosen


def _within(name: str, values: np.ndarray, bounds: slice) -> list[float]:
    """The grid values of axis ``name`` from ``bounds.start`` to ``bounds.stop`` inclusive
    (either None: open), in grid order; a ValueError for a step or a slice of none."""
    if bounds.step is not None:
        raise ValueError(
            f"{name} = {bounds!r}: a step is not allowed (a slice selects the grid values "
            "between its ends); use atlas.to_xarray().isel(...) to step through a grid"
        )
    lo = -math.inf if bounds.start is None else coordinate(name, bounds.start)
    hi = math.inf if bounds.stop is None else coordinate(name, bounds.stop)
    kept = [x.item() for x in values if lo <= x <= hi]
    if not kept:
        first, last = (
            with_unit(name, e, grid_unit(name, values)) for e in (min(values), max(values))
        )
        raise ValueError(
            f"{name} = {bounds!r} selects nothing: no grid value between its ends "
            f"(the grid: {first} ... {last})"
        )
    return kept
