#!/usr/bin/env python3
"""Adams, BDF, ARKODE ERK and DOP853 on soft and stiff strings, and what ``method="auto"`` picks.

Calibrates the stiffness estimate behind ``method="auto"`` (cpp/src/simulator.cpp,
``choose_method``). Each case runs both methods in the same process, so the ratio is robust to
a busy machine even when the absolute times are not.

    python benchmarks/bench_methods.py
"""

from __future__ import annotations

import time

import pydrill


def refined(n: int) -> pydrill.Params:
    """The dof-4 string's pipe section split into n elements: same total compliance and
    inertia, so the same stick-slip, but stiff element modes with strong damping."""
    return pydrill.preset(
        "reduced-scale",
        inertias=[0.518] + [0.025 / n] * n + [0.0318, 0.0318],
        stiffnesses=[0.073 * (n + 1)] * (n + 1) + [0.073],
        dampings=[1e-4 * (n + 1)] * (n + 1) + [1e-4],
    ).replace(name=f"refined-{n}")


CASES = [
    ("reduced-scale dof 2", pydrill.preset("reduced-scale", dof=2), 100.0, 8.1, 300.0),
    ("reduced-scale dof 4", pydrill.preset("reduced-scale", dof=4), 100.0, 8.3, 300.0),
    ("reduced-scale 10 pipes", pydrill.preset("reduced-scale", pipes=10), 100.0, 8.3, 300.0),
    ("reduced-scale 100 pipes", pydrill.preset("reduced-scale", pipes=100), 100.0, 8.3, 300.0),
    ("reduced-scale 500 pipes", pydrill.preset("reduced-scale", pipes=500), 100.0, 8.3, 300.0),
    ("real-string dof 2", pydrill.preset("real-string"), 7.0e4, 9.0e3, 100.0),
    (
        "stiff damped collars",
        pydrill.preset(
            "reduced-scale", dof=4, stiffnesses=[0.073, 500, 500], dampings=[1e-4, 5.0, 5.0]
        ),
        100.0,
        8.3,
        100.0,
    ),
    (
        "stiff undamped collars",
        pydrill.preset("reduced-scale", dof=4, stiffnesses=[0.073, 500, 500]),
        100.0,
        8.3,
        100.0,
    ),
    ("refined 20", refined(20), 100.0, 8.3, 100.0),
    ("refined 100", refined(100), 100.0, 8.3, 100.0),
    ("refined 500", refined(500), 100.0, 8.3, 60.0),
]


def timed(params, wob, torque, t_end, method):
    best = float("inf")
    for _ in range(2):
        t0 = time.perf_counter()
        r = pydrill.simulate(params, wob=wob, torque=torque, t_end=t_end, method=method, n_out=101)
        best = min(best, time.perf_counter() - t0)
    return best, r


def main() -> None:
    print(
        f"{'case':26s} {'ratio':>9s} {'zeta':>6s} {'adams s':>9s} {'bdf s':>9s} {'erk s':>9s} "
        f"{'dop853 s':>9s} {'auto':>6s} {'best':>6s}  regime"
    )
    for name, params, wob, torque, t_end in CASES:
        ta, ra = timed(params, wob, torque, t_end, "adams")
        tb, _rb = timed(params, wob, torque, t_end, "bdf")
        te, _re = timed(params, wob, torque, t_end, "erk")
        td, _rd = timed(params, wob, torque, t_end, "dop853")
        _, rauto = timed(params, wob, torque, t_end, "auto")
        auto = rauto.stats.method
        times = {"adams": ta, "bdf": tb, "erk": te, "dop853": td}
        best = min(times, key=times.get)
        est = pydrill._core.estimate_stiffness(params.to_core())
        zeta = est.fastest_decay / (2 * est.fastest_frequency)
        print(
            f"{name:26s} {rauto.stats.stiffness_ratio:9.3g} {zeta:6.3f} {ta:9.4f} {tb:9.4f} "
            f"{te:9.4f} {td:9.4f} {auto:>6s} {best:>6s}  {ra.regime}"
        )


if __name__ == "__main__":
    main()
