#!/usr/bin/env python3
"""Stability boundaries from the δ structure against brute-force eigenvalues.

    python benchmarks/bench_stability.py

Prints, measured in the same run: the time for every critical δ_k of strings of 10 … 500 pipes;
a 1000 × 1000 (Ω, W_ob) stability map from them; and the time per point of the brute-force
alternative (dense eigenvalues of the Jacobian at each point), with the ratio.
Goals (issue 3): all δ_k for 500 pipes in under 100 ms; the 1000 × 1000 map in under 1 s.

Then the eigenvalues a sweep records at each steady state: the structured solver (the roots
of Z_b(λ) = δ by Ehrlich–Aberth, O(n'²)) against the dense one (O(n'³)), at the same δ, with
the largest difference between them.
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


def eigenvalues_at_a_point() -> None:
    from pydrill import _core

    print(
        f"\n{'pipes':>6s} {'dof':>5s} {'dense (ms)':>11s} {'structured (ms)':>16s} "
        f"{'ratio':>7s} {'max |diff| / max |λ|':>21s}"
    )
    for pipes in (50, 100, 200, 300):
        p = pydrill.preset("reduced-scale", pipes=pipes)
        core = p.to_core()
        deltas = [0.001, 0.0107, 0.05, 0.5]  # around the first Hopf crossing, and far past it
        t_dense = t_fast = 0.0
        worst = 0.0
        for d in deltas:
            td, dense = best_of(lambda d=d, c=core: np.array(_core.eigenvalues(c, d)), repeats=1)
            tf, fast = best_of(lambda d=d, c=core: _core.roots_of_impedance(c, d), repeats=1)
            t_dense += td
            t_fast += tf
            if fast is None:
                print(f"{pipes:6d}: the structured solver declined at δ = {d}")
                continue
            diff = np.abs(dense[:, None] - np.array(fast)[None, :]).min(axis=1).max()
            worst = max(worst, diff / np.abs(dense).max())
        n = len(deltas)
        print(
            f"{pipes:6d} {p.dof:5d} {1e3 * t_dense / n:11.2f} {1e3 * t_fast / n:16.2f} "
            f"{t_dense / t_fast:6.1f}× {worst:21.1e}"
        )


if __name__ == "__main__":
    main()
    eigenvalues_at_a_point()
