"""Figures of atlases: regime maps with the analytic boundaries on top."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

from . import atlas_format as fmt
from .atlas_grid import CoordinateError, coordinate
from .plot import plt, scale_ticks, unit_scale
from .plot_atlas_title import context, keep_title_inside, title
from .suggest import did_you_mean

#: what ``atlas_figure(metric=...)`` can colour a map by: a simulation's summary values (from
#: one start) and a steady state's (the fastest), each with its units and meaning
METRICS = {
    **{n: (f[2], f[3]) for n, f in fmt.RUN_FIELDS.items()},
    **{n: (f[2], f[3].replace(", fastest first", "")) for n, f in fmt.EQ_FIELDS.items()},
}
#: what a map's title calls a metric whose field name says little to a driller
WORDS = {
    "spectral_abscissa": "growth rate",
    "hopf_margin": "stability margin",
    "unstable": "unstable eigenvalues",
    "omega_eq": "steady bit velocity",
    "delta": "Stribeck slope",
    "bit_top_ratio": "bit over top-drive speed",
}
#: why a steady state's metric (``omega_eq``, ``hopf_margin``, ...) cannot be mapped
NO_STABILITY = "this atlas did not record stability ([record] stability = false)"
# Signed: zero is the stability boundary, so the colours diverge there.
SIGNED = ("spectral_abscissa", "hopf_margin")
#: a regime's colour on maps and profiles (light: hatching and curves on top stay visible)
MAP_COLORS = {
    "steady": "#58d68d",
    "stick-slip": "#f5b041",
    "stuck": "#85929e",
    "oscillation": "#af7ac5",
    "failed": "#e74c3c",
    "missing": "#d5d8dc",  # as a metric map's blanks (white ran into the safe outline)
    "no-steady-state": "#d6eaf8",
}
#: what the axes are called on a figure (others by their own name)
AXIS_LABELS = {
    "wob": "weight on bit $W_{ob}$",
    "torque": "surface torque $u$",
    "dof": "degrees of freedom",
    "pipes": "drill pipes",
}
#: the SI unit of each axis that is not a model parameter, as a figure shows it
AXIS_SI = {"wob": "N", "torque": "N·m", "dof": "", "pipes": "", "depth": "m"}

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.figure import Figure


def drawn_axes(
    atlas, x: str | None, y: str | None, at: Mapping[str, float | str], profile: bool
) -> tuple[str, str | None, bool]:
    """The axes a figure of ``atlas`` draws, as ``atlas_figure`` chooses them: x, y (None for
    a profile) and whether it is a profile; every other axis is held, at ``at`` or its first
    value. ValueError for axes that do not fit the atlas."""
    order = list(atlas.axes)
    profile = profile or len(order) < 2  # one axis: nothing to map, a profile along it
    if profile and y is not None:
        why = f": this atlas has one axis, {order[0]}" if len(order) < 2 else " with --profile"
        raise ValueError(f"y = {y!r}{why}: a profile is drawn along x alone")
    for what, name in [("x", x), ("y", y)] + [("a held axis", n) for n in at]:
        if name is not None and name not in order:
            raise CoordinateError(
                f"{what} = {name!r} is not an axis of this atlas{did_you_mean(name, order)}; "
                f"axes: {', '.join(order)}"
            )
    if x is not None and x == y:
        raise ValueError(f"x and y are both {x!r}: a map needs two different axes")
    if {x, y} & set(at):
        raise ValueError(f"{sorted(set(at) & {x, y})[0]!r} is drawn; it cannot also be held")
    swept_first = sorted(order, key=lambda n: len(atlas.axes[n]) <= 1)
    free = [n for n in swept_first if n not in (x, y) and n not in at]
    if y is None and len(free) + (x is not None) == 1:
        # Every axis but one held (torque=8.3 on a (W_ob, u) atlas): a map has one axis left,
        # and the figure asked for is the profile along it.
        profile = True
    if len(free) < (x is None) + (y is None and not profile):
        raise ValueError(f"no axis left to draw: {', '.join(order)} are all given as x, y or held")
    xname = x or free.pop(0)
    yname = None if profile else y or free.pop(0)
    return xname, yname, profile


def atlas_figure(
    atlas,
    initial: str | None = None,
    x: str | None = None,
    y: str | None = None,
    at: Mapping[str, float | str] | None = None,
    metric: str | None = None,
    profile: bool = False,
) -> Figure:
    """Regime map of an atlas on the axes ``x`` and ``y`` (default: its first two swept ones),
    every other axis held at the grid value nearest ``at[name]`` (default: its first value;
    a ValueError more than half a grid step past either end, as ``Atlas.value`` refuses).
    On (W_ob, u) the stuck boundary u = μ_sb W_ob R_b and the first Hopf curve of the string
    at those values are drawn on top (the paper's Figs. 6b and 12); on other axes, the stuck
    boundary found at the grid points and where the fastest steady state's recorded spectral
    abscissa changes sign (see ``plot_atlas_bounds``). A regime map of an atlas with stability
    outlines its safe cells (``Atlas.safe_region``) in white.
    With ``profile`` (and always when one axis is left, of an atlas of one axis or all others
    held by ``at``: no map there) the figure is a profile along ``x`` instead, every other
    axis held as above: the bit velocity from each start with the fastest steady state and
    its stability, or ``metric``, above a regime strip per start (``plot_atlas_line``).

    With ``metric`` (a name of ``METRICS``: ``severity``, ``stuck_fraction``, ``period``,
    ``spectral_abscissa``, ...) the map is coloured by that value instead, with a colour bar
    in its units: a simulation's from ``initial``, a steady state's of the fastest one. Signed
    stability values (``spectral_abscissa``, ``hopf_margin``) are coloured about zero, red
    where unstable. A steady state's metric of an atlas swept without stability (``[record]
    stability = false``) is refused (ValueError): there is nothing to map."""
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap

    j = atlas._initial_index(initial)  # (TypeError, CoordinateError: as regimes() has them)
    init = atlas.initials[j]
    if metric is not None and metric not in METRICS:
        raise ValueError(f"metric = {metric!r} is not allowed: one of {', '.join(METRICS)}")
    if metric in fmt.EQ_FIELDS and not atlas.spec.record["stability"]:
        raise ValueError(f"metric = {metric!r}: {NO_STABILITY}")
    order = list(atlas.axes)
    at = dict(at or {})
    xname, yname, profile = drawn_axes(atlas, x, y, at, profile)
    held: dict[str, float] = {}
    index: list[int | slice] = []
    for name in order:
        values = atlas.axes[name]
        if name in (xname, yname):
            index.append(slice(None))
            continue
        k = nearest_index(atlas, name, at[name]) if name in at else 0
        held[name] = float(values[k])
        index.append(k)
    if profile:
        from .plot_atlas_line import profile_figure

        return profile_figure(atlas, init, metric, xname, held, index)
    assert yname is not None
    # A simulation's value from the start drawn; a steady state's of the fastest (column 0).
    column = 0 if metric in fmt.EQ_FIELDS else j
    grid = atlas._f[metric or "regime"][..., column][tuple(index)]
    regime = atlas._f["regime"][..., j][tuple(index)]
    if order.index(xname) > order.index(yname):
        grid, regime = grid.T, regime.T
    # grid is (x, y); plot y vertical.
    fig, ax = plt.subplots(figsize=(9.5, 6.2), layout="constrained")
    xs, ys = atlas.axes[xname], atlas.axes[yname]
    handles: list[Artist] = []
    if metric is None:
        shown, colors = list(MAP_COLORS), list(MAP_COLORS.values())
        lut = {fmt.REGIMES[n]: k for k, n in enumerate(shown)}
        mesh = ax.pcolormesh(
            *_cells(xs, ys),
            np.vectorize(lut.get)(grid).T,
            cmap=ListedColormap(colors),
            norm=BoundaryNorm(np.arange(-0.5, len(shown) + 0.5), len(shown)),
        )
        present = sorted({int(c) for c in np.unique(grid)}, key=lambda c: lut[c])
        handles = [_regime_patch(colors[lut[c]], fmt.REGIME_NAMES[c]) for c in present]
        if "caveat" in atlas._f:  # runs whose judgement carries a note: simulate them longer
            caveat = atlas._f["caveat"][..., j][tuple(index)]
            caveat = caveat.T if order.index(xname) > order.index(yname) else caveat
            away = np.isin(caveat, [fmt.CAVEATS[c] for c in fmt.FINAL_CAVEATS])
            longer = (caveat != 0) & ~away
            if np.any(longer):
                label = "judged with a caveat: simulate longer"
                handles.append(_hatch_cells(ax, mesh, longer, "..", label))
            if np.any(away):  # c_r + c_b = 0: no longer run settles these
                label = "run-away: no steady state holds the bit"
                handles.append(_hatch_cells(ax, mesh, away, "xx", label))
        from .plot_atlas_bounds import safe_outline

        swap = order.index(xname) > order.index(yname)
        handles += safe_outline(atlas, ax, mesh, index, swap)
        what = f"regime from {init}"
    else:
        # A stuck bit has no velocity spread (severity 0, as steady drilling): hatch it.
        stuck = regime == fmt.REGIMES["stuck"] if metric in fmt.RUN_FIELDS else None
        handles, what = _metric_mesh(fig, ax, xs, ys, grid, metric, init, stuck)
    si = AXIS_SI
    # A real string's forces in kN, torques in kN·m (the data stay in N and N·m).
    scales = {
        n: unit_scale(atlas.axes[n] if n in order else atlas.spec.fixed[n], si[n])
        for n in ("wob", "torque")
        if n in order or n in atlas.spec.fixed
    }
    units = {**si, **{n: unit for n, (_, unit) in scales.items()}}  # as shown: kN, kN·m
    labels = AXIS_LABELS
    for name, values, set_label, set_ticks, axis in (
        (xname, xs, ax.set_xlabel, ax.set_xticks, ax.xaxis),
        (yname, ys, ax.set_ylabel, ax.set_yticks, ax.yaxis),
    ):
        unit = units[name] if name in units else shown_unit(name)
        set_label(labels.get(name, name) + (f" ({unit})" if unit else ""))
        if len(values) <= 12 and np.all(values == np.round(values)):
            set_ticks(values)  # a few whole numbers (dof, pipes): a tick on each
        if name in scales:
            scale_ticks(axis, scales[name][0])
    from .plot_atlas_bounds import boundaries

    handles += boundaries(atlas, ax, xname, yname, held, index)
    if metric is None:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9)
    elif handles:  # the colour bar is on the right: the legend goes below
        ax.legend(
            handles=handles,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.1),
            # One row if it fits under the map; else two, not wider than it.
            ncol=len(handles) if sum(len(str(h.get_label())) for h in handles) < 90 else 2,
            fontsize=9,
        )
    string, count = context(atlas, held, scales)
    after = "" if metric in fmt.EQ_FIELDS else f" after {atlas.spec.simulation['t_end']:g} s"
    ax.set_title(title(string, f"{what}{after} ({count})"), fontsize=10)
    if metric is not None:
        _fit_bar_label(fig, fig.axes[1])  # the colour bar's axes
    keep_title_inside(fig, ax)
    return fig


def _regime_patch(color: str, name: str) -> Artist:
    """A regime's legend swatch; a light one edged in grey (missing: light grey on white)."""
    from matplotlib.colors import to_rgb
    from matplotlib.patches import Patch

    light = min(to_rgb(color)) > 0.8
    return Patch(facecolor=color, edgecolor="0.55" if light else color, label=name)


def shown_unit(name: str) -> str:
    """A model parameter's unit as a figure shows it (``N·m·s/rad``); "" for a dimensionless
    one (a friction coefficient, the Stribeck decay)."""
    from .model import _UNITS

    unit = _UNITS.get(name, "1")
    return "" if unit in ("1", "friction coefficient") else unit


def nearest_index(atlas, name: str, value: float | str) -> int:
    """The index of the grid value of axis ``name`` nearest ``value``; a ValueError beyond half
    a grid step past either end (or off an axis of one value), as ``Atlas.value(method=
    "nearest")`` refuses: the map would be drawn for a place the sweep never went."""
    probe: dict[str, float | str] = {n: float(v[0]) for n, v in atlas.axes.items()}
    probe[name] = coordinate(name, value)  # (float() of None or "9 kN·m" named no axis)
    return atlas.index("nearest", **probe)[list(atlas.axes).index(name)]


def _edges(v):
    """Cell edges about grid values ``v`` (increasing): halfway between neighbours, half a step
    beyond the ends, as pcolormesh's shading="nearest" draws them. A single value gets a cell
    of ±5 % (±0.5 about zero): "nearest" has no step to take and drew nothing."""
    import numpy as np

    v = np.asarray(v, dtype=float)
    if len(v) == 1:
        half = 0.05 * abs(v[0]) or 0.5
        return np.array([v[0] - half, v[0] + half])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


#: the hatching's colours: dark grey on the light cells, white on the dark ones
HATCH_DARK, HATCH_LIGHT = "0.3", "white"


def _hatch_cells(ax, mesh, where, hatch: str, label: str):
    """Hatch exactly the cells where ``where`` (x, y) holds, with the edges the colour mesh
    gives them (a contour would interpolate between grid points: a diagonal band across
    neighbouring cells), in whichever of dark grey and white stands out more on each cell's
    colour (grey on viridis' dark purple, a severity of 0, could not be seen); the legend's
    handle."""
    import numpy as np
    from matplotlib.collections import PatchCollection
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Patch, Rectangle

    edges = mesh.get_coordinates()  # (len(y) + 1, len(x) + 1, 2)
    faces = mesh.to_rgba(mesh.get_array()).reshape(*edges.shape[:2] - np.array([1, 1]), 4)
    dark: dict[tuple[int, int], Rectangle] = {}
    light: dict[tuple[int, int], Rectangle] = {}
    for i, j in zip(*np.nonzero(np.asarray(where).T), strict=True):
        cell = Rectangle(edges[i, j], *(edges[i + 1, j + 1] - edges[i, j]))
        face = faces[i, j]
        better = contrast(face, to_rgba(HATCH_LIGHT)) > contrast(face, to_rgba(HATCH_DARK))
        (light if better else dark)[i, j] = cell
    for color, cells in ((HATCH_DARK, dark), (HATCH_LIGHT, light)):
        if cells:
            ax.add_collection(
                PatchCollection(
                    list(cells.values()), facecolor="none", edgecolor=color, lw=0, hatch=hatch
                ),
                autolim=False,
            )
    return Patch(facecolor="none", edgecolor=HATCH_DARK, hatch=hatch, label=label)


def contrast(a, b) -> float:
    """The WCAG contrast ratio of two RGB(A) colours (1: the same lightness, 21: black and
    white)."""

    def luminance(c) -> float:
        rgb = [x / 12.92 if x <= 0.04045 else ((x + 0.055) / 1.055) ** 2.4 for x in c[:3]]
        return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]

    hi, lo = sorted((luminance(a), luminance(b)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


def _cells(x, y):
    """pcolormesh's coordinates: the cell edges along x and y."""
    return _edges(x), _edges(y)


def _extent(v) -> tuple[float, float]:
    """Axis limits: the first and last grid values (edge cells show half, as in the paper's
    maps), or a single value's whole cell."""
    if len(v) == 1:
        e = _edges(v)
        return float(e[0]), float(e[-1])
    return float(min(v)), float(max(v))


def _fit_bar_label(fig, bar) -> None:
    """Wrap the label of the colour bar's axes ``bar`` onto as many lines as keep it within
    the bar's height: on one line, bit_top_ratio's (110 characters) ran off the top of the
    figure. Last, once the legend below the map has shortened the bar."""
    import textwrap

    fig.draw_without_rendering()
    label = bar.yaxis.label
    room = 0.98 * bar.get_window_extent().height
    long = label.get_window_extent().height
    if long > room:
        text = label.get_text()
        width = max(20, int(0.9 * len(text) * room / long))  # words break early
        label.set_text("\n".join(textwrap.wrap(text, width)))


def _metric_mesh(fig, ax, x, y, grid, metric: str, init: str, stuck=None) -> tuple[list, str]:
    """Colour the map by ``metric`` with a colour bar; cells without a value (no steady state,
    a failed or missing point) in grey, ``stuck`` ones (a boolean grid) hatched. Returns the
    legend handles and the title's words."""
    import numpy as np
    from matplotlib import colormaps
    from matplotlib.colors import BoundaryNorm, Normalize, SymLogNorm
    from matplotlib.patches import Patch

    unit, meaning = METRICS[metric]
    values = np.ma.masked_invalid(np.asarray(grid, dtype=float))
    field = fmt.RUN_FIELDS.get(metric) or fmt.EQ_FIELDS[metric]
    counts = field[0].startswith("i")  # stick_events, unstable: counts, -1 for "no value"
    if counts:
        values = np.ma.masked_less(values, 0)
    lo, hi = (float(values.min()), float(values.max())) if values.count() else (0.0, 1.0)
    # A count of a few values (unstable eigenvalues: 0, 2, 4, ...): a colour for each whole
    # number, not a gradient that says 0 and 1 are nearly the same colour.
    discrete = counts and hi - lo <= 20
    norm: Normalize
    if discrete:
        cmap = colormaps["viridis"].resampled(int(hi - lo) + 1)
        norm = BoundaryNorm(np.arange(lo - 0.5, hi + 1.5), cmap.N)
    elif metric in SIGNED:  # red where unstable (> 0 abscissa; < 0 margin), blue where stable
        cmap = colormaps["RdBu" if metric == "hopf_margin" else "RdBu_r"]
        span = max(abs(lo), abs(hi), 1e-12)
        # Logarithmic on either side of zero: stable steady states sit close to it (-0.016/s
        # on the laboratory string) while unstable ones reach 3/s, and on a linear scale all
        # the stable ones would look white.
        norm = SymLogNorm(linthresh=span / 1000, linscale=0.3, vmin=-span, vmax=span)
    else:
        cmap, norm = colormaps["viridis"], Normalize(lo, hi if hi > lo else lo + 1)
    cmap = cmap.with_extremes(bad="#d5d8dc")
    mesh = ax.pcolormesh(*_cells(x, y), values.T, cmap=cmap, norm=norm)
    shown_unit = "" if unit == "1" else f" ({unit.replace(' ', '·')})"
    bar = fig.colorbar(mesh, ax=ax, pad=0.01)
    bar.set_label(f"{metric}{shown_unit}: {meaning}", fontsize=9)
    if discrete:  # a tick on each whole number (on every other one past ten of them)
        bar.set_ticks(np.arange(lo, hi + 1, 1 if hi - lo < 10 else 2))
        bar.minorticks_off()
    elif isinstance(norm, SymLogNorm):  # SIGNED: whole decades, clear of the band about 0
        top = math.floor(math.log10(span))
        decades = [10.0**d for d in range(math.ceil(math.log10(norm.linthresh)) + 1, top + 1)]
        bar.set_ticks([-d for d in decades[::-1]] + [0.0] + decades)
    blank = "no steady state (or not computed)" if metric in fmt.EQ_FIELDS else "no value"
    handles = [Patch(color="#d5d8dc", label=blank)] if values.mask.any() else []
    if stuck is not None and stuck.any():
        handles.append(_hatch_cells(ax, mesh, stuck, "////", "bit stuck"))
    steady = metric in fmt.EQ_FIELDS
    # A driller's words first, the field's name (what --metric takes) after them.
    name = f"{WORDS[metric]} ({metric})" if metric in WORDS else metric
    return handles, f"{name} " + ("of the fastest steady state" if steady else f"from {init}")
