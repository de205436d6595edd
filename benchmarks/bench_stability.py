#!/usr/bin/env python3
"""Stability boundaries from the δ structure against brute-force eigenvalues.

    python benchmarks/bench_stability.py

Prints, measured in the same run: the time for every critical δ_k of strings of 10 … 500 pipes;
a 1000 × 1000 (Ω, W_ob) stability map from them; and the time per point of the brute-force
alternative (dense eigenvalues of the Jacobian at each point), with the ratio.
Goals (issue 3): all δ_k for 500 pipes in under 100 ms; the 1000 × 1000 map in under 1 s.
"""

from __future__ import annotations

import time

import numpy as np

import pydrill
from pydrill import stability as st


def best_of(fn, repeats=3):
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    print(
        f"{'pipes':>6s} {'dof':>5s} {'crossings':>10s} {'all δ_k (ms)':>13s} "
        f"{'map 1000² (s)':>14s} {'eig / point (ms)':>17s} {'brute map (est. s)':>19s} "
        f"{'ratio':>9s}"
    )
    omega = np.linspace(0.05, 20.0, 1000)
    wob = np.linspace(1.0, 300.0, 1000)
    for pipes in (10, 50, 100, 200, 500):
        p = pydrill.preset("reduced-scale", pipes=pipes)
        t_cross, crossings = best_of(lambda p=p: st.critical_deltas(p))
        t_map, _counts = best_of(lambda p=p, c=crossings: st.stability_map(p, omega, wob, c))
        # Brute force: dense eigenvalues at a few points, extrapolated to the whole map.
        deltas = st.stribeck_slope(p, wob[::250], omega[::250])
        t0 = time.perf_counter()
        for d in deltas:
            st.eigenvalues(p, d)
        t_eig = (time.perf_counter() - t0) / len(deltas)
        brute = t_eig * omega.size * wob.size
        print(
            f"{pipes:6d} {p.dof:5d} {len(crossings):10d} {1e3 * t_cross:13.2f} "
            f"{t_map + t_cross:14.3f} {1e3 * t_eig:17.3f} {brute:19.0f} "
            f"{brute / (t_map + t_cross):8.0f}×"
        )


if __name__ == "__main__":
    main()
