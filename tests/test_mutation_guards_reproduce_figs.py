"""Mutation guards for ``pydrill reproduce``'s simulations and figures of Section 3 (the paper's
Figs. 4, 5, 7, 8, 9): reproduce_sims.py, reproduce_figures.py, reproduce_figures_sliding.py.

Each test runs ``pydrill.simulate`` / ``stability`` itself with the parameters the paper gives
for that figure (laboratory string, Eq. 14; W_ob and u from the caption) and compares what the
reproduction computed and drew (the matplotlib artists, Agg, nothing saved) with those runs and
with hand computations: T_s = μ_sb W_ob R_b = 0.08 W_ob N·m, the sliding strip's edges
θ = (±T_s − c ω)/k (Eq. 22), the quasi-equilibrium u/k (Eq. 30).
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from scipy.optimize import brentq

import pydrill
from pydrill import reproduce_figures as rf
from pydrill import reproduce_figures_sliding as rfs
from pydrill import reproduce_sims as rs
from pydrill.stability import stability

matplotlib.use("Agg")

K, C = 0.073, 0.0001  # collar-bit link of Eq. (14): k_tb (N·m/rad), c_tb (N·m·s/rad)
P4 = pydrill.preset("reduced-scale", dof=4)  # the paper's n = 8
P2 = pydrill.preset("reduced-scale", dof=2)  # the paper's n = 4


def _sim(p, wob, torque, **kw):
    return pydrill.simulate(p, wob=wob, torque=torque, t_end=300.0, **kw)


@pytest.fixture(scope="module")
def sims():
    """The reproduction's numbers and runs of each figure, and the figures drawn from them
    (``save`` replaced so that the figures stay open and nothing is written)."""
    out = {
        "fig04": rs.fig4(),
        "fig05": rs.fig5(),
        "fig07": rs.fig7(),
        "fig09": rs.fig9(),
    }
    out["fig08"] = rs.fig8()  # its own run, not Fig. 4's
    figs = {}
    saved = rf.save, rfs.save
    rf.save = rfs.save = lambda fig, path: figs.setdefault(path.stem, fig)
    try:
        for name, draw in (("fig04", rf.fig4), ("fig05", rf.fig5), ("fig07", rfs.fig7)):
            draw(_Out(), *out[name])
        rfs.fig8(_Out(), *out["fig08"])
        rfs.fig9(_Out(), *out["fig09"])
    finally:
        rf.save, rfs.save = saved
    yield out, figs
    import matplotlib.pyplot as plt

    for fig in figs.values():
        plt.close(fig)


class _Out:
    """A stand-in output directory: ``out / name`` gives something with ``.stem``."""

    def __truediv__(self, name):
        from pathlib import PurePath

        return PurePath(name)


# --- reproduce_sims.py: the paper's parameters per figure -----------------------------------------


def test_fig4_runs_are_the_papers_n8_w100_u83_from_rest(sims):
    n, runs = sims[0]["fig04"]
    exact = _sim(P4, 100.0, 8.3, n_out=6001)
    assert np.array_equal(runs["exact"].states, exact.states)
    karnopp = _sim(P4, 100.0, 8.3, n_out=6001, friction="karnopp")
    assert np.array_equal(runs["karnopp"].states, karnopp.states)
    near = _sim(P4, 100.0, 8.3, n_out=2, initial="equilibrium")
    assert n["from_equilibrium"]["bit_mean"] == near.summary.bit_mean
    assert n["from_equilibrium"]["regime"] == near.summary.regime
    # Ω of the steady state from u = (c_r + c_b) Ω + W_ob R_b μ_b(Ω), solved by hand.
    omega = brentq(lambda w: 0.19 * w + 10.0 * (0.5 + 0.3 * math.exp(-0.9 * w)) - 8.3, 1e-6, 100)
    assert n["steady_state"]["omega"] == pytest.approx(omega, rel=1e-9)


def test_fig8_visits_are_the_first_three_of_the_w100_run(sims):
    n, runs = sims[0]["fig08"]
    run = _sim(P4, 100.0, 8.3, n_out=6001)
    assert np.array_equal(runs["run"].states, run.states)
    intervals = run.stick_intervals()[:3]
    assert [(v["t_in"], v["t_out"]) for v in n["visits"]] == intervals
    for v, (a, b) in zip(n["visits"], intervals, strict=True):
        # φ̄_b: the bit angle held while stuck, read here between the two ends.
        held = (run.t > a) & (run.t < b)
        assert np.ptp(run.bit_angle[held]) < 1e-6
        assert v["phi_b"] == pytest.approx(run.bit_angle[held].mean(), abs=1e-6)
    assert n["static_torque"] == pytest.approx(0.08 * 100.0)
    for w, frac in n["stuck_fraction_by_wob"].items():
        assert frac == _sim(P4, float(w), 8.3, n_out=2).summary.stuck_fraction


def test_regime_interval_edges_are_where_the_regime_changes():
    """ε⁻'s edge by bisection: just below it the bit drills steadily, just above it sticks
    and slips (u = 8.1 N·m, n = 4), each judged by a run of its own."""
    iv = rs.regime_interval(P2, 8.1, 100.0, step=10.0)
    lo = iv["lower"]
    assert _sim(P2, lo - 0.1, 8.1, n_out=2).regime == "steady"
    assert _sim(P2, lo + 0.1, 8.1, n_out=2).regime == "stick-slip"


def test_fig5_is_the_papers_schedule_of_w_ob_with_the_state_carried_over(sims):
    n, runs = sims[0]["fig05"]
    wobs = [90.0, 100.0, 110.0, 120.0, 130.0, 140.0, 150.0]  # "W_ob from 90 N to 150 N"
    assert [s["wob"] for s in n["schedule"]] == wobs
    state, t0 = "rest", 0.0
    for (start, w, r), s in zip(runs["segments"], n["schedule"], strict=True):
        own = pydrill.simulate(P2, wob=w, torque=8.1, t_end=100.0, initial=state, n_out=2001)
        assert (start, s["t_start"]) == (t0, t0)
        assert np.array_equal(r.states, own.states)
        state, t0 = own.states[-1], t0 + 100.0
    for w in wobs:
        assert runs["orbits"][w].summary == _sim(P2, w, 8.1, n_out=6001).summary
    assert n["quasi_equilibrium_twist"] == pytest.approx(8.1 / K)  # u/k (Eq. 30)


def test_fig7_loads_a_steadily_drilling_string_to_160_n(sims):
    n, runs = sims[0]["fig07"]
    start = _sim(P4, 100.0, 8.3, n_out=2, initial="equilibrium").states[0]
    (eq,) = stability(P4, 100.0, torque=8.3)
    assert n["start_omega"] == pytest.approx(eq.omega, rel=1e-12)
    loaded = _sim(P4, 160.0, 8.3, n_out=6001, initial=start)
    assert np.array_equal(runs["loaded"].states, loaded.states)
    first = next(s for s in loaded.switches if s.kind == "stick")
    assert n["t_in"] == first.t and n["entries"] == 1
    assert n["rest"]["bit_max"] == 0.0  # from rest at 160 N the bit never moves


def test_fig9_is_the_w40_run_and_its_settling_time_by_hand(sims):
    n, runs = sims[0]["fig09"]
    run = _sim(P4, 40.0, 8.3, n_out=6001)
    assert np.array_equal(runs["run"].states, run.states)
    slips = [s.t for s in run.switches if s.kind == "slip"]
    assert n["first_slip"] == slips[0]
    # Within 1 % of Ω: every element, after the last sample at which any was farther.
    far = [
        i
        for i in range(len(run.t))
        if any(abs(w - n["omega"]) > 0.01 * n["omega"] for w in run.omega[i])
    ]
    assert n["settled_1pct"] == run.t[far[-1] + 1]


# --- Fig. 4 and Fig. 5 as drawn ------------------------------------------------------------------


def test_fig4_draws_each_elements_angle_and_velocity_with_the_papers_markers(sims):
    fig = sims[1]["fig04_stick_slip"]
    ax_a, ax_b = fig.axes[:2]
    run = _sim(P4, 100.0, 8.3, n_out=6001)
    keep = run.t <= 100.0
    for ax, data in ((ax_a, run.angles), (ax_b, run.omega)):
        lines = [ln for ln in ax.get_lines() if ln.get_linestyle() != "None"]
        assert len(lines) == 4  # top, pipe, collars, bit (the paper's order)
        for ln, k in zip(lines, (0, 1, 2, 3), strict=True):
            assert np.array_equal(ln.get_xdata(), run.t[keep])
            assert np.array_equal(ln.get_ydata(), data[keep, k])
        (ins,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
        (outs,) = [ln for ln in ax.get_lines() if ln.get_marker() == "D"]
        # x_in at each stick (and at t = 0: the bit starts stuck), x_out at each slip, t ≤ 100 s.
        sticks = [0.0] + [s.t for s in run.switches if s.kind == "stick" and s.t <= 100]
        slips = [s.t for s in run.switches if s.kind == "slip" and s.t <= 100]
        dt = run.t[1] - run.t[0]
        for line, times in ((ins, sticks), (outs, slips)):
            assert np.allclose(line.get_xdata(), times, atol=dt)
            bit = data[:, -1]
            assert np.allclose(line.get_ydata(), np.interp(line.get_xdata(), run.t, bit))
    assert np.allclose(ins.get_ydata(), 0.0, atol=1e-6)  # velocity markers: the bit at rest
    right = [p.get_x() + p.get_width() for p in ax_a.patches]  # the shaded stuck spans
    assert right == pytest.approx([min(b, 100.0) for a, b in run.stick_intervals() if a < 100.0])


def _lines3d(ax):
    return [
        ln for ln in ax.get_lines() if ln.get_linestyle() != "None" and len(ln.get_data_3d()[0]) > 1
    ]


def test_fig5_attractors_are_the_last_40_s_in_the_papers_coordinates(sims):
    fig = sims[1]["fig05_wob_steps"]
    ax3, ax_b = fig.axes[0], fig.axes[1]
    orbits = [ln for ln in _lines3d(ax3) if ln.get_label().startswith("$W_{ob}$ = ")]
    assert len(orbits) == 7
    for ln, w in zip(orbits, (90, 100, 110, 120, 130, 140, 150), strict=True):
        r = _sim(P2, float(w), 8.1, n_out=6001)
        keep = r.t >= 260.0
        x, y, z = ln.get_data_3d()  # (φ_r − φ_b, φ̇_r, φ̇_b)
        assert np.array_equal(x, r.twist[keep, 0]) and np.array_equal(y, r.omega[keep, 0])
        assert np.array_equal(z, r.omega[keep, 1])
    (star,) = [ln for ln in ax3.get_lines() if ln.get_marker() == "*"]
    assert [float(np.ravel(a)[0]) for a in star.get_data_3d()] == pytest.approx([8.1 / K, 0, 0])
    # Markers: the switches of each orbit's last 40 s, counted by hand.
    count = 0
    for w in (90, 100, 110, 120, 130, 140, 150):
        r = _sim(P2, float(w), 8.1, n_out=6001)
        count += sum(1 for s in r.switches if s.t >= 260.0 and s.kind in ("stick", "slip"))
    marks = [ln for ln in ax3.get_lines() if ln.get_marker() in ("o", "D")]
    assert sum(len(ln.get_data_3d()[0]) for ln in marks) == count
    # (b): time runs on, 100 s per W_ob, the bit solid and the top dashed.
    bit = [ln for ln in ax_b.get_lines() if ln.get_color() == rf.BIT and len(ln.get_xdata()) > 2]
    top = [ln for ln in ax_b.get_lines() if ln.get_color() == rf.TOP and len(ln.get_xdata()) > 2]
    assert len(bit) == len(top) == 7
    state = "rest"
    for k, (lb, lt) in enumerate(zip(bit, top, strict=True)):
        r = pydrill.simulate(
            P2, wob=90.0 + 10 * k, torque=8.1, t_end=100.0, initial=state, n_out=2001
        )
        state = r.states[-1]
        assert np.array_equal(lb.get_xdata(), r.t + 100.0 * k)
        assert np.array_equal(lb.get_ydata(), r.omega[:, 1])
        assert np.array_equal(lt.get_ydata(), r.omega[:, 0])


# --- Figs. 7, 8, 9 as drawn: the sliding region of Eq. (22) --------------------------------------


def _strip(ax):
    """The corners (θ, ω) of the shaded Σ̃ and its solid (∂Σ̃⁺) and dashed (∂Σ̃⁻) edges."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    (poly,) = [c for c in ax.collections if isinstance(c, Poly3DCollection)]
    edges = [ln for ln in ax.get_lines() if ln.get_color() == "#b9770e"]
    solid = [ln.get_data_3d() for ln in edges if ln.get_linestyle() == "-"]
    dashed = [ln.get_data_3d() for ln in edges if ln.get_linestyle() == "--"]
    return np.asarray(poly._faces)[0][:, :2], solid, dashed  # (θ, ω, 0) per corner


def _check_strip(ax, wob):
    ts = 0.08 * wob  # μ_sb W_ob R_b
    corners, (plus,), (minus,) = _strip(ax)
    for theta, omega in corners:  # every corner on k θ + c ω = ±T_s
        assert min(abs(K * theta + C * omega - ts), abs(K * theta + C * omega + ts)) < 1e-9
    assert np.allclose(K * plus[0] + C * plus[1], ts)  # ∂Σ̃⁺ solid
    assert np.allclose(K * minus[0] + C * minus[1], -ts)  # ∂Σ̃⁻ dashed
    assert np.allclose(plus[2], 0) and np.allclose(minus[2], 0)  # on the plane ω_b = 0


def _loaded():
    start = _sim(P4, 100.0, 8.3, n_out=2, initial="equilibrium").states[0]
    return _sim(P4, 160.0, 8.3, n_out=6001, initial=start)


def test_fig7_draws_the_trajectory_and_the_w160_strip_in_the_papers_coordinates(sims):
    fig = sims[1]["fig07_stuck"]
    ax3, ax_b = fig.axes[:2]
    r = _loaded()
    (traj,) = [ln for ln in ax3.get_lines() if ln.get_label() == "trajectory"]
    x, y, z = traj.get_data_3d()  # (φ_l − φ_b, φ̇_l, φ̇_b)
    assert np.array_equal(x, r.twist[:, -1]) and np.array_equal(y, r.omega[:, 2])
    assert np.array_equal(z, r.omega[:, 3])
    _check_strip(ax3, 160.0)
    first = next(s for s in r.switches if s.kind == "stick")
    (x_in,) = [ln for ln in ax3.get_lines() if ln.get_marker() == "o"]
    xi, yi, zi = (float(np.ravel(a)[0]) for a in x_in.get_data_3d())
    j = int(np.searchsorted(r.t, first.t))  # x_in: at the samples either side of the stick
    lo, hi = sorted(r.twist[j - 1 : j + 1, -1])
    assert lo <= xi <= hi and zi == 0
    assert min(r.omega[j - 1 : j + 1, 2]) <= yi <= max(r.omega[j - 1 : j + 1, 2])
    (star,) = [ln for ln in ax3.get_lines() if ln.get_marker() == "*"]
    assert float(np.ravel(star.get_data_3d()[0])[0]) == pytest.approx(8.3 / K)
    # (b): T_e against time in seconds up to 60 s; T_s = 0.08·160 = 12.8 and u = 8.3 N·m.
    (te,) = [ln for ln in ax_b.get_lines() if len(ln.get_xdata()) > 2]
    keep = r.t <= 60
    assert np.array_equal(te.get_xdata(), r.t[keep])
    assert np.allclose(te.get_ydata(), r.reaction_torque[keep])
    levels = sorted(float(ln.get_ydata()[0]) for ln in ax_b.get_lines() if len(ln.get_ydata()) == 2)
    assert levels == pytest.approx([8.3, 12.8])


def test_fig8_each_visit_on_its_own_strip_shifted_by_the_held_bit_angle(sims):
    n = sims[0]["fig08"][0]
    fig = sims[1]["fig08_sliding_visits"]
    ax, ax3 = fig.axes[:2]
    run = _sim(P4, 100.0, 8.3, n_out=6001)
    phi = run.angles
    ts = 0.08 * 100.0
    for i, (a, b) in enumerate(run.stick_intervals()[:3]):
        held = (run.t >= a) & (run.t <= b)
        phi_b = run.bit_angle[held].mean()
        color = ["#1f618d", "#b03a2e", "#7d3c98"][i]
        mine = [ln for ln in ax.get_lines() if ln.get_color() == color]
        (plus,) = [ln for ln in mine if ln.get_linestyle() == "-" and ln.get_linewidth() == 1]
        (minus,) = [ln for ln in mine if ln.get_linestyle() == "--"]
        # k (φ_l − φ̄_b) + c φ̇_l = ±T_s: ∂Σ̃_i⁺ solid, ∂Σ̃_i⁻ dashed (Eq. 22 on the held bit).
        assert np.allclose(K * (plus.get_xdata() - phi_b) + C * plus.get_ydata(), ts, atol=1e-6)
        assert np.allclose(K * (minus.get_xdata() - phi_b) + C * minus.get_ydata(), -ts, atol=1e-6)
        (visit,) = [ln for ln in mine if ln.get_linewidth() == 1.6]
        assert np.array_equal(visit.get_xdata(), phi[held, 2])  # φ_l, not φ_b
        assert np.array_equal(visit.get_ydata(), run.omega[held, 2])
        (v3,) = [ln for ln in ax3.get_lines() if ln.get_color() == color]
        assert np.array_equal(v3.get_data_3d()[2], phi[held, 3])  # (b): z is φ_b
    stars = [ln for ln in ax.get_lines() if ln.get_marker() == "*" and len(ln.get_xdata())]
    assert [float(np.ravel(s.get_xdata())[0]) for s in stars] == pytest.approx(
        [v["phi_b"] + 8.3 / K for v in n["visits"]]
    )
    (grey,) = [ln for ln in ax3.get_lines() if ln.get_label() == "slipping"]
    t_end = run.stick_intervals()[2][1] + 2  # up to the third visit's end
    assert len(grey.get_data_3d()[0]) == int(np.sum(run.t <= t_end))


def test_fig9_draws_velocities_and_the_w40_strip(sims):
    fig = sims[1]["fig09_steady"]
    ax, ax3 = fig.axes[:2]
    r = _sim(P4, 40.0, 8.3, n_out=6001)
    curves = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
    assert len(curves) == 4
    for ln, k in zip(curves, range(4), strict=True):
        assert np.array_equal(ln.get_ydata(), r.omega[:, k])
    omega = brentq(lambda w: 0.19 * w + 4.0 * (0.5 + 0.3 * math.exp(-0.9 * w)) - 8.3, 1, 100)
    (steady,) = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == 2]
    assert steady.get_ydata() == pytest.approx([omega, omega])
    _check_strip(ax3, 40.0)
    traj = max(_lines3d(ax3), key=lambda ln: len(ln.get_data_3d()[0]))
    x, y, z = traj.get_data_3d()
    assert np.array_equal(x, r.twist[:, -1]) and np.array_equal(y, r.omega[:, 2])
    assert np.array_equal(z, r.omega[:, 3])
    (eq,) = [ln for ln in ax3.get_lines() if ln.get_marker() == "o"]
    point = [float(np.ravel(a)[0]) for a in eq.get_data_3d()]
    assert point == pytest.approx([r.twist[-1, -1], omega, omega], rel=1e-4)
