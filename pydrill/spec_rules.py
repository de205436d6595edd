"""The rules a sweep specification must keep (``spec.parse_spec`` applies them): its limits,
and the checks of each table, each axis and the axes together. Every refusal is a
:class:`SpecError` naming the key at fault and what is allowed there."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from .file_kinds import misplaced
from .model import (
    _LISTS,
    _SCALARS,
    MAX_DOF,
    MAX_LOAD,
)  # MAX_DOF: the largest string, explained there
from .suggest import key_hint

T = TypeVar("T")

OPERATING_AXES = ("wob", "torque")
SIZE_AXES = ("dof", "pipes")
DEPTH_AXES = ("depth",)  # m, strings built from a tally
SCALAR_AXES = tuple(_SCALARS)
#: what [model] may hold
_MODEL_KEYS = ("preset", "dof", "pipes", "tally", "lump", "wob", "torque", *_LISTS, *_SCALARS)
SIMULATION_KEYS = {
    "t_end": 300.0,
    "initial": ["rest"],
    "friction": "exact",
    "method": "auto",
    "rtol": 1e-8,
    "atol": 1e-8,
    "window": 0.5,
    "max_steps": 5_000_000,
}
RECORD_KEYS = {"stability": True, "eigenvalues": 4}
# The largest grid: the client holds the whole atlas in memory, a few hundred bytes a point
# (35 GB at 1e8 points with 2 starts and 4 eigenvalues), and 1e8 points at 10 ms each are a
# month on a thousand cores: more is a typing mistake, not a sweep.
MAX_POINTS = 100_000_000
MAX_STEPS = 2**62  # simulate()'s own bound, below the C++ core's long


#: What a value of these keys measures: in a spec they may carry a unit ("100 kN",
#: "3000 ft", "5 kft·lbf"), as everywhere a person types them; a bare number is SI.
KINDS = {
    "wob": "force",
    "torque": "torque",
    "depth": "length",
    "bit_radius": "length",
    "stribeck_velocity": "velocity",
    "karnopp_band": "velocity",
    "top_damping": "damping",
    "bit_damping": "damping",
}


class SpecError(ValueError):
    """A sweep specification that cannot run; the message names the key."""


class ReadOnlyDict(dict):
    """A dict that refuses every change: the tables of a parsed :class:`SweepSpec`. It reads,
    compares, copies and pickles as a dict does."""

    def _refuse(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError("a sweep spec is read-only: edit its TOML and parse it again")

    __setitem__ = __delitem__ = __ior__ = _refuse  # type: ignore[assignment]
    clear = pop = popitem = setdefault = update = _refuse  # type: ignore[assignment]

    def __reduce__(self) -> tuple[Any, ...]:
        # the default rebuilds a dict subclass item by item through __setitem__
        return (type(self), (dict(self),))


def _fail(key: str, problem: str) -> SpecError:
    return SpecError(f"{key}: {problem}")


def printable(text: str | Path) -> str:
    """A path or a key the user gave, as a message shows it: as it is, or, if it holds a
    character a terminal does not print as itself (a NUL, an escape sequence, a newline), its
    repr: quoted, with those characters escaped (``'a\\x00b.toml'``)."""
    text = str(text)
    return text if text.isprintable() else repr(text)


def in_si(key: str, name: str, value: Any) -> Any:
    """``value`` of the quantity ``name`` in SI if it is a string with a unit (refused, naming
    ``key``, if that unit does not measure it); anything else as it is, for the checks."""
    if not isinstance(value, str) or name not in KINDS:
        return value
    from . import units

    try:
        return units.parse(value, KINDS[name])
    except ValueError as exc:
        raise _fail(key, str(exc)) from None


def _is_number(v: Any) -> bool:
    """A finite int or float: not a bool (an int to Python), a string or a list."""
    if isinstance(v, bool) or not isinstance(v, int | float):
        return False
    try:
        return math.isfinite(v)
    except OverflowError:  # an integer beyond any float
        return False


def _table(doc: dict[str, Any], name: str) -> dict[str, Any]:
    """Section ``name`` (empty if absent); ``model = 5`` is refused, not a TypeError later."""
    value = doc.get(name, {})
    if not isinstance(value, dict):
        raise _fail(name, f"{value!r} is not a table: write [{name}] and its keys below it")
    return dict(value)


def _range(key: str, value: dict[str, Any]) -> np.ndarray:
    if set(value) != {"start", "stop", "num"}:
        raise _fail(
            key,
            "a range needs exactly start, stop and num, e.g. "
            "{ start = 20.0, stop = 200.0, num = 19 }",
        )
    name = key.split(".")[-1]
    given = value["start"], value["stop"]
    if name in KINDS and isinstance(given[0], str) != isinstance(given[1], str):
        # { start = "20 kN", stop = 120 } read as 120 N ... 20 kN, without a word: the bare
        # end is SI, the other in a unit of its own (kN), and the two were surely meant alike.
        from .units import SI

        with_unit, bare = ("start", "stop") if isinstance(given[0], str) else ("stop", "start")
        number = re.match(r"\s*[-+]?[0-9.]+(e[-+]?[0-9]+)?", value[with_unit], re.I)
        si = in_si(f"{key}.{with_unit}", name, value[with_unit])
        if number is None or float(number.group()) != si:  # "120 N" beside 20.0 is alike
            raise _fail(
                key,
                f"{with_unit} = {value[with_unit]!r} has a unit and {bare} = {value[bare]!r} "
                f"has none (read as {value[bare]!r} {SI[KINDS[name]]}): give both ends their "
                "unit, or neither",
            )
    start, stop = (in_si(f"{key}.{k}", name, value[k]) for k in ("start", "stop"))
    num = value["num"]
    for k, v in (("start", start), ("stop", stop)):
        if not _is_number(v):
            raise _fail(f"{key}.{k}", f"{v!r} is not a finite number")
    if isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= 1_000_000:
        raise _fail(f"{key}.num", f"{num!r} is not allowed: an integer 1 ... 1000000")
    if num > 1 and start == stop:
        raise _fail(key, f"start = stop = {start:g} gives {num} equal values: give num = 1")
    if num == 1 and start != stop:
        raise _fail(
            key,
            f"num = 1 keeps start = {start:g} and drops stop = {stop:g}: give start = stop, "
            "or use a list",
        )
    # Increasing order: from the top down, it is the same grid (the same values and digest).
    low, high = sorted((float(start), float(stop)))
    if not math.isfinite(high - low):  # linspace would fill the axis with inf and nan
        raise _fail(
            key,
            f"start = {start:g} and stop = {stop:g} are too far apart: their difference "
            "overflows a float; give a list, or a range within about ±8.9e307",
        )
    values = np.linspace(low, high, num)
    if np.any(np.diff(values) <= 0):
        raise _fail(key, f"repeated values: steps of {(high - low) / (num - 1):g} are too fine")
    return values


def _list(key: str, value: list[Any]) -> np.ndarray:
    if not value:
        raise _fail(key, "an empty list: give at least one value")
    value = [in_si(key, key.split(".")[-1], v) for v in value]
    for v in value:
        if not _is_number(v):
            raise _fail(key, f"{v!r} is not a finite number")
    values = np.array(value, dtype=float)
    if len(np.unique(values)) != len(values):
        raise _fail(key, "repeated values")
    # Increasing order, as plots (pcolormesh) and xarray's sel(method="nearest") need.
    return np.sort(values)


def _axis(name: str, value: Any) -> np.ndarray:
    key = f"axes.{name}"
    value = in_si(key, name, value)
    if isinstance(value, dict):
        values = _range(key, value)
    elif isinstance(value, list):
        values = _list(key, value)
    elif _is_number(value):
        values = np.array([float(value)])
    else:
        raise _fail(key, f"{value!r}: give a list of numbers or {{ start, stop, num }}")
    if name == "wob" and np.any(values <= 0):
        raise _fail(key, "weights on bit must be > 0 (N)")
    if name in OPERATING_AXES and np.any(np.abs(values) > MAX_LOAD):
        raise _fail(key, _too_large(name, float(np.abs(values).max())))
    if name in SIZE_AXES:
        if np.any(values != np.round(values)):
            raise _fail(key, "must be whole numbers")
        low = 2 if name == "dof" else 1
        high = MAX_DOF if name == "dof" else MAX_DOF - 3
        if np.any(values < low):
            raise _fail(key, f"must be >= {low}")
        if np.any(values > high):
            raise _fail(key, f"{values.max():g} is not allowed: {low} ... {high}" + _LARGEST)
        # Counts: whole numbers in the atlas too (xarray's dof coordinate reads 2, 4, 8).
        values = values.astype(np.int64)
    return values


def _too_large(name: str, value: float) -> str:
    """The refusal of a W_ob or torque beyond ``MAX_LOAD``, which simulate() refuses at every
    point: a sweep of them would store nothing but failures."""
    unit = "N" if name == "wob" else "N·m"
    most = f"{MAX_LOAD:.0e}".replace("e+", "e")
    return f"{value:g} {unit} is not allowed: at most {most} {unit} in size (simulate's limit)"


_LARGEST = f" (a string has at most {MAX_DOF} inertias; pipes P means dof = P + 3)"


#: The longest spec or tally file read, in characters. Both are kilobytes (a tally of MAX_DOF
#: joints some 15 MB); reading /dev/zero, or a disk image named by mistake, filled the memory.
MAX_TEXT = 64 * 2**20


class TextTooLong(ValueError):
    """A file longer than ``MAX_TEXT`` characters (:func:`read_text`)."""

    def __init__(self) -> None:
        super().__init__(
            f"longer than {MAX_TEXT // 2**20} MiB, which no spec or tally is: is it the right file?"
        )


def read_text(path: Path) -> str:
    """``path.read_text()``, but at most ``MAX_TEXT`` characters: :class:`TextTooLong`
    beyond (and OSError, UnicodeDecodeError as read_text).

    TOML is UTF-8 whatever the locale: read in the locale's encoding, a tally's "kg·m2" was
    "not UTF-8 text" under an ASCII locale and mojibake under Windows' cp1252. A byte-order
    mark, as Windows editors write one, is passed over (tomllib refused it at line 1)."""
    with path.open(encoding="utf-8-sig") as file:
        text = file.read(MAX_TEXT + 1)
    if len(text) > MAX_TEXT:
        raise TextTooLong()
    return text


def load_toml(path: Path, kind: str, error: type[ValueError], parse: Callable[[str], T]) -> T:
    """``parse`` of the text of the ``kind`` (``"spec"`` or ``"tally"``) file ``path``, for
    ``spec.load_spec`` and ``tally.load_tally``; a file that cannot be read, or that ``parse``
    refuses, is an ``error`` saying why, or what kind of file it is when it is another's."""
    shown = printable(path)
    try:
        text = read_text(path)
    except UnicodeDecodeError:
        message = misplaced(path, kind, shown) or f"cannot read the {kind} {shown}: not UTF-8 text"
        raise error(message) from None
    except OSError as exc:
        raise error(f"cannot read the {kind} {shown}: {exc.strerror}") from None
    except TextTooLong as exc:
        raise error(f"cannot read the {kind} {shown}: {exc}") from None
    try:
        return parse(text)
    except error as exc:  # another kind of file given: say so, not its first odd key
        raise error(misplaced(path, kind, shown) or str(exc)) from None


def _check_size(dof: Any, pipes: Any) -> int | None:
    """The string's size from [model] dof or pipes, if given: ``dof``."""
    if dof is not None and pipes is not None:
        raise _fail("model.pipes", "give dof or pipes, not both")
    if pipes is not None:
        if isinstance(pipes, bool) or not isinstance(pipes, int) or not 1 <= pipes <= MAX_DOF - 3:
            raise _fail(
                "model.pipes",
                f"{pipes!r} is not allowed: an integer 1 ... {MAX_DOF - 3}" + _LARGEST,
            )
        return pipes + 3
    if dof is not None and (
        isinstance(dof, bool) or not isinstance(dof, int) or not 2 <= dof <= MAX_DOF
    ):
        raise _fail("model.dof", f"{dof!r} is not allowed: an integer 2 ... {MAX_DOF}" + _LARGEST)
    return dof


def _check_parameters(model: dict[str, Any]) -> None:
    """Each model parameter of its type: a number, or a list of numbers; what values are
    allowed is the model's to say (on the corners, in :func:`parse_spec`)."""
    for key, value in model.items():
        if key not in _LISTS + _SCALARS:
            raise _fail(
                f"model.{printable(key)}",
                "unknown parameter"
                + key_hint(key, value, _MODEL_KEYS)
                + "; allowed: "
                + ", ".join(_MODEL_KEYS),
            )
        if key in _SCALARS and not _is_number(value):
            raise _fail(f"model.{key}", f"{value!r} is not a finite number")
        if key in _LISTS and not isinstance(value, list):
            raise _fail(f"model.{key}", f"{value!r} is not allowed: a list of numbers")
        for v in value if key in _LISTS else ():
            if not _is_number(v):
                raise _fail(f"model.{key}", f"{v!r} is not a finite number")


def _check_grid(axes: dict[str, np.ndarray]) -> None:
    shape = [len(v) for v in axes.values()]
    if math.prod(shape) > MAX_POINTS:
        raise _fail(
            "axes",
            f"{' x '.join(map(str, shape))} = {math.prod(shape)} points is too many: "
            f"at most {MAX_POINTS} in one sweep",
        )


def _check_friction_pair(axes: dict[str, np.ndarray]) -> None:
    """mu_coulomb < mu_static at every point, not only at the corners. The model checks every
    other parameter alone, within an interval, so that an axis whose ends pass passes whole
    (``spec._corners``); this pair is the one constraint that couples two axes."""
    if "mu_coulomb" not in axes or "mu_static" not in axes:
        return  # one of them fixed: the corners of the other one are the worst cases
    highest, lowest = axes["mu_coulomb"].max(), axes["mu_static"].min()
    if not highest < lowest:
        raise _fail(
            "axes.mu_static",
            f"its smallest value {lowest:g} is not above the largest axes.mu_coulomb "
            f"{highest:g}: every pair of the grid is run, and each needs mu_coulomb < mu_static",
        )


def _check_axes(
    axes: dict[str, np.ndarray],
    model: dict[str, Any],
    dof: int | None,
    fixed: dict[str, Any],
    tally_text: str | None,
) -> None:
    """What the axes may not be together, or with [model]."""
    if "depth" in axes and np.any(axes["depth"] <= 0):
        raise _fail("axes.depth", "depths must be > 0 (m)")
    if tally_text is not None and ("dof" in axes or "pipes" in axes):
        raise _fail("axes.dof", "a tally string grows with depth: sweep depth, not dof/pipes")
    if "dof" in axes and "pipes" in axes:
        raise _fail("axes.pipes", "sweep dof or pipes, not both")
    if ("dof" in axes or "pipes" in axes) and (dof is not None or any(k in model for k in _LISTS)):
        raise _fail(
            "model.dof",
            "the size is swept in [axes]: remove dof/pipes and per-element lists from [model]",
        )
    for key in SCALAR_AXES:
        if key in axes and key in model:
            raise _fail(f"model.{key}", f"{key} is also an axis: give it in one place only")
    for key in OPERATING_AXES:
        if key in axes and key in fixed:
            raise _fail(f"model.{key}", f"{key} is also an axis: give it in one place only")
        if key not in axes and key not in fixed:
            raise _fail(f"axes.{key}", f"missing: {key} must be an axis or fixed in [model]")
        if key in fixed:
            v = fixed[key]
            if not _is_number(v):
                raise _fail(f"model.{key}", f"{v!r} is not a finite number")
            if key == "wob" and v <= 0:
                raise _fail("model.wob", "must be > 0 (N)")
            if abs(v) > MAX_LOAD:
                raise _fail(f"model.{key}", _too_large(key, abs(v)))
    _check_friction_pair(axes)


def require_coords(coords: dict[str, float], needed: list[str], spec: Any) -> None:
    """ValueError unless ``coords`` (a point of ``spec``, as ``SweepSpec.coords`` gives one)
    has every name in ``needed``: its missing ones, the spec's axes and values held fixed."""
    missing = [k for k in needed if k not in coords]
    if missing:
        held = f"; held in [model]: {', '.join(spec.fixed)}" if spec.fixed else ""
        raise ValueError(
            f"coords = {coords!r} lacks {', '.join(missing)}: give a value of every axis of the "
            f"spec ({', '.join(spec.axes)}{held}), e.g. spec.coords(i)"
        )
