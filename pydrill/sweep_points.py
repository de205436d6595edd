"""One sweep point, and a batch of them, computed where they run (a Dask worker, or the client
for a serial sweep): plain data in (the spec's text, point numbers), plain data out (records,
and their rows as columns for the atlas table)."""

from __future__ import annotations

import math
import time
from typing import Any, NamedTuple

import numpy as np

from . import atlas_format as fmt
from .journal_lines import line as journal_line
from .spec import SweepSpec, parse_spec


def _num(v: Any) -> Any:
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


# The crossings of each string a process has met (critical_deltas): they depend on the
# string alone, not on W_ob or u, and cost ~0.3 ms, a sixth of a dof-4 point. A (W_ob, u)
# sweep has one string; a size or depth sweep a few hundred at most. Kept checked
# (stability's _check_crossings) and as the core takes them (their fields): stability() did
# both at every point, on crossings that were always the string's own.
_CROSSINGS: dict[tuple, list] = {}
_CROSSINGS_KEPT = 1024


def _string_crossings(spec: SweepSpec, coords: dict[str, Any], params: Any) -> list:
    """The string's crossings, checked, as the core's stability_at_torque takes them."""
    from .spec import OPERATING_AXES
    from .stability import _check_crossings, critical_deltas

    key = (spec.text, spec.tally_text, tuple(sorted(
        (k, v) for k, v in coords.items() if k not in OPERATING_AXES
    )))  # fmt: skip
    found = _CROSSINGS.get(key)
    if found is None:
        if len(_CROSSINGS) >= _CROSSINGS_KEPT:
            _CROSSINGS.clear()
        checked = _check_crossings(params, critical_deltas(params))
        found = _CROSSINGS[key] = [vars(c) for c in checked]
    return found


# The core's options of each start, per spec and string length: they hold the spec's
# [simulation] settings only, and were checked and built anew (inside simulate) at every
# run. With the SimulationResult no longer built (evaluate_point), 8 % of a dof-4 point's
# CPU time: 122 of 1493 us, median of 41 interleaved rounds of 100 points of the main job's
# spec (paper-wob-torque.toml).
_OPTIONS: dict[tuple, Any] = {}


def _run_options(spec: SweepSpec, init: str, dof: int) -> Any:
    """The core's options for a run of ``spec`` from ``init`` on a string of ``dof`` inertias,
    checked as :func:`pydrill.simulate` checks them (the same code, ``simulate._options``,
    with simulate's own defaults for what a spec does not set)."""
    key = (spec.text, init, dof)
    found = _OPTIONS.get(key)
    if found is None:
        import inspect

        from .simulate import _options, simulate

        sim = spec.simulation
        given = {
            "t_end": sim["t_end"],
            "initial": init,
            "friction": sim["friction"],
            "method": sim["method"],
            "rtol": sim["rtol"],
            "atol": sim["atol"],
            "window_fraction": sim["window"],
            "n_out": 2,
            "max_steps": int(sim["max_steps"]),
        }
        # simulate's own defaults for _options's other settings (max_step, perturbation, ...):
        # one source of them, so that a sweep's run stays the run simulate() would make.
        wanted = [
            k for k, p in inspect.signature(_options).parameters.items() if p.kind is p.KEYWORD_ONLY
        ]
        defaults = inspect.signature(simulate).parameters
        kwargs = {k: given[k] if k in given else defaults[k].default for k in wanted}
        if len(_OPTIONS) >= _CROSSINGS_KEPT:
            _OPTIONS.clear()
        found = _OPTIONS[key] = _options(dof, **kwargs)[1]
    return found


def evaluate_point(spec: SweepSpec, index: int) -> dict[str, Any]:
    """Simulate one grid point from every initial condition and analyse its steady states."""
    from . import _core

    rec: dict[str, Any] = {"i": int(index), "status": "done", "message": "", "runs": {}}
    try:
        coords = spec.coords(index)
        params = spec.params_at(coords)
        wob, torque = spec.operating_point(coords)
        for init in spec.initials:
            # The core's own run, as pydrill.simulate makes it (the same checked options; W_ob
            # and u are plain floats from operating_point, which simulate passes on as they
            # are), without the SimulationResult around it: its array views and its stats and
            # Summary dataclasses are not read here (see _OPTIONS for the time saved).
            opts = _run_options(spec, init, params.dof)
            try:
                core = _core.simulate(params._core_params(), wob, torque, opts)
            except ValueError as exc:
                if init == "equilibrium" and "no steady rotation" in str(exc):
                    rec["runs"][init] = {"regime": "no-steady-state"}
                    continue
                raise
            s = core.summary
            rec["runs"][init] = {
                "regime": s["regime"],
                "bit_min": s["bit_min"],
                "bit_max": s["bit_max"],
                "bit_mean": s["bit_mean"],
                "top_mean": s["top_mean"],
                "top_min": s["top_min"],
                "top_max": s["top_max"],
                "bit_top_ratio": s["bit_top_ratio"],
                "severity": _num(s["severity"]),
                "stuck_fraction": s["stuck_fraction"],
                "period": s["period"],
                "stick_events": s["stick_events"],
                "wall_time": core.stats["wall_time"],
                "caveat": s["caveat"],
            }
        regimes = {
            v["regime"]
            for v in rec["runs"].values()
            if v["regime"] in fmt.REGIMES and fmt.REGIMES[v["regime"]] >= 0
        }
        if len(spec.initials) > 1 and len(rec["runs"]) == len(spec.initials):
            rec["coexistence"] = len(regimes) > 1
        if spec.record["stability"]:
            # stability(params, wob, torque=torque, crossings=...)'s steady states, from the
            # core as it computes them, without what the sweep need not repeat at every point:
            # its checks of wob and torque (finite, W_ob > 0, both within MAX_LOAD: parse_spec
            # refused any other, and the core's simulate has just refused them at this point
            # too), of the crossings (once, in _string_crossings) and its StabilityPoint
            # objects; with the coordinates' (SweepSpec.coords), 4-7 % of a dof-4 point's CPU
            # time (median of 41 interleaved rounds of 100 points of paper-wob-torque.toml).
            # Fastest first, by |Ω|: the core gives increasing Ω, so under a negative torque
            # (the string turned backwards) reversing it put the slow steady state first, and
            # 'the fastest steady state' (safe, maps) was the slow, usually unstable, one.
            known = _string_crossings(spec, coords, params)
            pts = sorted(
                _core.stability_at_torque(params._core_params(), wob, torque, known),
                key=lambda p: -abs(p["omega"]),
            )
            k = spec.record["eigenvalues"]
            rec["stability"] = {
                "omega_eq": [p["omega"] for p in pts],
                "delta": [p["delta"] for p in pts],
                "spectral_abscissa": [p["spectral_abscissa"] for p in pts],
                "hopf_margin": [_num(p["delta_margin"]) for p in pts],
                "unstable": [p["unstable"] for p in pts],
                "eigenvalues": [
                    [[complex(z).real, complex(z).imag] for z in p["eigenvalues"][:k]] for p in pts
                ],
            }
    except Exception as exc:
        rec = {
            "i": int(index),
            "status": "failed",
            "runs": {},
            "message": f"{type(exc).__name__}: {exc}",
        }
    return rec


def encode_batch(
    spec: SweepSpec, records: list[dict[str, Any]]
) -> tuple[np.ndarray, dict[str, np.ndarray], str]:
    """Finished records as the client absorbs them: their flat indices, their rows as a block
    of columns (``AtlasTable.columns``) and their journal lines."""
    block = fmt.AtlasTable(spec, points=len(records))
    block.fill(records)
    lines = "".join(journal_line(rec) for rec in records)
    return np.array([rec["i"] for rec in records], dtype=np.int64), block.columns(), lines


class Batch(NamedTuple):
    """A computed batch as the client absorbs it."""

    indices: np.ndarray  #: the points' flat indices
    block: dict[str, np.ndarray]  #: their rows, as columns (``AtlasTable.columns``)
    lines: str  #: their journal lines
    seconds: float  #: wall time the batch took to compute, where it ran
    left: list[int]  #: the points it did not reach, out of time (``budget``)


def evaluate_batch(
    spec_text: str,
    indices: list[int],
    tally_text: str | None = None,
    budget: float | None = None,
) -> Batch:
    """Worker entry point: plain data in and out (no pickled objects of ours). The records
    are encoded here (``encode_batch``), so that the client, which shares the machine with
    the workers, only appends text and assigns arrays. With a ``budget`` (s), the points
    after the one that runs past it are not computed but handed back (``Batch.left``)."""
    t0 = time.perf_counter()
    spec = parse_spec(spec_text, tally_text=tally_text)
    records = []
    for k, i in enumerate(indices):
        records.append(evaluate_point(spec, i))
        if budget is not None and time.perf_counter() - t0 > budget:
            left = [int(j) for j in indices[k + 1 :]]
            break
    else:
        left = []
    return Batch(*encode_batch(spec, records), time.perf_counter() - t0, left)
