"""Drillstring parameters: the lumped torsional chain of DESIGN.md §2 as a plain data class.

Everything is SI: kg·m², N·m/rad, N·m·s/rad, m, rad/s. A string has ``dof`` inertias, top drive
first and bit last; ``pipes`` drill pipes make ``dof = pipes + 3`` (top drive, pipes, drill
collars, bit).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, overload

import numpy as np
from numpy.typing import NDArray

from . import _core
from .model_values import _integer, _number, _plain, _show, check_new_length  # noqa: F401
from .suggest import param_hint

PRESETS = tuple(_core.preset_names())

# The largest string: a tally's at 10 km is some 1100 joints, the longest benchmarked 500 pipes;
# beyond 100000 inertias a point would take hours and a mistyped size runs out of memory.
MAX_DOF = 100_000

# The largest weight on bit (N) and surface torque (N·m) anything takes: far above any drill
# string's loads (a few hundred kN, some 100 kN·m), below where a run would overflow. The C++
# core refuses a simulation beyond it; the analyses and the command line apply it too.
MAX_LOAD = 1e15

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
_UNITS = {
    "inertias": "kg·m²",
    "stiffnesses": "N·m/rad",
    "dampings": "N·m·s/rad",
    "top_damping": "N·m·s/rad",
    "bit_damping": "N·m·s/rad",
    "bit_radius": "m",
    "mu_coulomb": "friction coefficient",
    "mu_static": "friction coefficient",
    "stribeck_decay": "1",
    "stribeck_velocity": "rad/s",
    "karnopp_band": "rad/s",
}


@dataclass(frozen=True)
class Params:
    """Mechanical chain and bit–rock friction law (no operating point).

    ``inertias[i]`` are top to bottom; spring ``i`` (``stiffnesses[i]``, ``dampings[i]``) joins
    inertia ``i`` and ``i + 1``. Build one with :func:`preset`, then change entries with
    :meth:`replace` for non-uniform strings. Every entry is a real number (a Python or numpy
    number, or a 0-d array): a string or a bool raises ``TypeError`` naming the field, a bad
    value ``ValueError``; a string has at most ``MAX_DOF`` (100000) inertias. At each inertia,
    the decay rate (the dampings acting on it over its inertia) must be at most 1e15 /s and the
    frequency (the stiffnesses' sqrt(k/J)) at most 1e150 rad/s: no double-precision solver
    integrates faster ones (a real string's are below 1e7). The bit's friction torque and its
    Stribeck slope must stay within a float at every weight on bit up to ``MAX_LOAD`` (1e15 N):
    ``mu_static * bit_radius`` at most 1.8e293, for one.
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
        if not isinstance(self.name, str):  # it labels results, JSON and atlases as text
            raise TypeError(f"name = {self.name!r} is not allowed: a label, must be a str")
        for key in _LISTS:
            values = getattr(self, key)
            n = _length(values)
            if n is not None and n > MAX_DOF:  # refused before a long list is converted
                raise ValueError(
                    f"{key} has {n} entries: a string has at most {MAX_DOF} inertias (MAX_DOF)"
                )
            object.__setattr__(self, key, _numbers(key, values))
        if self.dof > MAX_DOF:  # from an iterator without a length
            raise ValueError(f"inertias has {self.dof} entries: at most {MAX_DOF} (MAX_DOF)")
        for key in _SCALARS:
            object.__setattr__(self, key, _number(key, getattr(self, key), _UNITS[key]))
        _check_friction(self.mu_coulomb, self.mu_static, changed="mu_static")
        self._core_params().validate()  # raises ValueError naming the bad parameter
        _check_scale(self)

    def __repr__(self) -> str:
        # One line, as SimulationResult's: the dataclass's own listed every entry, 18881
        # characters for a tally's string of 300 inertias.
        k = self.stiffnesses
        return (
            f"<Params {self.name!r} dof={self.dof}: inertias {sum(self.inertias):.4g} kg·m² in "
            f"all (bit {self.inertias[-1]:.4g}), stiffnesses {min(k):.4g} ... {max(k):.4g} "
            f"N·m/rad, bit_radius {self.bit_radius:.4g} m, mu_static {self.mu_static:.4g}, "
            f"mu_coulomb {self.mu_coulomb:.4g}>"
        )

    def _core_params(self) -> _core.Params:
        """:meth:`to_core`, built once for this Params and shared by pydrill's own calls, which
        only read it (the core takes ``const Params&``): a sweep's point hands one string to
        the core three times, and building it was 3 % of a dof-4 point's time. Kept out of
        pickles (``__getstate__``): the core's Params cannot be pickled."""
        core = self.__dict__.get("_core")
        if core is None:
            core = self.__dict__["_core"] = self.to_core()  # (frozen: past __setattr__)
        return core

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state.pop("_core", None)
        return state

    @property
    def dof(self) -> int:
        """Number of inertias (degrees of freedom of the chain), ≥ 2."""
        return len(self.inertias)

    @property
    def pipes(self) -> int:
        """Number of drill pipes (``dof − 3``); 0 for the 2- and 3-DOF strings."""
        return max(self.dof - 3, 0)

    @overload
    def static_torque(self, wob: float) -> float: ...
    @overload
    def static_torque(self, wob: NDArray[np.float64]) -> NDArray[np.float64]: ...
    def static_torque(self, wob: float | NDArray[np.float64]) -> float | NDArray[np.float64]:
        """T_s = μ_sb · W_ob · R_b: the torque the rock holds on a still bit (N·m); of each
        weight on bit (N, finite, >= 0) for an array of them."""
        from .stability_checks import _checked  # (stability imports this module)

        w = _checked("wob", wob, 0.0, strict=False)  # NaN gave NaN, "abc" a TypeError of str's
        with np.errstate(over="ignore"):  # (redone below)
            ts = self.mu_static * w * self.bit_radius
        if not np.isfinite(ts).all():
            # μ_sb·W_ob overflowed (inf for mu_static = 3.4e293, bit_radius = 0.5, 1e15 N):
            # μ_sb·R_b first, the product _check_scale bounds. Only then: the order above is
            # the formula's, and T_s is compared with torques computed that way.
            ts = np.where(np.isfinite(ts), ts, self.mu_static * self.bit_radius * w)
        return float(ts) if w.ndim == 0 else ts

    def replace(self, **changes: Any) -> Params:
        """A copy with some fields changed (validated like any new Params)."""
        unknown = set(changes) - set(_LISTS) - set(_SCALARS) - {"name"}
        if unknown:
            raise ValueError(
                f"unknown parameter {sorted(unknown)[0]!r}"
                f"{param_hint(sorted(unknown)[0], _LISTS + _SCALARS)}: allowed are "
                + ", ".join(_LISTS + _SCALARS)
            )
        mu = [k for k in ("mu_coulomb", "mu_static") if k in changes]
        if len(mu) == 1:  # name the coefficient changed, not the one kept
            value = _number(mu[0], changes[mu[0]], _UNITS[mu[0]])
            coulomb = value if mu[0] == "mu_coulomb" else self.mu_coulomb
            static = value if mu[0] == "mu_static" else self.mu_static
            _check_friction(coulomb, static, changed=mu[0])
        check_new_length(self, changes)
        return dataclasses.replace(self, **changes)

    def to_core(self) -> _core.Params:
        """The same parameters as the C++ core's ``pydrill._core.Params``."""
        p = _core.Params()
        for key in _LISTS + _SCALARS:
            setattr(p, key, getattr(self, key))
        return p

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: every field (lists for the chain), ``dof`` and ``name``;
        :meth:`from_dict` reads it back."""
        d: dict[str, Any] = {key: list(getattr(self, key)) for key in _LISTS}
        d.update({key: getattr(self, key) for key in _SCALARS})
        d["dof"] = self.dof
        d["name"] = self.name
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Params:
        """The Params :meth:`to_dict` wrote (e.g. read back from JSON): ``dof``, derived, must
        agree with the chain's length if given; any other unknown key is refused by name."""
        if not isinstance(data, Mapping):  # (dict() of a list or a str said nothing of Params)
            raise TypeError(f"data must be a dict, as Params.to_dict writes, got {_show(data)}")
        data = dict(data)
        dof = data.pop("dof", None)
        unknown = set(data) - set(_LISTS) - set(_SCALARS) - {"name"}
        if unknown:
            raise ValueError(
                f"unknown parameter {sorted(unknown)[0]!r}"
                f"{param_hint(sorted(unknown)[0], _LISTS + _SCALARS)}: allowed are "
                + ", ".join((*_LISTS, *_SCALARS, "name", "dof"))
            )
        lost = [k for k in _LISTS + _SCALARS[:-2] if k not in data]  # (the last two: defaults)
        if lost:
            raise ValueError(
                f"{lost[0]} is missing: Params.from_dict needs every field to_dict writes"
            )
        params = cls(**data)
        if dof is not None and dof != params.dof:
            raise ValueError(f"dof = {dof!r} does not match the {params.dof} inertias given")
        return params


def resolve_dof(dof: int | None, pipes: int | None, default: int | None = 4) -> int:
    """``dof`` from either ``dof`` or ``pipes`` (``dof = pipes + 3``), each checked (an
    integer, as every integer argument: a float, even 3.0, is a ``TypeError``; at most
    ``MAX_DOF`` inertias)."""
    if dof is not None:
        dof = _integer("dof", dof, 2, MAX_DOF, hint=_LARGEST)
    if pipes is not None:
        pipes = _integer("pipes", pipes, 1, MAX_DOF - 3, hint=_LARGEST)
    if dof is not None and pipes is not None and dof != pipes + 3:
        raise ValueError(f"dof = {dof} and pipes = {pipes} disagree: pipes P means dof = P + 3")
    if pipes is not None:
        return pipes + 3
    if dof is None:
        if default is None:
            raise ValueError("give dof or pipes")
        return default
    return dof


def preset(
    name: str = "reduced-scale",
    dof: int | None = None,
    pipes: int | None = None,
    **overrides: Any,
) -> Params:
    """Named parameter set of DESIGN.md §4, optionally with some entries replaced.

    Parameters:

    - ``name``: one of :data:`PRESETS`: ``"reduced-scale"`` (the laboratory rig of the
      paper's Eq. 14, 2 to any number of inertias) or ``"real-string"`` (Eq. 53, 2 inertias).
    - ``dof``: the number of inertias, top drive first and bit last: an integer 2 ...
      ``MAX_DOF`` (100000). Default 4 (2 for ``"real-string"``), or the length of a full
      ``inertias`` list given as an override.
    - ``pipes``: the number of drill pipes instead, 1 ... 99997: ``dof = pipes + 3`` (top
      drive, pipes, drill collars, bit). Giving both, they must agree.
    - ``overrides``: fields of :class:`Params` to replace, e.g. ``bit_radius=0.12`` or a
      whole list ``stiffnesses=[...]`` (one entry per spring, ``dof − 1``).

    Bad input raises ``TypeError`` (a wrong type) or ``ValueError`` (a bad value), naming
    the parameter.

    >>> p = preset("reduced-scale", dof=4)
    >>> p.inertias
    (0.518, 0.025, 0.0318, 0.0318)
    >>> preset("reduced-scale", pipes=10).dof
    13
    >>> preset("reduced-scale", dof=3, stiffnesses=[0.073, 0.2]).stiffnesses
    (0.073, 0.2)
    """
    if not isinstance(name, str):
        raise TypeError(
            f"name must be a preset name, one of {', '.join(PRESETS)}, got {_show(name)}"
        )
    unknown = set(overrides) - set(_LISTS) - set(_SCALARS)
    if unknown:
        raise ValueError(
            f"unknown parameter {sorted(unknown)[0]!r}"
            f"{param_hint(sorted(unknown)[0], _LISTS + _SCALARS)}: allowed are "
            + ", ".join(_LISTS + _SCALARS)
        )
    # Each list read once: a generator, read again below, was found empty ("has 0 entries").
    overrides = {k: _as_list(k, v, 0) for k, v in overrides.items()}
    default = 2 if name == "real-string" else 4
    if dof is None and pipes is None:
        # A full list of inertias says how long the string is. The springs' lists do not:
        # two stiffnesses for the 4-inertia preset made a 3-inertia string without a word
        # (mostly an entry left out), where two dampings were refused; both must agree now.
        if "inertias" in overrides:
            default = len(_as_list("inertias", overrides["inertias"], 0))
        if default > MAX_DOF:
            raise ValueError(
                f"a string of {default} inertias is not allowed: at most {MAX_DOF} (MAX_DOF)"
            )
    n = resolve_dof(dof, pipes, default)
    for key in _LISTS:
        if key in overrides:
            values = _as_list(key, overrides[key], n)
            need = n if key == "inertias" else n - 1
            if len(values) != need:
                entries = "1 entry" if len(values) == 1 else f"{len(values)} entries"
                raise ValueError(
                    f"{key} has {entries}: dof = {n} needs {need}"
                    + (" (one per inertia)" if key == "inertias" else " (one per spring)")
                )
    if name == "real-string" and n != 2:
        # Refused here, not by the core: its message names C++'s Params::inertias.
        size = (
            f"dof = {n}"
            if dof is not None
            else f"pipes = {pipes} (dof = {n})"
            if pipes is not None
            else f"a string of {n} inertias (inertias has {n} entries)"
        )
        raise ValueError(
            f"{size} is not allowed for preset 'real-string': it is the paper's 2-DOF string "
            "(Eq. 53); use dof = 2, or give a longer string element by element "
            "(pydrill.Params(inertias=..., stiffnesses=..., dampings=..., ...)) or from a pipe "
            f"tally (pydrill.load_tally(path).to_params(dof={n}); "
            "examples/tallies/paper-eq53.toml is the paper's)"
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
    return _numbers(key, value)


# --- checks of single values, shared with pydrill.simulate -------------------------------------

_LARGEST = f" (a string has at most {MAX_DOF} inertias; pipes P means dof = P + 3)"


def _load(name: str, value: float, unit: str) -> float:
    """``value``, a weight on bit (N) or torque (N·m), refused by name beyond ``MAX_LOAD``."""
    if abs(value) > MAX_LOAD:
        raise ValueError(
            f"{name} = {value:g} is not allowed: at most 1e15 {unit} in size (MAX_LOAD; far "
            "above any drill string's loads)"
        )
    return value


def _numbers(key: str, values: Any) -> tuple[float, ...]:
    """A list field (``inertias``, …) as a tuple of floats, each entry checked by name:
    ``TypeError`` for what is no list of entries (a number, None, a str, a dict, a set),
    ``ValueError`` for an array of another shape."""
    if isinstance(values, np.ndarray) and values.ndim == 1 and values.dtype.kind in "iuf":
        return tuple(values.astype(float).tolist())
    if isinstance(values, np.ndarray) and values.ndim > 1:
        raise ValueError(f"{key} must be a 1-D list of numbers, got an array of {values.shape}")
    # (a set has no order: {1.0, 2.0} gave some order of the string's entries)
    if isinstance(values, (str, bytes, dict, set, frozenset)) or (
        isinstance(values, np.ndarray) and values.ndim == 0
    ):
        raise TypeError(f"{key} must be a list of numbers, got {_show(values)}")
    try:
        values = list(values)
    except TypeError:  # not iterable: a number, None
        raise TypeError(f"{key} must be a list of numbers, got {_show(values)}") from None
    unit = _UNITS[key]
    # Floats pass as they are; only another type has its entry named (and checked): a name
    # built for each of a long string's entries cost more than the rest of the check.
    return tuple(
        v if type(v) is float else _number(f"{key}[{i}]", v, unit) for i, v in enumerate(values)
    )


def _length(values: Any) -> int | None:
    try:
        return len(values)
    except TypeError:
        return None


def _check_scale(p: Params) -> None:
    """Refuse a friction law whose torque (μ_sb R_b W_ob) or Stribeck slope at Ω = 0 overflows
    a float at some allowed W_ob (up to MAX_LOAD): mu_static = 1e308 ran to a static_torque of
    inf, and its stability maps to overflow warnings."""
    slope = p.bit_radius * p.stribeck_decay / p.stribeck_velocity * (p.mu_static - p.mu_coulomb)
    for names, value in (
        (("mu_static", "bit_radius"), p.mu_static * p.bit_radius),
        (("bit_radius", "stribeck_decay", "stribeck_velocity", "mu_static", "mu_coulomb"), slope),
    ):
        if not value * MAX_LOAD < math.inf:
            given = ", ".join(f"{n} = {getattr(p, n):g}" for n in names)
            raise ValueError(
                f"{given} are not allowed together: the bit's friction torque (or its Stribeck "
                "slope) at the largest weight on bit, MAX_LOAD = 1e15 N, overflows a float"
            )


def _check_friction(coulomb: float, static: float, changed: str) -> None:
    """0 < μ_cb < μ_sb, blaming ``changed`` (the core names finiteness itself)."""
    if not (math.isfinite(coulomb) and math.isfinite(static)) or 0 < coulomb < static:
        return
    if changed == "mu_coulomb" or not coulomb > 0:
        raise ValueError(
            f"mu_coulomb = {coulomb:g} is not allowed: need 0 < mu_coulomb < mu_static ({static:g})"
        )
    raise ValueError(
        f"mu_static = {static:g} is not allowed: need mu_static > mu_coulomb ({coulomb:g})"
    )
