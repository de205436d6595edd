"""Mutation guards of the simulate figure (plot.py) and of the point names (plot_labels.py):
what a reader sees (each signal's line, the limits ±T_s and u, the units, the legend, the
shaded windows, zero in view; names beside their points, clear of markers and of each other)
checked through matplotlib's objects against the simulation's own arrays, μ_s W_ob R_b written
out, and boxes measured here. The analysis figures' guards: test_mutation_guards_analysis_plots."""

import math

import matplotlib
import numpy as np
import pytest
from matplotlib.colors import to_rgba

matplotlib.use("Agg")

import pydrill
from pydrill.plot import plt


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _legend_texts(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


def _line(ax, label):
    return next(ln for ln in ax.get_lines() if ln.get_label() == label)


def test_simulation_figure_draws_each_signal_from_its_own_array():
    from pydrill.plot import simulation_figure

    p = pydrill.preset("reduced-scale", dof=2)
    r = pydrill.simulate(p, wob=100.0, torque=8.5, t_end=40.0, n_out=401)
    s = r.summary
    assert s.regime == "stick-slip" and s.static_torque == pytest.approx(8.0)
    fig = simulation_figure(r)
    ax_v, ax_t = fig.axes[:2]
    np.testing.assert_array_equal(_line(ax_v, "bit $\\omega_b$").get_ydata(), r.bit_velocity)
    np.testing.assert_array_equal(_line(ax_v, "top drive $\\omega_0$").get_ydata(), r.top_velocity)
    # u = 8.5 N·m and T_s = μ_s W R_b = 8 N·m on lines of their own (distinct values here).
    assert set(_line(ax_t, "surface torque $u$").get_ydata()) == {8.5}
    np.testing.assert_allclose(_line(ax_t, "$T_s = \\mu_s W_{ob} R_b$").get_ydata(), 8.0)
    # "held by the rock": the points in stick or the Karnopp band (modes 'stick', 'band').
    held = np.isin(np.asarray(pydrill.MODES)[r.mode_index], ["stick", "band"])
    assert held.any()
    np.testing.assert_array_equal(_line(ax_t, "held by the rock").get_xdata(), r.t[held])
    # The legend: one "steady state Ω" (one equilibrium), "bit stuck" as the bit sticks.
    labels = _legend_texts(ax_v)
    assert labels.count("steady state $\\Omega$") == len(s.omega_equilibrium) == 1
    assert "bit stuck" in labels
    assert f"stuck {round(100 * s.stuck_fraction)} %" in ax_v.get_title()
    # Judged window shaded from its start, not from t = 0.
    spans = [
        a.get_patch_transform().transform(a.get_path().vertices)[:, 0]
        for a in ax_v.patches
        if to_rgba(a.get_facecolor())[:3] == to_rgba("0.5")[:3]
    ]
    assert [(min(x), max(x)) for x in spans] == [(s.window_start, s.window_end)]
    assert ax_t.get_xlim() == (r.t[0], r.t[-1])
    # The title in the regime's colour (stick-slip orange).
    assert to_rgba(fig._suptitle.get_color()) == to_rgba("#e67e22")


def test_simulation_figure_of_a_fast_steady_bit_keeps_zero_in_view_and_kilo_units():
    from pydrill.plot import simulation_figure

    real = pydrill.preset("real-string")
    # W_ob 30 kN beside u = 3.8 kN·m and T_s = μ_s W R_b = 3.7 kN·m: both under 5 kN·m, the
    # weight over 5 kN: the torques in kN·m (as the title's W_ob in kN).
    ts = real.mu_static * 30000.0 * real.bit_radius
    assert ts < 5e3
    r = pydrill.simulate(real, wob=30000.0, torque=3800.0, t_end=20.0, n_out=201)
    fig = simulation_figure(r)
    assert fig.axes[1].get_ylabel() == "torque at the bit (kN·m)"
    assert "$u$ = 3.8 kN·m" in fig._suptitle.get_text()
    assert "$W_{ob}$ = 30 kN" in fig._suptitle.get_text()
    # From its steady state (Ω = 78.9 rad/s at u = 20 N·m), a bit that never nears zero:
    # zero stays in view, not a panel filled by a wobble about 79 rad/s.
    p = pydrill.preset("reduced-scale", dof=2)
    r = pydrill.simulate(p, wob=100.0, torque=20.0, t_end=5.0, n_out=51, initial="equilibrium")
    assert r.bit_velocity.min() > 50.0
    assert simulation_figure(r).axes[0].get_ylim()[0] <= 0.0


def _placed(points, labels, right=True, ms=6.0):
    """A 6 x 4 inch axes (0..10, -1..1) with a square marker at each point, the names placed;
    the figure, the axes and each name's box in pixels."""
    from pydrill.plot_labels import place_labels

    fig, ax = plt.subplots(figsize=(6, 4))
    for x, y in points:
        ax.plot([x], [y], "s", ms=ms)
    ax.set_xlim(0, 10)
    ax.set_ylim(-1, 1)
    place_labels(fig, [(ax, text, xy, "red") for text, xy in labels], right=right)
    renderer = fig.canvas.get_renderer()
    return fig, ax, [t.get_window_extent(renderer) for t in ax.texts]


def _marker_box(ax, xy, ms):
    from matplotlib.transforms import Bbox

    x, y = ax.transData.transform(xy)
    half = (ms / 2 + 1.0) * ax.figure.dpi / 72  # default edge width 1 point
    return Bbox.from_extents(x - half, y - half, x + half, y + half)


def test_names_go_right_or_left_as_asked_and_stay_inside_the_axes():
    for right in (True, False):
        _, ax, (box,) = _placed([(5.0, 0.0)], [("HB1", (5.0, 0.0))], right=right)
        x = ax.transData.transform((5.0, 0.0))[0]
        assert box.x0 > x if right else box.x1 < x
    # A point at the right edge: its name goes inside (left), though asked right first.
    fig, ax, (box,) = _placed([(9.95, 0.0)], [("HB1", (9.95, 0.0))], right=True)
    frame = ax.get_window_extent(fig.canvas.get_renderer())
    assert frame.x0 <= box.x0 and box.x1 <= frame.x1


def test_two_names_of_one_place_do_not_overlap_nor_cover_a_big_marker():
    # A fold and a Hopf point at the same place (they nearly are on Fig. 11): two names.
    _, ax, boxes = _placed([(5.0, 0.0)], [("HB2", (5.0, 0.0)), ("LP", (5.0, 0.0))])
    assert len(boxes) == 2 and not boxes[0].overlaps(boxes[1])
    # A marker of 20 points: its name clear of it (the nearest offsets, 8 points, are not).
    _, ax, (box,) = _placed([(5.0, 0.0)], [("HB1", (5.0, 0.0))], ms=20.0)
    assert not box.overlaps(_marker_box(ax, (5.0, 0.0), 20.0))


def test_a_name_is_nearer_its_own_point_than_any_other_marker():
    # Where the first offset (8, 4) points writes the name, measured; another marker put just
    # past its right end (clear of it by 3 pixels, so no overlap), nearer that box than the
    # point it names: the name must go elsewhere.
    fig, ax, _ = _placed([(5.0, 0.0)], [])
    first = ax.annotate("HB1", (5.0, 0.0), textcoords="offset points", xytext=(8, 4), fontsize=8)
    box = first.get_window_extent(fig.canvas.get_renderer()).padded(fig.dpi / 72)
    half = (6 / 2 + 1.0) * fig.dpi / 72
    other = ax.transData.inverted().transform((box.x1 + half + 3, (box.y0 + box.y1) / 2))
    plt.close(fig)
    _, ax, (box,) = _placed([(5.0, 0.0), tuple(other)], [("HB1", (5.0, 0.0))])
    own, far = ax.transData.transform([(5.0, 0.0), tuple(other)])

    def dist(xy):
        dx = max(box.x0 - xy[0], 0, xy[0] - box.x1)
        return math.hypot(dx, max(box.y0 - xy[1], 0, xy[1] - box.y1))

    assert dist(own) < dist(far)
    assert not box.overlaps(_marker_box(ax, tuple(other), 6.0))


def test_simulation_figure_draws_the_lower_limit_minus_t_s_once_the_torque_is_negative():
    from pydrill.plot import simulation_figure

    p = pydrill.preset("reduced-scale", dof=2)
    # u = -3 N·m against T_s = 8 N·m: the bit stays stuck, the rock holding T_e = -3 N·m,
    # within (-T_s, 0): the limit it is held against is -T_s, drawn at -8 N·m.
    r = pydrill.simulate(p, wob=100.0, torque=-3.0, t_end=5.0, n_out=51)
    assert -8.0 < r.reaction_torque.min() < 0.0
    ax_t = simulation_figure(r).axes[1]
    np.testing.assert_allclose(_line(ax_t, "$-T_s$").get_ydata(), -8.0)
    np.testing.assert_allclose(_line(ax_t, "$T_s = \\mu_s W_{ob} R_b$").get_ydata(), 8.0)
    # a positive torque's figure has no lower limit
    r = pydrill.simulate(p, wob=100.0, torque=3.0, t_end=5.0, n_out=51)
    assert "$-T_s$" not in _legend_texts(simulation_figure(r).axes[1])
