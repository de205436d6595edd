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
