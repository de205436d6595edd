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
# sweep has one string; a size or depth sweep a few hundred at most.
_CROSSINGS: dict[tuple, list] = {}
_CROSSINGS_KEPT = 1024


def _string_crossings(spec: SweepSpec, coords: dict[str, Any], params: Any) -> list:
    from .spec import OPERATING_AXES
    from .stability import critical_deltas

    key = (spec.text, spec.tally_text, tuple(sorted(
        (k, v) for k, v in coords.items() if k not in OPERATING_AXES
    )))  # fmt: skip
    found = _CROSSINGS.get(key)
    if found is None:
        if len(_CROSSINGS) >= _CROSSINGS_KEPT:
            _CROSSINGS.clear()
        found = _CROSSINGS[key] = critical_deltas(params)
    return found


def evaluate_point(spec: SweepSpec, index: int) -> dict[str, Any]:
    """Simulate one grid point from every initial condition and analyse its steady states."""
    from . import simulate
    from .stability import stability

    rec: dict[str, Any] = {"i": int(index), "status": "done", "message": "", "runs": {}}
    try:
        coords = spec.coords(index)
        params = spec.params_at(coords)
        wob, torque = spec.operating_point(coords)
        sim = spec.simulation
        for init in spec.initials:
            try:
                r = simulate(
                    params,
                    wob=wob,
                    torque=torque,
                    t_end=sim["t_end"],
                    initial=init,
                    friction=sim["friction"],
                    method=sim["method"],
                    rtol=sim["rtol"],
                    atol=sim["atol"],
                    window_fraction=sim["window"],
                    n_out=2,
                    max_steps=int(sim["max_steps"]),
                )
            except ValueError as exc:
                if init == "equilibrium" and "no steady rotation" in str(exc):
                    rec["runs"][init] = {"regime": "no-steady-state"}
                    continue
                raise
            s = r.summary
            rec["runs"][init] = {
                "regime": s.regime,
                "bit_min": s.bit_min,
                "bit_max": s.bit_max,
                "bit_mean": s.bit_mean,
                "top_mean": s.top_mean,
                "top_min": s.top_min,
                "top_max": s.top_max,
                "bit_top_ratio": s.bit_top_ratio,
                "severity": _num(s.severity),
                "stuck_fraction": s.stuck_fraction,
                "period": s.period,
                "stick_events": s.stick_events,
                "wall_time": r.stats.wall_time,
                "caveat": s.caveat,
            }
        regimes = {
            v["regime"]
            for v in rec["runs"].values()
            if v["regime"] in fmt.REGIMES and fmt.REGIMES[v["regime"]] >= 0
        }
        if len(spec.initials) > 1 and len(rec["runs"]) == len(spec.initials):
            rec["coexistence"] = len(regimes) > 1
        if spec.record["stability"]:
            crossings = _string_crossings(spec, coords, params)
            # Fastest first, by |Ω|: stability() gives increasing Ω, so under a negative torque
            # (the string turned backwards) reversing it put the slow steady state first, and
            # 'the fastest steady state' (safe, maps) was the slow, usually unstable, one.
            pts = sorted(
                stability(params, wob, torque=torque, crossings=crossings),
                key=lambda p: -abs(p.omega),
            )
            k = spec.record["eigenvalues"]
            rec["stability"] = {
                "omega_eq": [p.omega for p in pts],
                "delta": [p.delta for p in pts],
                "spectral_abscissa": [p.spectral_abscissa for p in pts],
                "hopf_margin": [_num(p.delta_margin) for p in pts],
                "unstable": [p.unstable for p in pts],
                "eigenvalues": [[[z.real, z.imag] for z in p.eigenvalues[:k]] for p in pts],
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
