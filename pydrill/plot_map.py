"""The figure of ``pydrill map``: the (W_ob, u) operating map, where a stable steady state
exists and where the bit can stay stuck, with the sliding boundary, the Hopf and fold curves and
the regimes simulated from rest (the paper's Figs. 6b and 12)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .atlas_schema import FAILED
from .plot import fit_suptitle, plt, scale_ticks, unit_scale

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: a check whose simulation failed (map and window draw it alike): a grey question mark
FAILED_MARKER = r"$\mathbf{?}$"
FAILED_COLOR = "#424949"
FAILED_LABEL = "failed (no result; the output says why)"


def operating_figure(params, omap, crossings, checks=None) -> Figure:
    """(W_ob, u) map: where a stable steady state exists and where the bit can stay stuck, the
    sliding boundary u = μ_sb W_ob R_b, the Hopf and fold curves, and simulated regimes:
    ``checks`` are (W_ob, u, regime), a regime "failed" where the simulation failed (drawn as a
    grey question mark)."""
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    from .operating import CATEGORIES, hopf_curve_wu
    from .stability import unstable_count

    # Stable but the bit can stay stuck: the safe green, paler and hatched grey (both may
    # happen). It was light blue, the colour the atlas maps give "no steady state".
    colors = ["#abebc6", "#e3f7ea", "#f8c471", "#d5d8dc"]
    hatch = "//"
    fig, ax = plt.subplots(figsize=(10, 6.5), layout="constrained")
    from .plot_atlas import _edges

    def edges(v):
        """Cell edges about the grid ``v``, the first at 0 when the grid starts within a step
        of it (the command's grids start at 1/200 of their range): the axes then start at
        zero, with a 0 on each (they began at 1.25 N and 0.125 N·m, unlabelled)."""
        e = _edges(v)
        if len(v) > 1 and 0 < v[0] <= v[1] - v[0]:
            e[0] = 0.0
        return e

    x_edges, y_edges = edges(omap.wob), edges(omap.torque)
    ax.pcolormesh(
        x_edges,
        y_edges,
        omap.category,
        cmap=ListedColormap(colors),
        norm=BoundaryNorm(np.arange(-0.5, 4.5), 4),
        rasterized=True,
    )
    if (omap.category == 1).any():
        with plt.rc_context({"hatch.color": "0.6", "hatch.linewidth": 0.6}):
            ax.contourf(
                omap.wob,
                omap.torque,
                (omap.category == 1).astype(float),
                levels=[0.5, 1.5],
                colors="none",
                hatches=[hatch],
            )
    ax.plot(
        omap.wob,
        omap.static_torque,
        color="black",
        lw=2,
        label="$u = \\mu_{sb} W_{ob} R_b$ (sliding boundary, Eq. 38)",
    )
    omega = np.linspace(1e-3, 60.0, 2000)
    first = next((c for c in crossings if c.direction > 0 and c.type == "hopf"), None)
    if first is not None and unstable_count(crossings, first.delta) > 0:
        # Something is unstable before it (the fold at δ = 0 of a string without damping at
        # its ends): a crossing, but no boundary of stable drilling; as atlas plot draws it.
        first = None
    for c in crossings:
        if c.delta == 0:  # on the axis W_ob = 0: no curve in the map (its colours say it)
            continue
        w, u = hopf_curve_wu(params, c.delta, omega)
        keep = (w <= omap.wob.max() * 1.05) & (u <= omap.torque.max() * 1.05)
        if c.type == "fold":
            ax.plot(w[keep], u[keep], "--", color="#1f618d", lw=1.3, label="fold (LP) curve")
        elif c is first:
            ax.plot(w[keep], u[keep], color="#922b21", lw=2, label="first Hopf curve")
    if checks:
        marks = {
            "steady": ("o", "#1e8449"),
            "stick-slip": ("x", "#b9770e"),
            "stuck": ("s", "#566573"),
            "oscillation": ("^", "#7d3c98"),
            # a check whose simulation failed: drawn, not left out (the text says why)
            FAILED: (FAILED_MARKER, FAILED_COLOR),
        }
        for regime, (marker, color) in marks.items():
            pts = [(w, u) for w, u, r in checks if r == regime]
            if pts:
                ax.scatter(
                    [pt[0] for pt in pts],
                    [pt[1] for pt in pts],
                    marker=marker,
                    color=color,
                    s=80 if regime == FAILED else 26,
                    label=f"simulated from rest: {FAILED_LABEL if regime == FAILED else regime}",
                    zorder=5,
                    clip_on=False,  # the check grid ends on the map's edges: markers whole
                )
    ax.set_xlim(min(x_edges[0], omap.wob.min()), omap.wob.max())
    ax.set_ylim(min(y_edges[0], omap.torque.min()), omap.torque.max())
    xscale, xunit = unit_scale(omap.wob, "N")
    yscale, yunit = unit_scale(omap.torque, "N·m")
    scale_ticks(ax.xaxis, xscale)
    scale_ticks(ax.yaxis, yscale)
    ax.set_xlabel(f"weight on bit $W_{{ob}}$ ({xunit})")
    ax.set_ylabel(f"surface torque $u$ ({yunit})")
    handles, labels = ax.get_legend_handles_labels()
    # The categories the map shows (the legend named one the real string's map has not).
    shown = [k for k in range(len(colors)) if (omap.category == k).any()]
    handles += [
        Patch(facecolor=colors[k], edgecolor="0.6", lw=0, hatch=hatch if k == 1 else None)
        for k in shown
    ]
    labels += [list(CATEGORIES)[k] for k in shown]
    ax.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    # Over the whole figure, wrapped to fit: over the axes alone a tally's longer name pushed
    # the line off the figure's left edge. Stick-slip along the boundary is said where the
    # checks found it (a real string's 4 x 4 check found none, and the title said it anyway).
    slipped = any(r == "stick-slip" for _, _, r in checks or [])
    fit_suptitle(
        fig,
        f"{params.name}, dof {params.dof}: safe drilling = stable steady state (green) above "
        "the sliding boundary"
        + ("; from rest, stick-slip still fills a band along it (the paper's ε⁺, ρ⁺)" * slipped),
        fontsize=10,
    )
    return fig
