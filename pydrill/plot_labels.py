"""Names written beside points of a figure (Hopf points, folds) where they clear the
markers, the curves and one another: the bifurcation figures' and reproduce's Fig. 11."""

from __future__ import annotations


def place_labels(fig, labels, right: bool = True) -> None:
    """Write each (axes, text, (x, y), colour) of ``labels`` beside its point, at the first
    of a few offsets (on the ``right`` of the points first, else on their left) where it
    overlaps no marker of its axes and no label placed before, stays inside the axes and is
    nearer its own point than any other marker; of those, one that crosses no curve if there
    is one. Where none is clear, the offset that breaks the fewest of these. Lays the figure
    out first: the boxes compared are the ones drawn."""
    import numpy as np
    from matplotlib.transforms import Bbox

    if not labels:
        return
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    points = fig.dpi / 72
    near = [(8, 4), (8, -12), (-8, 4), (-8, -12), (0, 10), (0, -18)]
    offsets = [(dx if right else -dx, dy) for dx, dy in near]
    offsets += [(2 * dx, 2 * dy) for dx, dy in offsets]
    placed: dict = {}

    def distance(box, xy) -> float:
        dx = max(box.x0 - xy[0], 0, xy[0] - box.x1)
        return float(np.hypot(dx, max(box.y0 - xy[1], 0, xy[1] - box.y1)))

    seen: dict = {}  # each axes' markers and curve points: the labels add neither

    def scan(ax):
        markers, centres = [], []
        along = [np.empty((0, 2))]  # points on the curves, in pixels
        for line in ax.get_lines():
            xyd = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
            xyd = ax.transData.transform(xyd[np.isfinite(xyd).all(axis=1)])
            if line.get_marker() in ("None", "", None, " "):
                # The curve's vertices and points between them, every few pixels: segment
                # (a, b) gives a + (b - a) t at t = 0, 1/n, ..., (n - 1)/n. At once, not
                # point by point (a figure of long branches spent seconds here).
                a, step = xyd[:-1], np.diff(xyd, axis=0)
                n = (np.hypot(step[:, 0], step[:, 1]) // (2 * points)).astype(np.int64) + 1
                seg = np.repeat(np.arange(len(a)), n)
                t = (np.arange(seg.size) - np.repeat(np.cumsum(n) - n, n)) / n[seg]
                along.append(a[seg] + step[seg] * t[:, None])
                continue
            half = (line.get_markersize() / 2 + line.get_markeredgewidth()) * points
            for px, py in xyd:
                markers.append(Bbox.from_extents(px - half, py - half, px + half, py + half))
                centres.append((px, py))
        return markers, centres, np.concatenate(along)

    for ax, text, xy, color in labels:
        if ax not in seen:
            seen[ax] = scan(ax)
        markers, centres, curves = seen[ax]
        own = ax.transData.transform(xy)
        others = [c for c in centres if np.hypot(*np.subtract(c, own)) > 0.5]
        frame = ax.get_window_extent(renderer)
        taken = placed.setdefault(ax, [])
        best = None
        for dx, dy in offsets:
            note = ax.annotate(
                text,
                xy,
                textcoords="offset points",
                xytext=(dx, dy),
                ha="left" if dx > 0 else "right" if dx < 0 else "center",
                fontsize=8,
                color=color,
            )
            note.set_in_layout(False)
            box = note.get_window_extent(renderer).padded(points)
            note.remove()
            hard = (
                (not (frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)))
                + sum(box.overlaps(m) for m in markers + taken)
                + sum(distance(box, c) <= distance(box, own) for c in others)
            )
            soft = int(
                np.sum(
                    (curves[:, 0] > box.x0)
                    & (curves[:, 0] < box.x1)
                    & (curves[:, 1] > box.y0)
                    & (curves[:, 1] < box.y1)
                )
            )
            if best is None or (hard, soft) < best[0]:
                best = ((hard, soft), note, box)
            if (hard, soft) == (0, 0):
                break
        assert best is not None  # offsets is never empty
        _, note, box = best
        ax.add_artist(note)
        taken.append(box)
