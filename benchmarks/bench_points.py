#!/usr/bin/env python3
"""What one sweep point costs in Python, around the C++ core: the main job's spec
(sweeps/paper-wob-torque.toml: dof 4, 300 s from rest and from equilibrium, stability, four
eigenvalues), one process.

    python benchmarks/bench_points.py              # about half a minute
    python benchmarks/bench_points.py --rounds 41  # steadier medians on a busy machine

(a) where a point's time goes in ``evaluate_batch``: the core's runs (their own clock,
    ``stats.wall_time``, which the atlas keeps) and the rest (Python: the point's set-up,
    the records and their encoding for the atlas; and the core's steady states);
(b) ``evaluate_point`` against the same records made through the public API, as it made them
    until Dec. 2026 (``pydrill.simulate`` and ``pydrill.stability.stability`` at every point:
    their checks, their result objects), interleaved round by round on the same points, with
    the per-round ratio of their CPU times (less disturbed than wall time by other processes
    on a shared machine). The two give the same records (checked here, timing aside).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # before numpy loads: one process, one core

import numpy as np  # noqa: E402

import pydrill  # noqa: E402
from pydrill.spec import parse_spec  # noqa: E402
from pydrill.stability import critical_deltas, stability  # noqa: E402
from pydrill.sweep_points import _num, evaluate_batch, evaluate_point  # noqa: E402

SPEC = Path(__file__).resolve().parents[1] / "sweeps" / "paper-wob-torque.toml"
RUN_KEYS = ("regime", "bit_min", "bit_max", "bit_mean", "top_mean", "top_min", "top_max")
RUN_KEYS += ("bit_top_ratio", "severity", "stuck_fraction", "period", "stick_events")
CROSSINGS: dict[int, list] = {}  # by the id of the Params (SweepSpec.params_at keeps them)


def public_point(spec, index: int) -> dict:
    """A point's record through the public API (the baseline; failures are not expected on
    this spec and not caught)."""
    coords = spec.coords(index)
    params = spec.params_at(coords)
    wob, torque = spec.operating_point(coords)
    sim = spec.simulation
    rec: dict = {"i": index, "status": "done", "message": "", "runs": {}}
    for init in spec.initials:
        try:
            r = pydrill.simulate(
                params, wob=wob, torque=torque, t_end=sim["t_end"], initial=init,
                friction=sim["friction"], method=sim["method"], rtol=sim["rtol"],
                atol=sim["atol"], window_fraction=sim["window"], n_out=2,
                max_steps=int(sim["max_steps"]),
            )  # fmt: skip
        except ValueError as exc:
            if init == "equilibrium" and "no steady rotation" in str(exc):
                rec["runs"][init] = {"regime": "no-steady-state"}
                continue
            raise
        run = {k: getattr(r.summary, k) for k in RUN_KEYS}
        run["severity"] = _num(run["severity"])
        rec["runs"][init] = {**run, "wall_time": r.stats.wall_time, "caveat": r.summary.caveat}
    regimes = {v["regime"] for v in rec["runs"].values() if v["regime"] != "no-steady-state"}
    if len(rec["runs"]) == len(spec.initials) > 1:
        rec["coexistence"] = len(regimes) > 1
    # the string's crossings once, as evaluate_point has always kept them (0.3 ms a point)
    crossings = CROSSINGS.get(id(params))
    if crossings is None:
        crossings = CROSSINGS[id(params)] = critical_deltas(params)
    pts = stability(params, wob, torque=torque, crossings=crossings)
    pts.sort(key=lambda p: -abs(p.omega))
    k = spec.record["eigenvalues"]
    rec["stability"] = {
        "omega_eq": [p.omega for p in pts],
        "delta": [p.delta for p in pts],
        "spectral_abscissa": [p.spectral_abscissa for p in pts],
        "hopf_margin": [_num(p.delta_margin) for p in pts],
        "unstable": [p.unstable for p in pts],
        "eigenvalues": [[[z.real, z.imag] for z in p.eigenvalues[:k]] for p in pts],
    }
    return rec


def untimed(rec: dict) -> dict:
    """The record without the core's clock (``wall_time`` differs from run to run)."""
    runs = {s: {k: v for k, v in run.items() if k != "wall_time"} for s, run in rec["runs"].items()}
    return {**rec, "runs": runs}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=21, help="interleaved rounds (default 21)")
    ap.add_argument("--points", type=int, default=100, help="points per round (default 100)")
    args = ap.parse_args()
    spec = parse_spec(SPEC.read_text())
    points = list(range(0, spec.size, 3))[: args.points]  # spread over the grid
    for i in points:  # the same records, and everything warmed up
        assert untimed(evaluate_point(spec, i)) == untimed(public_point(spec, i)), i

    total, core = [], []
    for _ in range(args.rounds):
        t0 = time.perf_counter()
        batch = evaluate_batch(spec.text, points)
        total.append((time.perf_counter() - t0) / len(points))
        # the core's own clock of each run (NaN for a start with no steady state to begin from)
        core.append(float(np.nansum(batch.block["run:wall_time"])) / len(points))
    t, c = statistics.median(total), statistics.median(core)
    print(
        f"(a) {len(points)} points, median of {args.rounds} rounds: {1e6 * t:.0f} us a point; "
        f"the core's runs {1e6 * c:.0f} us ({100 * c / t:.0f} %), the rest {1e6 * (t - c):.0f} us "
        f"({100 * (t - c) / t:.0f} %: Python, and the core's steady states and eigenvalues)"
    )

    cpu: dict[str, list[float]] = {"evaluate_point": [], "public API": []}
    ways = {
        "evaluate_point": lambda: [evaluate_point(spec, i) for i in points],
        "public API": lambda: [public_point(spec, i) for i in points],
    }
    for r in range(args.rounds):
        for name in list(ways) if r % 2 == 0 else list(ways)[::-1]:  # each goes first half the time
            c0 = time.process_time()
            ways[name]()
            cpu[name].append((time.process_time() - c0) / len(points))
    new, old = (statistics.median(cpu[k]) for k in ways)
    ratios = [b / a for a, b in zip(*cpu.values(), strict=True)]
    print(
        f"(b) CPU time a point, median of {args.rounds} interleaved rounds: evaluate_point "
        f"{1e6 * new:.0f} us, the public API {1e6 * old:.0f} us: {1e6 * (old - new):.0f} us saved "
        f"({100 * (old - new) / old:.1f} %); per-round ratio median "
        f"{statistics.median(ratios):.3f}x, range {min(ratios):.3f}-{max(ratios):.3f}x"
    )


if __name__ == "__main__":
    main()
