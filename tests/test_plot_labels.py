"""Point names placed clear of the curves (plot_labels.place_labels), checked against the
curves sampled densely here: a name is never written over a curve when some offset is clear
(the placement samples the curves every two points, all segments at once)."""

import itertools

import matplotlib
import numpy as np

matplotlib.use("Agg")

from pydrill.plot import plt
from pydrill.plot_labels import place_labels


def _crossed(ax, box, lines):
    """Whether the label's box (pixels) holds a point of a curve, sampled every 0.1 pixel."""
    for x, y in lines:
        xy = ax.transData.transform(np.column_stack([x, y]))
        dense = np.concatenate(
            [np.linspace(a, b, int(np.hypot(*(b - a)) * 10) + 2) for a, b in itertools.pairwise(xy)]
        )
        inside = (
            (dense[:, 0] > box.x0)
            & (dense[:, 0] < box.x1)
            & (dense[:, 1] > box.y0)
            & (dense[:, 1] < box.y1)
        )
        if inside.any():
            return True
    return False


def test_a_name_is_not_written_over_a_curve_when_an_offset_is_clear():
    fig, ax = plt.subplots(figsize=(6, 4))
    try:
        # A curve just above and right of the point, where the first offset writes its name,
        # and one far off with 4000 vertices (the kind of branch that was slow).
        lines = [(np.array([5.05, 9.0]), np.array([0.06, 0.06]))]
        x = np.linspace(0, 10, 4000)
        lines.append((x, 0.6 + 0.05 * np.sin(x)))
        for lx, ly in lines:
            ax.plot(lx, ly, "-")
        ax.plot([5.0], [0.0], "s")
        ax.set_xlim(0, 10)
        ax.set_ylim(-1, 1)
        place_labels(fig, [(ax, "HB1", (5.0, 0.0), "red")])
        (note,) = ax.texts
        renderer = fig.canvas.get_renderer()
        box = note.get_window_extent(renderer)
        assert note.xyann != (8, 4)  # the first offset lies on the near curve
        assert not _crossed(ax, box, lines)
        first = ax.annotate("HB1", (5.0, 0.0), textcoords="offset points", xytext=(8, 4))
        assert _crossed(ax, first.get_window_extent(renderer), lines)  # (the test can fail)
    finally:
        plt.close(fig)
