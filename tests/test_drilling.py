"""Drilling ahead with connections: the string grows, the motion carries over."""

from pathlib import Path

import numpy as np
import pytest

import pydrill
from pydrill.drilling import add_stand, drill_ahead
from pydrill.tally import load_tally

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_connection_keeps_velocities_and_top_torque():
    p = load_tally(PAPER).to_params(dof=5)
    rng = np.random.default_rng(3)
    y = rng.normal(size=2 * p.dof - 1)
    k_new = 7.0e4
    z = add_stand(y, p.stiffnesses[0], k_new)
    assert z.size == y.size + 2
    assert z[0] == y[0] and z[2] == y[0]  # the new stand turns with the top drive
    assert k_new * z[1] == pytest.approx(p.stiffnesses[0] * y[1])  # same torque at the top
    np.testing.assert_array_equal(z[3:], y[1:])  # everything below is untouched


def test_drilling_a_few_stands():
    tally = load_tally(PAPER)
    run = drill_ahead(
        tally,
        depth_start=1000.0,
        depth_end=1090.0,
        rop=pydrill.units.parse("90 m/h", "rate"),
        wob=6e4,
        torque=8e3,
        lump=5,
        initial="equilibrium",
    )
    dofs = [c[2] for c in run.connections]
    assert dofs == sorted(dofs) and len(dofs) == len(run.regimes) - 1
    assert np.all(np.diff(run.t) >= 0) and np.all(np.diff(run.depth) >= -1e-9)
    # From the whole-joint string that reaches 1000 m down to the target depth.
    assert run.depth[0] == pytest.approx(tally.at_depth(1000.0).length)
    assert run.depth[-1] == pytest.approx(1090.0)
    # Steady drilling stays steady through the connections: no jump in the bit velocity.
    assert all(r == "steady" for *_, r in run.regimes)
    jumps = np.abs(np.diff(run.bit_velocity))
    assert jumps.max() < 0.05 * np.abs(run.bit_velocity).max()
    with pytest.raises(ValueError, match="rop"):
        drill_ahead(tally, depth_start=1000.0, depth_end=1010.0, rop=0.0, wob=6e4, torque=8e3)


def _energy(p, y):
    """Kinetic energy of the inertias and elastic energy of the springs, twist coordinates."""
    omega, theta = y[0::2], y[1::2]
    return 0.5 * np.dot(p.inertias, omega**2), 0.5 * np.dot(p.stiffnesses, theta**2)


def _equilibrium_state(p, wob, omega):
    """The steady state by hand: every inertia at Ω, every spring carrying h = u − c_r Ω."""
    h = pydrill.equilibrium_torque(p, wob, omega) - p.top_damping * omega
    y = np.empty(2 * p.dof - 1)
    y[0::2] = omega
    y[1::2] = h / np.array(p.stiffnesses)
    return y


def test_connections_carry_the_motion_over():
    """At each connection the new string starts from the old one's final state with the new
    stand inserted: velocities and spring torques continuous, kinetic energy up by exactly the
    new stand's ½ J ω_top², elastic energy of the old springs kept."""
    tally = load_tally(PAPER)
    run = drill_ahead(  # stick-slip: the connections come in the middle of the motion
        tally,
        depth_start=3000.0,
        depth_end=3000.0 + 3 * 45.0,
        rop=0.5,
        wob=1e5,
        torque=1.1e4,
        lump=5,
        initial="rest",
    )
    assert len(run.carried) == len(run.connections) == len(run.strings) - 1 >= 2
    assert all(regime == "stick-slip" for *_, regime in run.regimes)
    for (before, after), old, new in zip(
        run.carried, run.strings[:-1], run.strings[1:], strict=True
    ):
        assert new.dof == old.dof + 1
        j_new = new.inertias[1]
        assert j_new == pytest.approx(5 * tally.sections[0].joint_inertia())
        np.testing.assert_allclose(
            after[0::2], np.insert(before[0::2], 1, before[0]), rtol=1e-12, atol=1e-12
        )
        torque_old = np.array(old.stiffnesses) * before[1::2]
        # A real transient (the string twisted unevenly), not a steady state handed on.
        assert np.ptp(torque_old) > 0.005 * np.max(np.abs(torque_old))
        torque_new = np.array(new.stiffnesses) * after[1::2]
        np.testing.assert_allclose(
            torque_new, np.insert(torque_old, 0, torque_old[0]), rtol=1e-10, atol=1e-9
        )
        ke0, pe0 = _energy(old, before)
        ke1, pe1 = _energy(new, after)
        assert ke1 == pytest.approx(ke0 + 0.5 * j_new * before[0] ** 2, rel=1e-10)
        k_new = new.stiffnesses[0]
        assert pe1 == pytest.approx(pe0 + 0.5 * torque_old[0] ** 2 / k_new, rel=1e-10)


def test_steady_drilling_stays_exactly_steady_through_connections():
    """Started exactly at the steady state, each connection hands the longer string its own
    steady state (every spring carries the same torque h), so the bit never feels it."""
    tally = load_tally(PAPER)
    p0 = tally.at_depth(2000.0).to_params(lump=5)
    wob, omega = 4e4, 120 * 2 * np.pi / 60
    u = pydrill.equilibrium_torque(p0, wob, omega)
    run = drill_ahead(
        tally,
        depth_start=2000.0,
        depth_end=2000.0 + 4 * 45.0,
        rop=0.1,
        wob=wob,
        torque=u,
        lump=5,
        initial=_equilibrium_state(p0, wob, omega),
    )
    assert len(run.connections) >= 3
    assert np.max(np.abs(run.bit_velocity - omega)) < 1e-6 * omega
    assert np.max(np.abs(run.top_velocity - omega)) < 1e-6 * omega
    for (_, after), new in zip(run.carried, run.strings[1:], strict=True):
        np.testing.assert_allclose(after, _equilibrium_state(new, wob, omega), rtol=1e-7)
