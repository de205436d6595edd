"""The simulator against the paper's stated behaviour, analytic results and invariants."""

import numpy as np
import pytest

import pydrill


def test_paper_fig4_stick_slip(paper_dof4):
    r = paper_dof4[100.0]
    s = r.summary
    assert s.regime == "stick-slip"
    assert s.stick_events >= 5
    assert 0.3 < s.stuck_fraction < 0.95
    # The bit spins at several times the surface speed between sticks (paper Section 1:
    # "up to six times the rotary speed measured at the surface").
    assert 3.0 < s.bit_top_ratio < 7.0
    assert s.bit_min == 0.0
    # The cycle of Fig. 4 (and of the reproduce report): 17.5 s, so 8 onsets in [150, 300] s.
    assert s.period == pytest.approx(17.54, abs=0.01)
    # Counted in the judged window only, as the switches list says independently.
    onsets = [w.t for w in r.switches if w.kind == "stick" and w.t >= s.window_start]
    assert s.stick_events == len(onsets) == 8


def test_paper_fig7_stuck(paper_dof4):
    r = paper_dof4[160.0]
    assert r.summary.regime == "stuck"
    assert r.summary.stuck_fraction == 1.0
    assert r.switches == ()  # never leaves the initial stick: u < T_s = 12.8 N·m
    assert np.all(r.bit_velocity == 0.0)


def test_paper_fig9_steady_converges_to_analytic_omega():
    p = pydrill.preset("reduced-scale", dof=4)
    (omega,) = pydrill.equilibrium_velocities(p, 40.0, 8.3)
    # From rest the slowest mode decays over a few hundred seconds; 1000 s is enough
    # for 1e-6 (the bound) everywhere over the last 100 s.
    r = pydrill.simulate(p, wob=40.0, torque=8.3, t_end=1000.0, n_out=10001)
    assert r.regime == "steady"
    tail = r.t >= 900.0
    rel = np.abs(r.bit_velocity[tail] - omega) / omega
    assert rel.max() < 1e-6
    # Every element turns at Ω and every spring carries h(Ω) = u − c_r Ω (the pipe modes,
    # damped by c_t = 1e-4 only, still ring at the 1e-6 level).
    h = 8.3 - p.top_damping * omega
    np.testing.assert_allclose(r.omega[-1], omega, rtol=1e-5)
    np.testing.assert_allclose(r.twist[-1] * np.array(p.stiffnesses), h, rtol=1e-5)


def test_dof2_stick_slip_gives_way_to_stuck_bit():
    """Paper Fig. 5: dof 2, u = 8.1 N·m, W_ob from 90 to 150 N. The bit is permanently stuck
    beyond W* + ε⁺ with W* = u / (μ_s R_b) = 101.25 N (Eq. 38), stick-slip below."""
    p = pydrill.preset("reduced-scale", dof=2)

    def regime(w):
        return pydrill.simulate(p, wob=w, torque=8.1, t_end=300.0, n_out=301).regime

    wobs = np.arange(90.0, 151.0, 10.0)
    regimes = [regime(w) for w in wobs]
    assert set(regimes) == {"stick-slip", "stuck"}
    first_stuck = regimes.index("stuck")
    assert all(r == "stick-slip" for r in regimes[:first_stuck])
    assert all(r == "stuck" for r in regimes[first_stuck:])
    lo, hi = wobs[first_stuck - 1], wobs[first_stuck]
    while hi - lo > 0.5:  # bisect the transition
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if regime(mid) == "stick-slip" else (lo, mid)
    w_star = 8.1 / (0.8 * 0.1)
    # ε⁺ > 0: the string's momentum carries T_e past T_s although u < T_s.
    assert w_star < lo < 150.0
    # The stick-slip orbit grows with W_ob (paper: a different periodic orbit for each W_ob).
    periods = [
        pydrill.simulate(p, wob=w, torque=8.1, t_end=300.0, n_out=301).summary.period
        for w in (70.0, 90.0, 100.0)
    ]
    assert periods[0] < periods[1] < periods[2]


@pytest.mark.parametrize("wob", [100.0, 160.0, 40.0])
def test_exact_and_karnopp_friction_agree(paper_dof4, wob):
    exact = paper_dof4[wob]
    karnopp = pydrill.simulate(wob=wob, torque=8.3, dof=4, t_end=300.0, friction="karnopp")
    assert karnopp.regime == exact.regime
    if exact.summary.period is not None:
        assert karnopp.summary.period == pytest.approx(exact.summary.period, rel=0.01)
        assert karnopp.summary.stick_events == exact.summary.stick_events


def test_energy_balance_over_stick_slip(paper_dof4):
    r = paper_dof4[100.0]
    work = r.work_input[-1]
    out = r.viscous_loss[-1] + r.friction_loss[-1] + (r.energy[-1] - r.energy[0])
    assert abs(work - out) / work < 1e-6
    # Along the way too, and the ledger's parts are what they claim to be.
    balance = r.viscous_loss + r.friction_loss + r.energy - r.energy[0] - r.work_input
    assert np.max(np.abs(balance)) < 1e-6 * work
    assert np.all(np.diff(r.viscous_loss) >= -1e-9)
    assert np.all(np.diff(r.friction_loss) >= -1e-9)


def test_in_stick_bit_is_exactly_still_and_torque_within_static_limit(paper_dof4):
    r = paper_dof4[100.0]
    stick = np.array(r.modes) == "stick"
    assert stick.sum() > 100
    assert np.all(r.bit_velocity[stick] == 0.0)
    ts = r.summary.static_torque
    assert np.all(np.abs(r.reaction_torque[stick]) <= ts * (1 + 1e-9))
    # Outside stick the bit turns forward here.
    assert np.all(r.bit_velocity[~stick] >= 0.0)


def test_every_switch_sits_on_its_root(paper_dof4):
    r = paper_dof4[100.0]
    ts = r.summary.static_torque
    assert len(r.switches) >= 10
    for s in r.switches:
        if s.kind == "stick":  # root ω_b = 0
            assert abs(s.root_residual) < 1e-8
            assert abs(s.reaction_torque) <= ts
        else:  # root |T_e| = T_s
            assert s.kind == "slip"
            assert abs(s.root_residual) < 1e-8 * ts
            assert s.reaction_torque == pytest.approx(ts, rel=1e-9)
    kinds = [s.kind for s in r.switches]
    assert kinds[::2] == ["slip"] * len(kinds[::2])  # stick and slip alternate
    assert kinds[1::2] == ["stick"] * len(kinds[1::2])


def test_outputs_are_dense_at_requested_times():
    t_out = np.linspace(0.0, 50.0, 7)
    r = pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=50.0, t_out=t_out)
    np.testing.assert_array_equal(r.t, t_out)
    assert r.states.shape == (7, 7)
    # Angles recovered from twists: φ_0 − φ_b is the sum of the twists.
    np.testing.assert_allclose(r.angles[:, 0] - r.angles[:, -1], r.twist.sum(axis=1))


def test_equilibrium_start_stays_put_when_stable():
    p = pydrill.preset("reduced-scale", dof=4)
    r = pydrill.simulate(p, wob=40.0, torque=8.3, initial="equilibrium", t_end=200.0)
    (omega,) = r.summary.omega_equilibrium
    assert r.regime == "steady"
    assert r.bit_velocity[0] == pytest.approx(omega * 1.001)  # the stated perturbation
    assert abs(r.bit_velocity[-1] - omega) < 1e-5 * omega


def test_equilibrium_start_refused_without_steady_state():
    with pytest.raises(ValueError, match="no steady rotation"):
        pydrill.simulate(wob=160.0, torque=8.3, dof=4, initial="equilibrium")


def test_user_state_start_and_four_integrators_agree():
    p = pydrill.preset("reduced-scale", dof=3)
    y0 = [1.0, 0.5, 1.0, 0.5, 1.0]
    runs = {
        m: pydrill.simulate(p, wob=100.0, torque=8.3, initial=y0, t_end=60.0, method=m)
        for m in ("adams", "bdf", "erk", "dop853")
    }
    for m, r in runs.items():
        assert r.stats.method == m
        np.testing.assert_allclose(r.states[0], y0)
    assert runs["bdf"].stats.jac_evals > 0 and runs["adams"].stats.jac_evals == 0
    # Four different integrators (multistep implicit, multistep explicit, two one-step
    # explicit with different rootfinders: SUNDIALS' and ours), one answer: same switch
    # sequence, same trajectory to the tolerance the switch times carry forward.
    a = runs["adams"]
    for m in ("bdf", "erk", "dop853"):
        r = runs[m]
        np.testing.assert_allclose(r.states, a.states, atol=1e-4 * np.abs(a.states).max())
        assert [s.kind for s in r.switches] == [s.kind for s in a.switches]
        np.testing.assert_allclose([s.t for s in r.switches], [s.t for s in a.switches], atol=1e-4)
        assert r.energy_balance_error() < 1e-6
    with pytest.raises(ValueError, match="2\\*dof-1 = 5"):
        pydrill.simulate(p, wob=100.0, torque=8.3, initial=[0.0, 1.0])


def test_auto_method_reports_its_choice():
    r = pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=10.0)
    assert r.stats.method == "dop853"
    assert "non-stiff" in r.stats.method_reason
    # Collars 10^4 times stiffer and 5·10^4 times more damped than the pipe: fast modes
    # that die 10^5 times faster than the string winds up. BDF steps over them.
    stiff = pydrill.preset(
        "reduced-scale", dof=4, stiffnesses=[0.073, 1000.0, 1000.0], dampings=[1e-4, 50.0, 50.0]
    )
    r = pydrill.simulate(stiff, wob=100.0, torque=8.3, t_end=10.0)
    assert r.stats.method == "bdf"
    assert r.stats.stiffness_ratio > 1e4


def test_five_hundred_pipe_string_sticks_and_slips():
    """500 pipes: the dof-4 string's pipe section refined into 500 elements (same total
    compliance and inertia), so the stick-slip happens on the same time scale while the
    element modes are stiff: BDF with the banded chain solver."""
    n = 500
    inertias = [0.518] + [0.025 / n] * n + [0.0318, 0.0318]
    stiffnesses = [0.073 * (n + 1)] * (n + 1) + [0.073]
    dampings = [1e-4 * (n + 1)] * (n + 1) + [1e-4]
    r = pydrill.simulate(
        wob=100.0,
        torque=8.3,
        inertias=inertias,
        stiffnesses=stiffnesses,
        dampings=dampings,
        t_end=80.0,
        n_out=801,
    )
    assert r.dof == 503
    assert r.stats.method == "bdf"
    assert r.regime == "stick-slip"
    assert r.summary.stick_events >= 2
    assert r.energy_balance_error() < 1e-6


@pytest.mark.parametrize(
    ("wob", "initial", "dof", "friction"),
    [
        (105.0, "rest", 4, "exact"),  # stick-slip: 0.2 % low from the output samples
        (100.0, "rest", 13, "exact"),
        (100.0, "rest", 4, "karnopp"),
        (40.0, "rest", 4, "exact"),  # steady: a small swing, both extremes smooth
    ],
)
def test_velocity_extremes_are_the_motions_whatever_the_sampling(wob, initial, dof, friction):
    # Independent reference: the same run sampled every 0.5 ms, whose largest sample is
    # within 1e-8 of the peak. bit_max used to be the largest of n_out samples (and of the
    # integrator's steps), 0.2 % low at the default n_out.
    kw = {"wob": wob, "torque": 8.3, "t_end": 300.0, "initial": initial, "dof": dof}
    dense = pydrill.simulate(**kw, friction=friction, n_out=600_001)
    inside = dense.t >= dense.summary.window_start
    for n_out in (3001, 2):  # the default, and a sweep's (the steps alone)
        s = pydrill.simulate(**kw, friction=friction, n_out=n_out).summary
        for got, want in (
            (s.bit_max, dense.bit_velocity[inside].max()),
            (s.bit_min, dense.bit_velocity[inside].min()),
            (s.top_max, dense.top_velocity[inside].max()),
            (s.top_min, dense.top_velocity[inside].min()),
        ):
            assert got == pytest.approx(want, rel=1e-4, abs=1e-9), (n_out, got, want)


@pytest.mark.parametrize(
    ("kw", "state"),
    [
        ({"wob": 100.0, "torque": 8.3, "dof": 4}, None),  # stick-slip (Fig. 4)
        ({"wob": 40.0, "torque": 8.3, "dof": 4}, None),  # steady
        ({"wob": 100.0, "torque": 8.3, "dof": 13}, None),
        ({"wob": 100.0, "torque": 8.3, "dof": 4, "friction": "karnopp"}, None),
        # a start wound backwards: the bit reverses at once, then sticks
        ({"wob": 100.0, "torque": 0.5, "dof": 2}, [0.0, -300.0, 2.0]),
    ],
)
def test_turning_the_other_way_mirrors_the_run_exactly(kw, state):
    """The model is odd in (u, state): friction opposes the slip whichever its sign. So
    u -> -u from the mirrored start must give the mirrored run, switch for switch. Every
    test above turns the bit forward; this is what checks backward slip, a stick reached
    with T_e < 0 and a break-away in the negative direction."""
    t_end = 60.0 if state is not None else 300.0
    fwd = pydrill.simulate(**kw, t_end=t_end, initial=state or "rest")
    back_kw = {**kw, "torque": -kw["torque"]}
    back = pydrill.simulate(
        **back_kw, t_end=t_end, initial=[-x for x in state] if state else "rest"
    )
    np.testing.assert_array_equal(back.t, fwd.t)
    np.testing.assert_allclose(
        back.states, -fwd.states, rtol=0, atol=1e-9 * np.abs(fwd.states).max()
    )
    assert [(w.kind, -w.direction) for w in back.switches] == [
        (w.kind, w.direction) for w in fwd.switches
    ]
    np.testing.assert_allclose([w.t for w in back.switches], [w.t for w in fwd.switches])
    a, b = fwd.summary, back.summary
    assert (b.regime, b.stick_events, b.period) == (a.regime, a.stick_events, a.period)
    assert (b.bit_mean, b.bit_min, b.bit_max) == pytest.approx(
        (-a.bit_mean, -a.bit_max, -a.bit_min)
    )
    assert b.severity == pytest.approx(a.severity) and b.stuck_fraction == a.stuck_fraction
    # The steady states reversed, and the bit's fastest turn against the top drive's mean.
    assert b.omega_equilibrium == pytest.approx([-o for o in reversed(a.omega_equilibrium)])
    assert (b.bit_top_ratio, b.caveat) == (pytest.approx(a.bit_top_ratio), a.caveat)


def test_a_bit_stopped_against_the_rock_reverses_when_the_torque_exceeds_t_s():
    # Wound backwards (T_e = -21.9 N·m, beyond -T_s = -8 N·m) while still turning forward:
    # at ω_b = 0 the rock cannot hold it, the bit must slip backwards, not stick.
    r = pydrill.simulate(wob=100.0, torque=0.5, dof=2, initial=[0.0, -300.0, 2.0], t_end=50.0)
    ts = r.summary.static_torque
    first = r.switches[0]
    assert first.kind == "reversal" and first.direction == -1
    assert first.reaction_torque < -ts
    stick = np.array(r.modes) == "stick"
    assert stick.any() and np.all(r.bit_velocity[stick] == 0.0)
    assert np.all(np.abs(r.reaction_torque[stick]) <= ts * (1 + 1e-9))
    for w in r.switches:
        if w.kind == "stick":
            assert abs(w.reaction_torque) <= ts
    # Held from 1.99 s, T_e climbs past T_s at 2.28 s and falls back below it within one of
    # DOP853's long steps: a crossing seen only at step ends was missed there, and the bit
    # stayed stuck at T_e = 8.19 N·m. Every integrator must see the same switches.
    times = [(w.kind, round(w.t, 6)) for w in r.switches]
    assert ("slip", 2.278) in [(k, round(t, 3)) for k, t in times]
    for method in ("bdf", "adams", "erk"):
        other = pydrill.simulate(
            wob=100.0, torque=0.5, dof=2, initial=[0.0, -300.0, 2.0], t_end=50.0, method=method
        )
        assert [w.kind for w in other.switches] == [w.kind for w in r.switches], method
        np.testing.assert_allclose(
            [w.t for w in other.switches], [w.t for w in r.switches], atol=1e-5
        )


def test_a_hidden_break_away_is_found_by_the_sundials_integrators_too():
    # Found by a random scan (360 runs): ARKODE's ERK at rtol 1e-4 stepped over a T_e that
    # rose past T_s and fell back within one step, and the bit stayed stuck with T_e = 6.28
    # above T_s = 6.14 N·m. CVODES and ARKODE check sign changes only at step ends; the
    # step-end rates now catch a turn inside the step there as in DOP853.
    state = [1.2568154303882233, -19.334971654966253, 107.85961614770281, 67.36139039464413,
             -4.446730188420687, 50.31305141594867, 16.998505692780892]  # fmt: skip
    kw = {"wob": 76.72623689173508, "torque": 2.1761829714613397, "dof": 4, "t_end": 40.0}
    reference = pydrill.simulate(**kw, initial=state, method="dop853", rtol=1e-10, atol=1e-10)
    assert [w.kind for w in reference.switches] == ["stick", "slip", "stick"]
    for method in ("erk", "bdf", "adams"):
        r = pydrill.simulate(**kw, initial=state, method=method, rtol=1e-4, atol=1e-4, n_out=8001)
        assert [w.kind for w in r.switches] == ["stick", "slip", "stick"], method
        np.testing.assert_allclose(
            [w.t for w in r.switches], [w.t for w in reference.switches], atol=2e-3
        )
        stick = np.array(r.modes) == "stick"
        assert np.abs(r.reaction_torque[stick]).max() <= r.summary.static_torque * (1 + 1e-3)


@pytest.mark.parametrize(("wob", "torque"), [(95.0, 9.8), (80.0, 6.8), (180.0, 15.8)])
def test_default_tolerances_see_every_switch_a_tight_run_sees(wob, torque):
    # Points of the paper's (W_ob, u) atlas where DOP853 at the default rtol stepped over a
    # switch that came and went within one step: 12 of 1147 points had their stick-slip
    # period off, at (95 N, 9.8 N·m) 12.37 s instead of 10.00 s. The reference is BDF at
    # rtol 1e-11, a different method with far shorter steps.
    kw = {"wob": wob, "torque": torque, "dof": 4, "t_end": 300.0, "n_out": 2}
    default = pydrill.simulate(**kw)
    tight = pydrill.simulate(**kw, method="bdf", rtol=1e-11, atol=1e-11)
    assert [w.kind for w in default.switches] == [w.kind for w in tight.switches]
    np.testing.assert_allclose(
        [w.t for w in default.switches], [w.t for w in tight.switches], atol=1e-3
    )  # rtol 1e-8 drifts by 1e-4 s over 40 switches; a missed one moves them by seconds
    assert default.summary.period == pytest.approx(tight.summary.period, rel=1e-5)


def _right_half_plane(params, wob, torque):
    """Eigenvalues with Re > 0 at the fastest steady state (where ``initial="equilibrium"``
    starts), by numpy on the Jacobian: brute force."""
    from pydrill import stability

    omega = max(pydrill._core.equilibrium_velocities(params.to_core(), wob, torque))
    delta = float(stability.stribeck_slope(params, wob, omega))
    return int((np.linalg.eigvals(stability.jacobian(params, delta)).real > 0).sum())


@pytest.mark.parametrize("method", ["dop853", "erk"])
def test_a_coarse_tolerance_does_not_pass_an_unstable_state_for_steady(method):
    """At rtol 1e-4 the integrator's ringing may reach a fifth of the mean, and a sustained
    swing below that once counted as steady: the 10-pipe string at W_ob 60 N, u 4 N·m, whose
    steady state is Hopf-unstable, circles it in a 7 % limit cycle and came out "steady".
    Independent judge: the eigenvalues at that steady state. A stable one (the dof-2 string
    at 120 N) stays steady at the same tolerance despite the ringing."""
    ten, two = pydrill.preset(pipes=10), pydrill.preset(dof=2)
    assert _right_half_plane(ten, 60.0, 4.0) > 0
    assert _right_half_plane(two, 120.0, 8.1) == 0
    opts = {"t_end": 600.0, "initial": "equilibrium", "rtol": 1e-4, "method": method}
    s = pydrill.simulate(ten, wob=60.0, torque=4.0, **opts).summary
    assert s.regime == "oscillation"
    assert 0.03 < (s.bit_max - s.bit_min) / s.bit_mean < 0.2  # within the old floor
    assert pydrill.simulate(two, wob=120.0, torque=8.1, **opts).summary.regime == "steady"


def test_a_bit_that_stuck_for_good_late_in_the_window_is_stuck():
    """dof 2, W_ob 113.25 N, u 8.1 N·m < T_s: the bit slips, sticks at about 29 s and stays.
    Judged at 58 s (window 29-58 s) it once came out "stick-slip" from a single stick; the
    run to 300 s, whose window is held throughout, says stuck: so must the short one, with
    the caveat that it stuck late."""
    short = pydrill.simulate(dof=2, wob=113.25, torque=8.1, t_end=58.0).summary
    long = pydrill.simulate(dof=2, wob=113.25, torque=8.1, t_end=300.0).summary
    assert long.regime == "stuck" and long.stuck_fraction == 1.0 and not long.caveat
    assert short.regime == "stuck" and short.caveat == "late-stick"
    assert short.stick_events == 1 and 0.0 < short.stuck_fraction < 1.0


def test_the_metrics_are_the_designs_formulas_on_a_dense_trace():
    """DESIGN §2's metrics recomputed from a dense output of the same run (a sample every
    1.5 ms over the window): severity (max ω_b − min ω_b)/(2 mean ω_b), the ratio
    max ω_b / mean ω_top, and the fraction of the window the bit is held. Samples can only
    miss an extreme by a little, and trapezoid means are as close."""
    r = pydrill.simulate(wob=100, torque=8.3, dof=4, t_end=300.0, n_out=200_001)
    s = r.summary
    assert s.regime == "stick-slip"
    w = (r.t >= s.window_start) & (r.t <= s.window_end)
    t, bit, top = r.t[w], r.bit_velocity[w], r.top_velocity[w]

    def mean(y):  # trapezoids (np.trapezoid needs numpy 2)
        return float(np.sum((y[1:] + y[:-1]) * np.diff(t)) / (2 * (t[-1] - t[0])))

    bit_mean, top_mean = mean(bit), mean(top)
    assert s.bit_mean == pytest.approx(bit_mean, rel=1e-4)
    assert s.bit_max == pytest.approx(bit.max(), rel=1e-4) and s.bit_max >= bit.max()
    assert s.bit_min == bit.min() == 0.0  # held: exactly zero while stuck
    assert s.severity == pytest.approx((bit.max() - bit.min()) / (2 * bit_mean), rel=2e-4)
    assert s.bit_top_ratio == pytest.approx(bit.max() / top_mean, rel=2e-4)
    held = mean((bit == 0.0).astype(float))
    assert s.stuck_fraction == pytest.approx(held, abs=2e-3)
