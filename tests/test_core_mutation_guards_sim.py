"""Guards from a second mutation audit of the C++ core's simulation side (session 37).

Each test failed on a small change to the code that decides what a run returns (a flipped
comparison, a swapped output, a dropped term) that no other test noticed, and checks the run
against something of its own: statics (a stuck bit's torque balance), the angles turned
(DESIGN.md: the mean speeds are exact, from the angles), the stick condition |T_e| <= T_s, the
mirror symmetry u -> -u, or the Python API's own documented defaults.
"""

import inspect

import numpy as np
import pytest

import pydrill
from pydrill import _core

WOB = 100.0  # N: T_s = mu_sb W_ob R_b = 8 N m on the reduced-scale string


def _static_torque(p):
    return p.mu_static * WOB * p.bit_radius


def test_a_stuck_bit_spends_nothing_on_friction_and_the_string_carries_u():
    """u < T_s from rest: the rock holds the bit for good. Friction does no work on a still
    bit, so its ledger entry stays 0 and the work put in is the viscous loss plus the energy
    stored; at rest every spring carries u (statics: theta_i = u / k_i) and T_e = u."""
    p = pydrill.preset("reduced-scale", dof=4)
    u = 5.0
    assert u < _static_torque(p)
    r = pydrill.simulate(p, wob=WOB, torque=u, t_end=400.0, n_out=401)
    assert r.regime == "stuck"
    assert set(r.modes) == {"stick"}
    assert np.all(r.bit_velocity == 0.0)
    assert np.all(r.friction_loss == 0.0)
    assert r.viscous_loss[-1] > 0.0
    np.testing.assert_allclose(
        r.work_input - r.viscous_loss, r.energy - r.energy[0], rtol=0, atol=1e-7 * r.work_input[-1]
    )
    # The string still rings a little (light damping): statics to 1 %.
    np.testing.assert_allclose(r.twist[-1], u / np.asarray(p.stiffnesses), rtol=1e-2)
    assert r.reaction_torque[-1] == pytest.approx(u, rel=1e-2)


@pytest.mark.parametrize("window_fraction", [0.5, 0.3])
def test_the_window_means_are_the_angles_turned_over_the_window(window_fraction):
    """bit_mean and top_mean are exact (DESIGN.md): the angles turned over the window divided by
    its length. The angles at the window's ends come here from output times placed there, the
    bit's as phi_0 minus the twists, a path of its own."""
    p = pydrill.preset("reduced-scale", dof=4)
    t_end = 120.0
    t0 = t_end * (1.0 - window_fraction)
    r = pydrill.simulate(
        p, wob=WOB, torque=8.3, t_end=t_end, t_out=[t0, t_end], window_fraction=window_fraction
    )
    assert r.regime == "stick-slip"
    s = r.summary
    assert s.window_start == pytest.approx(t0, rel=1e-12)
    span = t_end - t0
    assert s.top_mean == pytest.approx((r.top_angle[1] - r.top_angle[0]) / span, rel=1e-8)
    assert s.bit_mean == pytest.approx((r.bit_angle[1] - r.bit_angle[0]) / span, rel=1e-8)


def _mirrored(p, state, u, friction, t_end=60.0):
    kw = dict(wob=WOB, t_end=t_end, n_out=601, friction=friction)
    fwd = pydrill.simulate(p, torque=u, initial=state, **kw)
    back = pydrill.simulate(p, torque=-u, initial=[-v for v in state], **kw)
    return fwd, back


@pytest.mark.parametrize("friction", ["exact", "karnopp"])
def test_a_start_with_the_bit_turning_backwards_mirrors_the_forward_one(friction):
    """phi -> -phi maps a run from state y at u onto the run from -y at -u. Here the bit starts
    turning backwards (omega_b < 0) against a forward torque: its first mode is slip-, the
    mirror's slip+."""
    p = pydrill.preset("reduced-scale", dof=4)
    state = [1.0, 0.5, 1.0, 0.5, 1.0, 0.5, -2.0]
    fwd, back = _mirrored(p, state, 8.3, friction)
    assert fwd.modes[0] == "slip-"
    assert back.modes[0] == "slip+"
    assert [s.kind for s in back.switches] == [s.kind for s in fwd.switches]
    np.testing.assert_allclose([s.t for s in back.switches], [s.t for s in fwd.switches], rtol=1e-6)
    np.testing.assert_allclose(back.states, -fwd.states, rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_bit_reversed_through_the_karnopp_band_is_not_held_beyond_t_s(sign):
    """The bit slips forwards while the spring above it is wound far backwards (T_e ~ -3 T_s):
    it decelerates into the Karnopp band with |T_e| > T_s, which the rock cannot hold
    (DESIGN.md: stick only while |T_e| <= T_s), so it creeps through the band and leaves it
    backwards, as the exact law reverses it. And the mirror image (sign -1) does the same."""
    p = pydrill.preset("reduced-scale", dof=4)
    ts = _static_torque(p)
    theta = -3.0 * ts / p.stiffnesses[-1]
    state = [sign * v for v in [0.0, 0.0, 0.0, 0.0, 0.0, theta, 0.5]]
    kar = pydrill.simulate(
        p, wob=WOB, torque=0.0 * sign, initial=state, t_end=2.0, n_out=201, friction="karnopp"
    )
    first = kar.switches[0]
    assert first.kind == "band-enter"
    assert abs(first.reaction_torque) > ts
    assert kar.switches[1].kind == "band-leave"
    assert kar.switches[1].direction == -int(sign)
    exact = pydrill.simulate(p, wob=WOB, torque=0.0, initial=state, t_end=2.0, n_out=201)
    assert exact.switches[0].kind == "reversal"
    assert exact.switches[0].direction == -int(sign)


def test_the_core_defaults_are_those_simulate_documents():
    """A C++ caller who leaves SimulationOptions at its defaults runs what pydrill.simulate
    runs by default: the two are written down in different places (simulator.hpp and the
    signature of simulate)."""
    defaults = {
        k: v.default
        for k, v in inspect.signature(pydrill.simulate).parameters.items()
        if v.default is not inspect.Parameter.empty
    }
    o = _core.SimulationOptions()
    for name in (
        "t_end",
        "n_out",
        "rtol",
        "atol",
        "max_step",
        "max_order",
        "max_steps",
        "perturbation",
        "window_fraction",
        "max_switch_rate",
        "method",
        "friction",
        "initial",
    ):
        assert getattr(o, name) == defaults[name], name


@pytest.mark.parametrize("method", ["dop853", "bdf"])
def test_max_steps_allows_exactly_that_many_steps(method):
    """max_steps is the number of internal steps a run may take (docstring of simulate): a run
    that took n steps runs again within max_steps = n, to the same end, and stops at n - 1.
    The run has friction switches, so its steps are counted across restarts."""
    p = pydrill.preset("reduced-scale", dof=4)
    kw = dict(wob=WOB, torque=8.3, t_end=40.0, n_out=2, method=method)
    free = pydrill.simulate(p, **kw)
    n = free.stats.steps
    assert free.stats.reinits > 2
    exact = pydrill.simulate(p, max_steps=n, **kw)
    np.testing.assert_array_equal(exact.states, free.states)
    with pytest.raises(pydrill.SolverError, match="max_steps"):
        pydrill.simulate(p, max_steps=n - 1, **kw)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_still_bit_wound_past_t_s_does_not_start_held(sign):
    """A start with the bit still and the spring above it wound past T_s, either way: the rock
    cannot hold it (DESIGN.md: stick only while |T_e| <= T_s). Karnopp starts it creeping in the
    band, the exact law slipping the way T_e pulls."""
    p = pydrill.preset("reduced-scale", dof=4)
    ts = _static_torque(p)
    state = [0.0, 0.0, 0.0, 0.0, 0.0, sign * 2.0 * ts / p.stiffnesses[-1], 0.0]
    kw = dict(wob=WOB, torque=0.0, initial=state, t_end=1.0, n_out=11)
    assert abs(pydrill.simulate(p, **kw).reaction_torque[0]) == pytest.approx(2.0 * ts)
    assert pydrill.simulate(p, friction="karnopp", **kw).modes[0] == "band"
    assert pydrill.simulate(p, **kw).modes[0] == ("slip+" if sign > 0 else "slip-")


@pytest.mark.parametrize(
    "collar_k, collar_c, method",
    [
        (1000.0, 50.0, "bdf"),  # fast modes overdamped, dying ~2e4 times faster: stiff
        (100.0, 5.0, "dop853"),  # overdamped, but only ~2e3 times faster: not stiff enough
        (1e7, 50.0, "dop853"),  # ~2e4 times faster decay, but ringing (damping ratio ~0.1)
    ],
)
def test_auto_picks_bdf_only_for_fast_modes_that_die(collar_k, collar_c, method):
    """README (Integrators): "auto" picks BDF for very stiff strings, "fast modes that die 1e4
    times faster than the string winds up", else DOP853. Both halves are checked here on the
    estimates "auto" decides from (decay / fundamental above 1e4, and fast modes damped beyond
    a damping ratio of 0.5, which is what makes them die rather than ring)."""
    p = pydrill.preset(
        "reduced-scale",
        dof=4,
        stiffnesses=[0.073, collar_k, collar_k],
        dampings=[1e-4, collar_c, collar_c],
    )
    e = _core.estimate_stiffness(p.to_core())
    ratio = e.fastest_decay / e.fundamental
    zeta = e.fastest_decay / (2.0 * e.fastest_frequency)
    assert (ratio > 1e4 and zeta > 0.5) == (method == "bdf")
    assert ratio > 1e3  # every case is past a tenfold lower threshold
    r = pydrill.simulate(p, wob=WOB, torque=8.3, t_end=0.01, n_out=2)
    assert r.stats.method == method
