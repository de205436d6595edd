"""Operating windows in (W_ob, surface rpm) for strings built from a tally."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import pydrill
from pydrill import stability as st
from pydrill.tally import load_tally
from pydrill.window import RPM, operating_window

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_window_agrees_with_eigenvalues_and_the_sliding_condition():
    p = load_tally(PAPER).at_depth(1000.0).to_params(dof=10)
    wob = np.linspace(2e4, 3e5, 9)
    rpm = np.linspace(10.0, 200.0, 8)
    w = operating_window(p, wob, rpm)
    for i, r in enumerate(rpm):
        for j, wb in enumerate(wob):
            omega = r * RPM
            delta = float(st.stribeck_slope(p, wb, omega))
            brute_stable = np.all(st.eigenvalues(p, delta).real < 0)
            assert w.stable[i, j] == brute_stable
            u = pydrill.equilibrium_torque(p, wb, omega)
            assert abs(w.torque[i, j] - u) < 1e-9 * u
            assert w.unstick[i, j] == (u > p.static_torque(wb))


def test_safe_points_drill_steadily_in_simulation():
    p = load_tally(PAPER).at_depth(1000.0).to_params(dof=8)
    wob = np.array([3e4, 6e4])
    rpm = np.array([120.0, 180.0])
    w = operating_window(p, wob, rpm)
    assert w.safe.any()
    for i, r in enumerate(rpm):
        for j, wb in enumerate(wob):
            if not w.safe[i, j]:
                continue
            u = pydrill.equilibrium_torque(p, wb, r * RPM)
            res = pydrill.simulate(p, wob=wb, torque=u, initial="equilibrium", t_end=120.0)
            assert res.regime == "steady"
            assert abs(res.summary.bit_mean - r * RPM) < 1e-3 * r * RPM


def test_window_command_over_depths():
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pydrill",
            "window",
            str(PAPER),
            "--depth",
            "500m,3000m,5000m",
            "--json",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    assert [w["depth"] for w in data["windows"]] == [500.0, 3000.0, 5000.0]
    dofs = [w["dof"] for w in data["windows"]]
    assert dofs == sorted(dofs) and dofs[0] < dofs[-1]
    for w in data["windows"]:
        assert 0 < w["safe_fraction"] < 1
        assert len(w["min_rpm"]) == len(data["wob"])
