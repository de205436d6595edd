"""The Python face of the C++ core: no copies, clear exceptions, released GIL."""

import threading
import time

import numpy as np
import pytest

import pydrill
from pydrill import _core


def test_arrays_are_read_only_views_without_copies():
    r = pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=20.0, n_out=201)
    states = r.states
    assert not states.flags.writeable
    assert not states.flags.owndata  # a view of the core's memory
    assert np.shares_memory(r.omega, states) and np.shares_memory(r.twist, states)
    assert r.omega.base is not None
    with pytest.raises(ValueError):
        states[0, 0] = 1.0
    # The view keeps the core result alive after the result object is gone.
    t = r.t
    del r
    assert t[-1] == 20.0


def test_solver_error_carries_time_reached():
    with pytest.raises(pydrill.SolverError) as err:
        pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=300.0, max_steps=200)
    assert err.value.t_reached > 0
    assert "max_steps" in str(err.value)
    assert isinstance(err.value, RuntimeError)


def test_chattering_guard_raises_instead_of_hanging():
    with pytest.raises(pydrill.SolverError, match="chattering"):
        pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=600.0, max_switch_rate=1e-3)


def test_invalid_argument_becomes_value_error():
    with pytest.raises(ValueError, match="t_end"):
        pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=-1.0)
    with pytest.raises(ValueError, match="t_out"):
        pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=10.0, t_out=[0.0, 20.0])
    with pytest.raises(ValueError, match="method"):
        pydrill.simulate(wob=100.0, torque=8.3, dof=4, method="rk4")
    with pytest.raises(ValueError, match="wob"):
        pydrill.simulate(wob=0.0, torque=8.3, dof=4)


def test_long_simulations_release_the_gil():
    """Two threads each running a simulation take about as long as one when the core
    releases the GIL — measured against a Python-only workload that cannot overlap."""
    p = pydrill.preset("reduced-scale", dof=40)

    def work():
        pydrill.simulate(p, wob=100.0, torque=8.3, t_end=400.0, n_out=11)

    t0 = time.perf_counter()
    work()
    single = time.perf_counter() - t0
    # If the GIL were held, the main thread could not count while the worker runs.
    counts = 0
    worker = threading.Thread(target=work)
    worker.start()
    deadline = time.perf_counter() + single * 0.8
    while time.perf_counter() < deadline and worker.is_alive():
        counts += 1
    worker.join()
    assert counts > 1000


def test_core_version_matches_package():
    assert pydrill.__version__ == _core.__version__
