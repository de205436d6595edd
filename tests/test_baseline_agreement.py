"""The benchmark's pure-Python baseline and the C++ core simulate the same model: checked
here so the benchmark's ratios compare like with like (and the core against an independent
implementation of the event-driven friction law)."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import pydrill


@pytest.fixture(scope="module")
def baseline():
    path = Path(__file__).resolve().parents[1] / "benchmarks" / "baseline_scipy.py"
    spec = importlib.util.spec_from_file_location("baseline_scipy", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("method", ["dop853", "erk", "adams", "bdf"])
def test_stick_slip_switches_and_states_agree(baseline, method):
    p = pydrill.preset("reduced-scale", dof=4)
    t = np.linspace(0.0, 100.0, 401)
    core = pydrill.simulate(p, wob=100.0, torque=8.3, t_end=100.0, t_out=t, method=method)
    base = baseline.simulate_baseline(
        **baseline.from_params(p),
        wob=100.0,
        torque=8.3,
        t_end=100.0,
        t_eval=t,
        rtol=1e-10,
        atol=1e-10,
    )
    kinds = {"stick": "stick", "slip+": "slip", "slip-": "slip"}
    assert [s.kind for s in core.switches] == [kinds[k] for k in base["switch_kinds"]]
    np.testing.assert_allclose(
        [s.t for s in core.switches], base["switch_times"], atol=1e-4, rtol=0
    )
    scale = np.abs(core.states).max()
    assert np.abs(core.states - base["y"]).max() < 1e-4 * scale


def test_equilibrium_start_on_a_longer_string_agrees(baseline):
    p = pydrill.preset("reduced-scale", pipes=20)
    t = np.linspace(0.0, 20.0, 81)
    core = pydrill.simulate(p, wob=100.0, torque=8.3, t_end=20.0, t_out=t, initial="equilibrium")
    base = baseline.simulate_baseline(
        **baseline.from_params(p),
        wob=100.0,
        torque=8.3,
        t_end=20.0,
        t_eval=t,
        initial="equilibrium",
        rtol=1e-10,
        atol=1e-10,
    )
    assert np.abs(core.states - base["y"]).max() < 1e-6 * np.abs(core.states).max()
