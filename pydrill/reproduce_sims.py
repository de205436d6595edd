"""The paper's simulated figures (Section 3: Figs. 4, 5, 7, 8, 9), recomputed with pydrill.

Each ``figN`` function runs the simulations the paper describes and returns ``(numbers,
runs)``: ``numbers`` is plain JSON-ready data for the report and the tests, ``runs`` the
:class:`~pydrill.SimulationResult` objects the figures draw. Everything uses the laboratory
string of Eq. (14) (``reduced-scale``); the paper's state dimension n is ``2·dof``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .model import Params, preset
from .simulate import SimulationResult, simulate
from .sliding import quasi_equilibrium, reference_values
from .stability import critical_deltas, stability

PRESET = "reduced-scale"
T_END = 300.0  #: s, the runs of Figs. 4, 7, 8, 9 (long enough for ~8 stick-slip cycles)


def lab(dof: int) -> Params:
    return preset(PRESET, dof=dof)


def _stick_table(run: SimulationResult, count: int) -> list[dict[str, float]]:
    """The first ``count`` visits to the sliding region Σ̃: when the bit stuck (x_in), when it
    broke free (x_out), the bit angle held meanwhile (the paper's φ̄_b) and T_e at x_out."""
    out = []
    phi_b = run.bit_angle
    for t_in, t_out in run.stick_intervals()[:count]:
        k = int(np.searchsorted(run.t, 0.5 * (t_in + t_out)))
        freed = [s for s in run.switches if s.t == t_out]
        out.append(
            {
                "t_in": float(t_in),
                "t_out": float(t_out),
                "duration": float(t_out - t_in),
                "phi_b": float(phi_b[min(k, len(phi_b) - 1)]),
                "torque_out": float(freed[0].reaction_torque) if freed else float("nan"),
            }
        )
    return out


def _summary(run: SimulationResult) -> dict[str, Any]:
    s = run.summary
    return {
        "regime": s.regime,
        "period": s.period,
        "bit_min": s.bit_min,
        "bit_max": s.bit_max,
        "bit_mean": s.bit_mean,
        "top_mean": s.top_mean,
        "bit_top_ratio": s.bit_top_ratio,
        "stuck_fraction": s.stuck_fraction,
        "stick_events": s.stick_events,
        "static_torque": s.static_torque,
        "omega_equilibrium": list(s.omega_equilibrium),
        "window": [s.window_start, s.window_end],
        "method": run.stats.method,
        "switches": run.stats.switches,
    }


def fig4() -> tuple[dict[str, Any], dict[str, SimulationResult]]:
    """Fig. 4 (n = 8, W_ob = 100 N, u = 8.3 N·m): stick-slip from rest, exact friction and the
    paper's Karnopp switch model (Eq. 9); the steady state's stability and the start near it."""
    p = lab(4)
    exact = simulate(p, wob=100.0, torque=8.3, t_end=T_END, n_out=6001)
    karnopp = simulate(p, wob=100.0, torque=8.3, t_end=T_END, friction="karnopp", n_out=6001)
    near = simulate(p, wob=100.0, torque=8.3, t_end=T_END, initial="equilibrium", n_out=2)
    (eq,) = stability(p, 100.0, torque=8.3)
    numbers = {
        "dof": 4,
        "wob": 100.0,
        "torque": 8.3,
        "exact": _summary(exact),
        "karnopp": _summary(karnopp),
        "first_switches": [
            {"t": s.t, "kind": s.kind, "reaction_torque": s.reaction_torque}
            for s in exact.switches[:4]
        ],
        "steady_state": {
            "omega": eq.omega,
            "delta": eq.delta,
            "stable": eq.stable,
            "spectral_abscissa": eq.spectral_abscissa,
            "delta_1": critical_deltas(p)[0].delta,
        },
        "from_equilibrium": _summary(near),
    }
    return numbers, {"exact": exact, "karnopp": karnopp}


def regime_interval(
    params: Params, torque: float, wob_max: float, step: float = 5.0, tol: float = 0.05
) -> dict[str, Any]:
    """From rest at fixed ``torque``: the smallest W_ob at which the bit sticks and slips
    (below it drills steadily: the paper's W*_ob − ε⁻) and the largest (above it stays stuck:
    W*_ob + ε⁺), by a scan in steps of ``step`` N and bisection to ``tol`` N."""

    def regime(w: float) -> str:
        return simulate(params, wob=w, torque=torque, t_end=T_END, n_out=2).regime

    grid = np.arange(step, wob_max + step / 2, step)
    regimes = [regime(w) for w in grid]
    slip = [i for i, r in enumerate(regimes) if r == "stick-slip"]
    if not slip:
        star = reference_values(params, 1.0, torque)["wob_star"]
        return {"lower": None, "upper": None, "below": None, "above": None, "wob_star": star}

    def bisect(a: float, b: float, inside_b: bool) -> float:
        while b - a > tol:
            m = 0.5 * (a + b)
            if (regime(m) == "stick-slip") == inside_b:
                b = m
            else:
                a = m
        return 0.5 * (a + b)

    i, j = slip[0], slip[-1]
    lower = bisect(grid[i - 1], grid[i], True) if i > 0 else float(grid[0])
    upper = bisect(grid[j], grid[j + 1], False) if j + 1 < len(grid) else float(grid[-1])
    return {
        "lower": float(lower),
        "upper": float(upper),
        "below": regimes[i - 1] if i > 0 else None,
        "above": regimes[j + 1] if j + 1 < len(grid) else None,
        "wob_star": reference_values(params, 1.0, torque)["wob_star"],
    }


FIG5_WOB = (90.0, 100.0, 110.0, 120.0, 130.0, 140.0, 150.0)
FIG5_SEGMENT = 100.0  #: s at each W_ob of the schedule


def fig5() -> tuple[dict[str, Any], dict[str, Any]]:
    """Fig. 5 (n = 4, u = 8.1 N·m, W_ob from 90 to 150 N): W_ob raised in steps while the
    string keeps turning (the state carried over), each W_ob's own orbit from rest, and the
    W_ob range of stick-slip."""
    p = lab(2)
    state: Any = "rest"
    schedule, segments = [], []
    t0 = 0.0
    for w in FIG5_WOB:
        r = simulate(p, wob=w, torque=8.1, t_end=FIG5_SEGMENT, initial=state, n_out=2001)
        schedule.append({"wob": w, "t_start": t0, **_summary(r)})
        segments.append((t0, w, r))
        state = r.states[-1]
        t0 += FIG5_SEGMENT
    orbits = {w: simulate(p, wob=w, torque=8.1, t_end=T_END, n_out=6001) for w in FIG5_WOB}
    qe = quasi_equilibrium(p, 100.0, 8.1)
    numbers = {
        "dof": 2,
        "torque": 8.1,
        "schedule": schedule,
        "orbits": {f"{w:g}": _summary(r) for w, r in orbits.items()},
        "interval": regime_interval(p, 8.1, 200.0),
        "quasi_equilibrium_twist": qe.collar_twist,
    }
    return numbers, {"segments": segments, "orbits": orbits}


def fig7() -> tuple[dict[str, Any], dict[str, SimulationResult]]:
    """Fig. 7 (n = 8, W_ob = 160 N, u = 8.3 N·m): the bit sticks for good. From rest it never
    moves; drilling steadily at W_ob = 100 N and then loading the bit to 160 N, the trajectory
    hits the sliding region once and stays there, relaxing to the quasi-equilibrium."""
    p = lab(4)
    rest = simulate(p, wob=160.0, torque=8.3, t_end=T_END, n_out=2)
    start = simulate(p, wob=100.0, torque=8.3, initial="equilibrium", t_end=1.0, n_out=2).states[0]
    loaded = simulate(p, wob=160.0, torque=8.3, initial=start, t_end=T_END, n_out=6001)
    qe = quasi_equilibrium(p, 160.0, 8.3)
    sticks = [s for s in loaded.switches if s.kind == "stick"]
    te = loaded.reaction_torque
    numbers = {
        "dof": 4,
        "wob": 160.0,
        "torque": 8.3,
        "rest": _summary(rest),
        "loaded": _summary(loaded),
        "start_omega": float(start[0]),
        "entries": len(sticks),
        "t_in": sticks[0].t if sticks else None,
        "final_reaction_torque": float(te[-1]),
        "final_collar_twist": float(loaded.twist[-1, -1]),
        "quasi_equilibrium_twist": qe.collar_twist,
        "quasi_equilibrium_real": qe.real,
        "static_torque": qe.static_torque,
    }
    return numbers, {"loaded": loaded}


def fig8(run4: SimulationResult | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
    """Fig. 8 (n = 8, W_ob = 100 N, u = 8.3 N·m, the run of Fig. 4): the first three visits to
    Σ̃, each with its own strip Σ̃_i (it moves with the held bit angle φ̄_b), and the stuck time
    against W_ob (the paper: the smaller W_ob, the less time on Σ̃)."""
    p = lab(4)
    run = run4 or simulate(p, wob=100.0, torque=8.3, t_end=T_END, n_out=6001)
    stuck = {}
    for w in (95.0, 100.0, 105.0, 110.0):
        stuck[f"{w:g}"] = simulate(p, wob=w, torque=8.3, t_end=T_END, n_out=2).summary
    numbers = {
        "dof": 4,
        "wob": 100.0,
        "torque": 8.3,
        "visits": _stick_table(run, 3),
        "static_torque": p.static_torque(100.0),
        "stuck_fraction_by_wob": {w: s.stuck_fraction for w, s in stuck.items()},
        "regime_by_wob": {w: s.regime for w, s in stuck.items()},
    }
    return numbers, {"run": run}


def fig9() -> tuple[dict[str, Any], dict[str, Any]]:
    """Fig. 9 (n = 8, W_ob = 40 N, u = 8.3 N·m): the bit leaves Σ̃ and the string settles to
    the steady state x̄_e, which the analysis of Section 4 says is stable."""
    p = lab(4)
    run = simulate(p, wob=40.0, torque=8.3, t_end=T_END, n_out=6001)
    (eq,) = stability(p, 40.0, torque=8.3)
    first_slip = next((s.t for s in run.switches if s.kind == "slip"), None)
    dev = np.abs(run.omega - eq.omega).max(axis=1)
    settled = run.t[np.flatnonzero(dev > 0.01 * eq.omega)[-1] + 1] if np.any(dev > 0) else 0.0
    numbers = {
        "dof": 4,
        "wob": 40.0,
        "torque": 8.3,
        "run": _summary(run),
        "omega": eq.omega,
        "delta": eq.delta,
        "delta_1": critical_deltas(p)[0].delta,
        "stable": eq.stable,
        "spectral_abscissa": eq.spectral_abscissa,
        "first_slip": first_slip,
        "settled_1pct": float(settled),
        "stick_events_total": sum(s.kind == "stick" for s in run.switches),
    }
    return numbers, {"run": run, "omega": eq.omega}
