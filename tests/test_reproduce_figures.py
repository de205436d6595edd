"""The paper's figures as ``pydrill reproduce`` draws them, checked as a reviewer would, on the
drawn artists: every text on the canvas, no legend or inset over the curves and points it
explains, names in the insets that do not overlap, the atlas maps' regime colours."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from test_plot_review import data_points, drawn, hidden_by, outside_canvas

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def reproduced(reproduce_quick):
    """Every figure ``pydrill reproduce --quick`` draws, as matplotlib figures: the numbers of
    one quick run (the session's, conftest.py), drawn again with ``save`` keeping the figures
    open."""
    from pydrill import (
        reproduce_figures,
        reproduce_figures_sliding,
        reproduce_plots,
        reproduce_plots_long,
    )
    from pydrill import reproduce_sims as rs

    out, _ = reproduce_quick
    numbers = json.loads((out / "numbers.json").read_text())
    figures: dict[str, object] = {}

    def keep(fig, path):
        figures[Path(path).stem] = fig
        return Path(path)

    modules = (reproduce_figures, reproduce_figures_sliding, reproduce_plots, reproduce_plots_long)
    saved = [m.save for m in modules]
    for m in modules:
        m.save = keep
    try:
        pipes = tuple(int(k[5:]) for k in numbers if k.startswith("pipes"))
        reproduce_plots.draw_analysis(out, numbers, pipes)
        n5, runs5 = rs.fig5()
        reproduce_figures.fig5(out, n5, runs5)
        n7, runs7 = rs.fig7()
        reproduce_figures_sliding.fig7(out, n7, runs7)
    finally:
        for m, s in zip(modules, saved, strict=True):
            m.save = s
    yield figures
    import matplotlib.pyplot as plt

    for fig in figures.values():
        plt.close(fig)


def test_reproduced_figures_keep_every_text_on_the_canvas(reproduced):
    # Fig. 5(b)'s title ran off the right edge ("... = 1" of "101.25 N").
    assert {"fig05_wob_steps", "fig07_stuck", "fig10_stability_region", "fig11_bifurcation"} <= set(
        reproduced
    )
    for name, fig in reproduced.items():
        assert outside_canvas(fig) == [], name


def test_fig11_insets_hide_no_orbit_nor_branch_and_their_names_do_not_overlap(reproduced):
    panels = [
        ax
        for name, fig in reproduced.items()
        if name.startswith("fig11")
        for ax in fig.axes
        if ax.child_axes
    ]
    assert len(panels) >= 4
    for ax in panels:
        renderer = drawn(ax.figure)
        (inset,) = ax.child_axes
        # The inset with its tick labels and title: at a fixed place it hid the first
        # periodic orbits found from rest in Fig. 11(b) and (d).
        box = inset.get_tightbbox(renderer)
        assert hidden_by(box, data_points(ax)) == 0, ax.get_title()
        names = [t for t in inset.texts if t.get_text() in ("LP",) or t.get_text().startswith("HB")]
        assert names, ax.get_title()
        boxes = [t.get_window_extent(renderer) for t in names]
        for (a, ta), (b, tb) in itertools.combinations(zip(boxes, names, strict=True), 2):
            # HB2 and LP of Fig. 11(a), 0.1 N apart, were written over one another.
            assert not a.overlaps(b), (ax.get_title(), ta.get_text(), tb.get_text())


def test_fig7_fig10_and_fig12_legends_hide_no_curve_nor_point(reproduced):
    fig7 = reproduced["fig07_stuck"]
    (torque_ax,) = [a for a in fig7.axes if a.get_legend() is not None and a.name == "rectilinear"]
    twins = [a for a in fig7.axes if a is not torque_ax and a.bbox.bounds == torque_ax.bbox.bounds]
    drawn(fig7)
    points = np.concatenate([data_points(a) for a in (torque_ax, *twins)])
    # At "center right" it hid the reaction torque's last swings; the twin's bit velocity too.
    assert twins and len(torque_ax.get_legend().get_texts()) == 4
    assert hidden_by(torque_ax.get_legend().get_window_extent(), points) == 0
    fig10 = reproduced["fig10_stability_region"]
    drawn(fig10)
    for ax in fig10.axes:
        # In the upper left, the fold and H1 lines of (a) ran under it.
        assert hidden_by(ax.get_legend().get_window_extent(), data_points(ax)) == 0, ax.get_title()
    fig12 = reproduced["fig12_hopf_wob_torque"]
    drawn(fig12)
    for ax in fig12.axes:
        # In the upper left, (b)'s hid the stick-slip points at W_ob = 90-103 N above 10.6 N·m.
        assert hidden_by(ax.get_legend().get_window_extent(), data_points(ax)) == 0, ax.get_title()


def test_fig6b_regimes_have_the_atlas_maps_colours(reproduced):
    from matplotlib.colors import to_rgba

    from pydrill.plot_atlas import MAP_COLORS
    from pydrill.reproduce_plots import REGIME_ORDER

    fig = reproduced["fig06b_regime_map"]
    for ax in fig.axes[:2]:
        mesh = ax.collections[0]
        cmap = mesh.get_cmap()
        drawn = [tuple(cmap(k)) for k in range(cmap.N)]
        assert drawn == [to_rgba(MAP_COLORS[r]) for r in REGIME_ORDER]
        assert mesh.get_alpha() in (None, 1.0)
