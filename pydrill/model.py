"""Drillstring parameters: the lumped torsional chain of DESIGN.md §2 as a plain data class.

Everything is SI: kg·m², N·m/rad, N·m·s/rad, m, rad/s. A string has ``dof`` inertias, top drive
first and bit last; ``pipes`` drill pipes make ``dof = pipes + 3`` (top drive, pipes, drill
collars, bit).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

from . import _core

PRESETS = tuple(_core.preset_names())

_SCALARS = (
    "top_damping",
    "bit_damping",
    "bit_radius",
    "mu_coulomb",
    "mu_static",
    "stribeck_decay",
    "stribeck_velocity",
    "karnopp_band",
)
_LISTS = ("inertias", "stiffnesses", "dampings")


@dataclass(frozen=True)
class Params:
    """Mechanical chain and bit–rock friction law (no operating point).

    ``inertias[i]`` are top to bottom; spring ``i`` (``stiffnesses[i]``, ``dampings[i]``) joins
    inertia ``i`` and ``i + 1``. Build one with :func:`preset`, then change entries with
    :meth:`replace` for non-uniform strings.
    """

    inertias: tuple[float, ...]  #: J_i, kg·m², top drive first, bit last
    stiffnesses: tuple[float, ...]  #: k_i, N·m/rad, one per spring (dof − 1)
    dampings: tuple[float, ...]  #: c_i, N·m·s/rad, one per spring (dof − 1)
    top_damping: float  #: c_r, N·m·s/rad
    bit_damping: float  #: c_b, N·m·s/rad
    bit_radius: float  #: R_b, m
    mu_coulomb: float  #: μ_cb
    mu_static: float  #: μ_sb
    stribeck_decay: float  #: γ_b
    stribeck_velocity: float = 1.0  #: v_f, rad/s
    karnopp_band: float = 1e-6  #: D_v, rad/s (Karnopp friction only)
    name: str = field(default="custom", compare=False)  #: label (the preset's name)

    def __post_init__(self) -> None:
        for key in _LISTS:
            object.__setattr__(self, key, tuple(float(v) for v in getattr(self, key)))
        for key in _SCALARS:
            object.__setattr__(self, key, float(getattr(self, key)))
        self.to_core().validate()  # raises ValueError naming the bad parameter

    @property
    def dof(self) -> int:
        """Number of inertias (degrees of freedom of the chain), ≥ 2."""
        return len(self.inertias)

    @property
    def pipes(self) -> int:
        """Number of drill pipes (``dof − 3``); 0 for the 2- and 3-DOF strings."""
        return max(self.dof - 3, 0)

    def static_torque(self, wob: float) -> float:
        """T_s = μ_sb · W_ob · R_b: the torque the rock holds on a still bit (N·m)."""
        return self.mu_static * wob * self.bit_radius

    def replace(self, **changes: Any) -> Params:
        """A copy with some fields changed (validated like any new Params)."""
        unknown = set(changes) - set(_LISTS) - set(_SCALARS) - {"name"}
        if unknown:
            raise ValueError(
                f"unknown parameter {sorted(unknown)[0]!r}: allowed are "
                + ", ".join(_LISTS + _SCALARS)
            )
        return dataclasses.replace(self, **changes)

    def to_core(self) -> _core.Params:
        """The same parameters as the C++ core's ``pydrill._core.Params``."""
        p = _core.Params()
        for key in _LISTS + _SCALARS:
            setattr(p, key, getattr(self, key))
        return p

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: every field (lists for the chain), ``dof`` and ``name``."""
        d = {key: list(getattr(self, key)) for key in _LISTS}
        d.update({key: getattr(self, key) for key in _SCALARS})
        d["dof"] = self.dof
        d["name"] = self.name
        return d


def resolve_dof(dof: int | None, pipes: int | None, default: int | None = 4) -> int:
    """``dof`` from either ``dof`` or ``pipes`` (``dof = pipes + 3``)."""
    if dof is not None and pipes is not None and dof != pipes + 3:
        raise ValueError(f"dof = {dof} and pipes = {pipes} disagree: pipes P means dof = P + 3")
    if pipes is not None:
        if isinstance(pipes, bool) or int(pipes) != pipes or pipes < 1:
            raise ValueError(f"pipes = {pipes!r} is not allowed: need an integer >= 1")
        return int(pipes) + 3
    if dof is None:
        if default is None:
            raise ValueError("give dof or pipes")
        return default
    if isinstance(dof, bool) or int(dof) != dof or dof < 2:
        raise ValueError(f"dof = {dof!r} is not allowed: need an integer >= 2")
    return int(dof)


def preset(
    name: str = "reduced-scale",
    dof: int | None = None,
    pipes: int | None = None,
    **overrides: Any,
) -> Params:
    """Named parameter set of DESIGN.md §4, optionally with some entries replaced.

    >>> p = preset("reduced-scale", dof=4)
    >>> p.inertias
    (0.518, 0.025, 0.0318, 0.0318)
    >>> preset("reduced-scale", pipes=10).dof
    13
    >>> preset("reduced-scale", dof=3, stiffnesses=[0.073, 0.2]).stiffnesses
    (0.073, 0.2)
    """
    default = 2 if name == "real-string" else 4
    if dof is None and pipes is None:
        # A full list of inertias (or springs) says how long the string is.
        if "inertias" in overrides:
            default = len(_as_list("inertias", overrides["inertias"], 0))
        elif "stiffnesses" in overrides:
            default = len(_as_list("stiffnesses", overrides["stiffnesses"], 0)) + 1
    n = resolve_dof(dof, pipes, default)
    for key in _LISTS:
        if key in overrides:
            values = _as_list(key, overrides[key], n)
            need = n if key == "inertias" else n - 1
            if len(values) != need:
                raise ValueError(
                    f"{key} has {len(values)} entries: dof = {n} needs {need}"
                    + (" (one per inertia)" if key == "inertias" else " (one per spring)")
                )
    core = _core.preset(name, n)
    fields = {key: getattr(core, key) for key in _LISTS + _SCALARS}
    params = Params(**fields, name=name)
    if overrides:
        params = params.replace(**{k: _as_list(k, v, n) for k, v in overrides.items()})
    return params


def _as_list(key: str, value: Any, dof: int) -> Any:
    if key not in _LISTS:
        return value
    if isinstance(value, (str, bytes)):
        raise ValueError(f"{key} must be a list of numbers, got {value!r}")
    try:
        return tuple(float(v) for v in value)
    except TypeError:
        raise ValueError(f"{key} must be a list of numbers, got {value!r}") from None
