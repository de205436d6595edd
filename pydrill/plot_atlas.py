"""Figures of atlases: regime maps with the analytic boundaries on top."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .plot import plt

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def atlas_figure(atlas, initial: str | None = None) -> Figure:
    """Regime map of an atlas on its two first non-trivial axes, with the stuck boundary
    u = μ_sb W_ob R_b and the first Hopf curve when the axes are (W_ob, u) (Figs. 6b, 12)."""
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    from . import atlas_format as fmt

    init = initial or atlas.initials[0]
    j = atlas.initials.index(init) if init in atlas.initials else None
    if j is None:
        raise ValueError(f"initial = {init!r} is not in this atlas: {atlas.initials}")
    names = [n for n, v in atlas.axes.items() if len(v) > 1]
    if len(names) < 2:
        names = list(atlas.axes)[:2]
    if len(names) < 2:
        raise ValueError("the atlas has one axis: a map needs two")
    xname, yname = names[0], names[1]
    codes = atlas._f["regime"][..., j]
    # Collapse any other axis by taking its first value.
    order = list(atlas.axes)
    sl = tuple(slice(None) if n in (xname, yname) else 0 for n in order)
    grid = codes[sl]
    if order.index(xname) > order.index(yname):
        grid = grid.T
    # grid is (x, y); plot y vertical.
    shown = ["steady", "stick-slip", "stuck", "oscillation", "failed", "missing", "no-steady-state"]
    colors = ["#58d68d", "#f5b041", "#85929e", "#af7ac5", "#e74c3c", "#ffffff", "#d6eaf8"]
    lut = {fmt.REGIMES[n]: k for k, n in enumerate(shown)}
    img = np.vectorize(lut.get)(grid).T
    fig, ax = plt.subplots(figsize=(9.5, 6.2), layout="constrained")
    x, y = atlas.axes[xname], atlas.axes[yname]
    ax.pcolormesh(
        x,
        y,
        img,
        cmap=ListedColormap(colors),
        norm=BoundaryNorm(np.arange(-0.5, len(shown) + 0.5), len(shown)),
        shading="nearest",
    )
    units = {"wob": "N", "torque": "N·m", "dof": "", "pipes": "", "depth": "m"}
    label = {
        "wob": "weight on bit $W_{ob}$",
        "torque": "surface torque $u$",
        "dof": "degrees of freedom",
        "pipes": "drill pipes",
    }
    ax.set_xlabel(f"{label.get(xname, xname)} ({units.get(xname, 'SI')})")
    ax.set_ylabel(f"{label.get(yname, yname)} ({units.get(yname, 'SI')})")
    present = sorted({int(c) for c in np.unique(grid)}, key=lambda c: lut[c])
    handles = [Patch(color=colors[lut[c]], label=fmt.REGIME_NAMES[c]) for c in present]
    if {xname, yname} == {"wob", "torque"} and len(atlas.axes) == 2:
        from .stability import critical_deltas

        params = atlas.spec.params_at({})
        wob = np.linspace(
            x.min() if xname == "wob" else y.min(), x.max() if xname == "wob" else y.max(), 200
        )
        ts = params.static_torque(wob)
        first = next(
            (c for c in critical_deltas(params) if c.type == "hopf" and c.direction > 0), None
        )
        curves = [(wob, ts, "black", "-", "stuck boundary $u = \\mu_{sb} W_{ob} R_b$")]
        if first is not None:
            from .operating import hopf_curve_wu

            w, u = hopf_curve_wu(params, first.delta, np.linspace(1e-3, 80, 3000))
            curves.append((w, u, "#922b21", "--", "first Hopf curve (steady state stable above)"))
        for cw, cu, color, style, lab in curves:
            px, py = (cw, cu) if xname == "wob" else (cu, cw)
            ax.plot(px, py, style, color=color, lw=2, label=lab)
        ax.set_xlim(x.min(), x.max())
        ax.set_ylim(y.min(), y.max())
        handles += ax.get_legend_handles_labels()[0]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9)
    s = atlas.spec
    total = int(np.prod(atlas.shape))
    missing = atlas.summary()["status"]["missing"]
    # An interrupted sweep's atlas: say so, or the white cells read as a regime of their own.
    count = f"{total - missing} of {total} points done" if missing else f"{total} points"
    ax.set_title(
        f"{s.preset}, dof {s.dof if s.dof else 'swept'}: regime from {init} "
        f"after {s.simulation['t_end']:g} s ({count})",
        fontsize=10,
    )
    return fig
