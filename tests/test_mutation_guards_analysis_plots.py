"""Mutation guards of the analysis figures (plot_analysis.py: Hopf map, eigenvalues, bifurcation
diagram; the simulate figure and point names: test_mutation_guards_plot_sim_labels): what a
reader sees (curves, units, limits, legend entries, colours, labels) checked through matplotlib's
objects against values computed here: the Hopf boundary W_ob = δ e^{γΩ/v_f} / (R_b γ/v_f
(μ_s − μ_c)) written out, unit factors (1 kN = 1e3 N, 1 rpm = π/30 rad/s) written here, and the
API's results (crossings, branch points, simulation arrays) read directly."""

import math
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest
from matplotlib.axes._secondary_axes import SecondaryAxis
from matplotlib.colors import to_rgba

matplotlib.use("Agg")

from test_undamped import UNDAMPED

import pydrill
from pydrill.plot import plt

RPM = math.pi / 30  # rad/s per rpm, written here and not taken from pydrill


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _hopf_wob(p, delta, omega):
    """The Hopf boundary by hand: δ(Ω, W) = W R_b (μ_s − μ_c) (γ/v_f) e^{−γΩ/v_f} = δ_k."""
    rate = p.stribeck_decay / p.stribeck_velocity
    return (
        delta
        * np.exp(rate * np.asarray(omega))
        / (p.bit_radius * rate * (p.mu_static - p.mu_coulomb))
    )


def _legend_texts(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


def test_hopf_map_draws_each_boundary_where_the_formula_puts_it_on_a_log_axis_and_in_rpm():
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    p = pydrill.preset("reduced-scale", dof=4)
    crossings = critical_deltas(p)
    fig = hopf_figure(p, crossings, n=60)
    fig.draw_without_rendering()
    ax = fig.axes[0]
    hopf = sorted(c.delta for c in crossings if c.type == "hopf" and c.delta > 0)
    first = min(c.delta for c in crossings if c.type == "hopf" and c.direction > 0)
    solid = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-"]
    dashed = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    # One solid curve per Hopf crossing (5 here, under the cap of 8), the fold dashed.
    assert len(solid) == len(hopf) == 5 and len(dashed) == 1
    for ln, delta in zip(sorted(solid, key=lambda ln: ln.get_ydata()[0]), hopf, strict=True):
        np.testing.assert_allclose(ln.get_ydata(), _hopf_wob(p, delta, ln.get_xdata()), rtol=1e-9)
    fold = next(c.delta for c in crossings if c.type == "fold")
    np.testing.assert_allclose(
        dashed[0].get_ydata(), _hopf_wob(p, fold, dashed[0].get_xdata()), rtol=1e-9
    )
    # The first Hopf curve is the one drawn bold.
    bold = max(solid, key=lambda ln: ln.get_linewidth())
    assert bold.get_ydata()[0] == pytest.approx(_hopf_wob(p, first, 0.0))
    assert all(ln.get_linewidth() < bold.get_linewidth() for ln in solid if ln is not bold)
    # W_ob on a log axis from a third of the first boundary at Ω = 0, four decades at most.
    assert ax.get_yscale() == "log"
    lo, hi = ax.get_ylim()
    assert lo == pytest.approx(_hopf_wob(p, first, 0.0) / 3)
    assert hi == pytest.approx(1e4 * lo)
    # Ω stops a quarter past where the first curve leaves the top (not at the 20 rad/s asked).
    leaves = math.log(hi / _hopf_wob(p, first, 0.0)) / (p.stribeck_decay / p.stribeck_velocity)
    assert ax.get_xlim() == pytest.approx((0.0, 1.25 * leaves))
    assert "of the 20 by default" in ax.get_title()
    # The secondary axis on top reads the same Ω in rpm.
    (top,) = [a for a in ax.child_axes if a.get_xlabel().startswith("steady bit speed")]
    assert top.get_xlim() == pytest.approx(tuple(x / RPM for x in ax.get_xlim()))
    # The legend names δ_1 and its frequency, and lists the further crossings and the fold.
    texts = _legend_texts(ax)
    f1 = next(c for c in crossings if c.delta == first)
    assert texts[0].startswith(
        f"first Hopf: $\\delta_1$ = {first:.4g} N·m·s/rad, {f1.frequency:.3g}"
    )
    assert texts[1:] == ["further Hopf crossings", "fold ($\\delta = c_r + c_b$)"]
    assert f"({len(hopf)} Hopf crossings in all)" in ax.get_title()


def test_hopf_map_colours_the_stable_side_green_and_the_unstable_side_orange():
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    p = pydrill.preset("reduced-scale", dof=2)
    fig = hopf_figure(p, critical_deltas(p), n=40)
    mesh = fig.axes[0].collections[0]
    counts = np.asarray(mesh.get_array()).ravel()
    rgba = mesh.to_rgba(counts)
    # No unstable eigenvalue: light green (green above red); one or more: orange (red above green).
    assert (counts == 0).any() and (counts > 0).any()
    assert np.all(rgba[counts == 0, 1] > rgba[counts == 0, 0])
    assert np.all(rgba[counts > 0, 0] > rgba[counts > 0, 1])
    # One colour per count: the colour bar's ticks are the whole numbers 0 ... max.
    assert len({tuple(c) for c in rgba[counts == 1]}) == 1


def test_hopf_map_in_kilonewtons_once_its_top_is_past_5_kn():
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    # A bit of a tenth of the radius: the boundary at Ω = 0 is ten times the weight, 4 N, and
    # the map runs from 1.3 N to 13 kN: its axis must read kN (by its top, not its foot).
    p = pydrill.preset("reduced-scale", dof=2).replace(bit_radius=0.01)
    fig = hopf_figure(p, critical_deltas(p), n=40)
    fig.draw_without_rendering()
    ax = fig.axes[0]
    assert ax.get_ylim()[1] > 5e3 > ax.get_ylim()[0]
    assert ax.get_ylabel().endswith("(kN)")
    lo, hi = ax.get_ylim()
    ticks = [
        (at, t.get_text())
        for at, t in zip(ax.get_yticks(), ax.get_yticklabels(), strict=True)
        if lo <= at <= hi and t.get_text()
    ]
    assert ticks
    for at, text in ticks:  # labels like "$\mathdefault{10^{1}}$" are not what is wanted
        assert float(text.replace("−", "-")) == pytest.approx(at / 1e3)


def _point(wob, torque, eigenvalues, omega=1.0):
    ev = [complex(z) for z in eigenvalues]
    n = sum(z.real > 0 for z in ev)
    return SimpleNamespace(
        wob=wob, torque=torque, omega=omega, eigenvalues=ev, stable=n == 0, unstable=n
    )


def test_eigenvalue_plot_legend_scale_and_title_units():
    from pydrill.plot_analysis import eigenvalue_figure

    p = pydrill.preset("reduced-scale", dof=2)
    # |Re| from 1 to 1000: more than the hundredfold past which the axis is logarithmic.
    pts = [
        _point(6000.0, 300.0, [-1000, -1 + 2j, -1 - 2j], 2.0),
        _point(6000.0, 300.0, [5, -3], 1.0),
    ]
    fig = eigenvalue_figure(p, pts)
    ax = fig.axes[0]
    assert ax.get_xscale() == "symlog"
    texts = _legend_texts(ax)
    assert "Ω = 2 rad/s: stable (0 unstable)" in texts
    assert "Ω = 1 rad/s: UNSTABLE (1 unstable)" in texts
    # W_ob 6 kN beside u = 300 N·m: both in the kilo units of the larger.
    assert "6 kN" in ax.get_title() and "0.3 kN·m" in ax.get_title()
    # Shaded: Re λ > 0 only, up to the right edge.
    (shade,) = [a for a in ax.patches if a.get_label() == "unstable half-plane"]
    x = shade.get_patch_transform().transform(shade.get_path().vertices)[:, 0]  # data x
    assert min(x) == 0.0 and max(x) == pytest.approx(ax.get_xlim()[1])
    # |Re| from 1 to 50: linear.
    fig = eigenvalue_figure(p, [_point(60.0, 3.0, [-50, -1, 2])])
    assert fig.axes[0].get_xscale() == "linear"


def test_bifurcation_figure_draws_the_branch_stable_where_no_eigenvalue_is_unstable():
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    p = pydrill.preset("reduced-scale", dof=2)
    b = branch(p, vary="wob", torque=8.1)
    fig = bifurcation_figure(p, b)
    ax = fig.axes[0]
    solid = next(ln for ln in ax.get_lines() if ln.get_label() == "stable steady state")
    dashed = next(ln for ln in ax.get_lines() if ln.get_label() == "unstable steady state")
    np.testing.assert_array_equal(solid.get_xdata(), b.wob)  # against W_ob, in N
    y = np.asarray(solid.get_ydata())
    np.testing.assert_array_equal(np.isfinite(y), b.unstable == 0)
    np.testing.assert_array_equal(np.isfinite(dashed.get_ydata()), b.unstable > 0)
    assert ax.get_ylim()[0] == 0.0
    assert ax.get_xlabel().endswith("(N)")
    # The special points span 5.5 % of the W_ob drawn (137 ... 145 N of 0 ... 145 N), under
    # the 15 % below which an inset zooms in on them.
    xs = [pt.wob for pt in b.points]
    assert 0.02 < np.ptp(xs) / np.ptp(b.wob) < 0.15
    insets = [a for a in ax.child_axes if not isinstance(a, SecondaryAxis)]  # not the rpm axis
    assert len(insets) == 1
    assert "$u$ = 8.1 N·m" in ax.get_title()  # the torque held, in N·m
    # W_ob varying, names go right of their points first: all three clear there in the inset.
    (inset,) = insets
    assert sorted(t.get_text() for t in inset.texts) == ["HB1", "HB2", "LP"]
    assert all(t.xyann[0] > 0 for t in inset.texts)


def test_bifurcation_figure_in_kilo_units_when_only_the_weight_held_is_a_real_strings():
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    p = pydrill.preset("reduced-scale", dof=2)
    b = branch(p, vary="torque", wob=6000.0)
    assert np.max(np.abs(b.torque)) < 5e3  # the torques alone would be in N·m
    fig = bifurcation_figure(p, b)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "surface torque $u$ (kN·m)"
    assert "$W_{ob}$ = 6 kN" in ax.get_title()


def test_bifurcation_figure_of_many_hopf_points_names_the_first_and_the_fold():
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    p = pydrill.preset("reduced-scale", dof=8)
    b = branch(p, vary="torque", wob=100.0)
    hb = [pt for pt in b.points if pt.type == "HB"]
    assert len(hb) > 4
    top = max(hb, key=lambda pt: pt.omega)
    fig = bifurcation_figure(p, b)
    ax = fig.axes[0]
    axes = [ax, *ax.child_axes]
    names = [(t.get_text(), t.xy) for a in axes for t in a.texts]
    # The first Hopf point (highest Ω, where the stable branch ends) named, with its place;
    # no other Hopf point named in the main axes (an inset's short names aside).
    main = [(s, xy) for s, xy in ((t.get_text(), t.xy) for t in ax.texts)]
    hopf_names = [(s, xy) for s, xy in main if s.startswith("HB")]
    assert len(hopf_names) <= 1
    named = [xy for s, xy in names if s.startswith(top.label)]
    assert named and all(xy == pytest.approx((top.torque, top.omega)) for xy in named)
    assert any(s == "LP" for s, _ in names)  # the fold is named however many Hopf points
    # u varying, the stable branch leaves HB1 to the upper right: names go left first (LP's
    # first offset on the left is clear).
    (lp,) = [t for t in ax.texts if t.get_text() == "LP"]
    assert lp.xyann[0] < 0
    # Each Hopf marker's colour says its criticality; the legend counts each kind.
    colours = {"supercritical": to_rgba("#27ae60"), "subcritical": to_rgba("#c0392b")}
    for pt in hb:
        (mk,) = [
            ln
            for ln in ax.get_lines()
            if ln.get_marker() == "s"
            and len(ln.get_xdata()) == 1
            and ln.get_xdata()[0] == pt.torque
        ]
        assert to_rgba(mk.get_color()) == colours[pt.criticality]
    sub = sum(pt.criticality == "subcritical" for pt in hb)
    texts = _legend_texts(ax)
    assert f"Hopf point, subcritical ({sub})" in texts
    assert f"Hopf point, supercritical ({len(hb) - sub})" in texts


def test_hopf_map_with_one_hopf_curve_lists_no_further_ones():
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    # The crossings given are the ones drawn: here the first Hopf crossing and the fold only.
    p = pydrill.preset("reduced-scale", dof=2)
    crossings = [c for c in critical_deltas(p) if c.direction > 0]
    assert [c.type for c in crossings] == ["hopf", "fold"]
    fig = hopf_figure(p, crossings, n=40)
    texts = _legend_texts(fig.axes[0])
    assert len(texts) == 2 and texts[0].startswith("first Hopf") and "fold" in texts[1]


@pytest.mark.parametrize("damping", [1e-6, 0.0])
def test_hopf_title_counts_the_crossings_at_zero_damping_too(damping):
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    # Six equal masses and springs, no damping at the ends (the fold's eigenvalue crosses at
    # δ = 0) and a little between them, or none at all (every Hopf crossing at δ = 0 too,
    # drawn on no curve): the title counts them all.
    p = UNDAMPED.replace(dampings=[damping] * 5)  # test_undamped's fuzzer reproducer
    crossings = critical_deltas(p)
    at_zero = [c for c in crossings if c.delta == 0 and c.direction > 0]
    assert at_zero
    n_hopf = sum(c.type == "hopf" for c in crossings)
    fig = hopf_figure(p, crossings, n=40)
    title = fig.axes[0].get_title()
    assert f"({n_hopf} Hopf crossings in all)" in title
    n = sum(c.multiplicity for c in at_zero)  # 1 (the fold) with damping between the masses
    verb = "eigenvalue crosses" if n == 1 else "eigenvalues cross"
    assert "steady drilling is unstable at every" in title
    assert f"{n} {verb} at $\\delta$ = 0" in title
