"""The C++ core at the edges: absurd-but-finite parameters and tolerances refused before a run,
with the parameter and its range named, and the BDF solver's setup count."""

import math
import subprocess
import sys
import time

import pytest

import pydrill
from pydrill import _core


def test_bdf_counts_its_setups_the_times_it_refactored():
    """lin_setups was 0 for BDF since the chain solver replaced CVODES's linear solver (CVODES
    calls no setup for a solver that forms its own matrix). It counts the refactorisations:
    at least one per smooth piece (each restart starts a new step size), at most one per step
    attempt, far fewer than the solves, and none without a linear solver."""
    kw = dict(wob=100.0, torque=8.3, t_end=300.0, dof=12, dampings=[0.05] * 11, n_out=301)
    s = pydrill.simulate(method="bdf", **kw).stats
    assert s.switches >= 4 and s.reinits == s.switches
    assert s.reinits < s.lin_setups <= s.steps + s.err_test_fails + s.nonlin_conv_fails
    assert 2 * s.lin_setups < s.lin_solves <= s.nonlin_iters
    assert s.lin_setups == s.jac_evals  # forming I - gamma*J and factoring it are one step here
    for method in ("adams", "dop853", "erk"):
        assert pydrill.simulate(method=method, **kw).stats.lin_setups == 0


# Absurd-but-finite parameters, refused before a run. Measured before: top_damping = 1e300
# ground through max_steps (2e6 steps to t = 1e-13 s), an inertia of 1e-300 failed at t = 0
# with CVODES's "h = nan", stiffnesses 1e300 with DOP853's "step size fell", bit_damping 1e300
# as "chattering".
@pytest.mark.parametrize(
    ("override", "words"),
    [
        (
            {"top_damping": 1e300},
            "top_damping = 1e+300 is not allowed with inertias[0] = 0.518: the decay rate at "
            "inertia 0, (top_damping + dampings[0]) / inertias[0] = 1.93e+300 /s, must be <= "
            "1e15 /s (no step of a double-precision solver resolves a faster decay; a real "
            "string's are below 1e7 /s: check the units)",
        ),
        (
            {"inertias": [1e-300, 0.025, 0.0318, 0.0318]},
            "inertias[0] = 1e-300 is not allowed with top_damping = 0.18: the decay rate",
        ),
        (
            {"stiffnesses": [1e300, 0.073, 0.073]},
            "stiffnesses[0] = 1e+300 is not allowed with inertias[0] = 0.518: the frequency at "
            "inertia 0, sqrt(stiffnesses[0] / inertias[0]) = 1.39e+150 rad/s, must be <= 1e150",
        ),
        ({"bit_damping": 1e300}, "bit_damping = 1e+300 is not allowed with inertias[3]"),
        ({"dampings": [1e-4, 1e300, 1e-4]}, "dampings[1] = 1e+300 is not allowed with inertias[1]"),
    ],
)
def test_a_rate_a_double_cannot_square_is_refused_by_name(override, words):
    with pytest.raises(ValueError) as err:
        pydrill.simulate(wob=100.0, torque=8.3, t_end=60.0, **override)
    assert str(err.value).startswith(words), str(err.value)
    overflow = "a double overflows at 1.8e308"
    assert (overflow in str(err.value)) == ("the frequency" in str(err.value))


def test_the_rate_limit_is_where_it_says():
    """Just below 1e15 /s (a decay) accepted, just above refused, whichever parameter sets it;
    nothing of the paper's strings (the real one's rates are below 1/s) comes near."""
    for field in ("top_damping", "bit_damping"):
        for factor, ok in ((0.999, True), (1.001, False)):
            p = _core.preset("reduced-scale", 4)
            inertia = p.inertias[0] if field == "top_damping" else p.inertias[-1]
            setattr(p, field, factor * 1e15 * inertia)
            if ok:
                p.validate()
            else:
                with pytest.raises(ValueError, match=f"^{field} = "):
                    p.validate()
    p = _core.preset("reduced-scale", 4)
    p.inertias = [0.518, 0.025, 0.0318, (1e-4 + 0.01) / 0.999e15]  # (c_2 + c_b)/I_3
    p.validate()
    p.inertias = [0.518, 0.025, 0.0318, (1e-4 + 0.01) / 1.001e15]
    with pytest.raises(ValueError, match=r"^inertias\[3\] = "):
        p.validate()
    _core.preset("real-string", 2).validate()


def test_a_decay_too_fast_for_double_precision_is_refused_at_once_and_the_limit_runs_cleanly():
    """A top damping of 1e40 (a units slip) ground 80 s through BDF's 5e7 steps to t = 3e-20 s,
    then advised raising max_steps: BDF's Newton matrix I - gamma*h*J loses its identity part
    once gamma*h*rate nears 1/eps. Now it is refused before any step; and just under the limit,
    1e15 /s, BDF runs the paper's 300 s without one failed Newton iteration."""
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"^top_damping = 1e\+40 is not allowed .* 1e15 /s"):
        pydrill.simulate(wob=60.0, torque=8.3, t_end=10.0, top_damping=1e40)
    assert time.perf_counter() - t0 < 1.0
    inertia = _core.preset("reduced-scale", 4).inertias[0]
    r = pydrill.simulate(wob=60.0, torque=8.3, t_end=300.0, top_damping=0.999e15 * inertia - 1e-4)
    assert r.stats.method == "bdf" and r.stats.nonlin_conv_fails == 0, r.stats
    assert r.stats.steps < 2000, r.stats


CLI = [sys.executable, "-m", "pydrill"]


def test_the_command_line_names_an_absurd_stiffness_on_one_line():
    proc = subprocess.run(
        [*CLI, "simulate", "--wob", "100", "--torque", "8.3", "--stiffnesses", "1e300,0.073,0.073"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert "stiffnesses[0] = 1e+300 is not allowed" in proc.stderr


def _fastest(k0, k1, inertia):
    """The frequency of an inertia between two springs, rad/s: inertia 1's below."""
    return math.sqrt((k0 + k1) / inertia)


@pytest.mark.parametrize(("method", "radius"), [("dop853", 6.8), ("erk", 5.01), ("adams", 3.65)])
def test_a_run_that_cannot_fit_in_max_steps_is_refused_before_it_starts(method, radius):
    """A stiff spring (1e6 N·m/rad on the paper's dof-4 string: 6325 rad/s) holds an explicit
    method's steps below radius/6325 s, so t_end·6325/radius steps at least. A run takes more
    than that (the bound never refuses a run that would fit); a run that would grind (over a
    million state updates) with one step fewer is refused at t = 0, naming the mode, the bound
    and what to change; at the bound it is tried; a small max_steps fails by itself."""
    kw = dict(wob=100.0, torque=8.3, n_out=11, method=method, stiffnesses=[1e6, 0.073, 0.073])
    w = _fastest(1e6, 0.073, 0.025)
    assert pydrill.simulate(**kw, t_end=10.0).stats.steps >= 10.0 * w / radius
    bound = 300.0 * w / radius
    with pytest.raises(pydrill.SolverError) as err:
        pydrill.simulate(**kw, t_end=300.0, max_steps=math.floor(bound) - 1)
    assert err.value.t_reached == 0.0
    message = str(err.value)
    assert f"cannot take method '{method}' to t_end = 300 s (refused before integrating)" in message
    assert "at inertias[1] (frequency >= 6.32e+03 rad/s)" in message
    assert f"needs at least {math.ceil(bound)} steps" in message
    assert message.endswith("; raise max_steps or shorten t_end")
    with pytest.raises(pydrill.SolverError, match="internal steps reached") as err:
        pydrill.simulate(**kw, t_end=300.0, max_steps=math.ceil(bound))
    assert err.value.t_reached > 0.0
    with pytest.raises(pydrill.SolverError, match="internal steps reached") as err:
        pydrill.simulate(**kw, t_end=300.0, max_steps=100)
    assert err.value.t_reached > 0.0


def test_bdf_is_not_held_to_the_explicit_methods_bound():
    """BDF steps over fast modes that have died: its run is tried, and stops at max_steps."""
    with pytest.raises(pydrill.SolverError, match="internal steps reached") as err:
        pydrill.simulate(wob=100.0, torque=8.3, t_end=10.0, method="bdf", max_steps=10)
    assert err.value.t_reached > 0.0


@pytest.mark.parametrize("method", ["auto", "dop853", "bdf", "adams", "erk"])
def test_tolerances_looser_than_the_regimes_allow_are_refused(method):
    """--atol 1e300 was taken (every method then failed or called every run 'stuck'); rtol
    up to 1 was too. Ceilings: rtol 0.01, atol 0.001 (beyond, the paper's cases were misjudged)."""
    kw = dict(wob=100.0, torque=8.3, t_end=2.0, n_out=5, method=method)
    for rtol in (0.0101, 0.5):
        with pytest.raises(ValueError, match=r"need 1e-14 <= rtol <= 0\.01 \("):
            pydrill.simulate(**kw, rtol=rtol)
    for atol in (0.0011, 1.0, 1e300):
        with pytest.raises(ValueError, match=r"need 1e-20 <= atol <= 0\.001 \(rad and rad/s"):
            pydrill.simulate(**kw, atol=atol)
    assert pydrill.simulate(**kw, rtol=0.01, atol=0.001).t[-1] == 2.0


@pytest.mark.parametrize(("dof", "rtol"), [(2, 1e-2), (4, 1e-3), (10, 1e-4)])
def test_dop853_at_a_loose_tolerance_does_not_run_away_at_a_break_away(dof, rtol):
    """Within the tolerances allowed, DOP853's bit velocity reached 1e10 ... 1e11 rad/s in the
    paper's stick-slip (the step of a long stick carried over to the break-away, and the error
    test, scaled by the new state, accepted the runaway). Against the same run at 1e-10."""
    kw = dict(wob=100.0, torque=8.3, dof=dof, method="dop853", n_out=301)
    ref = pydrill.simulate(**kw, rtol=1e-10, atol=1e-10).summary
    s = pydrill.simulate(**kw, rtol=rtol).summary
    assert s.regime == ref.regime == "stick-slip"
    assert s.bit_max < 1.1 * ref.bit_max
