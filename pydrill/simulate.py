"""Simulation of one operating point: ``pydrill.simulate`` and its result."""

from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from . import model as _model
from .model import Params

Regime = Literal["steady", "stick-slip", "stuck", "oscillation"]
REGIMES: tuple[str, ...] = ("steady", "stick-slip", "stuck", "oscillation")
MODES: tuple[str, ...] = tuple(_core.mode_names())  # index = value in SimulationResult.modes

UNITS = {
    "time": "s",
    "velocity": "rad/s",
    "angle": "rad",
    "torque": "N·m",
    "wob": "N",
    "energy": "J",
    "period": "s",
    "wall_time": "s",
}


@dataclass(frozen=True)
class Switch:
    """One friction switch: the bit sticks, slips, or reverses."""

    t: float  #: s
    kind: str  #: "stick", "slip", "reversal" (exact) or "band-enter", "band-leave" (Karnopp)
    direction: int  #: bit direction after the switch: +1, −1, or 0 when held
    reaction_torque: float  #: T_e at the switch, N·m
    root_residual: float  #: value of the root function that triggered it (≈ 0)


@dataclass(frozen=True)
class SolverStats:
    """What the integrator did; counters are summed across re-initialisations."""

    method: str
    method_reason: str
    stiffness_ratio: float
    steps: int
    rhs_evals: int
    jac_evals: int
    lin_setups: int
    lin_solves: int
    nonlin_iters: int
    nonlin_conv_fails: int
    err_test_fails: int
    root_evals: int
    reinits: int
    switches: int
    wall_time: float  #: s spent in the C++ core


@dataclass(frozen=True)
class Summary:
    """The regime and its metrics, judged on the window ``[window_start, window_end]``."""

    regime: str
    window_start: float
    window_end: float
    bit_min: float
    bit_max: float
    bit_mean: float
    top_min: float
    top_max: float
    top_mean: float
    severity: float  #: (max ω_b − min ω_b) / (2 mean ω_b)
    bit_top_ratio: float  #: max ω_b / mean ω_top
    stuck_fraction: float
    period: float | None  #: s, stick-slip or oscillation period
    stick_events: int
    static_torque: float  #: T_s = μ_sb W_ob R_b
    omega_equilibrium: tuple[float, ...]  #: every steady velocity Ω > 0 for (W_ob, u)
    note: str = ""  #: caveat about the judgement (e.g. the run was too short)


class SimulationResult:
    """Output of :func:`simulate`. Arrays are read-only views of the core's memory (no copies).

    ``states`` holds the twist coordinates ``(ω_0, θ_0, ω_1, …, θ_{N−2}, ω_b)`` at times ``t``;
    ``omega`` and ``twist`` are strided views of it.
    """

    def __init__(self, core: Any, params: Params, settings: dict[str, Any]) -> None:
        self._core = core
        self.params = params
        self.settings = settings
        self.wob: float = core.wob
        self.torque: float = core.torque
        self.t: NDArray[np.float64] = core.t
        self.states: NDArray[np.float64] = core.states
        self.top_angle: NDArray[np.float64] = core.top_angle
        self.work_input: NDArray[np.float64] = core.work_input
        self.viscous_loss: NDArray[np.float64] = core.viscous_loss
        self.friction_loss: NDArray[np.float64] = core.friction_loss
        self.energy: NDArray[np.float64] = core.energy
        self.mode_index: NDArray[np.int32] = core.modes
        self.stats = SolverStats(**core.stats)
        summary = dict(core.summary)
        summary["omega_equilibrium"] = tuple(summary["omega_equilibrium"])
        self.summary = Summary(**summary)

    @functools.cached_property
    def switches(self) -> list[Switch]:
        """Every stick, slip and reversal of the bit, in time order. Built when first asked
        for: a sweep reads only the summary, and a long stick-slip run has thousands."""
        return [Switch(**s) for s in self._core.switches]

    @property
    def dof(self) -> int:
        """Number of inertias of the simulated string (top drive first, bit last)."""
        return self.params.dof

    @property
    def regime(self) -> str:
        """``"steady"``, ``"stick-slip"``, ``"stuck"`` or ``"oscillation"`` (see :data:`REGIMES`),
        judged on the last ``window_fraction`` of the run; the metrics are in :attr:`summary`."""
        return self.summary.regime

    @property
    def omega(self) -> NDArray[np.float64]:
        """Angular velocities, shape (len(t), dof), top drive first (rad/s)."""
        return self.states[:, 0::2]

    @property
    def twist(self) -> NDArray[np.float64]:
        """Twists θ_i = φ_i − φ_{i+1}, shape (len(t), dof − 1) (rad)."""
        return self.states[:, 1::2]

    @property
    def bit_velocity(self) -> NDArray[np.float64]:
        """ω_b, the bit's angular velocity at times ``t`` (rad/s)."""
        return self.states[:, -1]

    @property
    def top_velocity(self) -> NDArray[np.float64]:
        """ω_0, the top drive's angular velocity at times ``t`` (rad/s)."""
        return self.states[:, 0]

    @property
    def angles(self) -> NDArray[np.float64]:
        """Absolute angles φ_i, shape (len(t), dof), recovered by summing twists (rad)."""
        phi = np.empty((len(self.t), self.dof))
        phi[:, 0] = self.top_angle
        phi[:, 1:] = self.top_angle[:, None] - np.cumsum(self.twist, axis=1)
        return phi

    @property
    def bit_angle(self) -> NDArray[np.float64]:
        """φ_b, the bit's absolute angle at times ``t`` (rad)."""
        return self.top_angle - self.twist.sum(axis=1)

    @property
    def reaction_torque(self) -> NDArray[np.float64]:
        """T_e = k θ_{N−2} + c (ω_{N−2} − ω_b) − c_b ω_b: what the rock must hold (N·m)."""
        p = self.params
        wb = self.bit_velocity
        return (
            p.stiffnesses[-1] * self.twist[:, -1]
            + p.dampings[-1] * (self.omega[:, -2] - wb)
            - p.bit_damping * wb
        )

    @property
    def modes(self) -> list[str]:
        """The friction mode at each output time: ``"slip+"``, ``"slip-"``, ``"stick"`` or
        ``"band"`` (Karnopp); ``mode_index`` holds the same as codes into ``MODES``
        (``from pydrill.simulate import MODES``)."""
        return [MODES[i] for i in self.mode_index]

    def stick_intervals(self) -> list[tuple[float, float]]:
        """Time intervals in which the rock holds the bit (stick, or the Karnopp band)."""
        held = {"stick", "band-enter"}
        intervals: list[tuple[float, float]] = []
        start = 0.0 if MODES[self.mode_index[0]] in ("stick", "band") else None
        for s in self.switches:
            if s.kind in held and start is None:
                start = s.t
            elif s.kind not in held and start is not None:
                intervals.append((start, s.t))
                start = None
        if start is not None:
            intervals.append((start, float(self.t[-1])))
        return intervals

    def energy_balance_error(self) -> float:
        """Relative mismatch of work in = dissipation + Δ(kinetic + elastic energy)."""
        work = self.work_input[-1]
        out = self.viscous_loss[-1] + self.friction_loss[-1] + self.energy[-1] - self.energy[0]
        return abs(work - out) / max(abs(work), 1e-300)

    def to_dict(self) -> dict[str, Any]:
        """The summary as plain JSON-ready data (see ``pydrill simulate --json``)."""
        s = self.summary

        def num(x: float | None) -> float | None:
            return None if x is None or not math.isfinite(x) else float(x)

        return {
            "regime": s.regime,
            "bit_velocity": {"min": s.bit_min, "max": s.bit_max, "mean": s.bit_mean},
            "top_velocity": {"min": s.top_min, "max": s.top_max, "mean": s.top_mean},
            "severity": num(s.severity),
            "bit_top_ratio": num(s.bit_top_ratio),
            "stuck_fraction": s.stuck_fraction,
            "period": num(s.period),
            "stick_events": s.stick_events,
            "static_torque": s.static_torque,
            "omega_equilibrium": list(s.omega_equilibrium),
            "window": [s.window_start, s.window_end],
            "note": s.note or None,
            "solver": {
                k: v
                for k, v in asdict(self.stats).items()
                if k not in ("lin_setups", "nonlin_conv_fails")
            },
            "inputs": {
                "preset": self.params.name,
                "dof": self.dof,
                "wob": self.wob,
                "torque": self.torque,
                **self.settings,
            },
            "units": {
                "bit_velocity": "rad/s",
                "top_velocity": "rad/s",
                "omega_equilibrium": "rad/s",
                "period": "s",
                "static_torque": "N·m",
                "window": "s",
                "wob": "N",
                "torque": "N·m",
                "t_end": "s",
                "wall_time": "s",
                "severity": "1",
                "stuck_fraction": "1",
            },
        }

    def __repr__(self) -> str:
        s = self.summary
        period = f", period {s.period:.4g} s" if s.period else ""
        return (
            f"<SimulationResult dof={self.dof} wob={self.wob:g} N torque={self.torque:g} N·m: "
            f"{s.regime}, bit {s.bit_min:.4g}..{s.bit_max:.4g} rad/s (mean {s.bit_mean:.4g})"
            f"{period}; {self.stats.method}, {self.stats.steps} steps>"
        )


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
    max_switch_rate: float = 1e4,
    preset: str = "reduced-scale",
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
    (explicit Runge–Kutta 8(5,3), non-stiff strings), ``"bdf"`` (CVODES, banded Newton, for
    stiff strings), ``"adams"`` (CVODES) or ``"erk"`` (ARKODE Runge–Kutta 7(8)).

    Bad input raises ``ValueError`` naming the parameter; a solver failure raises
    :class:`pydrill.SolverError` with the integrator's message and the time reached.

    >>> r = simulate(wob=100, torque=8.3, dof=4, t_end=300)
    >>> r.regime
    'stick-slip'
    """
    if params is None:
        params = _model.preset(preset, dof=dof, pipes=pipes, **overrides)
    else:
        if dof is not None or pipes is not None or overrides:
            if dof is not None and dof != params.dof:
                raise ValueError(f"dof = {dof} disagrees with params (dof = {params.dof})")
            params = params.replace(**overrides) if overrides else params
    opts = _core.SimulationOptions()
    opts.t_end = float(t_end)
    if t_out is not None:
        opts.t_out = [float(v) for v in np.asarray(t_out, dtype=float).ravel()]
    opts.n_out = _integer("n_out", n_out)
    opts.method = _choice("method", method, ("auto", "bdf", "adams", "erk", "dop853"))
    opts.friction = _choice("friction", friction, ("exact", "karnopp"))
    if isinstance(initial, str):
        opts.initial = _choice("initial", initial, ("rest", "equilibrium"))
        initial_label = initial
    else:
        opts.initial = "state"
        opts.state = [float(v) for v in np.asarray(initial, dtype=float).ravel()]
        initial_label = "state"
    opts.rtol = float(rtol)
    opts.atol = float(atol)
    opts.max_step = float(max_step)
    opts.max_order = _integer("max_order", max_order)
    opts.max_steps = _integer("max_steps", max_steps)
    opts.perturbation = float(perturbation)
    opts.window_fraction = float(window_fraction)
    opts.max_switch_rate = float(max_switch_rate)
    core = _core.simulate(params.to_core(), float(wob), float(torque), opts)
    settings = {
        "t_end": float(t_end),
        "initial": initial_label,
        "friction": friction,
        "method": method,
        "rtol": float(rtol),
        "atol": float(atol),
    }
    return SimulationResult(core, params, settings)


def _choice(name: str, value: Any, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise ValueError(f"{name} = {value!r} is not allowed: choose one of {', '.join(allowed)}")
    return str(value)


def _integer(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} = {value!r} is not allowed: must be an integer")
    if not -(2**62) < value < 2**62:
        raise ValueError(f"{name} = {value!r} is not allowed: out of range")
    return int(value)
