#!/usr/bin/env python3
"""Long strings: what one simulation costs at about 100, 300 and 560 inertias.

The strings users sweep: the paper's real string from its pipe tally
(examples/tallies/paper-eq53.toml, every 9 m joint one inertia: 900 m, 2700 m and 5030 m give
101, 301 and 560 inertias), 200 s in stick-slip from rest and in steady drilling from its
steady state; a lightly damped field string of as many 9 m joints of 5 in pipe (the
300-inertia string of cpp/tests/test_simulator.cpp, c = 50 N·m·s/rad a joint), 60 s of
stick-slip; and the laboratory string (reduced-scale) with as many pipes, 300 s. Each case
runs ``method="auto"`` and both of the methods it chooses between, dop853 and bdf, in the
same process, so the ratio of the other method to auto's choice is measured under the same
load (this 2-core machine is shared and its speed drifts: compare ratios, and CPU times
rather than wall times). A method that fails on a string is shown as such: DOP853's explicit
steps on the tally's overdamped joints (decay rates 10^7 times the fundamental) end in
chattering at the first switch, or crawl past a budget of MAX_STEPS steps.

    python benchmarks/bench_long_strings.py                      # about a minute
    python benchmarks/bench_long_strings.py --save before.json   # keep the times
    python benchmarks/bench_long_strings.py --against before.json

``--against`` prints, beside each time, this run's over the saved one (e.g. a build of the
previous commit): run both back to back, more than once, before believing a ratio.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

import pydrill
from pydrill.tally_parse import load_tally

ROOT = Path(__file__).resolve().parent.parent
TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"
METHODS = ("auto", "dop853", "bdf")
MAX_STEPS = 50_000  # ~1 s of DOP853 on these strings; BDF takes at most ~25000 here


def field_string(dof: int) -> pydrill.Params:
    """Top drive, dof - 2 joints of 5 in x 4.408 in pipe whose length and bore vary by a few
    per cent, and the paper's BHA inertia at the bit: cpp/tests/test_simulator.cpp's string."""
    g, rho = 79.3e9, 7850.0
    inertias, stiffnesses, dampings = [2122.0], [], []
    for i in range(dof - 2):
        length = 9.0 * (1.0 + 0.03 * math.sin(0.9 * i))
        inner = 0.112 * (1.0 + 0.01 * math.cos(1.7 * i))
        polar = math.pi / 32.0 * (0.127**4 - inner**4)
        inertias.append(rho * polar * length)
        stiffnesses.append(g * polar / length)
        dampings.append(50.0 * (1.0 + 0.5 * math.sin(2.3 * i)))
    inertias.append(471.9698)
    stiffnesses.append(g * math.pi / 32.0 * (0.127**4 - 0.112**4) / 9.0)
    dampings.append(50.0)
    return pydrill.preset("real-string").replace(
        inertias=inertias, stiffnesses=stiffnesses, dampings=dampings
    )


def cases():
    tally = load_tally(TALLY)
    for depth in (900.0, 2700.0, 5030.0):
        p = tally.at_depth(depth).to_params()
        name = f"paper-eq53 {depth:.0f} m"
        yield f"{name}, rest", p, dict(wob=1e5, torque=1.1e4, t_end=200.0)
        yield (
            f"{name}, equilibrium",
            p,
            dict(wob=6e4, torque=9e3, t_end=200.0, initial="equilibrium"),
        )
    for dof in (101, 301, 560):
        p = field_string(dof)
        yield f"field string {dof}, rest", p, dict(wob=1e5, torque=1.2e4, t_end=60.0)
    for dof in (101, 301, 560):
        p = pydrill.preset("reduced-scale", dof=dof)
        name = f"reduced-scale {dof - 3} pipes"
        yield f"{name}, rest", p, dict(wob=100.0, torque=8.3, t_end=300.0)
        yield (
            f"{name}, equilibrium",
            p,
            dict(wob=40.0, torque=8.3, t_end=300.0, initial="equilibrium"),
        )


def timed(params, kw, method, repeats):
    """Median CPU and wall time of `repeats` runs (s), and the last result (None on failure)."""
    cpu, wall, result = [], [], None
    for _ in range(repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        try:
            result = pydrill.simulate(params, method=method, n_out=201, max_steps=MAX_STEPS, **kw)
        except pydrill.SolverError as exc:
            return None, None, "chatters" if "chattering" in str(exc) else "> steps"
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    return statistics.median(cpu), statistics.median(wall), result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3, help="runs per case and method (median)")
    ap.add_argument("--save", type=Path, help="write the CPU times to this JSON file")
    ap.add_argument("--against", type=Path, help="a JSON file of --save: print new/old ratios")
    ap.add_argument("--only", default="", help="run only the cases whose name contains this")
    args = ap.parse_args()
    before = json.loads(args.against.read_text()) if args.against else {}
    saved: dict[str, dict[str, float]] = {}
    head = f"{'case':40s} {'dof':>4s} {'regime':>11s} {'auto':>6s}"
    for m in METHODS:
        head += f" {m + ' ms':>10s}" + (f" {'/old':>5s}" if before else "")
    head += "  other/auto  steps(bdf)"
    print(head)
    for name, params, kw in cases():
        if args.only not in name:
            continue
        times, results = {}, {}
        for m in METHODS:
            cpu, _wall, out = timed(params, kw, m, args.repeats)
            times[m] = cpu
            results[m] = out
        auto = results["auto"]
        line = f"{name:40s} {params.dof:4d} {auto.regime:>11s} {auto.stats.method:>6s}"
        for m in METHODS:
            if times[m] is None:
                line += f" {results[m]:>10s}" + (f" {'':>5s}" if before else "")
                continue
            line += f" {times[m] * 1e3:10.1f}"
            if before:
                old = before.get(name, {}).get(m)
                line += f" {times[m] / old:5.2f}" if old else f" {'-':>5s}"
        other = "bdf" if auto.stats.method == "dop853" else "dop853"
        ratio = f"{times[other] / times['auto']:10.2f}" if times[other] else f"{'-':>10s}"
        bdf = results["bdf"]
        line += f"  {ratio}  {bdf.stats.steps if not isinstance(bdf, str) else '-':>10}"
        print(line, flush=True)
        saved[name] = {m: t for m, t in times.items() if t is not None}
    if args.save:
        args.save.write_text(json.dumps(saved, indent=1))
        print(f"CPU times written to {args.save}", file=sys.stderr)


if __name__ == "__main__":
    main()
