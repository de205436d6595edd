"""Figures people would rather look at than read (matplotlib, no screen needed)."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")  # files only: works on servers and in CI
import matplotlib.pyplot as plt
from matplotlib.patches import Patch
from matplotlib.ticker import Formatter

# Above KILO N (or N·m) a string is a real one: its forces in kN, torques in kN·m; one
# threshold for the figures and the commands' text.
from .cli_options import KILO

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .simulate import SimulationResult

BIT = "#c0392b"
TOP = "#2c3e50"
STICK = "#f5b041"
HELD = "#9c640c"  #: the torque held by the rock, drawn over the stick shading
EQUILIBRIUM = "#27ae60"

REGIME_COLORS = {
    "steady": "#27ae60",
    "stick-slip": "#e67e22",
    "stuck": "#7f8c8d",
    "oscillation": "#8e44ad",
}


def unit_scale(values, unit: str) -> tuple[float, str]:
    """(1e3, "kN") for the forces of a real string (any above ``KILO`` N), (1.0, "N") for the
    laboratory string's; the same for "N·m"."""
    import numpy as np

    v = np.abs(np.asarray(values, dtype=float))
    big = v.size and np.isfinite(v).any() and np.nanmax(v) > KILO
    return (1e3, "k" + unit) if big else (1.0, unit)


def quantity(value: float, unit: str, scale: float | None = None) -> str:
    """``60000, "N"`` → "60 kN", ``8.1, "N·m"`` → "8.1 N·m": in the units of ``unit_scale``
    (of ``value`` alone unless ``scale`` is given)."""
    if scale is None:
        scale, shown = unit_scale(value, unit)
    else:
        shown = unit if scale == 1.0 else "k" + unit
    return f"{value / scale:g} {shown}"


class _Scaled(Formatter):
    """Tick labels of an axis in N shown in kN: the labels its own formatter would write (or
    leave out), divided by ``scale``."""

    def __init__(self, inner: Formatter, scale: float) -> None:
        self.inner, self.scale = inner, scale

    def set_axis(self, axis) -> None:
        super().set_axis(axis)
        self.inner.set_axis(axis)

    def set_locs(self, locs) -> None:
        super().set_locs(locs)
        self.inner.set_locs(locs)

    def __call__(self, x, pos=None) -> str:
        return f"{x / self.scale:g}" if self.inner(x, pos) else ""


def scale_ticks(axis, scale: float) -> None:
    """Label the ticks of ``axis`` (ax.xaxis, ...) whose data are in N (N·m) in kN (kN·m):
    the data stay in SI, only the numbers written change. Call after setting its scale."""
    if scale != 1.0:
        axis.set_major_formatter(_Scaled(axis.get_major_formatter(), scale))
        axis.set_minor_formatter(_Scaled(axis.get_minor_formatter(), scale))


def simulation_figure(result: SimulationResult) -> Figure:
    """The paper's Fig. 4, readable at a glance: velocities over time with stick shaded (top),
    and the torque the rock must hold against its static limit ±T_s (bottom)."""
    s = result.summary
    fig, (ax_v, ax_t) = plt.subplots(
        2, 1, figsize=(11.5, 6.4), sharex=True, height_ratios=(3, 2), layout="constrained"
    )
    t = result.t
    intervals = result.stick_intervals()
    for ax in (ax_v, ax_t):
        for a, b in intervals:
            ax.axvspan(a, b, color=STICK, alpha=0.25, lw=0)
        ax.grid(alpha=0.3)
        ax.axvspan(s.window_start, s.window_end, color="0.5", alpha=0.06, lw=0)

    ax_v.plot(t, result.top_velocity, color=TOP, lw=1.3, label="top drive $\\omega_0$")
    ax_v.plot(t, result.bit_velocity, color=BIT, lw=1.3, label="bit $\\omega_b$")
    # A steady state past the fold is unstable on any string (the bit cannot stay there): not
    # drawn as the one it may settle at (both were "steady state Ω", 4.7 rpm beside 64.5 rpm).
    said = set()
    for omega, past in zip(s.omega_equilibrium, result.past_fold(), strict=True):
        label = "unstable steady state (past the fold)" if past else "steady state $\\Omega$"
        ax_v.axhline(
            omega,
            color="0.45" if past else EQUILIBRIUM,
            ls=":" if past else "--",
            lw=1,
            label=None if label in said else label,
        )
        said.add(label)
    ax_v.set_ylabel("angular velocity (rad/s)")
    # Zero in view, as on the atlas profiles: from equilibrium, autoscaled to the data alone,
    # a decaying wobble of 0.02 rad/s about 33.16 rad/s filled the panel as if the bit shook.
    ax_v.update_datalim([(float(t[0]), 0.0)], updatex=False)
    ax_v.autoscale_view(scalex=False)
    handles, labels = ax_v.get_legend_handles_labels()
    if intervals:
        handles.append(Patch(color=STICK, alpha=0.4))
        labels.append("bit stuck")
    handles.append(Patch(color="0.5", alpha=0.15))
    labels.append("window judged for the regime")
    ax_v.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9)

    te = result.reaction_torque
    held = result.mode_index >= 2  # stick or Karnopp band
    ax_t.plot(t, te, color=TOP, lw=1.1, label="reaction torque $T_e$")
    ax_t.axhline(s.static_torque, color=BIT, ls=":", lw=1.2, label="$T_s = \\mu_s W_{ob} R_b$")
    if te.min() < 0:  # the bit is pushed backwards too: show the lower limit
        ax_t.axhline(-s.static_torque, color=BIT, ls=":", lw=1.2, label="$-T_s$")
    ax_t.axhline(result.torque, color="0.4", ls="-.", lw=1, label="surface torque $u$")
    if held.any():
        # Darker than the stick shading it lies on (the shading's own orange was 1.6:1 on it).
        ax_t.plot(t[held], te[held], ".", color=HELD, ms=2, label="held by the rock")
    # A real string's torques in kN·m, even a light one's 3.8 kN·m beside its W_ob = 30 kN
    # (was "u = 3800 N·m" in the title beside "W_ob = 30 kN", and an axis in N·m).
    scale, unit = unit_scale([result.wob, result.torque, s.static_torque], "N·m")
    scale_ticks(ax_t.yaxis, scale)
    ax_t.set_ylabel(f"torque at the bit ({unit})")
    ax_t.set_xlabel("time (s)")
    ax_t.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9)
    ax_t.set_xlim(t[0], t[-1])

    p = result.params
    period = f", period {s.period:.3g} s" if s.period else ""
    fig.suptitle(
        f"{s.regime.upper()} — {p.name}, dof {p.dof}, $W_{{ob}}$ = {quantity(result.wob, 'N')}, "
        f"$u$ = {quantity(result.torque, 'N·m', scale)}",
        color=REGIME_COLORS.get(s.regime, "black"),
        fontweight="bold",
    )
    changed = _changed_fields(result)
    ax_v.set_title(
        f"bit {s.bit_min:.3g}…{s.bit_max:.3g} rad/s (mean {s.bit_mean:.3g}), "
        f"stuck {100 * s.stuck_fraction:.0f} % of the judged window{period}; "
        f"{s.stick_events} stick events" + "".join(f"\n{line}" for line in changed),
        fontsize=9,
        color="0.3",
    )
    if s.note:  # the verdict is not to be trusted yet: say so under the big regime title
        from .atlas_format import CAVEAT_TEXT

        short = CAVEAT_TEXT.get(s.caveat) or s.note
        ax_v.annotate(
            f"caveat: {s.caveat} — {short}" if s.caveat else f"caveat: {short}",
            xy=(0.5, 1.0),
            xycoords="axes fraction",
            xytext=(0, 20 + 11 * len(changed)),  # above the lines of the title
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=10,
            fontweight="bold",
            color="#a04000",
        )
    return fig


def _changed_fields(result: SimulationResult) -> list[str]:
    """The fields of the run's string that differ from its preset's (what ``--set`` or
    ``preset(..., bit_damping=...)`` changed), as lines for the figure to say which string it
    was (none for a preset's own string, or one that is no preset's)."""
    import textwrap

    from .model import _LISTS, _SCALARS, _UNITS

    inputs = result.inputs()
    if inputs["preset"] is None:
        return []
    shown = []
    for key in _LISTS + _SCALARS:
        if key not in inputs:
            continue
        if key in _LISTS:
            shown.append(f"{key} ({len(inputs[key])} values)")
        else:
            unit = "" if key.startswith("mu_") or _UNITS[key] == "1" else f" {_UNITS[key]}"
            shown.append(f"{key} = {inputs[key]:.3g}{unit}")
    if not shown:
        return []
    return textwrap.wrap(f"changed from {result.params.name}: " + ", ".join(shown), 130)


def fit_suptitle(fig: Figure, text: str, **kwargs):
    """``fig.suptitle(text)``, wrapped onto more lines where one would be wider than the figure
    (a one-panel figure cut a long title off at both edges); the title's Text."""
    import textwrap

    title = fig.suptitle(text, **kwargs)
    # The Agg canvas pydrill draws on has a renderer; FigureCanvasBase's stub does not say so.
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    room = 0.96 * fig.bbox.width
    width = title.get_window_extent(renderer).width
    if width > room:
        chars = max(20, int(len(text) * room / width))
        title.set_text("\n".join(textwrap.wrap(text, chars)))
    return title


def save(fig: Figure, path: str | Path, dpi: int = 130) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        # An axis of a range no tick can label (a window charted to 1e-300 rpm) collapses
        # matplotlib's layout, which it says in a UserWarning on stderr beside the notes; the
        # figure is saved without it, and the command has noted the range.
        warnings.filterwarnings("ignore", "constrained_layout not applied", UserWarning)
        fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


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
    insets = [c.get_window_extent().padded(14 * pad / 3) for c in ax.child_axes]
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
    if outside == "below" or twins:  # a twin's tick labels are on the right
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
