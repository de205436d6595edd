"""Bad and extreme inputs thrown at the Python API: a clear exception or a result, never an
abort or a segfault (a crash would take the test process down with it)."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import pydrill

anything = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e6, max_value=1e6),
    st.sampled_from([0.0, -0.0, 1e-300, 1e300, -1.0, math.inf, -math.inf, math.nan]),
)
positive = st.floats(min_value=1e-3, max_value=1e3)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    wob=anything,
    torque=anything,
    t_end=st.one_of(
        st.sampled_from([0.0, -1.0, math.nan, math.inf, -math.inf]),
        st.floats(min_value=1e-3, max_value=20.0),
    ),
    dof=st.integers(min_value=-3, max_value=12),
)
def test_operating_point_fuzz(wob, torque, t_end, dof):
    try:
        r = pydrill.simulate(wob=wob, torque=torque, t_end=t_end, dof=dof, n_out=11)
    except (ValueError, pydrill.SolverError) as exc:
        assert str(exc)
        return
    assert r.regime in pydrill.REGIMES
    assert np.all(np.isfinite(r.states))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    inertias=st.lists(st.one_of(positive, anything), min_size=0, max_size=6),
    stiffness=st.one_of(positive, anything),
    damping=st.one_of(st.floats(min_value=0.0, max_value=10.0), anything),
    mu=st.tuples(anything, anything),
    method=st.sampled_from(["auto", "bdf", "adams", "erk", "dop853"]),
    friction=st.sampled_from(["exact", "karnopp"]),
)
def test_parameter_fuzz(inertias, stiffness, damping, mu, method, friction):
    n = len(inertias)
    try:
        params = pydrill.preset("reduced-scale", dof=max(n, 2)).replace(
            inertias=inertias,
            stiffnesses=[stiffness] * max(n - 1, 0),
            dampings=[damping] * max(n - 1, 0),
            mu_coulomb=mu[0],
            mu_static=mu[1],
        )
        r = pydrill.simulate(
            params,
            wob=100.0,
            torque=8.3,
            t_end=5.0,
            n_out=11,
            method=method,
            friction=friction,
            max_steps=200_000,
        )
    except (ValueError, pydrill.SolverError) as exc:
        assert str(exc)
        return
    assert r.regime in pydrill.REGIMES


@settings(max_examples=40, deadline=None)
@given(
    state=st.lists(anything, min_size=0, max_size=9),
    rtol=st.one_of(anything, st.floats(min_value=1e-12, max_value=1e-2)),
    atol=st.one_of(anything, st.floats(min_value=1e-14, max_value=1e-2)),
)
def test_state_and_tolerance_fuzz(state, rtol, atol):
    try:
        r = pydrill.simulate(
            wob=100.0,
            torque=8.3,
            dof=4,
            initial=state,
            rtol=rtol,
            atol=atol,
            t_end=2.0,
            n_out=5,
            max_steps=100_000,
        )
    except (ValueError, pydrill.SolverError) as exc:
        assert str(exc)
        return
    assert r.states.shape == (5, 7)


def test_infinite_right_hand_side_fails_fast_with_every_method():
    """A start at 1e300 rad/s and rad makes the right-hand side overflow at t = 0: every
    integrator must give up with a SolverError, not shrink its step for ever (DOP853 once did,
    its smallest step being a subnormal ulp flushed to zero). (A torque of 1e300 N·m did the
    same; simulate now refuses it by name, beyond 1e15, before any integrator starts.)"""
    state = np.full(7, 1e300)
    for method in ("auto", "dop853", "erk", "adams", "bdf"):
        with pytest.raises(pydrill.SolverError, match="at t = "):
            pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=5.0, method=method, initial=state)
