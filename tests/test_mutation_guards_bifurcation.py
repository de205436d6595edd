"""Mutation guards for pydrill.bifurcation: the branch's samples against the documented grid
worked out by hand, its stability counts and each point's crossing direction against the
dense eigenvalues of pydrill.stability just either side, and the refusals of omega_max."""

import math

import numpy as np
import pytest

import pydrill
from pydrill import stability as st
from pydrill.bifurcation import FLOOR, branch


def wob_on_branch(p, torque, omega):
    """W_ob of the steady state at Ω under surface torque u, from the friction law by hand:
    u = (c_r + c_b)Ω + W_ob R_b μ_b(Ω)."""
    c = p.top_damping + p.bit_damping
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * math.exp(
        -p.stribeck_decay * omega / p.stribeck_velocity
    )
    return (torque - c * omega) / (p.bit_radius * mu)


def unstable_at(p, vary, fixed, omega):
    """Eigenvalues in Re > 0 of the steady state at Ω, from the dense eigenvalues."""
    wob = wob_on_branch(p, fixed, omega) if vary == "wob" else fixed
    (pt,) = st.stability(p, wob, omega=omega)
    return int(sum(z.real > 0 for z in pt.eigenvalues))


def test_the_samples_are_half_geometric_from_the_floor_and_half_even_up_to_omega_max():
    """40 samples up to 30 rad/s: 20 from FLOOR v_f/γ_b (1e-6 of the friction law's velocity
    scale) growing by a constant ratio to below 30, and 20 evenly spaced up to 30 (less one part
    in 1e9); all Ω > 0, none repeated."""
    p = pydrill.preset(dof=4)
    b = branch(p, vary="torque", wob=100.0, omega_max=30.0, samples=40)
    top = 30.0 * (1 - 1e-9)
    start = FLOOR * p.stribeck_velocity / p.stribeck_decay
    assert start == pytest.approx(1e-6 / 0.9, rel=1e-12)  # reduced-scale: v_f = 1, γ_b = 0.9
    ratio = (top / start) ** (1 / 20)
    geometric = start * ratio ** np.arange(20)
    even = top / 20 * np.arange(1, 21)
    assert len(b.omega) == 40 and np.all(np.diff(b.omega) > 0) and b.omega[0] > 0
    np.testing.assert_allclose(b.omega, np.sort(np.r_[geometric, even]), rtol=1e-9)
    # An omega_max below the friction law's scale starts the branch at 1e-6 of it instead
    low = branch(p, vary="torque", wob=100.0, omega_max=0.5, samples=40)
    assert low.omega[0] == pytest.approx(FLOOR * 0.5 * (1 - 1e-9), rel=1e-12)


def test_the_wob_branch_ends_where_the_weight_on_bit_reaches_zero_whatever_omega_max():
    """With the torque held, W_ob(Ω) = (u − (c_r + c_b)Ω) / (R_b μ_b) reaches 0 at
    Ω = u / (c_r + c_b): an omega_max beyond gives the default branch, never W_ob < 0."""
    p = pydrill.preset(dof=2)
    c = p.top_damping + p.bit_damping
    default = branch(p, vary="wob", torque=8.1, samples=200)
    beyond = branch(p, vary="wob", torque=8.1, omega_max=1e3, samples=200)
    assert beyond == default
    assert default.omega[-1] == pytest.approx(8.1 / c, rel=1e-8) and default.omega[-1] < 8.1 / c
    assert np.all(default.wob >= 0)
    for w, om in zip(default.wob[::20], default.omega[::20], strict=True):
        assert w == pytest.approx(wob_on_branch(p, 8.1, om), rel=1e-12)


def test_without_damping_at_the_ends_the_wob_branch_goes_as_far_as_asked():
    """With c_r + c_b = 0 the weight on bit W_ob = u / (R_b μ_b(Ω)) > 0 at every Ω: there is
    no end to stop at, so omega_max is taken as given (it was cut to 100 rad/s silently);
    without it the branch goes to 100 rad/s."""
    p = pydrill.preset(dof=2).replace(top_damping=0.0, bit_damping=0.0)
    far = branch(p, vary="wob", torque=8.1, omega_max=500.0, samples=200)
    assert far.omega[-1] == pytest.approx(500.0, rel=1e-8)
    assert far.wob[-1] == pytest.approx(8.1 / (p.bit_radius * p.mu_coulomb), rel=1e-9)
    assert branch(p, vary="wob", torque=8.1, samples=200).omega[-1] == pytest.approx(100.0)


@pytest.mark.parametrize(("dof", "vary", "fixed"), [(4, "torque", 100.0), (2, "wob", 8.1)])
def test_stability_along_the_branch_and_at_its_points_matches_the_dense_eigenvalues(
    dof, vary, fixed
):
    """Each sample's count of unstable eigenvalues is the dense one at its own Ω; and across
    each point (Ω ± 1e-6 relative) the count changes by the point's direction times 2 (a Hopf
    pair) or 1 (the fold) as δ grows, i.e. as Ω falls (δ decreases along the branch)."""
    p = pydrill.preset(dof=dof)
    kw = {"torque": fixed} if vary == "wob" else {"wob": fixed}
    b = branch(p, vary=vary, omega_max=30.0 if vary == "torque" else None, samples=60, **kw)
    counts = [unstable_at(p, vary, fixed, om) for om in b.omega]
    np.testing.assert_array_equal(b.unstable, counts)
    assert {pt.type for pt in b.points} == {"HB", "LP"}
    for pt in b.points:
        above, below = (unstable_at(p, vary, fixed, pt.omega * (1 + s)) for s in (1e-6, -1e-6))
        step = 2 if pt.type == "HB" else 1
        assert below - above == pt.direction * step, pt.label
        assert pt.others_unstable == min(above, below), pt.label
    omegas = [pt.omega for pt in b.points]
    assert omegas == sorted(omegas, reverse=True)  # from the highest Ω down, HB1 first


@pytest.mark.parametrize("vary", ["wob", "torque"])
@pytest.mark.parametrize("omega_max", [math.inf, -1.0, 0.0, math.nan])
def test_an_omega_max_not_finite_and_positive_is_refused_by_name(vary, omega_max):
    """omega_max is "a finite number > 0": inf was taken as 'up to where W_ob reaches 0'."""
    p = pydrill.preset(dof=2)
    kw = {"torque": 8.1} if vary == "wob" else {"wob": 100.0}
    with pytest.raises(ValueError, match=r"omega_max = .*finite omega_max > 0"):
        branch(p, vary=vary, omega_max=omega_max, **kw)


def test_the_varied_parameter_is_refused_by_name_when_given():
    p = pydrill.preset(dof=2)
    with pytest.raises(ValueError, match=r"wob = 100\.0 is not allowed with vary = 'wob'"):
        branch(p, vary="wob", torque=8.1, wob=100.0)
    with pytest.raises(ValueError, match=r"torque = 8\.1 is not allowed with vary = 'torque'"):
        branch(p, vary="torque", torque=8.1, wob=100.0)


def test_an_omega_max_whose_steady_torque_passes_max_load_is_refused():
    """vary="torque": u(omega_max) = (c_r + c_b) omega_max + W_ob R_b μ_b is at most MAX_LOAD
    (1e15 N·m), as in simulate; 10 % either side of the limit, worked out by hand."""
    p = pydrill.preset(dof=4)
    c = p.top_damping + p.bit_damping
    limit = (1e15 - 100.0 * p.bit_radius * p.mu_coulomb) / c  # μ_b = μ_c that far out
    b = branch(p, vary="torque", wob=100.0, omega_max=0.9 * limit, samples=10)
    assert b.torque[-1] == pytest.approx(0.9e15, rel=1e-6)
    with pytest.raises(ValueError, match=r"omega_max = .*beyond MAX_LOAD"):
        branch(p, vary="torque", wob=100.0, omega_max=1.1 * limit, samples=10)
