"""The rpm axis beside rad/s on the simulation and bifurcation figures (drillers think in rpm;
the text gave both, these figures rad/s alone): on every string, as the hopf figure's, its
ticks where the same speed in rad/s is on the main axis, clear of the legends and titles.

rpm are converted here by hand (one turn = 2π rad, one minute = 60 s), not with pydrill's
factor, and each tick is checked where it is drawn, in pixels."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from matplotlib.axes._secondary_axes import SecondaryAxis
from matplotlib.backends.backend_agg import FigureCanvasAgg

matplotlib.use("Agg")

import pydrill

RAD_PER_S_PER_RPM = 2 * math.pi / 60


def drawn(fig):
    """``fig`` laid out as it is saved (constrained layout, legends moved) and its renderer."""
    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def rpm_axes(ax) -> list:
    return [
        a
        for a in ax.child_axes
        if isinstance(a, SecondaryAxis) and "(rpm)" in (a.get_xlabel() + a.get_ylabel())
    ]


def check_ticks(ax, sec, which: str, renderer) -> int:
    """Each labelled tick of the rpm axis ``sec`` is drawn (to half a pixel) where its value,
    converted to rad/s, is on ``ax``'s axis, once drawn; how many there are in view."""
    axis = sec.yaxis if which == "y" else sec.xaxis
    lo, hi = sorted(ax.get_ylim() if which == "y" else ax.get_xlim())
    k = 1 if which == "y" else 0
    n = 0
    for tick in axis.get_major_ticks():
        label = tick.label2  # on the right of a y axis, the top of an x axis
        text = label.get_text().replace("\u2212", "-")
        if not label.get_visible() or not text:
            continue
        rad_s = float(text) * RAD_PER_S_PER_RPM
        if not lo <= rad_s <= hi:
            continue
        main = ax.transData.transform([(rad_s, rad_s)])[0][k]
        box = label.get_window_extent(renderer)
        centre = (box.y0 + box.y1) / 2 if which == "y" else (box.x0 + box.x1) / 2
        # Where the tick mark is: the label centred on it, to the label's own rounding.
        at = tick.tick2line.get_transform().transform(tick.tick2line.get_xydata())[0][k]
        assert at == pytest.approx(main, abs=0.5), (text, at, main)
        # and its label on the tick (a y label's box sits a pixel or two off its baseline)
        size = box.height if which == "y" else box.width
        assert centre == pytest.approx(main, abs=max(1.5, size / 4)), (text, centre, main)
        n += 1
    return n


def overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


@pytest.fixture(scope="module")
def runs():
    # The engineer's two runs, short: a real string settling at 6.75 rad/s (64.5 rpm), the
    # laboratory string in stick-slip up to 67 rad/s (640 rpm).
    return {
        "real-string": pydrill.simulate(
            preset="real-string", wob=100e3, torque=11e3, t_end=15.0, n_out=301
        ),
        "reduced-scale": pydrill.simulate(
            preset="reduced-scale", wob=100.0, torque=8.3, t_end=30.0, n_out=301
        ),
    }


@pytest.mark.parametrize("name", ["real-string", "reduced-scale"])
def test_simulation_figure_reads_velocity_in_rpm_on_the_right_clear_of_legends(runs, name):
    from pydrill.plot import simulation_figure

    fig = simulation_figure(runs[name])
    ax_v, ax_t = fig.axes
    (sec,) = rpm_axes(ax_v)
    assert not rpm_axes(ax_t)  # torque has no rpm
    renderer = drawn(fig)
    assert check_ticks(ax_v, sec, "y", renderer) >= 3
    # The whole range, not just the ticks: the same speeds at either end.
    assert sec.get_ylim() == pytest.approx([w / RAD_PER_S_PER_RPM for w in ax_v.get_ylim()])
    labels = sec.get_tightbbox(renderer)  # tick labels and "angular velocity (rpm)"
    assert labels.x0 >= ax_v.get_window_extent().x1 - 1  # on the right of the axes
    legends = [ax_v.get_legend(), ax_t.get_legend()]
    boxes = [lg.get_window_extent(renderer) for lg in legends]
    for box in boxes:
        assert box.x0 > labels.x1  # at 1.01 of the axes the top legend lay on the labels
        assert box.x1 <= fig.bbox.x1 + 1  # and still on the canvas
    assert boxes[0].x0 == pytest.approx(boxes[1].x0, abs=1)  # one above the other
    for text in (ax_v.title, fig._suptitle):
        assert not overlap(text.get_window_extent(renderer), labels)


@pytest.mark.parametrize(
    ("name", "vary", "fixed"),
    # the laboratory string's, with its inset; a real string's, in kN
    [("reduced-scale", "wob", 8.1), ("real-string", "wob", 11e3)],
)
def test_bifurcation_figure_reads_omega_in_rpm_on_the_right_clear_of_the_legend(name, vary, fixed):
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    p = pydrill.preset(name, dof=2)
    b = branch(p, vary=vary, **({"torque": fixed} if vary == "wob" else {"wob": fixed}))
    fig = bifurcation_figure(p, b)
    ax = fig.axes[0]
    (sec,) = rpm_axes(ax)
    assert sec.get_ylabel() == "steady bit speed (rpm)"  # the hopf figure's words
    renderer = drawn(fig)
    assert check_ticks(ax, sec, "y", renderer) >= 3
    labels = sec.get_tightbbox(renderer)
    assert labels.x0 >= ax.get_window_extent().x1 - 1
    legend = ax.get_legend().get_window_extent(renderer)
    assert not overlap(legend, labels)
    assert not overlap(ax.title.get_window_extent(renderer), labels)
    assert labels.x1 <= fig.bbox.x1 + 1


def test_hopf_figure_has_its_rpm_axis_on_every_string_as_the_two_now_do():
    """The condition the new axes follow: the hopf figure draws its rpm axis (on top) for
    the laboratory string as for a real one, as the simulation and bifurcation figures now
    do (the tests above, on both presets)."""
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    for name in ("real-string", "reduced-scale"):
        p = pydrill.preset(name)
        fig = hopf_figure(p, critical_deltas(p), n=30)
        ax = fig.axes[0]
        (sec,) = rpm_axes(ax)
        drawn(fig)  # (a secondary axis takes its limits when drawn)
        assert sec.get_xlim() == pytest.approx([w / RAD_PER_S_PER_RPM for w in ax.get_xlim()])


def test_a_legend_with_no_room_inside_goes_below_not_over_the_rpm_labels():
    """place_legend's last resort was beside the axes on the right: over the labels of an
    rpm axis there. And it took that axis (a line on the spine) for an inset to keep clear
    of, refusing every spot on the right where the legend hides nothing."""
    from pydrill.plot import place_legend, plt, rpm_axis

    # Data everywhere: no spot inside is clear.
    fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    x = np.linspace(0, 1, 40)
    for c in np.linspace(-1, 1, 25):
        ax.plot(x, x + c, color="0.5", label="_")
    ax.plot([], [], label="a curve")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    sec = rpm_axis(ax, "speed (rpm)", "right")
    place_legend(ax)
    renderer = drawn(fig)
    legend = ax.get_legend().get_window_extent(renderer)
    assert not overlap(legend, sec.get_tightbbox(renderer))
    assert legend.y1 < ax.get_window_extent().y0  # below the axes
    plt.close(fig)

    # Data on the left half only: the legend goes inside, on the right, hiding none of it.
    fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    for c in np.linspace(0, 1, 30):
        ax.plot([0, 0.45], [c, c], color="0.5")
    ax.plot([], [], label="a curve")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    rpm_axis(ax, "speed (rpm)", "right")
    place_legend(ax)
    renderer = drawn(fig)
    legend = ax.get_legend().get_window_extent(renderer)
    frame = ax.get_window_extent()
    assert frame.x0 + 0.45 * frame.width < legend.x0 and legend.x1 < frame.x1
    plt.close(fig)
