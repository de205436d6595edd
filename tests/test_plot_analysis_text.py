"""Text of the analysis figures: the eigenvalue plot's tick labels on a symlog axis, and what
the Hopf figure's title says of an Ω range nobody asked for."""

import itertools
from pathlib import Path

import pydrill
from pydrill import load_tally
from pydrill.plot_analysis import eigenvalue_figure, hopf_figure
from pydrill.stability import critical_deltas, stability

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_the_eigenvalue_plots_tick_labels_do_not_touch():
    """A tally string's eigenvalues span 1e-1 ... 1e6 on the left: on its symlog axis the label
    of -10^-1 stood against that of 0 (linthresh 0.03, its band drawn narrow)."""
    p = load_tally(PAPER).at_depth(3000.0).to_params()
    points = stability(p, 100e3, torque=11e3)
    fig = eigenvalue_figure(p, points)
    fig.draw_without_rendering()
    ax = fig.axes[0]
    assert ax.get_xscale() == "symlog"
    renderer = fig.canvas.get_renderer()
    boxes = sorted(
        (t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()),
        key=lambda b: b.x0,
    )
    assert len(boxes) >= 5
    for left, right in itertools.pairwise(boxes):
        assert right.x0 - left.x1 >= 4, (left, right)  # pixels between neighbouring labels


def test_the_hopf_title_says_whose_omega_range_it_falls_short_of():
    p = pydrill.preset("reduced-scale", dof=4)
    crossings = critical_deltas(p)
    default = hopf_figure(p, crossings).axes[0].get_title()
    asked = hopf_figure(p, crossings, omega_max=30.0).axes[0].get_title()
    assert "of the 20 by default (--omega-max):" in default and "asked" not in default
    assert "of the 30 asked:" in asked
