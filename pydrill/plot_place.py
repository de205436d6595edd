"""Where a legend or an inset goes on a figure: clear of its data (``data_pixels``), beside
the axes where no spot inside is. For every figure; imported through :mod:`pydrill.plot`."""

from __future__ import annotations

from matplotlib.axes._secondary_axes import SecondaryAxis


def data_pixels(ax, step: float = 3.0):
    """Where ``ax`` draws data, in display pixels: every vertex of its lines and points along
    their segments every ``step`` pixels (a straight line of two vertices crosses the whole
    axes), and the points of its scatters. What a legend or an inset must not hide."""
    import numpy as np

    out = [np.empty((0, 2))]
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
        if not len(xy):
            continue
        px = line.get_transform().transform(xy)
        ok = np.isfinite(px).all(axis=1)
        out.append(px[ok])
        if line.get_linestyle() in ("None", "", " "):
            continue
        for a, b, both in zip(px[:-1], px[1:], ok[:-1] & ok[1:], strict=True):
            if both:
                n = min(int(np.hypot(*(b - a)) // step), 2000)
                if n > 1:
                    t = np.arange(1, n)[:, None] / n
                    out.append(a + (b - a) * t)
    from matplotlib.collections import PathCollection

    for coll in ax.collections:  # scatters (not meshes, nor fills: a legend may sit on those)
        offsets = coll.get_offsets()
        if isinstance(coll, PathCollection) and coll.get_visible() and len(offsets):
            px = coll.get_offset_transform().transform(np.asarray(offsets, dtype=float))
            out.append(px[np.isfinite(px).all(axis=1)])
    return np.concatenate(out)


#: where ``place_legend`` tries a legend, in this order: matplotlib's codes, and a few spots
#: between them (a code with the point of the axes, in axes fraction, it is anchored to)
LEGEND_SPOTS: tuple[tuple[str, tuple[float, float] | None], ...] = (
    ("upper left", None),
    ("upper right", None),
    ("lower right", None),
    ("lower left", None),
    ("center right", None),
    ("center left", None),
    ("upper center", None),
    ("lower center", None),
    ("center right", (1.0, 0.7)),
    ("center left", (0.0, 0.7)),
    ("center right", (1.0, 0.3)),
    ("center left", (0.0, 0.3)),
    ("center", (0.5, 0.7)),
    ("center", (0.5, 0.3)),
)


def place_legend(ax, *args, twins=(), outside: str = "right", **kwargs):
    """``ax.legend(*args, **kwargs)`` in the first of ``LEGEND_SPOTS`` where it hides no data
    of ``ax`` nor of ``twins`` (axes drawn over it: a twinx) nor an inset, else beside the
    axes (on the ``outside`` "right" or "below"). matplotlib's loc="best" sees ``ax``'s own
    lines only (a twin's curve ran under it: Fig. 7(b)) and, where no spot is clear, picks the
    least bad one over the data. Lays the figure out to measure. The legend."""
    import numpy as np

    fig = ax.figure
    fig.draw_without_rendering()
    pad = 3 * fig.dpi / 72
    points = np.concatenate([data_pixels(a) for a in (ax, *twins)])
    # Not what lies on the frame (a curve held at the axis limit runs under the spine).
    frame = ax.get_window_extent().padded(-1.5)
    points = points[
        (points[:, 0] > frame.x0)
        & (points[:, 0] < frame.x1)
        & (points[:, 1] > frame.y0)
        & (points[:, 1] < frame.y1)
    ]
    # Not a secondary axis (rpm beside rad/s): a line on the spine, its labels outside.
    insets = [
        c.get_window_extent().padded(14 * pad / 3)
        for c in ax.child_axes
        if not isinstance(c, SecondaryAxis)
    ]
    for loc, anchor in LEGEND_SPOTS:
        legend = ax.legend(*args, loc=loc, bbox_to_anchor=anchor, **kwargs)
        box = legend.get_window_extent().padded(pad)
        if any(box.overlaps(i) for i in insets):
            continue
        inside = (
            (points[:, 0] > box.x0)
            & (points[:, 0] < box.x1)
            & (points[:, 1] > box.y0)
            & (points[:, 1] < box.y1)
        )
        if not inside.any():
            return legend
    # A twin's tick labels are on the right, and those of a secondary axis there (rpm).
    right = any(c.get_tightbbox().x1 > ax.get_window_extent().x1 + pad for c in ax.child_axes)
    if outside == "below" or twins or right:
        return ax.legend(*args, loc="upper center", bbox_to_anchor=(0.5, -0.12), **kwargs)
    return ax.legend(*args, loc="upper left", bbox_to_anchor=(1.01, 1.0), **kwargs)


def clear_inset(ax, spots, decorate):
    """An inset of ``ax``, drawn by ``decorate(inset)`` (its curves, limits, ticks, title), at
    the first of ``spots`` (rectangles in axes fraction: x0, y0, w, h) where it hides none of
    ``ax``'s data (``data_pixels``) with its tick labels and title, else at the one hiding the
    fewest: at a fixed place an inset hid the middle of the very branch it zooms in on, and the
    first periodic orbits of Fig. 11(b, d). Returns the inset and what ``decorate`` returned
    (drawn once more if the inset moves)."""
    import numpy as np
    from matplotlib.transforms import Bbox

    fig = ax.figure
    inset = ax.inset_axes(spots[0])
    result = decorate(inset)
    fig.draw_without_rendering()
    points = data_pixels(ax)
    frame, inner = ax.get_window_extent(), inset.get_window_extent()
    outer = inset.get_tightbbox()
    pad = 2 * fig.dpi / 72
    # What the inset draws around its frame (tick labels, title), in pixels on each side.
    around = (
        inner.x0 - outer.x0 + pad,
        inner.y0 - outer.y0 + pad,
        outer.x1 - inner.x1 + pad,
        outer.y1 - inner.y1 + pad,
    )
    best = None
    for spot in spots:
        x0, y0, w, h = spot
        left, bottom = frame.x0 + x0 * frame.width, frame.y0 + y0 * frame.height
        box = Bbox.from_extents(
            left - around[0],
            bottom - around[1],
            left + w * frame.width + around[2],
            bottom + h * frame.height + around[3],
        )
        hidden = int(
            np.sum(
                (points[:, 0] > box.x0)
                & (points[:, 0] < box.x1)
                & (points[:, 1] > box.y0)
                & (points[:, 1] < box.y1)
            )
        )
        if best is None or hidden < best[0]:
            best = (hidden, spot)
        if hidden == 0:
            break
    assert best is not None
    if best[1] != spots[0]:
        inset.remove()
        inset = ax.inset_axes(best[1])
        result = decorate(inset)
    return inset, result
