"""The titles of atlas figures: what a map or profile holds constant and how much of the
atlas it shows, on one line or two, and kept inside the figure."""

from __future__ import annotations

from typing import Any

from .plot import quantity


def title(string: str, what: str) -> str:
    """A figure's title, "string: what" on one line, or on two where one would run past the
    figure's edges (a real string's name, dof, torque and depth, and a metric's meaning)."""
    return f"{string}: {what}" if len(string) + len(what) <= 95 else f"{string}:\n{what}"


def context(atlas, held: dict[str, float], scales: dict[str, tuple[float, str]]):
    """What a figure's title says of the string and how much of the atlas is done: ("reduced-
    scale, dof 4, torque = 8.3 N·m", "42 points" or "30 of 42 points done"). ``held``: the
    axes held at a value; ``scales``: the kN scales of wob and torque, as the figure uses."""
    import numpy as np

    from .plot_atlas import AXIS_SI, shown_unit

    s = atlas.spec
    total = int(np.prod(atlas.shape))
    missing = atlas.summary()["status"]["missing"]
    # An interrupted sweep's atlas: say so, or the white cells read as a regime of their own.
    points = "point" if total == 1 else "points"
    count = f"{total - missing} of {total} {points} done" if missing else f"{total} {points}"
    # Everything a figure holds constant: the held axes, and what the spec fixes (e.g. torque).
    # (a model parameter held with its unit: "bit_damping = 0.05 N·m·s/rad")
    where = "".join(
        f", {n} = "
        + (quantity(v, AXIS_SI[n], scales[n][0]) if n in scales else f"{v:.4g}")
        + (f" {AXIS_SI[n]}" if AXIS_SI.get(n) and n not in scales else "")  # depth's m
        + ("" if n in AXIS_SI or not shown_unit(n) else f" {shown_unit(n)}")
        for n, v in {**s.fixed, **held}.items()
    )
    size = f", dof {s.dof}" if s.dof and "dof" not in atlas.axes else ""
    if s.tally_text:
        from .tally import parse_tally

        string = f"string {parse_tally(s.tally_text).name}"
    else:
        string = s.preset
    return f"{string}{size}{where}", count


def keep_title_inside(fig: Any, ax: Any) -> None:
    """Shift the title of ``ax``, centred over it, to lie inside ``fig``: over a map narrowed by
    a wide legend beside it, a title of 80 characters ran past the figure's left edge and was
    cut ("ing paper-eq53, ..."). Lays the figure out once to measure it."""
    fig.draw_without_rendering()
    box, frame, axes = ax.title.get_window_extent(), fig.bbox, ax.get_window_extent()
    pad = 4.0  # px
    shift = max(0.0, frame.x0 + pad - box.x0) - max(0.0, box.x1 - (frame.x1 - pad))
    if shift:
        ax.title.set_x(ax.title.get_position()[0] + shift / axes.width)
