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
    """While a thread is inside a long simulation, Python code in another thread runs at a
    good share of its own speed; if the core held the GIL it would be stopped for the whole
    call (the simulation is one C++ call of ~0.1 s or more)."""
    p = pydrill.preset("reduced-scale", pipes=300)

    def work():
        pydrill.simulate(p, wob=100.0, torque=8.3, t_end=10000.0, n_out=11)

    def count_for(seconds, alive=lambda: True):
        n, t0 = 0, time.perf_counter()
        while time.perf_counter() - t0 < seconds and alive():
            n += 1
        return n / (time.perf_counter() - t0)

    solo = count_for(0.05)
    worker = threading.Thread(target=work)
    worker.start()
    time.sleep(0.005)  # let the worker enter the core
    shared = count_for(10.0, worker.is_alive)
    worker.join()
    # Two cores: one counts, one simulates. Held GIL: ~0 (only the call's edges).
    assert shared > 0.2 * solo


def test_core_version_matches_package():
    assert pydrill.__version__ == _core.__version__
