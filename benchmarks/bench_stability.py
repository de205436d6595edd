#!/usr/bin/env python3
"""Stability boundaries from the δ structure against brute-force eigenvalues.

    python benchmarks/bench_stability.py

Prints, measured in the same run: the time for every critical δ_k of strings of 10 … 500 pipes;
a 1000 × 1000 (Ω, W_ob) stability map from them; and the time per point of the brute-force
alternative (dense eigenvalues of the Jacobian at each point, by LAPACK through numpy), with
the ratio. Run with OPENBLAS_NUM_THREADS=1 for one core's numbers.
Goals (issue 3): all δ_k for 500 pipes in under 100 ms; the 1000 × 1000 map in under 1 s.

Then the eigenvalues a sweep records at each steady state: the structured solver (the roots
of Z_b(λ) = δ by Ehrlich–Aberth, O(n'²)) against the dense one (O(n'³)), at the same δ, with
the largest difference between them: on the reduced-scale preset (lightly damped) and on a
real string from a tally (c = β k: most modes overdamped, their roots bunched near −1/β).

Last, the first Lyapunov coefficient at a Hopf crossing (its criticality): the core's banded
solves, O(n'), against the same formula on dense LU factorisations (scipy, O(n'³)), as the
core computed it before.
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
    from pathlib import Path

    from pydrill import _core

    tally = pydrill.load_tally(
        Path(__file__).resolve().parents[1] / "examples/tallies/paper-eq53.toml"
    )
    # around the first Hopf crossing and far past it; a real string's δ at W_ob 20 ... 200 kN
    small = [0.001, 0.0107, 0.05, 0.5]
    strings = [
        (f"{n} pipes", pydrill.preset("reduced-scale", pipes=n), small) for n in (50, 100, 200, 300)
    ]
    strings += [
        (f"tally {d:.0f} m", tally.at_depth(d).to_params(), [1.0, 100.0, 1e4])
        for d in (1000.0, 3000.0)
    ]
    print(
        f"\n{'string':>14s} {'dof':>5s} {'dense (ms)':>11s} {'structured (ms)':>16s} "
        f"{'ratio':>7s} {'max |diff| / max |λ|':>21s}"
    )
    for label, p, deltas in strings:
        core = p.to_core()
        t_dense = t_fast = 0.0
        worst = 0.0
        for d in deltas:
            td, dense = best_of(lambda d=d, c=core: np.array(_core.eigenvalues(c, d)), repeats=1)
            tf, fast = best_of(lambda d=d, c=core: _core.roots_of_impedance(c, d), repeats=1)
            t_dense += td
            t_fast += tf
            if fast is None:
                print(f"{label:>14s}: the structured solver declined at δ = {d}")
                continue
            diff = np.abs(dense[:, None] - np.array(fast)[None, :]).min(axis=1).max()
            worst = max(worst, diff / np.abs(dense).max())
        n = len(deltas)
        print(
            f"{label:>14s} {p.dof:5d} {1e3 * t_dense / n:11.2f} {1e3 * t_fast / n:16.2f} "
            f"{t_dense / t_fast:6.1f}× {worst:21.1e}"
        )


def dense_lyapunov(p, delta: float, w: float) -> float:
    """The first Lyapunov coefficient by dense LU: null vectors by three steps of inverse
    iteration, then Kuznetsov's formula with the friction's B and C on the bit's velocity."""
    from scipy.linalg import lu_factor, lu_solve

    A = st.jacobian(p, delta).astype(complex)
    n, iw = len(A), 1j * w
    eye = np.eye(n)

    def null_vector(M):
        lu = lu_factor(M - 1e-10 * max(1.0, w) * eye)
        v = np.ones(n, complex)
        for _ in range(3):
            v = lu_solve(lu, v)
            v /= np.linalg.norm(v)
        return v

    q, adj = null_vector(A - iw * eye), null_vector(A.T + iw * eye)
    adj /= np.conj(np.vdot(adj, q))
    g = p.stribeck_decay / p.stribeck_velocity
    beta, kappa = -delta * g / p.inertias[-1], delta * g**2 / p.inertias[-1]
    e = np.zeros(n, complex)
    e[-1] = 1.0
    a1 = lu_solve(lu_factor(A), beta * q[-1] * np.conj(q[-1]) * e)
    a2 = lu_solve(lu_factor(2 * iw * eye - A), beta * q[-1] ** 2 * e)
    pb = np.conj(adj[-1])
    s = pb * (kappa * q[-1] ** 2 * np.conj(q[-1]) - 2 * beta * q[-1] * a1[-1])
    s += pb * beta * np.conj(q[-1]) * a2[-1]
    return float(s.real / (2 * w))


def lyapunov_at_a_crossing() -> None:
    from pydrill import _core

    print(
        f"\n{'pipes':>6s} {'dof':>5s} {'dense LU (ms)':>14s} {'banded (ms)':>12s} {'ratio':>7s} "
        f"{'relative difference':>20s}"
    )
    dense_lyapunov(pydrill.preset("reduced-scale", dof=4), 0.01, 1.0)  # scipy's import, untimed
    for pipes in (50, 100, 200, 300, 500):
        p = pydrill.preset("reduced-scale", pipes=pipes)
        c = next(c for c in st.critical_deltas(p) if c.type == "hopf")
        td, dense = best_of(lambda p=p, c=c: dense_lyapunov(p, c.delta, c.frequency), repeats=1)
        core = p.to_core()
        tb, banded = best_of(
            lambda c=c, core=core: _core.first_lyapunov_coefficient(core, c.delta, c.frequency)
        )
        print(
            f"{pipes:6d} {p.dof:5d} {1e3 * td:14.1f} {1e3 * tb:12.2f} {td / tb:6.0f}× "
            f"{abs(banded - dense) / abs(dense):20.1e}"
        )


if __name__ == "__main__":
    main()
    eigenvalues_at_a_point()
    lyapunov_at_a_crossing()
