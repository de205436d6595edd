"""Sweep specifications (TOML): what to vary, what to hold, how to simulate.

A spec is refused before anything runs, with the key at fault and what is allowed there::

    [model]                      # the string: a preset, its size, any parameter overrides
    preset = "reduced-scale"
    dof = 4                      # or pipes = P
    [axes]                       # the grid, in this order: ranges or lists
    wob = { start = 20.0, stop = 200.0, num = 19 }
    torque = [6.0, 8.3, 10.0]
    [simulation]
    t_end = 300.0
    initial = ["rest"]           # any of "rest", "equilibrium"
    [record]                     # optional
    stability = true             # equilibria, eigenvalues, Hopf margin
    eigenvalues = 4              # leading eigenvalues kept per point
"""

from __future__ import annotations

import hashlib
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .model import _LISTS, _SCALARS, PRESETS, Params, preset

OPERATING_AXES = ("wob", "torque")
SIZE_AXES = ("dof", "pipes")
DEPTH_AXES = ("depth",)  # m, strings built from a tally
SCALAR_AXES = tuple(_SCALARS)
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


class SpecError(ValueError):
    """A sweep specification that cannot run; the message names the key."""


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep specification (from :func:`load_spec` or :func:`parse_spec`): the
    model, the grid of axes, the simulation settings and what to record. Points are numbered
    in C order over ``axes``."""

    text: str  #: the TOML as given (stored in the atlas)
    preset: str  #: the parameter set (``pydrill.PRESETS``)
    dof: int | None  #: lumped elements, or None when an axis sets the size
    overrides: dict[str, Any]  #: model parameters changed from the preset
    axes: dict[str, np.ndarray]  #: name -> values, in grid order
    simulation: dict[str, Any]  #: t_end, initial, friction, method, tolerances, window
    record: dict[str, Any]  #: stability (bool), eigenvalues (how many kept)
    fixed: dict[str, float] = field(default_factory=dict)  #: wob/torque held fixed, if any
    tally_text: str | None = None  #: the tally the string is built from, if any
    lump: int = 1  #: drill-pipe joints per element (tally strings)

    @property
    def shape(self) -> tuple[int, ...]:
        """Points along each axis, in the order of ``axes``."""
        return tuple(len(v) for v in self.axes.values())

    @property
    def size(self) -> int:
        """Points in the grid."""
        return math.prod(self.shape)

    @property
    def initials(self) -> list[str]:
        """The starts simulated at each point (``"rest"``, ``"equilibrium"``)."""
        return list(self.simulation["initial"])

    @property
    def digest(self) -> str:
        """Identity of the sweep: the parsed content, not its formatting."""
        canon = repr(
            (
                self.preset,
                self.dof,
                sorted(self.overrides.items()),
                # as floats: an atlas's identity from before size axes were ints stays the same
                [(k, v.astype(float).tolist()) for k, v in self.axes.items()],
                sorted(self.simulation.items()),
                sorted(self.record.items()),
                sorted(self.fixed.items()),
            )
        )
        return hashlib.sha256(canon.encode()).hexdigest()[:16]

    def coords(self, flat_index: int) -> dict[str, float | int]:
        """The axis values of point number ``flat_index``."""
        idx = np.unravel_index(flat_index, self.shape)
        # .item(): a plain float, or an int on a size axis (dof, pipes).
        return {k: v[i].item() for (k, v), i in zip(self.axes.items(), idx, strict=True)}

    def params_at(self, coords: dict[str, float]) -> Params:
        """The string at one grid point (size, depth and parameter axes applied)."""
        if self.tally_text is not None:
            from .tally import parse_tally

            tally = parse_tally(self.tally_text)
            if "depth" in coords:
                tally = tally.at_depth(coords["depth"])
            params = tally.to_params(dof=self.dof, lump=self.lump)
            over = {k: v for k, v in self.overrides.items() if k not in ("tally", "lump")}
            over.update({k: v for k, v in coords.items() if k in SCALAR_AXES})
            return params.replace(**over) if over else params
        dof = self.dof
        if "dof" in coords:
            dof = int(coords["dof"])
        if "pipes" in coords:
            dof = int(coords["pipes"]) + 3
        over = dict(self.overrides)
        over.update({k: v for k, v in coords.items() if k in SCALAR_AXES})
        return preset(self.preset, dof=dof, **over)

    def operating_point(self, coords: dict[str, float]) -> tuple[float, float]:
        """(W_ob in N, surface torque in N·m) at a point: swept, or held fixed."""
        get = {**self.fixed, **coords}
        return float(get["wob"]), float(get["torque"])


def _fail(key: str, problem: str) -> SpecError:
    return SpecError(f"{key}: {problem}")


def _axis(name: str, value: Any) -> np.ndarray:
    key = f"axes.{name}"
    if isinstance(value, dict):
        extra = set(value) - {"start", "stop", "num"}
        if extra or set(value) != {"start", "stop", "num"}:
            raise _fail(
                key,
                "a range needs exactly start, stop and num, e.g. "
                "{ start = 20.0, stop = 200.0, num = 19 }",
            )
        start, stop, num = value["start"], value["stop"], value["num"]
        for k, v in (("start", start), ("stop", stop)):
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                raise _fail(f"{key}.{k}", f"{v!r} is not a finite number")
        if isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= 1_000_000:
            raise _fail(f"{key}.num", f"{num!r} is not allowed: an integer 1 ... 1000000")
        values = np.linspace(float(start), float(stop), num)
    elif isinstance(value, list):
        if not value:
            raise _fail(key, "an empty list: give at least one value")
        for v in value:
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                raise _fail(key, f"{v!r} is not a finite number")
        values = np.array(value, dtype=float)
        if len(np.unique(values)) != len(values):
            raise _fail(key, "repeated values")
    elif isinstance(value, int | float) and not isinstance(value, bool):
        values = np.array([float(value)])
    else:
        raise _fail(key, f"{value!r}: give a list of numbers or {{ start, stop, num }}")
    if name == "wob" and np.any(values <= 0):
        raise _fail(key, "weights on bit must be > 0 (N)")
    if name in SIZE_AXES:
        if np.any(values != np.round(values)):
            raise _fail(key, "must be whole numbers")
        low = 2 if name == "dof" else 1
        if np.any(values < low):
            raise _fail(key, f"must be >= {low}")
        # Counts: whole numbers in the atlas too (xarray's dof coordinate reads 2, 4, 8).
        values = values.astype(np.int64)
    return values


def parse_spec(text: str, tally_text: str | None = None, base: Path | None = None) -> SweepSpec:
    """Parse and validate a spec; raises :class:`SpecError` naming the key at fault.

    A spec may build its string from a tally (``[model] tally = "path.toml"``, resolved against
    ``base``); the tally's text travels with the spec (``tally_text``) so that workers on other
    machines and later readers of the atlas need no file."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"not valid TOML: {exc}") from None
    unknown = set(doc) - {"model", "axes", "simulation", "record"}
    if unknown:
        raise _fail(
            sorted(unknown)[0], "unknown section; allowed: [model], [axes], [simulation], [record]"
        )
    model = dict(doc.get("model", {}))
    tally_path = model.pop("tally", None)
    lump = model.pop("lump", 1)
    if isinstance(lump, bool) or not isinstance(lump, int) or lump < 1:
        raise _fail("model.lump", f"{lump!r} is not allowed: an integer >= 1")
    if tally_path is not None and tally_text is None:
        path = Path(tally_path)
        if not path.is_absolute() and base is not None and (base / path).exists():
            path = base / path
        try:
            tally_text = path.read_text()
        except OSError as exc:
            raise _fail("model.tally", f"cannot read {tally_path}: {exc.strerror}") from None
    if tally_text is not None:
        from .tally import TallyError, parse_tally

        try:
            parse_tally(tally_text)
        except TallyError as exc:
            raise _fail("model.tally", str(exc)) from None
    name = model.pop("preset", "reduced-scale")
    if name not in PRESETS:
        raise _fail("model.preset", f"{name!r} is unknown; choose one of {', '.join(PRESETS)}")
    dof = model.pop("dof", None)
    pipes = model.pop("pipes", None)
    if dof is not None and pipes is not None:
        raise _fail("model.pipes", "give dof or pipes, not both")
    if pipes is not None:
        if isinstance(pipes, bool) or not isinstance(pipes, int) or pipes < 1:
            raise _fail("model.pipes", f"{pipes!r} is not allowed: an integer >= 1")
        dof = pipes + 3
    if dof is not None and (isinstance(dof, bool) or not isinstance(dof, int) or dof < 2):
        raise _fail("model.dof", f"{dof!r} is not allowed: an integer >= 2")
    fixed = {}
    for key in OPERATING_AXES:
        if key in model:
            fixed[key] = model.pop(key)
    for key in model:
        if key not in _LISTS + _SCALARS:
            raise _fail(
                f"model.{key}",
                "unknown parameter; allowed: preset, dof, pipes, wob, "
                "torque, " + ", ".join(_LISTS + _SCALARS),
            )
    axes_doc = doc.get("axes")
    if not axes_doc:
        raise _fail("axes", "missing: the sweep needs at least one axis, e.g. wob = [...]")
    allowed_axes = OPERATING_AXES + SIZE_AXES + SCALAR_AXES + (DEPTH_AXES if tally_text else ())
    axes: dict[str, np.ndarray] = {}
    for key, value in axes_doc.items():
        if key not in allowed_axes:
            raise _fail(f"axes.{key}", "cannot be swept; allowed: " + ", ".join(allowed_axes))
        axes[key] = _axis(key, value)
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
    for key in OPERATING_AXES:
        if key in axes and key in fixed:
            raise _fail(f"model.{key}", f"{key} is also an axis: give it in one place only")
        if key not in axes and key not in fixed:
            raise _fail(f"axes.{key}", f"missing: {key} must be an axis or fixed in [model]")
        if key in fixed:
            v = fixed[key]
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
                raise _fail(f"model.{key}", f"{v!r} is not a finite number")
            if key == "wob" and v <= 0:
                raise _fail("model.wob", "must be > 0 (N)")
    sim = dict(SIMULATION_KEYS)
    for key, value in doc.get("simulation", {}).items():
        if key not in SIMULATION_KEYS:
            raise _fail(f"simulation.{key}", "unknown; allowed: " + ", ".join(SIMULATION_KEYS))
        sim[key] = value
    initial = sim["initial"]
    if isinstance(initial, str):
        initial = [initial]
    if (
        not isinstance(initial, list)
        or not initial
        or any(i not in ("rest", "equilibrium") for i in initial)
        or len(set(initial)) != len(initial)
    ):
        raise _fail(
            "simulation.initial",
            f"{sim['initial']!r}: a list of distinct values from 'rest', 'equilibrium'",
        )
    sim["initial"] = initial
    for key in ("t_end", "rtol", "atol"):
        v = sim[key]
        if (
            isinstance(v, bool)
            or not isinstance(v, int | float)
            or not (v > 0 and math.isfinite(v))
        ):
            raise _fail(f"simulation.{key}", f"{v!r} is not allowed: a finite number > 0")
        sim[key] = float(v)
    if not 0 < sim["window"] <= 1:
        raise _fail("simulation.window", f"{sim['window']!r} is not allowed: 0 < window <= 1")
    if sim["friction"] not in ("exact", "karnopp"):
        raise _fail("simulation.friction", f"{sim['friction']!r}: choose 'exact' or 'karnopp'")
    if sim["method"] not in ("auto", "dop853", "bdf", "adams", "erk"):
        raise _fail(
            "simulation.method", f"{sim['method']!r}: choose auto, dop853, bdf, adams or erk"
        )
    rec = dict(RECORD_KEYS)
    for key, value in doc.get("record", {}).items():
        if key not in RECORD_KEYS:
            raise _fail(f"record.{key}", "unknown; allowed: " + ", ".join(RECORD_KEYS))
        rec[key] = value
    if not isinstance(rec["stability"], bool):
        raise _fail("record.stability", "true or false")
    if (
        isinstance(rec["eigenvalues"], bool)
        or not isinstance(rec["eigenvalues"], int)
        or not (0 <= rec["eigenvalues"] <= 64)
    ):
        raise _fail("record.eigenvalues", "an integer 0 ... 64")
    spec = SweepSpec(
        text,
        name,
        dof,
        model,
        axes,
        sim,
        rec,
        {k: float(v) for k, v in fixed.items()},
        tally_text,
        lump,
    )
    # Every string of the grid must be buildable: try the corners of the size/parameter axes.
    for corner in _corners(spec):
        try:
            spec.params_at(corner)
        except ValueError as exc:
            # Name the swept values that made the string (pipes = 50 means dof = 53).
            where = ", ".join(f"axes.{k} = {v:g}" for k, v in corner.items())
            raise _fail(f"model (at {where})" if where else "model", str(exc)) from None
    return spec


def _corners(spec: SweepSpec) -> list[dict[str, float]]:
    keys = [k for k in spec.axes if k not in OPERATING_AXES]
    if not keys:
        return [{}]
    lows = {k: float(spec.axes[k].min()) for k in keys}
    highs = {k: float(spec.axes[k].max()) for k in keys}
    return [lows, highs]


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a sweep specification (TOML) from ``path``; a tally it names is
    resolved next to it. Raises :class:`SpecError` naming the key at fault, before anything
    runs."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise SpecError(f"cannot read the spec {path}: {exc.strerror}") from None
    return parse_spec(text, base=path.parent)
