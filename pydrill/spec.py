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

Axes are stored in increasing order, whatever order they are written in. A string has at most
``MAX_DOF`` inertias and a grid at most ``MAX_POINTS`` points.
"""

from __future__ import annotations

import hashlib
import math
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from .model import PRESETS, Params, preset
from .model_values import _integer
from .spec_rules import (  # noqa: F401 - the limits and SpecError are spec's API too
    DEPTH_AXES,
    MAX_DOF,
    MAX_POINTS,
    MAX_STEPS,
    OPERATING_AXES,
    RECORD_KEYS,
    SCALAR_AXES,
    SIMULATION_KEYS,
    SIZE_AXES,
    ReadOnlyDict,
    SpecError,
    _axis,
    _check_axes,
    _check_grid,
    _check_parameters,
    _check_size,
    _fail,
    _is_number,
    _table,
    in_si,
    load_toml,
    printable,
    require_coords,
)
from .spec_sections import record as _record
from .spec_sections import simulation as _simulation
from .spec_sections import swept_in_vain as _swept_in_vain
from .spec_tally import _check_lists, _check_tally, _check_tally_size, _fixed_depth, _read_tally
from .suggest import did_you_mean, meant_hint

_PARAMS_KEPT = 16  # strings a spec keeps built (params_at)


def _writable(values: Any) -> bool:
    return not isinstance(values, np.ndarray) or values.flags.writeable


@dataclass(frozen=True, eq=False)  # (the fields' ==, of arrays, raised "truth value of an array")
class SweepSpec:
    """A validated sweep specification (from :func:`load_spec` or :func:`parse_spec`): the
    model, the grid of axes, the simulation settings and what to record. Points are numbered
    in C order over ``axes``. Two specs are equal, and hash alike, when they are the same
    sweep: the same :attr:`digest`, as an atlas tells its own sweep, whatever the formatting."""

    text: str  #: the TOML as given (stored in the atlas)
    preset: str  #: the parameter set (``pydrill.PRESETS``)
    dof: int | None  #: lumped elements, or None when an axis sets the size
    overrides: dict[str, Any]  #: model parameters changed from the preset
    axes: dict[str, np.ndarray]  #: name -> values, in grid order (read-only arrays)
    simulation: dict[str, Any]  #: t_end, initial, friction, method, tolerances, window
    record: dict[str, Any]  #: stability (bool), eigenvalues (how many kept)
    fixed: dict[str, float] = field(default_factory=dict)  #: wob/torque held fixed, if any
    tally_text: str | None = None  #: the tally the string is built from, if any
    lump: int = 1  #: drill-pipe joints per element (tally strings)

    def __post_init__(self) -> None:
        # frozen=True stops `spec.axes = ...` but not `spec.axes["wob"] = ...`: a spec changed
        # after parsing would no longer be its ``text``, which the workers and the atlas read.
        # The axes too, however the spec was made (numpy's pickle, so deepcopy and a Dask
        # worker's copy, dropped parse_spec's flag); a caller's writable array is copied.
        axes = {k: np.array(v) if _writable(v) else v for k, v in self.axes.items()}
        for values in axes.values():
            values.flags.writeable = False
        object.__setattr__(self, "axes", axes)
        for name in ("overrides", "axes", "simulation", "record", "fixed"):
            object.__setattr__(self, name, ReadOnlyDict(getattr(self, name)))

    def __reduce__(self) -> tuple[Any, ...]:
        # through __init__, so __post_init__ freezes the copy (the default restored __dict__)
        return (type(self), tuple(getattr(self, f.name) for f in fields(self)))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SweepSpec) and other.digest == self.digest

    def __hash__(self) -> int:
        return hash(self.digest)

    def __repr__(self) -> str:
        # One line, as Params's: the dataclass's own held the whole TOML and tally texts.
        grid = " x ".join(f"{name} {len(v)}" for name, v in self.axes.items())
        string = repr(self.preset)
        if self.tally_text is not None:
            string = f"tally {tomllib.loads(self.tally_text).get('name', '?')!r}"
        size = f" dof={self.dof}" if self.dof is not None else ""
        starts = " and ".join(self.initials)
        return (
            f"<SweepSpec {string}{size}: {self.size} points ({grid}), from {starts}, "
            f"t_end {self.simulation['t_end']:g} s, digest {self.digest}>"
        )

    def differences(self, other: SweepSpec) -> list[str]:
        """What makes ``other`` another sweep than this one, key by key, e.g.
        ``"simulation.t_end: 300 here, 100 there"`` (the parsed content, as the digest)."""
        from .spec_diff import spec_differences

        return spec_differences(self, other)

    def part(self, k: int, n: int) -> SweepSpec:
        """Part ``k`` of ``n`` (1 <= k <= n) of this sweep, as ``pydrill sweep --part K/N``
        sweeps it: every ``n``-th value of the first axis, from the ``k``-th.
        ``pydrill.merge_atlases`` makes the parts' atlases this sweep's."""
        from .spec_parts import spec_part

        return spec_part(self, k, n)

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
        parts: tuple[Any, ...] = (
            self.preset,
            self.dof,
            sorted(self.overrides.items()),
            # as floats: an atlas's identity from before size axes were ints stays the same
            [(k, v.astype(float).tolist()) for k, v in self.axes.items()],
            sorted(self.simulation.items()),
            sorted(self.record.items()),
            sorted(self.fixed.items()),
        )
        if self.tally_text is not None:
            # The tally's text (its path says nothing of what is in it) and the lumping make the
            # string. Only here: every other spec's digest stays as it was, and so its atlases
            # stay resumable.
            tally = hashlib.sha256(self.tally_text.encode()).hexdigest()
            parts = (*parts, ("tally", tally), ("lump", self.lump))
            if self.dof is not None and self.dof > 2:
                # Reduced strings share their inertias between the groups' ends since Dec. 2026
                # (Tally.to_params): an atlas of the older rule is another sweep, not resumed.
                parts = (*parts, ("reduction", "shared inertia"))
        return hashlib.sha256(repr(parts).encode()).hexdigest()[:16]

    def coords(self, flat_index: int) -> dict[str, float | int]:
        """The axis values of point number ``flat_index`` (an integer 0 ... ``size`` − 1)."""
        # numpy's own refusal named neither the argument nor its range, and took True as 1
        rest = _integer("flat_index", flat_index, 0, self.size - 1)
        # The axes as lists of plain values (a float, or an int on a size axis: what .item()
        # gave), made once, and the index unravelled by divmod, last axis fastest as numpy's
        # unravel_index (C order): the same coordinates in 2.2 us instead of 5.9 (a sweep asks
        # once a point).
        lists = self.__dict__.get("_axis_lists")
        if lists is None:  # (frozen: set past __setattr__)
            lists = self.__dict__["_axis_lists"] = [(k, v.tolist()) for k, v in self.axes.items()]
        picked = []
        for k, values in reversed(lists):
            rest, i = divmod(rest, len(values))
            picked.append((k, values[i]))
        return dict(reversed(picked))

    def params_at(self, coords: dict[str, float]) -> Params:
        """The string at one grid point (size, depth and parameter axes applied): ``coords``
        gives every axis of the spec but W_ob and torque (ValueError naming those missing)."""
        # A point without its dof, depth or parameter value was built silently from the
        # preset's default instead (dof 4): another string than the grid's.
        require_coords(coords, [k for k in self.axes if k not in OPERATING_AXES], self)
        # The string is the same at every point of a (W_ob, u) grid, and of any grid along its
        # operating axes: built (a preset scaled, validated) once, not at each point (measured:
        # 5 % of a dof-4 point's time). Params are frozen, so one may serve many points. The
        # last few are kept: points are dealt in a shuffled order (batching.dealing_order), so
        # along other axes a batch rarely meets the same string twice in a row.
        key = tuple((k, v) for k, v in coords.items() if k not in ("wob", "torque"))
        cache = self.__dict__.setdefault("_params", {})  # (frozen: set past __setattr__)
        params = cache.get(key)
        if params is None:
            params = cache[key] = self._params_at(coords)
            while len(cache) > _PARAMS_KEPT:
                del cache[next(iter(cache))]  # the oldest
        return params

    def _params_at(self, coords: dict[str, float]) -> Params:
        if self.tally_text is not None:
            from .tally import parse_tally

            tally = parse_tally(self.tally_text)
            depth = coords.get("depth", self.fixed.get("depth"))  # swept, or held in [model]
            if depth is not None:
                tally = tally.at_depth(depth)
            params = tally.to_params(dof=self.dof, lump=self.lump)
            over = {k: v for k, v in self.overrides.items() if k not in ("tally", "lump")}
            _check_lists(over, params.dof)
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
        """(W_ob in N, surface torque in N·m) at a point: swept, or held fixed (ValueError
        when ``coords`` lacks a swept one)."""
        # (a bare KeyError: 'torque' said nothing)
        require_coords(coords, [k for k in ("wob", "torque") if k not in self.fixed], self)
        get = {**self.fixed, **coords}
        return float(get["wob"]), float(get["torque"])


def parse_spec(text: str, tally_text: str | None = None, base: Path | None = None) -> SweepSpec:
    """Parse and validate a spec; raises :class:`SpecError` naming the key at fault.

    A spec may build its string from a tally (``[model] tally = "path.toml"``, resolved against
    ``base``); the tally's text travels with the spec (``tally_text``) so that workers on other
    machines and later readers of the atlas need no file."""
    if not isinstance(text, str):  # e.g. an atlas's spec attribute rewritten as a number
        shown = repr(text) if len(repr(text)) <= 60 else repr(text)[:57] + "..."
        raise SpecError(f"the spec is {shown} ({type(text).__name__}), not TOML text (a str)")
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"not valid TOML: {exc}") from None
    unknown = set(doc) - {"model", "axes", "simulation", "record"}
    if unknown:
        raise _fail(
            printable(sorted(unknown)[0]),
            "unknown section"
            + did_you_mean(sorted(unknown)[0], ("model", "axes", "simulation", "record"))
            + "; allowed: [model], [axes], [simulation], [record]",
        )
    model = _table(doc, "model")
    axes_doc, sim_doc, rec_doc = (_table(doc, k) for k in ("axes", "simulation", "record"))
    tally_path = model.pop("tally", None)
    lump_given = "lump" in model
    lump = model.pop("lump", 1)
    if isinstance(lump, bool) or not isinstance(lump, int) or lump < 1:
        raise _fail("model.lump", f"{lump!r} is not allowed: an integer >= 1")
    if tally_path is not None and tally_text is None:
        if isinstance(tally_path, str) and base is not None:
            beside = base / tally_path  # what a relative path means (an absolute one: itself)
            if not beside.exists() and not Path(tally_path).exists():
                raise _fail(
                    "model.tally",
                    f"cannot read {printable(tally_path)}: there is no file "
                    f"{printable(beside.absolute())}"
                    + (
                        ""
                        if Path(tally_path).is_absolute()
                        else f" (a relative path is resolved against the spec file's folder, "
                        f"{printable(base.absolute())})"
                    ),
                )
        tally_text = _read_tally(tally_path, base)
    if tally_text is not None:
        _check_tally(tally_text)
    elif lump_given:
        raise _fail("model.lump", "lump needs tally: it groups a tally's drill-pipe joints")
    name = model.pop("preset", "reduced-scale")
    if name not in PRESETS:
        raise _fail("model.preset", f"{name!r} is unknown; choose one of {', '.join(PRESETS)}")
    dof = _check_size(model.pop("dof", None), model.pop("pipes", None))
    fixed = {
        key: in_si(f"model.{key}", key, model.pop(key)) for key in OPERATING_AXES if key in model
    }
    if "depth" in model:  # a tally string at one depth, as an operating value is held
        fixed["depth"] = _fixed_depth(model.pop("depth"), tally_text, axes_doc)
    model = {key: in_si(f"model.{key}", key, v) for key, v in model.items()}
    _check_parameters(model)
    if not axes_doc:
        raise _fail("axes", "missing: the sweep needs at least one axis, e.g. wob = [...]")
    allowed_axes = OPERATING_AXES + SIZE_AXES + SCALAR_AXES + (DEPTH_AXES if tally_text else ())
    axes: dict[str, np.ndarray] = {}
    for key, value in axes_doc.items():
        if key in DEPTH_AXES and not tally_text:  # a preset's length is its dof or pipes
            raise _fail(
                f"axes.{key}",
                'needs a tally string ([model] tally = "FILE.toml"); a preset\'s length is '
                "swept with dof or pipes",
            )
        if key not in allowed_axes:
            raise _fail(
                f"axes.{printable(key)}",
                "cannot be swept"
                + (did_you_mean(key, allowed_axes) or meant_hint(key))
                + "; allowed: "
                + ", ".join(allowed_axes),
            )
        axes[key] = _axis(key, value)
    _check_grid(axes)
    _check_axes(axes, model, dof, fixed, tally_text)
    if tally_text is not None:
        depths = axes.get("depth")
        if "depth" in fixed:
            depths = np.array([fixed["depth"]])
        _check_tally_size(
            tally_text, lump, depths, "axes.depth" if "depth" in axes else "model.depth"
        )
    for values in axes.values():
        # A frozen spec, frozen grid: an axis changed in place would make an atlas whose
        # coordinates disagree with what its points computed (workers parse ``text``).
        values.flags.writeable = False
    simulation = _simulation(sim_doc)
    _swept_in_vain(axes, simulation)
    spec = SweepSpec(
        text,
        name,
        dof,
        model,
        axes,
        simulation,
        _record(rec_doc),
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
            message = str(exc)
            if "for preset 'real-string'" in message:  # preset()'s advice is Python's
                message = message.split("; use dof = 2", 1)[0] + (
                    "; give dof = 2, or the string pipe by pipe from a tally: [model] tally = "
                    '"TALLY.toml" with dof, lump or depth (examples/tallies/paper-eq53.toml '
                    "is the paper's)"
                )
            raise _fail(f"model (at {where})" if where else "model", message) from None
    return spec


def _corners(spec: SweepSpec) -> list[dict[str, float]]:
    """The lowest and highest values of every size/parameter axis. Enough: the model checks
    each parameter alone against bounds (so do the preset and the tally the size and depth),
    and the one pair it couples, mu_coulomb < mu_static, has its own check."""
    keys = [k for k in spec.axes if k not in OPERATING_AXES]
    if not keys:
        return [{}]
    lows = {k: float(spec.axes[k].min()) for k in keys}
    highs = {k: float(spec.axes[k].max()) for k in keys}
    return [lows, highs]


def _require_spec(spec: object) -> SweepSpec:
    """``spec`` if it is a :class:`SweepSpec`; a path or a TOML text is refused (TypeError)
    with what to call, rather than an AttributeError from deep inside the sweep."""
    if not isinstance(spec, SweepSpec):
        shown = repr(spec) if len(repr(spec)) <= 80 else repr(spec)[:77] + "..."
        raise TypeError(
            f"spec = {shown} ({type(spec).__name__}) is not a SweepSpec: read one with "
            "pydrill.load_spec(path), or pydrill.parse_spec(text) for TOML text"
        )
    return spec


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a sweep specification (TOML) from ``path``; a tally it names is
    resolved next to it. Raises :class:`SpecError` naming the key at fault, before anything
    runs."""
    path = Path(path)
    return load_toml(path, "spec", SpecError, lambda text: parse_spec(text, base=path.parent))
