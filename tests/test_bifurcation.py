"""Hopf criticality and bifurcation diagrams, checked against simulation and eigenvalues."""

import json
import subprocess
import sys

import numpy as np
import pytest
from matplotlib.axes._secondary_axes import SecondaryAxis

import pydrill
from pydrill import _core
from pydrill import stability as st
from pydrill.bifurcation import branch


def test_lyapunov_coefficient_matches_the_amplitude_growth_of_a_simulation():
    """At the Hopf point the normal form gives d|z|/dt = Re(c1)|z|³ with Re(c1) = ω·l1; the
    simulator, started on the critical eigenvector, must grow (l1 > 0) at that rate."""
    p = pydrill.preset("real-string")
    hopf = st.critical_deltas(p)[0]
    l1 = _core.first_lyapunov_coefficient(p.to_core(), hopf.delta, hopf.frequency)
    omega = 1.0
    wob = float(hopf.wob(p, omega))
    torque = pydrill.equilibrium_torque(p, wob, omega)
    A = st.jacobian(p, hopf.delta)
    ev, V = np.linalg.eig(A)
    q = V[:, np.argmin(np.abs(ev - 1j * hopf.frequency))]
    q /= np.linalg.norm(q)
    evt, W = np.linalg.eig(A.T)
    adj = W[:, np.argmin(np.abs(evt + 1j * hopf.frequency))]
    adj /= np.conj(np.vdot(adj, q))
    y_eq = np.array(_core.equilibrium_state(p.to_core(), wob, omega))
    y0 = y_eq + 2 * (0.02 * omega / abs(q[-1])) * q.real
    r = pydrill.simulate(
        p, wob=wob, torque=torque, initial=y0, t_end=400.0, n_out=4001, rtol=1e-11, atol=1e-12
    )
    amp = np.abs((r.states - y_eq) @ np.conj(adj))
    growth = -np.polyfit(r.t, 1.0 / amp**2, 1)[0] / 2  # Re(c1)
    assert l1 > 0
    assert growth == pytest.approx(hopf.frequency * l1, rel=0.05)


@pytest.mark.parametrize("pipes", [30, 150])
def test_lyapunov_coefficient_of_long_strings_matches_dense_linear_algebra(pipes):
    """The core solves banded systems in O(n'); here the same normal-form formula (Kuznetsov,
    Eq. 3.20) on numpy's dense eigenvectors and solves, for the first and the last crossing."""
    p = pydrill.preset("reduced-scale", pipes=pipes)
    hopf = [c for c in st.critical_deltas(p) if c.type == "hopf"]
    g = p.stribeck_decay / p.stribeck_velocity
    for c in (hopf[0], hopf[-1]):
        A = st.jacobian(p, c.delta)
        iw = 1j * c.frequency
        ev, V = np.linalg.eig(A)
        q = V[:, np.argmin(np.abs(ev - iw))]
        evt, W = np.linalg.eig(A.T)
        adj = W[:, np.argmin(np.abs(evt + iw))]
        adj /= np.conj(np.vdot(adj, q))  # <p, q> = 1
        beta, kappa = -c.delta * g / p.inertias[-1], c.delta * g**2 / p.inertias[-1]

        def B(x, y, beta=beta):  # the friction acts on the bit's velocity, the last state
            e = np.zeros(len(x), complex)
            e[-1] = beta * x[-1] * y[-1]
            return e

        cqqq = np.zeros(len(q), complex)
        cqqq[-1] = kappa * q[-1] ** 2 * np.conj(q[-1])
        a1 = np.linalg.solve(A, B(q, np.conj(q)))
        a2 = np.linalg.solve(2 * iw * np.eye(len(q)) - A, B(q, q))
        s = np.vdot(adj, cqqq) - 2 * np.vdot(adj, B(q, a1)) + np.vdot(adj, B(np.conj(q), a2))
        dense = s.real / (2 * c.frequency)
        banded = _core.first_lyapunov_coefficient(p.to_core(), c.delta, c.frequency)
        assert banded == pytest.approx(dense, rel=1e-8), (pipes, c.frequency)


def test_branch_special_points_are_exact():
    p = pydrill.preset("reduced-scale", dof=2)
    b = branch(p, vary="wob", torque=8.1)
    crossings = st.critical_deltas(p)
    assert {pt.type for pt in b.points} == {"HB", "LP"}
    for pt in b.points:
        # On the branch: the torque holds Ω at this W_ob.
        assert pydrill.equilibrium_torque(p, pt.wob, pt.omega) == pytest.approx(8.1, rel=1e-12)
        # At a critical slope, to 1e-10 relative.
        assert min(abs(pt.delta - c.delta) / c.delta for c in crossings) < 1e-10
        delta = float(st.stribeck_slope(p, pt.wob, pt.omega))
        assert delta == pytest.approx(pt.delta, rel=1e-10)
        ev = st.eigenvalues(p, delta)
        target = 1j * (pt.frequency or 0.0)
        assert np.min(np.abs(ev - target)) < 1e-7
    (lp,) = [pt for pt in b.points if pt.type == "LP"]
    # The branch folds there: W_ob(Ω) = (u − (c_r + c_b)Ω) / (R_b μ_b(Ω)) is extremal.
    c = p.top_damping + p.bit_damping

    def wob_of(om):
        mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-p.stribeck_decay * om)
        return (8.1 - c * om) / (p.bit_radius * mu)

    h = 1e-5
    assert wob_of(lp.omega) >= max(wob_of(lp.omega - h), wob_of(lp.omega + h))
    # Stability along the branch changes at the special points only.
    changes = np.nonzero(np.diff(b.unstable))[0]
    for i in changes:
        assert any(b.omega[i] <= pt.omega <= b.omega[i + 1] for pt in b.points)


def test_subcritical_hopf_shows_hysteresis():
    """Paper Fig. 5 string (dof 2, u = 8.1 N·m): the Hopf point on the upper branch is
    subcritical, so below it the stable steady state coexists with a stuck bit: starting
    near the steady state it drills on; starting from rest it never gets going."""
    p = pydrill.preset("reduced-scale", dof=2)
    b = branch(p, vary="wob", torque=8.1)
    hb = max((pt for pt in b.points if pt.type == "HB"), key=lambda pt: pt.omega)
    assert hb.criticality == "subcritical"
    wob = 120.0
    assert wob < hb.wob
    (pt,) = [s for s in st.stability(p, wob, torque=8.1) if s.stable]
    near = pydrill.simulate(p, wob=wob, torque=8.1, initial="equilibrium", t_end=600.0)
    rest = pydrill.simulate(p, wob=wob, torque=8.1, initial="rest", t_end=600.0)
    assert near.regime == "steady"
    assert near.bit_velocity[-1] == pytest.approx(pt.omega, rel=1e-4)
    assert rest.regime in ("stuck", "stick-slip")


def test_vary_torque_branch_and_bad_input():
    p = pydrill.preset("reduced-scale", dof=4)
    b = branch(p, vary="torque", wob=100.0)
    assert np.all(np.isclose(b.wob, 100.0))
    (lp,) = [pt for pt in b.points if pt.type == "LP"]
    assert lp.delta == pytest.approx(p.top_damping + p.bit_damping, rel=1e-12)
    with pytest.raises(ValueError, match="torque"):
        branch(p, vary="wob")
    with pytest.raises(ValueError, match="vary"):
        branch(p, vary="depth", wob=1.0)


def test_bifurcation_command_json(tmp_path):
    png = tmp_path / "fig11.png"
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pydrill",
            "bifurcation",
            "--dof",
            "2",
            "--vary",
            "wob",
            "--torque",
            "8.1",
            "--json",
            "--plot",
            str(png),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    assert data["points"]
    for pt in data["points"]:
        assert pt["type"] in ("HB", "LP")
        for key in ("wob", "torque", "omega", "frequency", "lyapunov", "criticality"):
            assert key in pt
        if pt["type"] == "HB":
            assert pt["criticality"] in ("supercritical", "subcritical")
        else:
            assert pt["frequency"] is None and pt["criticality"] is None
    assert len(data["branch"]["omega"]) == len(data["branch"]["wob"])
    assert png.stat().st_size > 20_000
    bad = subprocess.run(
        [sys.executable, "-m", "pydrill", "bifurcation", "--vary", "wob"],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2 and "--torque" in bad.stderr and "Traceback" not in bad.stderr


def test_a_long_strings_diagram_zooms_in_on_its_hopf_points():
    """100 pipes: 101 Hopf points within 1 N·m of torque. The figure draws every one (in an
    inset over their range), counts them by criticality in the legend, and labels only HB1."""
    import matplotlib

    matplotlib.use("Agg")
    from pydrill.plot_analysis import bifurcation_figure

    p = pydrill.preset("reduced-scale", pipes=100)
    b = branch(p, vary="torque", wob=60.0)
    hb = [pt for pt in b.points if pt.type == "HB"]
    sub = sum(pt.criticality == "subcritical" for pt in hb)
    assert len(hb) == 101 and 0 < sub < 101
    fig = bifurcation_figure(p, b)
    (main,) = fig.axes
    # (the other child: the rpm axis on the right)
    (inset,) = [a for a in main.child_axes if not isinstance(a, SecondaryAxis)]
    legend = [t.get_text() for t in main.get_legend().get_texts()]
    assert f"Hopf point, subcritical ({sub})" in legend
    assert f"Hopf point, supercritical ({101 - sub})" in legend
    squares = [ln for ln in inset.get_lines() if ln.get_marker() == "s" and len(ln.get_xdata())]
    assert len(squares) == 101
    lo, hi = inset.get_xlim()
    assert all(lo < pt.torque < hi for pt in hb)
    assert [t.get_text() for t in inset.texts if t.get_text().startswith("HB")] == ["HB1"]
    assert not [t for t in main.texts if t.get_text().startswith("HB")]  # all in the inset
    assert inset.get_title().startswith("101 Hopf points; HB1 at ")
    # A short string's few points: each labelled.
    dof2 = pydrill.preset("reduced-scale", dof=2)
    fig = bifurcation_figure(dof2, branch(dof2, vary="wob", torque=8.1))
    labels = sorted(t.get_text() for ax in fig.axes[0].child_axes for t in ax.texts)
    assert labels == ["HB1", "HB2", "LP"]


def test_first_hopf_point_is_subcritical_across_the_parameter_space():
    """Why no supercritical test: with this friction law the first destabilising Hopf point is
    subcritical for every string we tried — here a grid over bit and string damping, top
    damping, stiffness and both inertias (216 strings)."""
    import itertools

    base = pydrill.preset("reduced-scale", dof=2)
    checked = 0
    for cb, ct, cr, kt, jb, jr in itertools.product(
        [0.01, 0.5, 2.0],
        [1e-4, 0.05, 0.5],
        [0.18, 5.0],
        [0.073, 1.0],
        [0.0318, 0.5],
        [0.518, 0.1],
    ):
        p = base.replace(
            bit_damping=cb, dampings=[ct], top_damping=cr, stiffnesses=[kt], inertias=[jr, jb]
        )
        crossings = st.critical_deltas(p)
        first = next(
            (
                c
                for c in crossings
                if c.type == "hopf"
                and c.direction > 0
                and st.unstable_count(crossings, c.delta * (1 - 1e-9)) == 0
            ),
            None,
        )
        if first is None:
            continue
        checked += 1
        assert _core.first_lyapunov_coefficient(p.to_core(), first.delta, first.frequency) > 0
    assert checked > 50


@pytest.mark.parametrize(("dof", "vary", "fixed"), [(2, "wob", 8.1), (4, "torque", 80.0)])
def test_other_unstable_eigenvalues_at_each_point_are_counted_by_brute_force(dof, vary, fixed):
    """``others_unstable``: eigenvalues in Re > 0 on both sides of a point besides its own,
    counted here from dense eigenvalues just below and just above its δ."""
    p = pydrill.preset(dof=dof)
    kw = {"torque": fixed} if vary == "wob" else {"wob": fixed}
    b = branch(p, vary=vary, **kw)
    assert any(pt.others_unstable for pt in b.points)  # the case exists on both branches
    assert any(pt.type == "HB" and not pt.others_unstable for pt in b.points)
    for pt in b.points:
        counts = [
            int((np.linalg.eigvals(st.jacobian(p, pt.delta * f)).real > 0).sum())
            for f in (1 - 1e-7, 1 + 1e-7)
        ]
        own = 2 if pt.type == "HB" else 1
        assert abs(counts[0] - counts[1]) == own
        assert pt.others_unstable == min(counts)
