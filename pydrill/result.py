"""What a simulation returns: ``pydrill.SimulationResult`` and its parts (``Summary``,
``Switch``, ``SolverStats``), plain data over the core's arrays."""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from types import MappingProxyType
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from . import _core
from . import model as _model
from .model import _LISTS, _SCALARS, PRESETS, Params

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

    method: str  #: what ran: "dop853", "bdf", "adams" or "erk"
    method_reason: str  #: why ``method="auto"`` chose it
    stiffness_ratio: float  #: the stiffness estimate ``"auto"`` used
    steps: int  #: internal steps taken
    rhs_evals: int  #: right-hand side evaluations
    jac_evals: int  #: Jacobian evaluations (bdf)
    lin_setups: int  #: refactorisations of the Newton matrix I - gamma*J (bdf)
    lin_solves: int  #: linear solves (bdf)
    nonlin_iters: int  #: nonlinear iterations: Newton's (bdf), fixed-point (adams)
    nonlin_conv_fails: int  #: nonlinear convergence failures (bdf, adams)
    err_test_fails: int  #: steps refused by the error test, then retried smaller
    root_evals: int  #: evaluations of the switching functions (rootfinding)
    reinits: int  #: restarts of the integrator, one at each friction switch
    switches: int  #: friction switches (stick, slip, reversal)
    wall_time: float  #: s spent in the C++ core


@dataclass(frozen=True)
class Summary:
    """The regime and its metrics, judged on the window ``[window_start, window_end]``."""

    regime: str  #: "steady", "stick-slip", "stuck" or "oscillation"
    window_start: float  #: s, the judged window's start
    window_end: float  #: s, its end (t_end)
    # The extremes are of the motion, not of the output samples (each step's values and
    # slopes place a peak between steps): n_out changes them by 1e-4 at most (5e-5 on the
    # 4-inertia stick-slip peak with n_out = 2, as a sweep runs it, against 2e-7 at 3001).
    bit_min: float  #: rad/s, least ω_b in the window (of the motion to 1e-4, any ``n_out``)
    bit_max: float  #: rad/s, greatest ω_b in the window (of the motion to 1e-4, any ``n_out``)
    bit_mean: float  #: rad/s, exact: from the angle turned over the window
    top_min: float  #: rad/s, least top-drive velocity ω_0 in the window
    top_max: float  #: rad/s, greatest ω_0 in the window
    top_mean: float  #: rad/s, mean ω_0 over the window
    severity: float  #: (max ω_b − min ω_b) / (2 mean ω_b)
    #: max ω_b / mean ω_top (min ω_b / mean ω_top when mean ω_top < 0: the bit's fastest turn in
    #: the top drive's direction, which is u's but for a window where the string swings back)
    bit_top_ratio: float
    stuck_fraction: float  #: fraction of the window the bit is held (stick)
    period: float | None  #: s, stick-slip or oscillation period
    stick_events: int  #: slip → stick transitions in the window
    static_torque: float  #: T_s = μ_sb W_ob R_b
    #: rad/s, every steady velocity Ω for (W_ob, u): > 0, or < 0 when u < 0 (the mirror image)
    omega_equilibrium: tuple[float, ...]
    note: str = ""  #: caveat about the judgement (e.g. the run was too short)
    #: the note's kind, for tables (an atlas keeps this): "first-wind-up", "one-stick-phase",
    #: "one-break-away", "late-stick", "growing", "short-window", "run-away" (no damping at
    #: the ends, c_r + c_b = 0, and |u| > T_c: the bit speeds up without bound),
    #: "approaching" (steady, its mean still on its way: moving by over 1 % across the window,
    #: or towards a steady state over 1 % away); "" without a note
    caveat: str = ""


class SimulationResult:
    """Output of :func:`simulate`. Arrays are read-only views of the core's memory (no copies).

    ``states`` holds the twist coordinates ``(ω_0, θ_0, ω_1, …, θ_{N−2}, ω_b)`` at times ``t``;
    ``omega`` and ``twist`` are strided views of it.

    A result can be pickled (e.g. returned from a ``multiprocessing`` worker) and deep-copied:
    the copy holds copies of the arrays (read-only too) and of every switch, not the core's
    memory. To send less, send ``result.summary`` or ``result.to_dict()``.
    """

    def __init__(self, core: Any, params: Params, settings: dict[str, Any]) -> None:
        self._core = core
        self.params: Params = params  #: the string simulated
        # Kept behind the read-only :attr:`settings` (its lists as tuples): changed through the
        # result, they would no longer be what ran, yet inputs() would repeat them.
        self._settings = {k: tuple(v) if isinstance(v, list) else v for k, v in settings.items()}
        self.wob: float = core.wob  #: N, weight on bit
        self.torque: float = core.torque  #: N·m, surface torque u
        self.t: NDArray[np.float64] = core.t  #: s, the output times, shape (n,)
        #: the twist coordinates (ω_0, θ_0, ω_1, …, θ_{N−2}, ω_b) at ``t``, shape (n, 2·dof − 1)
        self.states: NDArray[np.float64] = core.states
        self.top_angle: NDArray[np.float64] = core.top_angle  #: rad, φ_0 at ``t``
        #: J, work done by the surface torque since t = 0, ∫ u ω_0 dt; the ledger balances:
        #: E(t) − E(0) = work_input − viscous_loss − friction_loss
        self.work_input: NDArray[np.float64] = core.work_input
        self.viscous_loss: NDArray[np.float64] = core.viscous_loss  #: J, ∫ viscous dissipation dt
        self.friction_loss: NDArray[np.float64] = core.friction_loss  #: J, ∫ T_f ω_b dt at the bit
        self.energy: NDArray[np.float64] = core.energy  #: J, kinetic + elastic at ``t``
        #: the bit's friction mode at ``t``, as codes into ``pydrill.MODES``
        self.mode_index: NDArray[np.int32] = core.modes
        self.stats: SolverStats = SolverStats(**core.stats)  #: the solver's work
        summary = dict(core.summary)
        summary["omega_equilibrium"] = tuple(summary["omega_equilibrium"])
        # (The core's short-window note ends "(window_fraction)", the keyword simulate() takes
        # as C++'s SimulationOptions does: kept as it is; the command line's says --window.)
        self.summary: Summary = Summary(**summary)  #: the regime and its metrics

    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any]]]:
        # The core's Result cannot be pickled: copy its data (the arrays, by pickle or deepcopy,
        # and the switches) and leave the core behind.
        state = {k: v for k, v in self.__dict__.items() if k != "_core"}
        state["switches"] = self.switches
        return _restore_result, (state,)

    @property
    def settings(self) -> Mapping[str, Any]:
        """The simulation settings as given to :func:`simulate` (``t_end``, ``method``, …),
        read-only (lists as tuples; ``max_switch_rate`` inf for None, no limit): :meth:`inputs`
        gives them as a new, plain dict, JSON-ready (None there)."""
        return MappingProxyType(self._settings)

    @functools.cached_property
    def switches(self) -> tuple[Switch, ...]:
        """Every stick, slip and reversal of the bit, in time order (a tuple: the result's,
        not to be changed). Built when first asked for: a sweep reads only the summary, and a
        long stick-slip run has thousands."""
        return tuple(Switch(**s) for s in self._core.switches)

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
        ``"band"`` (Karnopp); ``mode_index`` holds the same as codes into ``pydrill.MODES``."""
        return [MODES[i] for i in self.mode_index]

    def past_fold(self) -> tuple[bool, ...]:
        """For each of ``summary.omega_equilibrium``, whether it lies past the fold: its
        Stribeck slope δ(|Ω|) above c_r + c_b, where the characteristic polynomial's constant
        term has changed sign (DESIGN.md §3), so a real eigenvalue is positive and the bit
        cannot stay there, whatever the string. The slower of two steady states always is. One
        not past the fold may still be unstable by a Hopf crossing: ``pydrill.stability``."""
        from .stability import stribeck_slope

        p, ends = self.params, self.params.top_damping + self.params.bit_damping
        return tuple(
            bool(stribeck_slope(p, abs(self.wob), abs(w)) > ends)
            for w in self.summary.omega_equilibrium
        )

    def stick_intervals(self) -> list[tuple[float, float]]:
        """Time intervals in which the rock holds the bit (stick, or the Karnopp band), within
        the output span ``[t[0], t[-1]]`` (an interval under way at ``t[0]`` starts there, one
        still under way at ``t[-1]`` ends there)."""
        held = {"stick", "band-enter"}
        first, last = float(self.t[0]), float(self.t[-1])
        intervals: list[tuple[float, float]] = []
        start = first if MODES[self.mode_index[0]] in ("stick", "band") else None
        for s in self.switches:
            if s.t < first:  # the mode at t[0] already tells what happened before
                continue
            if s.t > last:
                break
            if s.t == first:  # output asked for at a switch: t[0]'s mode is the one before
                start = first if s.kind in held else None
                continue
            if s.kind in held and start is None:
                start = s.t
            elif s.kind not in held and start is not None:
                intervals.append((start, s.t))
                start = None
        if start is not None:
            intervals.append((start, last))
        return intervals

    def energy_balance_error(self) -> float:
        """Relative mismatch of work in = dissipation + Δ(kinetic + elastic energy): the largest,
        over the output times after the first, of the balance between ``t[0]`` and that time,
        relative to the run's energy scale: the largest of the work put in, the change of
        energy, the energy dissipated (viscous and friction) over any of those spans, and the
        energy at ``t[0]`` and at the end. That scale is 0 only if nothing happens (a string at
        rest with no torque), and then so is the mismatch: 0.0, as with a single output time.
        (Relative to the work alone, a string coasting down from a spin with no torque, whose
        ledger balanced to 6e-10 of its energy, was off by 1e293.)"""
        work = self.work_input[1:] - self.work_input[0]
        lost = (self.viscous_loss[1:] - self.viscous_loss[0]) + (
            self.friction_loss[1:] - self.friction_loss[0]
        )
        change = self.energy[1:] - self.energy[0]
        if len(work) == 0:
            return 0.0
        mismatch = float(np.max(np.abs(work - lost - change)))
        scale = max(
            float(np.max(np.abs(work))),
            float(np.max(np.abs(change))),
            float(np.max(np.abs(lost))),
            abs(float(self.energy[0])),
            abs(float(self.energy[-1])),
        )
        if scale == 0.0:  # nothing moved, nothing was put in: nothing to mismatch
            return 0.0
        return mismatch / scale

    def to_dict(self) -> dict[str, Any]:
        """The summary as plain JSON-ready data (see ``pydrill simulate --json``); its
        ``inputs`` are :meth:`inputs`."""
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
            "caveat": s.caveat or None,
            "solver": asdict(self.stats),
            "inputs": self.inputs(),
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

    def inputs(self) -> dict[str, Any]:
        """Everything the run was made from, as JSON-ready keyword arguments of
        :func:`simulate`: ``simulate(**r.inputs())`` repeats the run. The string is ``preset``
        and ``dof`` with the fields that differ from the preset (overrides); for a string that
        is no preset's (its label, ``params.name``, is not in ``PRESETS``) ``preset`` is None
        and every field is given (the repeat's label is then ``"custom"``). ``initial`` is
        ``"rest"``, ``"equilibrium"`` or the state (a list), ``t_out`` None or the list of
        output times, ``max_switch_rate`` None for no limit."""
        p = self.params
        try:
            base = _model.preset(p.name, dof=p.dof) if p.name in PRESETS else None
        except ValueError:  # e.g. a real-string preset made longer than its 2 inertias
            base = None
        model: dict[str, Any] = {}
        for key in _LISTS + _SCALARS:
            value = getattr(p, key)
            if base is None or value != getattr(base, key):
                model[key] = list(value) if key in _LISTS else value
        settings = {k: list(v) if isinstance(v, tuple) else v for k, v in self._settings.items()}
        if settings.get("max_switch_rate") == math.inf:  # no limit: null, as inf is not JSON
            settings["max_switch_rate"] = None
        return {
            "preset": None if base is None else p.name,
            "dof": p.dof,
            "wob": self.wob,
            "torque": self.torque,
            **settings,
            **model,
        }

    def __repr__(self) -> str:
        s = self.summary
        period = f", period {s.period:.4g} s" if s.period else ""
        return (
            f"<SimulationResult dof={self.dof} wob={self.wob:g} N torque={self.torque:g} N·m: "
            f"{s.regime}, bit {s.bit_min:.4g}..{s.bit_max:.4g} rad/s (mean {s.bit_mean:.4g})"
            f"{period}; {self.stats.method}, {self.stats.steps} steps>"
        )


def _restore_result(state: dict[str, Any]) -> SimulationResult:
    """A pickled or deep-copied :class:`SimulationResult`: its data, without the core."""
    result = SimulationResult.__new__(SimulationResult)
    for value in state.values():
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    result.__dict__.update(state)
    result._core = None
    return result
