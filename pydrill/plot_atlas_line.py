"""The figure of an atlas with one axis: what the bit does along it, and the regimes below.

A sweep of one value (a weight-on-bit ramp, a string growing pipe by pipe) has no map to
draw; its figure is the sweep's bifurcation diagram: the bit velocity's least, mean and
largest value from each start against the axis, the fastest steady state (solid where
stable, dashed where not), and under it a strip per start coloured by regime, as the maps
colour them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from . import atlas_format as fmt
from .plot import plt, scale_ticks, unit_scale
from .plot_atlas import (
    AXIS_LABELS,
    AXIS_SI,
    MAP_COLORS,
    METRICS,
    _edges,
    shown_unit,
)
from .plot_atlas_title import context, keep_title_inside, title

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: a start's line style on the profile (two starts side by side stay apart in grey print)
STARTS = {"rest": ("#1f4e79", "o"), "equilibrium": ("#7b241c", "s")}


def profile_figure(
    atlas, initial: str, metric: str | None, name: str, held: dict[str, float], index: list
) -> Figure:
    """A profile along the axis ``name``, every other axis held (``held``: their values,
    ``index``: the atlas's grid index, a slice along ``name``): bit velocities (or
    ``metric``) from every start (``initial`` first), the fastest steady state's velocity
    with its stability when recorded, and a strip per start coloured by regime."""
    import numpy as np
    from matplotlib.patches import Patch

    x = np.asarray(atlas.axes[name], dtype=float)
    cut = tuple(index)

    def read(dataset: str, j: int):
        """Dataset ``dataset`` along the profile, at start (or steady state) ``j``."""
        return atlas._f[dataset][..., j][cut]

    starts = [initial] + [s for s in atlas.initials if s != initial]
    columns = {s: atlas.initials.index(s) for s in starts}
    fig, (ax, strip) = plt.subplots(
        2,
        1,
        figsize=(9.5, 6.2),
        sharex=True,
        height_ratios=[5, 0.45 * len(starts)],
        layout="constrained",
    )
    lines = []
    if metric is None:
        for s in starts:
            j = columns[s]
            color, marker = STARTS.get(s, ("#1f4e79", "o"))
            low, mean, high = (read(k, j).astype(float) for k in ("bit_min", "bit_mean", "bit_max"))
            ax.fill_between(x, low, high, color=color, alpha=0.15, lw=0)
            (line,) = ax.plot(x, mean, marker=marker, ms=3, color=color, lw=1.2)
            line.set_label(f"from {s}: mean (band: least to largest)")
            lines.append(line)
        if atlas.spec.record["stability"]:
            lines += _steady_line(ax, x, read("omega_eq", 0), read("spectral_abscissa", 0))
        ax.set_ylabel("bit velocity (rad/s)")
        what = "bit velocity and regime"
    else:
        unit, meaning = METRICS[metric]
        steady = metric in fmt.EQ_FIELDS
        for s in starts[:1] if steady else starts:
            values = read(metric, 0 if steady else columns[s]).astype(float)
            if (fmt.RUN_FIELDS.get(metric) or fmt.EQ_FIELDS[metric])[0].startswith("i"):
                values[values < 0] = np.nan  # a count's -1: not measured
            color, marker = STARTS.get(s, ("#1f4e79", "o"))
            label = "fastest steady state" if steady else f"from {s}"
            (line,) = ax.plot(x, values, marker=marker, ms=3, color=color, lw=1.2, label=label)
            lines.append(line)
            stuck = read("regime", columns[s]) == fmt.REGIMES["stuck"]
            if not steady and stuck.any():
                # A stuck bit's severity is 0, as steady drilling's: crossed out, as the maps
                # hatch those cells (a profile drew them as plain points on the zero line).
                cross = ax.scatter(
                    x[stuck], values[stuck], marker="x", color=color, s=64, lw=1.6, zorder=4
                )
                cross.set_label(f"from {s}: bit stuck")
                lines.append(cross)
        if metric in ("spectral_abscissa", "hopf_margin"):
            ax.axhline(0.0, color="0.4", lw=0.8, ls=":")  # the stability boundary
        shown = "" if unit == "1" else f" ({unit.replace(' ', '·')})"
        ax.set_ylabel(f"{metric}{shown}")
        what = f"{metric}: {meaning}"
    ax.grid(alpha=0.3)
    # Zero in view: autoscaled to the data alone, steady drilling's last 1e-4 of residual
    # wobble (9.1185 ... 9.1203 rad/s along depth) filled the plot as if the bit shook.
    ax.update_datalim([(float(x[0]), 0.0)], updatex=False)
    ax.autoscale_view(scalex=False)
    # The regime strip: one row per start, each cell as wide as its grid value's.
    codes = np.array([read("regime", columns[s]) for s in starts])
    order = {fmt.REGIMES[n]: k for k, n in enumerate(MAP_COLORS)}
    from matplotlib.colors import BoundaryNorm, ListedColormap

    colors = list(MAP_COLORS.values())
    strip.pcolormesh(
        _edges(x),
        np.arange(len(starts) + 1),
        np.vectorize(order.get)(codes),
        cmap=ListedColormap(colors),
        norm=BoundaryNorm(np.arange(-0.5, len(colors) + 0.5), len(colors)),
        edgecolors="face",
    )
    strip.set_yticks(np.arange(len(starts)) + 0.5, [f"from {s}" for s in starts], fontsize=9)
    strip.set_ylim(len(starts), 0)
    strip.tick_params(axis="y", length=0)
    present = sorted({int(c) for c in np.unique(codes)}, key=lambda c: order[c])
    regimes = [Patch(color=colors[order[c]], label=fmt.REGIME_NAMES[c]) for c in present]
    ax.legend(handles=lines, loc="best", fontsize=9, framealpha=0.9)
    # The regimes' key under the strip, in one row: the strip is as wide as the plot.
    fig.legend(
        handles=regimes, loc="outside lower center", ncol=len(regimes), fontsize=9, frameon=False
    )
    si = AXIS_SI.get(name)
    scale, si_unit = unit_scale(x, si) if si in ("N", "N·m") else (1.0, si)
    unit = shown_unit(name) if si_unit is None else si_unit
    strip.set_xlabel(AXIS_LABELS.get(name, name) + (f" ({unit})" if unit else ""))
    if len(x) <= 12 and np.all(x == np.round(x)):
        strip.set_xticks(x)  # a few whole numbers (dof, pipes): a tick on each
    scale_ticks(strip.xaxis, scale)
    lo, hi = _edges(x)[[0, -1]] if len(x) == 1 else (x[0], x[-1])
    ax.set_xlim(lo, hi)
    both = {**atlas.spec.fixed, **held}
    scales = {n: unit_scale(both[n], AXIS_SI[n]) for n in ("wob", "torque") if n in both}
    string, count = context(atlas, held, scales)
    if len(atlas.axes) > 1:  # a row of a bigger atlas: how many of its points are drawn
        count = f"{len(x)} points of an atlas of {count}"
    after = "" if metric in fmt.EQ_FIELDS else f" after {atlas.spec.simulation['t_end']:g} s"
    ax.set_title(title(string, f"{what}{after} ({count})"), fontsize=10)
    keep_title_inside(fig, ax)
    return fig


def _steady_line(ax, x, omega, abscissa) -> list:
    """The fastest steady state's bit velocity: solid where it is stable (every eigenvalue in
    the left half-plane), dashed where not; nothing where there is none."""
    import numpy as np

    omega = omega.astype(float)
    stable = abscissa < 0
    handles = []
    for where, style, face, label in (
        (stable, "-", "#196f3d", "fastest steady state, stable"),
        # open markers: an unstable steady state at one grid value alone is still seen
        (~stable, "--", "white", "fastest steady state, unstable"),
    ):
        shown = np.where(where, omega, np.nan)
        if np.isfinite(shown).any():
            (line,) = ax.plot(
                x, shown, style, color="#196f3d", lw=2, marker="o", ms=4, mfc=face, zorder=3
            )
            line.set_label(label)
            handles.append(line)
    return handles
