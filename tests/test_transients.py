"""Runs whose transient outlasts the judged window are judged by where they are going.

The independent judge is the same run ten times longer (3000 s), whose window lies long
after the transient. The strings are laboratory strings with their dampings changed, found
among random strings whose 300 s judgement a 3000 s run did not confirm (see
``cpp/src/stick_phases.hpp`` and the spinning-up bit in ``cpp/src/summary.cpp``)."""

import dataclasses
import itertools

import pytest

import pydrill


def _string(top_damping: float, bit_damping: float, dof: int = 3) -> pydrill.Params:
    base = pydrill.preset("reduced-scale", dof=dof)
    return dataclasses.replace(base, top_damping=top_damping, bit_damping=bit_damping)


def _phases(result: pydrill.SimulationResult, start: float) -> list[tuple[float, float]]:
    return [(a, b) for a, b in result.stick_intervals() if b > start]


def test_sticks_that_end_in_one_for_good_are_stuck():
    """u = 5.55 N·m < T_s: sticks of ~10 s, then one from 218 s that never ends. Judged at
    300 s it was "stick-slip" (four stick phases in the window); it is stuck, as the 3000 s
    run says with its window held throughout."""
    p = _string(0.017456395378208863, 0.00016020099527506288)
    op = {"wob": 107.07103949603524, "torque": 5.549950473096398}
    run = pydrill.simulate(p, t_end=300.0, **op)
    s = run.summary
    assert abs(op["torque"]) <= s.static_torque
    *before, last = _phases(run, s.window_start)
    assert last[1] == 300.0 and before  # the window saw the cycle, then the last stick
    longest = max(b - a for a, b in before)
    assert 300.0 - last[0] > 2.0 * longest
    assert s.regime == "stuck" and s.caveat == "late-stick"
    assert f"since t = {last[0]:.3g} s" in s.note
    long = pydrill.simulate(p, t_end=3000.0, **op).summary
    assert long.regime == "stuck" and long.stuck_fraction == 1.0 and not long.caveat


def test_sticks_that_stop_say_the_stick_slip_may_have_died_out():
    """The bit sticks every ~20 s, then not at all after 241 s. Judged at 300 s it was
    "stick-slip" without a word; it still is (it stuck in the window), with the caveat that
    the bit has turned freely for over twice its longest slip: the 3000 s run is steady."""
    p = _string(0.0011595087485610014, 0.0007480710677527699)
    op = {"wob": 165.01110294679276, "torque": 9.672541206585555}
    run = pydrill.simulate(p, t_end=300.0, **op)
    s = run.summary
    phases = _phases(run, s.window_start)
    slips = [b[0] - a[1] for a, b in itertools.pairwise(phases)]
    assert len(slips) >= 2 and 300.0 - phases[-1][1] > 2.0 * max(slips)
    assert s.regime == "stick-slip" and s.caveat == "one-break-away"
    assert "the stick-slip may have died out" in s.note
    long = pydrill.simulate(p, t_end=3000.0, **op).summary
    assert long.regime == "steady" and not long.caveat
    assert long.severity < 0.01


@pytest.mark.parametrize(
    ("dampings", "op"),
    [
        # was "oscillation": 545 -> 711 rad/s in the window's halves, on its way to 1898
        (
            (0.0003448748015384755, 0.0010367464962172546),
            (31.73641899967938, 4.209161517567566),
        ),
        # was "oscillation", "growing": 1307 -> 1700 rad/s, to 4193 (the swing grows, no
        # faster than the mean)
        (
            (0.0013348771793190212, 0.00020786479222174015),
            (42.57019216689258, 8.596749829942393),
        ),
    ],
)
def test_a_bit_spinning_up_under_a_swing_is_steady_by_where_it_is_going(dampings, op):
    """Dampings a hundredth to a thousandth of the laboratory's on an 11-DOF string: the bit
    climbs towards a far steady state under a swing that does not grow against its mean.
    Judged at 300 s it was an oscillation (a limit cycle, or one growing away from its
    steady state); it is a transient: at 3000 s the mean is within 3 % of the steady state
    and the swing has shrunk to under a fifth against it. The steady state is stable by its
    eigenvalues."""
    p = _string(*dampings, dof=11)
    wob, torque = op
    (point,) = pydrill.stability.stability(p, wob, torque=torque)
    assert point.spectral_abscissa < 0
    s = pydrill.simulate(p, wob=wob, torque=torque, t_end=300.0).summary
    assert (s.regime, s.caveat) == ("steady", "approaching")
    assert f"steady state at {point.omega:.3g} rad/s, which is linearly stable" in s.note
    long = pydrill.simulate(p, wob=wob, torque=torque, t_end=3000.0).summary
    assert long.regime == "steady"
    assert abs(long.bit_mean - point.omega) < 0.03 * point.omega
    assert long.severity < s.severity / 5


def test_a_swing_dying_out_about_an_unstable_steady_state_is_still_growing():
    """A random 4-DOF string from equilibrium: the stable modes' transient dies out across the
    300 s run's window, and it was judged steady; but its steady state has a pair of
    eigenvalues in the right half-plane (growth 5.8e-4 1/s, e-fold in 1700 s), and the 3000 s
    run shows the swing growing away from it. Judged at 300 s now by the linear analysis: an
    oscillation still growing, as at 3000 s."""
    p = pydrill.Params(
        inertias=(0.2842918141745474, 0.04221102868100544, 0.018195212527569397,
                  0.02915676584842923),
        stiffnesses=(0.20949869143928979, 0.2004939668004729, 0.11620747254886823),
        dampings=(0.0001209076307713312, 3.579170671719983e-05, 2.0955789028174593e-05),
        top_damping=0.4874947561352748,
        bit_damping=0.01548205756643636,
        bit_radius=0.1,
        mu_coulomb=0.3017276203380748,
        mu_static=0.40386714594992146,
        stribeck_decay=1.2606978443991514,
    )  # fmt: skip
    op = {"wob": 159.80296058161363, "torque": 6.683701555661293, "initial": "equilibrium"}
    (point,) = pydrill.stability.stability(p, op["wob"], torque=op["torque"])
    assert point.spectral_abscissa > 0 and not point.stable
    s = pydrill.simulate(p, t_end=300.0, **op).summary
    assert (s.regime, s.caveat) == ("oscillation", "growing")
    assert f"steady state ({point.omega:.3g} rad/s;" in s.note
    assert f"e-fold every {1 / point.spectral_abscissa:.3g} s" in s.note
    assert s.severity < 1e-3  # it was steady by its swing alone
    long = pydrill.simulate(p, t_end=3000.0, **op).summary
    assert (long.regime, long.caveat) == ("oscillation", "growing")
    assert long.severity > 2 * s.severity
