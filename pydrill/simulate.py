"""Simulation of one operating point: ``pydrill.simulate`` (its result: ``pydrill.result``)."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from . import model as _model
from .model import _LISTS, _SCALARS, PRESETS, Params, _integer, _number, _plain, _show
from .result import (  # re-exported: pydrill.simulate.SimulationResult and kin (__all__)
    MODES,
    REGIMES,
    UNITS,
    Regime,
    SimulationResult,
    SolverStats,
    Summary,
    Switch,
)
from .simulate_checks import _check_normal_times, _check_output_size
from .suggest import param_hint

#: The longest run, s: 317 years, beyond the life of any bit or rig. Beyond it a run cannot be
#: done: CVODES's first step overflows (t_end = 1e300 failed at t = 0 with h = 1e109), and
#: DOP853 runs for minutes into its step limit (``max_steps``).
MAX_T_END = 1e10
YEAR = 365.25 * 86400.0

# What this module exports, for ``from pydrill.simulate import MODES`` under mypy --strict (an
# import is re-exported only if listed). ``pydrill.simulate`` itself is the function (it
# shadows the module): ``pydrill.MODES``, ``pydrill.MAX_T_END`` are the same objects.
__all__ = [
    "MAX_T_END",
    "MODES",
    "REGIMES",
    "UNITS",
    "Regime",
    "SimulationResult",
    "SolverStats",
    "Summary",
    "Switch",
    "simulate",
]


def simulate(
    params: Params | None = None,
    *,
    wob: float,
    torque: float,
    t_end: float = 300.0,
    initial: str | ArrayLike = "rest",
    friction: str = "exact",
    method: str = "auto",
    t_out: ArrayLike | None = None,
    n_out: int = 3001,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    max_step: float = 0.0,
    max_order: int = 0,
    max_steps: int = 50_000_000,
    perturbation: float = 1e-3,
    window_fraction: float = 0.5,
    max_switch_rate: float | None = 1e4,
    preset: str | None = None,
    dof: int | None = None,
    pipes: int | None = None,
    **overrides: Any,
) -> SimulationResult:
    """Simulate the string at weight on bit ``wob`` (N) and surface torque ``torque`` (N·m).

    The string is ``params``, or the preset ``preset`` with ``dof`` (or ``pipes``) and any
    parameter ``overrides`` (e.g. ``inertias=[...]``). ``initial`` is ``"rest"`` (everything
    still — the driller's start-up), ``"equilibrium"`` (the fastest steady state with the bit
    velocity perturbed by ``perturbation`` relative), or a twist-coordinate state of length
    ``2·dof − 1``. ``friction="exact"`` locates every stick/slip switch by rootfinding;
    ``"karnopp"`` is the paper's Eq. (9) with its zero-velocity band. ``method`` is ``"auto"``
    (chosen from a stiffness estimate; ``stats.method_reason`` says why), ``"dop853"``
    (explicit Runge–Kutta 8(5,3), non-stiff strings), ``"bdf"`` (CVODES, each Newton solve a
    tridiagonal one by pydrill's chain solver, for stiff strings), ``"adams"`` (CVODES) or
    ``"erk"`` (ARKODE Runge–Kutta 7(8)).

    Parameters:

    - ``params``: a :class:`Params` (from :func:`preset` or ``Params(...)``), or None to
      build the string from ``preset``, ``dof``/``pipes`` and ``overrides``.
    - ``wob`` (N), ``torque`` (N·m): the operating point, weight on bit > 0 and the torque
      the top drive applies; both at most 1e15 in size (far above any drill string's loads,
      below where the run would overflow).
    - ``t_end`` (s): simulated time, from t = 0; > 0, at most ``pydrill.MAX_T_END`` (1e10 s,
      317 years).
    - ``initial``: ``"rest"``, ``"equilibrium"`` or a 1-D state of ``2·dof − 1`` numbers
      (ω_0, θ_0, ω_1, …, θ_{N−2}, ω_b; rad/s and rad).
    - ``t_out`` (s): the output times, a non-empty 1-D increasing list in ``[0, t_end]``;
      None (default) for ``n_out`` uniform times from 0 to ``t_end``. Each time is 0 or at least
      2.2e-308 s, and the uniform ones at least that far apart (the core computes with
      subnormal numbers flushed to 0).
    - ``n_out``: how many uniform output times, 2 ... 1e8. With ``t_out`` it is not used
      (only checked): its default, 3001, cannot be told from one given. The output, 2·dof − 1
      numbers of 8 bytes at each output time, must fit in the machine's memory.
    - ``rtol`` (1e-14 <= rtol <= 0.01), ``atol`` (1e-20 <= atol <= 0.001, in the state's
      units: rad and rad/s): the integrator's relative and absolute error tolerances per
      step. Looser ones misjudge the regime (at rtol 0.05 a steady case was judged stick-slip).
    - ``max_step`` (s): the longest internal step; 0 (default) for no limit.
    - ``max_order``: the highest order of ``"bdf"`` (1 ... 5) or ``"adams"`` (1 ... 12);
      0 (default) for the method's own. Other methods take only 0.
    - ``max_steps``: internal steps allowed over the whole run before a
      :class:`pydrill.SolverError`, 1 ... 2**62. An explicit method (dop853, erk, adams)
      whose fastest mode needs more steps than that to reach ``t_end`` stable is refused
      with the SolverError at t = 0, naming the mode and the steps it needs, rather than
      after grinding through them.
    - ``perturbation``: relative kick of the bit velocity for ``initial="equilibrium"``,
      ``|perturbation| < 1``.
    - ``window_fraction``: the last fraction of the run the regime is judged on, in (0, 1].
    - ``max_switch_rate`` (switches/s): the chattering guard. At each friction switch
      the 50 intervals back to the 50th switch before it are timed: shorter than 50 /
      ``max_switch_rate`` s in all (their mean rate above it), the run is stopped with a
      :class:`pydrill.SolverError`. Only such bursts are stopped, not a run's mean rate: a
      run of 50 switches or fewer never is. None (or inf) for no limit.
    - ``preset``: the name of the parameter set (:data:`PRESETS`); None (default) for
      ``"reduced-scale"``. Only without ``params``, or equal to ``params.name``.
    - ``dof``: the number of inertias, 2 ... ``MAX_DOF`` (100000); default 4. With
      ``params`` it must agree with ``params.dof``.
    - ``pipes``: the number of drill pipes instead: ``dof = pipes + 3``.
    - ``overrides``: fields of :class:`Params` to replace, e.g. ``bit_radius=0.12``.

    Every number may be a Python or numpy number or a 0-d array. A wrong type (a string, a
    bool, a list for a number) raises ``TypeError`` and a bad value ``ValueError``, naming
    the parameter; a solver failure raises :class:`pydrill.SolverError` with the
    integrator's message and the time reached. The result's :meth:`SimulationResult.inputs`
    repeats the run: ``simulate(**r.inputs())``.

    >>> r = simulate(wob=100, torque=8.3, dof=4, t_end=300)
    >>> r.regime
    'stick-slip'
    """
    if preset is not None and not isinstance(preset, str):
        raise TypeError(
            f"preset must be a preset name, one of {', '.join(PRESETS)}, got {_show(preset)}"
        )
    _check_keys(overrides)
    if params is None:
        params = _model.preset(
            "reduced-scale" if preset is None else preset, dof=dof, pipes=pipes, **overrides
        )
        if preset is None and set(_LISTS + _SCALARS) <= set(overrides):
            # Every field given (as inputs() writes a string that is no preset's): nothing of
            # the reduced-scale rig is left, so it is not labelled as one.
            params = params.replace(name="custom")
    elif not isinstance(params, Params):
        hint = (
            f" (for a preset by name, write preset={params!r})" if isinstance(params, str) else ""
        )
        raise TypeError(
            "params must be a pydrill.Params (from pydrill.preset or Params(...)), got "
            f"{_type_name(params)}{hint}"
        )
    else:
        if preset is not None and preset != params.name:
            raise ValueError(
                f"preset = {preset!r} disagrees with params (a {params.name!r} string): give "
                "params or preset, not both"
            )
        if dof is not None or pipes is not None:
            n = _model.resolve_dof(dof, pipes, params.dof)
            if n != params.dof:
                given = f"dof = {n}" if pipes is None else f"pipes = {n - 3} (dof = {n})"
                raise ValueError(
                    f"{given} disagrees with params (dof = {params.dof}, pipes = {params.pipes})"
                )
        params = params.replace(**overrides) if overrides else params
    wob = _number("wob", wob, "N")
    torque = _number("torque", torque, "N·m")
    settings, opts = _options(
        params.dof,
        t_end=t_end,
        initial=initial,
        friction=friction,
        method=method,
        t_out=t_out,
        n_out=n_out,
        rtol=rtol,
        atol=atol,
        max_step=max_step,
        max_order=max_order,
        max_steps=max_steps,
        perturbation=perturbation,
        window_fraction=window_fraction,
        max_switch_rate=max_switch_rate,
    )
    core = _core.simulate(params._core_params(), wob, torque, opts)
    return SimulationResult(core, params, settings)


def _options(
    dof: int,
    *,
    t_end: float,
    initial: str | ArrayLike,
    friction: str,
    method: str,
    t_out: ArrayLike | None,
    n_out: int,
    rtol: float,
    atol: float,
    max_step: float,
    max_order: int,
    max_steps: int,
    perturbation: float,
    window_fraction: float,
    max_switch_rate: float | None,
) -> tuple[dict[str, Any], _core.SimulationOptions]:
    """simulate's settings, checked (each refused by name, as documented there), and the core's
    options made of them, for a string of ``dof`` inertias. Apart from simulate so that a sweep
    builds them once for all its points (sweep_points._run_options): they do not depend on
    W_ob, u or the string's parameters, and checking and building them anew at every run was,
    with the SimulationResult a sweep does not read, 8 % of a dof-4 point's CPU time."""
    t_end = _number("t_end", t_end, "s")
    if not 0 < t_end <= MAX_T_END:  # (a NaN fails it too)
        raise ValueError(
            f"t_end = {t_end:g} is not allowed: need 0 < t_end <= 1e10 s ("
            f"{MAX_T_END / YEAR:.0f} years)"
        )
    settings: dict[str, Any] = {"t_end": t_end}
    opts = _core.SimulationOptions()
    opts.t_end = t_end
    settings["initial"] = _initial(initial, dof)
    if isinstance(settings["initial"], str):
        opts.initial = settings["initial"]
    else:
        opts.initial = "state"
        opts.state = settings["initial"]
    settings["friction"] = opts.friction = _choice("friction", friction, ("exact", "karnopp"))
    settings["method"] = opts.method = _choice(
        "method", method, ("auto", "bdf", "adams", "erk", "dop853")
    )
    settings["t_out"] = _times(t_out)
    if settings["t_out"] is not None:
        opts.t_out = settings["t_out"]
    settings["n_out"] = opts.n_out = _integer("n_out", n_out, 2, 100_000_000)
    _check_output_size(settings["t_out"], settings["n_out"], dof)
    _check_normal_times(t_end, settings["t_out"], settings["n_out"])
    for key, value, unit in (
        ("rtol", rtol, "relative tolerance"),
        ("atol", atol, "absolute tolerance"),
        ("max_step", max_step, "s"),
        ("perturbation", perturbation, "relative to the steady bit velocity"),
        ("window_fraction", window_fraction, "a fraction of the run"),
        # None (JSON's null, as inputs() writes it) for no limit: inf is not JSON
        ("max_switch_rate", math.inf if max_switch_rate is None else max_switch_rate, "switches/s"),
    ):
        settings[key] = _number(key, value, unit)
        setattr(opts, key, settings[key])
    settings["max_order"] = opts.max_order = _integer(
        "max_order", max_order, 0, 12, hint=" (0: the method's own; bdf 1 ... 5, adams 1 ... 12)"
    )
    settings["max_steps"] = opts.max_steps = _integer("max_steps", max_steps, 1, 2**62)
    return settings, opts


# simulate's own keyword arguments (what an unknown one is checked against)
_OPTIONS = (
    "wob",
    "torque",
    "t_end",
    "initial",
    "friction",
    "method",
    "t_out",
    "n_out",
    "rtol",
    "atol",
    "max_step",
    "max_order",
    "max_steps",
    "perturbation",
    "window_fraction",
    "max_switch_rate",
    "preset",
    "dof",
    "pipes",
)


def _check_keys(overrides: dict[str, Any]) -> None:
    """Refuse a keyword that is neither an option of simulate nor a model parameter."""
    if "name" in overrides:
        raise ValueError(
            f"name = {overrides['name']!r} is not an option of simulate: choose the parameter "
            "set with preset=..., or label a string with Params.replace(name=...) and pass it"
        )
    for key in sorted(set(overrides) - set(_LISTS) - set(_SCALARS)):
        hint = param_hint(key, _OPTIONS + _LISTS + _SCALARS)
        raise ValueError(
            f"unknown parameter {key!r}{hint}: not an option of simulate nor a model parameter; "
            f"the options are {', '.join(_OPTIONS)}; the model parameters are "
            + ", ".join(_LISTS + _SCALARS)
        )


def _initial(value: Any, dof: int) -> str | list[float]:
    """``"rest"``, ``"equilibrium"`` or a checked state of ``2·dof − 1`` floats."""
    if isinstance(value, str):
        return _choice("initial", value, ("rest", "equilibrium"))
    allowed = f"'rest', 'equilibrium' or a state of 2*dof-1 = {2 * dof - 1} numbers"
    state = _vector("initial", value, allowed, "rad/s and rad")
    if len(state) != 2 * dof - 1:
        raise ValueError(
            f"initial has {len(state)} entries: dof = {dof} needs 2*dof-1 = {2 * dof - 1} "
            "(w_0, theta_0, ..., theta_{N-2}, w_bit)"
        )
    for k, v in enumerate(state):  # named as given, not as the core's "state[k]"
        if not math.isfinite(v):
            raise ValueError(f"initial[{k}] = {v} is not allowed: must be finite")
    return state


def _times(value: Any) -> list[float] | None:
    """``t_out``: None, or a non-empty 1-D list of times as floats."""
    if value is None:
        return None
    times = _vector("t_out", value, "a list of output times (s), or None", "s")
    if not times:
        raise ValueError(
            "t_out is empty: give at least one output time in [0, t_end] (s), or None for "
            "n_out uniform times"
        )
    return times


def _vector(name: str, value: Any, allowed: str, unit: str) -> list[float]:
    """A 1-D array-like of real numbers as a list of floats; ``TypeError`` for anything else
    (None, a string, a number, booleans), ``ValueError`` for another shape."""
    if value is None or isinstance(value, (str, bytes, dict)):
        raise TypeError(f"{name} must be {allowed}, got {_show(value)}")
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):  # ragged nesting
        raise TypeError(f"{name} must be {allowed}, got {_show(value)}") from None
    if array.ndim == 0:
        raise TypeError(f"{name} must be {allowed}, got {_show(_plain(value))}")
    if array.dtype.kind not in "iuf":
        # The entries as given: numpy made [0, "1"] an array of strings, and "0" was blamed.
        for v in _entries(value) if isinstance(value, (list, tuple)) else array.ravel():
            entry = _plain(v)
            if isinstance(entry, bool) or not isinstance(entry, (int, float)):
                raise TypeError(f"{name} must be {allowed}: an entry is {_show(entry)}")
        if array.dtype.kind == "O":  # Python integers beyond int64: as floats (or refused)
            array = np.array([_number(name, v, unit) for v in array.ravel()]).reshape(array.shape)
    if array.ndim != 1:
        raise ValueError(f"{name} has shape {array.shape}, not 1-D: it must be {allowed}")
    return array.astype(float).tolist()


def _entries(value: Any) -> Iterator[Any]:
    """The leaves of nested lists and tuples, in order."""
    for v in value:
        if isinstance(v, (list, tuple)):
            yield from _entries(v)
        else:
            yield v


def _type_name(value: Any) -> str:
    """``dict``, or ``pydrill._core.Params`` for a type that is no builtin."""
    cls = type(value)
    return cls.__name__ if cls.__module__ == "builtins" else f"{cls.__module__}.{cls.__qualname__}"


def _choice(name: str, value: Any, allowed: tuple[str, ...]) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{name} must be one of {', '.join(allowed)}, got {_show(value)}")
    if value not in allowed:
        raise ValueError(f"{name} = {value!r} is not allowed: choose one of {', '.join(allowed)}")
    return str(value)
