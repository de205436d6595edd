"""Figures people would rather look at than read (matplotlib, no screen needed)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")  # files only: works on servers and in CI
import matplotlib.pyplot as plt
from matplotlib.patches import Patch

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .simulate import SimulationResult

BIT = "#c0392b"
TOP = "#2c3e50"
STICK = "#f5b041"
EQUILIBRIUM = "#27ae60"

REGIME_COLORS = {
    "steady": "#27ae60",
    "stick-slip": "#e67e22",
    "stuck": "#7f8c8d",
    "oscillation": "#8e44ad",
}


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
    for k, omega in enumerate(s.omega_equilibrium):
        ax_v.axhline(
            omega,
            color=EQUILIBRIUM,
            ls="--",
            lw=1,
            label="steady state $\\Omega$" if k == 0 else None,
        )
    ax_v.set_ylabel("angular velocity (rad/s)")
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
        ax_t.plot(t[held], te[held], ".", color=STICK, ms=2, label="held by the rock")
    ax_t.set_ylabel("torque at the bit (N·m)")
    ax_t.set_xlabel("time (s)")
    ax_t.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9)
    ax_t.set_xlim(t[0], t[-1])

    p = result.params
    period = f", period {s.period:.3g} s" if s.period else ""
    fig.suptitle(
        f"{s.regime.upper()} — {p.name}, dof {p.dof}, $W_{{ob}}$ = {result.wob:g} N, "
        f"$u$ = {result.torque:g} N·m",
        color=REGIME_COLORS.get(s.regime, "black"),
        fontweight="bold",
    )
    ax_v.set_title(
        f"bit {s.bit_min:.3g}…{s.bit_max:.3g} rad/s (mean {s.bit_mean:.3g}), "
        f"stuck {100 * s.stuck_fraction:.0f} % of the judged window{period}; "
        f"{s.stick_events} stick events",
        fontsize=9,
        color="0.3",
    )
    return fig


def save(fig: Figure, path: str | Path, dpi: int = 130) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def hopf_figure(params, crossings, omega_max: float = 20.0, n: int = 400) -> Figure:
    """Stability boundaries in (Ω, W_ob) — the paper's Fig. 10 for any dof: regions coloured by
    the number of unstable eigenvalues, the Hopf curves W_ob(Ω) = δ_k e^{γΩ/v_f}/(…) on top."""
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D

    from .stability import boundary_wob, stability_map

    omega = np.linspace(0.0, omega_max, n)
    first = next((c for c in crossings if c.direction > 0), crossings[0])
    w_lo = float(boundary_wob(params, first.delta, 0.0)) / 3.0
    # Up to the boundary at Ω_max, but no more than four decades: beyond, no drill string goes.
    w_hi = min(
        max(float(boundary_wob(params, first.delta, omega_max)) * 3.0, 30.0 * w_lo), 1e4 * w_lo
    )
    wob = np.geomspace(w_lo, w_hi, n)
    counts = stability_map(params, omega, wob, crossings)
    top = max(int(counts.max()), 1)
    levels = np.arange(-0.5, top + 1.5)
    colors = ["#d5f5e3"] + [plt.cm.Oranges(0.25 + 0.65 * k / top) for k in range(1, top + 1)]
    fig, ax = plt.subplots(figsize=(9.5, 6.2), layout="constrained")
    mesh = ax.pcolormesh(
        omega,
        wob,
        counts,
        cmap=ListedColormap(colors),
        norm=BoundaryNorm(levels, len(colors)),
        shading="nearest",
        rasterized=True,
    )
    shown = 0
    for c in crossings:
        w = boundary_wob(params, c.delta, omega)
        if c.type == "fold":
            ax.plot(omega, w, "--", color="#1f618d", lw=1.4)
        elif shown < 8:
            ax.plot(
                omega,
                w,
                color="#7b241c" if c is first else "#922b21",
                lw=2.2 if c is first else 0.8,
                alpha=1.0 if c is first else 0.6,
            )
            shown += 1
    ax.set_yscale("log")
    ax.set_xlim(0, omega_max)
    ax.set_ylim(w_lo, w_hi)
    ax.set_xlabel("steady bit velocity $\\Omega$ (rad/s)")
    ax.set_ylabel("weight on bit $W_{ob}$ (N)")
    cbar = fig.colorbar(mesh, ax=ax, ticks=range(0, top + 1, max(1, top // 10)))
    cbar.set_label("unstable eigenvalues of the steady state")
    legend = [
        Line2D(
            [],
            [],
            color="#7b241c",
            lw=2.2,
            label=f"first Hopf: $\\delta_1$ = {first.delta:.4g} N·m·s/rad, "
            f"{(first.frequency or 0):.3g} rad/s",
        ),
        Line2D([], [], color="#922b21", lw=0.8, label="further Hopf crossings"),
        Line2D([], [], color="#1f618d", ls="--", label="fold ($\\delta = c_r + c_b$)"),
    ]
    ax.legend(handles=legend, loc="lower right", fontsize=9, framealpha=0.95)
    n_hopf = sum(c.type == "hopf" for c in crossings)
    ax.set_title(
        f"{params.name}, dof {params.dof}: steady drilling is stable below the first Hopf curve "
        f"({n_hopf} Hopf crossings in all)",
        fontsize=10,
    )
    return fig


def eigenvalue_figure(params, points) -> Figure:
    """Eigenvalues of each steady state in the complex plane, the unstable half-plane shaded."""
    fig, ax = plt.subplots(figsize=(8, 5.5), layout="constrained")
    ax.axvspan(0, 1, color="#f5b7b1", alpha=0.5, lw=0, label="unstable half-plane")
    markers = ["o", "s", "^"]
    for k, pt in enumerate(points):
        ev = pt.eigenvalues
        ax.scatter(
            [z.real for z in ev],
            [z.imag for z in ev],
            marker=markers[k % 3],
            s=28,
            label=f"Ω = {pt.omega:.4g} rad/s: {'stable' if pt.stable else 'UNSTABLE'}"
            f" ({pt.unstable} unstable)",
        )
    re = [z.real for pt in points for z in pt.eigenvalues]
    lo = min([*re, -0.1])
    hi = max([*re, 0.0])
    span = hi - lo
    ax.set_xlim(lo - 0.05 * span, max(hi + 0.15 * span, 0.1 * span))
    ax.axvline(0, color="black", lw=0.8)
    ax.set_xlabel("Re λ (1/s)")
    ax.set_ylabel("Im λ (rad/s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=9, loc="upper left")
    if points:
        ax.set_title(
            f"{params.name}, dof {params.dof}, $W_{{ob}}$ = {points[0].wob:g} N", fontsize=10
        )
    return fig


def bifurcation_figure(params, branch) -> Figure:
    """The paper's Fig. 11: steady velocity against the varied parameter, stable solid,
    unstable dashed, Hopf (HB) and fold (LP) points marked with their criticality."""
    import numpy as np

    fig, ax = plt.subplots(figsize=(9, 5.8), layout="constrained")
    x = branch.wob if branch.vary == "wob" else branch.torque
    stable = branch.unstable == 0
    for mask, style, label in (
        (stable, "-", "stable steady state"),
        (~stable, "--", "unstable steady state"),
    ):
        y = np.where(mask, branch.omega, np.nan)
        ax.plot(x, y, style, color="#1f618d" if style == "-" else "#922b21", lw=2, label=label)
    for pt in branch.points:
        px = pt.wob if branch.vary == "wob" else pt.torque
        if pt.type == "HB":
            color = "#27ae60" if pt.criticality == "supercritical" else "#c0392b"
            ax.plot(px, pt.omega, "s", color=color, ms=8, zorder=5)
            ax.annotate(
                f"HB ({pt.criticality[:3]}), {pt.frequency:.3g} rad/s",
                (px, pt.omega),
                textcoords="offset points",
                xytext=(8, 6),
                fontsize=8,
                color=color,
            )
        else:
            ax.plot(px, pt.omega, "D", color="black", ms=7, zorder=5)
            ax.annotate(
                "LP", (px, pt.omega), textcoords="offset points", xytext=(8, -12), fontsize=8
            )
    if branch.vary == "wob":
        ax.set_xlabel("weight on bit $W_{ob}$ (N)")
        fixed = f"$u$ = {branch.fixed:g} N·m"
    else:
        ax.set_xlabel("surface torque $u$ (N·m)")
        fixed = f"$W_{{ob}}$ = {branch.fixed:g} N"
    ax.set_ylabel("steady bit velocity $\\Omega$ (rad/s)")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.plot([], [], "s", color="#c0392b", label="Hopf point, subcritical")
    ax.plot([], [], "s", color="#27ae60", label="Hopf point, supercritical")
    ax.plot([], [], "D", color="black", label="limit point (fold)")
    ax.legend(fontsize=9, loc="best")
    ax.set_title(f"{params.name}, dof {params.dof}, {fixed}", fontsize=10)
    return fig


def operating_figure(params, omap, crossings, checks=None) -> Figure:
    """(W_ob, u) map: where a stable steady state exists and where the bit can stay stuck, the
    sliding boundary u = μ_sb W_ob R_b, the Hopf and fold curves, and simulated regimes."""
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    from .operating import CATEGORIES, hopf_curve_wu

    colors = ["#abebc6", "#d6eaf8", "#f8c471", "#d5d8dc"]
    fig, ax = plt.subplots(figsize=(10, 6.5), layout="constrained")
    ax.pcolormesh(
        omap.wob,
        omap.torque,
        omap.category,
        cmap=ListedColormap(colors),
        norm=BoundaryNorm(np.arange(-0.5, 4.5), 4),
        shading="nearest",
        rasterized=True,
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
    for c in crossings:
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
        }
        for regime, (marker, color) in marks.items():
            pts = [(w, u) for w, u, r in checks if r == regime]
            if pts:
                ax.scatter(
                    *zip(*pts, strict=True),
                    marker=marker,
                    color=color,
                    s=26,
                    label=f"simulated from rest: {regime}",
                    zorder=5,
                )
    ax.set_xlim(omap.wob.min(), omap.wob.max())
    ax.set_ylim(omap.torque.min(), omap.torque.max())
    ax.set_xlabel("weight on bit $W_{ob}$ (N)")
    ax.set_ylabel("surface torque $u$ (N·m)")
    handles, labels = ax.get_legend_handles_labels()
    handles += [Patch(color=c) for c in colors]
    labels += list(CATEGORIES)
    ax.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(
        f"{params.name}, dof {params.dof}: the analysis' safe set (green) is a stable steady state "
        "above the sliding boundary;\nfrom rest, stick-slip still fills a band along that boundary "
        "(the paper's ε⁺, ρ⁺)"
        if checks
        else f"{params.name}, dof {params.dof}: safe drilling = stable steady state above "
        "the sliding boundary",
        fontsize=10,
    )
    return fig


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
    units = {"wob": "N", "torque": "N·m", "dof": "", "pipes": ""}
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
    ax.set_title(
        f"{s.preset}, dof {s.dof if s.dof else 'swept'}: regime from {init} "
        f"after {s.simulation['t_end']:g} s ({int(np.prod(atlas.shape))} points)",
        fontsize=10,
    )
    return fig
