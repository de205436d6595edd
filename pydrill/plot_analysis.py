"""Figures of the stability analysis: boundaries, eigenvalues, bifurcations, the operating map."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .plot import plt

if TYPE_CHECKING:
    from matplotlib.figure import Figure


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
            f"{(first.frequency or 0):.3g} rad/s{_criticality_note(params, first)}",
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


def _criticality_note(params, crossing) -> str:
    """ ", subcritical ($l_1$ = …)" for a Hopf crossing: what happens past the boundary."""
    from .stability import criticality

    l1 = crossing.lyapunov(params)
    return "" if l1 is None else f", {criticality(l1)} ($l_1$ = {l1:.2g})"


def bifurcation_figure(params, branch) -> Figure:
    """The paper's Fig. 11: steady velocity against the varied parameter, stable solid,
    unstable dashed, Hopf (HB) and fold (LP) points marked with their criticality. Long
    strings have hundreds of Hopf points: then only the first (highest Ω, where the stable
    branch ends) is labelled. Where the special points crowd into a small part of the range,
    an inset zooms in on them."""
    import numpy as np

    fig, ax = plt.subplots(figsize=(9, 5.8), layout="constrained")
    x = branch.wob if branch.vary == "wob" else branch.torque
    hb = sorted((pt for pt in branch.points if pt.type == "HB"), key=lambda pt: -pt.omega)
    few = len(hb) <= 4

    def draw(ax, labels: bool, short: bool = False) -> None:
        stable = branch.unstable == 0
        for mask, style, label in (
            (stable, "-", "stable steady state"),
            (~stable, "--", "unstable steady state"),
        ):
            y = np.where(mask, branch.omega, np.nan)
            color = "#1f618d" if style == "-" else "#922b21"
            ax.plot(x, y, style, color=color, lw=2, label=label)
        for i, pt in enumerate(hb):
            px = pt.wob if branch.vary == "wob" else pt.torque
            color = "#27ae60" if pt.criticality == "supercritical" else "#c0392b"
            ax.plot(px, pt.omega, "s", color=color, ms=8 if few else 5, zorder=5)
            if labels and (few or i == 0):
                ax.annotate(
                    f"HB{i + 1}"
                    if short
                    else f"HB{i + 1} ({pt.criticality[:3]}), {pt.frequency:.3g} rad/s",
                    (px, pt.omega),
                    textcoords="offset points",
                    # Varying the torque, the stable branch leaves HB1 to the upper right;
                    # close points get their labels one under the other.
                    xytext=(8, 6 - 11 * (i % 3))
                    if branch.vary == "wob"
                    else (-8, 8 - 11 * (i % 3)),
                    ha="left" if branch.vary == "wob" else "right",
                    fontsize=8,
                    color=color,
                )
        for pt in branch.points:
            if pt.type == "LP":
                px = pt.wob if branch.vary == "wob" else pt.torque
                ax.plot(px, pt.omega, "D", color="black", ms=7, zorder=5)
                if labels:
                    # Beside the fold, away from the branch's two arms.
                    ax.annotate(
                        "LP",
                        (px, pt.omega),
                        textcoords="offset points",
                        xytext=(8, -12) if branch.vary == "wob" else (-10, -3),
                        ha="left" if branch.vary == "wob" else "right",
                        fontsize=8,
                    )

    xs = np.array([pt.wob if branch.vary == "wob" else pt.torque for pt in branch.points])
    zoom = len(xs) > 1 and np.ptp(xs) < 0.15 * np.ptp(x)
    draw(ax, labels=not zoom)
    if zoom:
        # The special points sit within a few per cent of the range: zoom in on them.
        pad = max(0.15 * np.ptp(xs), 0.01 * xs.max())
        top = max(pt.omega for pt in branch.points)
        ins = ax.inset_axes(
            [0.5, 0.4, 0.47, 0.42] if branch.vary == "wob" else [0.5, 0.08, 0.47, 0.42]
        )
        draw(ins, labels=True, short=True)
        ins.set_xlim(xs.min() - pad, xs.max() + 2 * pad)
        ins.set_ylim(0, top * 1.25 + 0.3)
        ins.tick_params(labelsize=7)
        ins.grid(alpha=0.3)
        first = f"; HB1 at {hb[0].frequency:.3g} rad/s, {hb[0].criticality}" if hb else ""
        ins.set_title(f"{len(hb)} Hopf points{first}", fontsize=8)
        ax.indicate_inset_zoom(ins, edgecolor="0.4")
    if branch.vary == "wob":
        ax.set_xlabel("weight on bit $W_{ob}$ (N)")
        fixed = f"$u$ = {branch.fixed:g} N·m"
    else:
        ax.set_xlabel("surface torque $u$ (N·m)")
        fixed = f"$W_{{ob}}$ = {branch.fixed:g} N"
    ax.set_ylabel("steady bit velocity $\\Omega$ (rad/s)")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    sub = sum(pt.criticality == "subcritical" for pt in hb)
    ax.plot([], [], "s", color="#c0392b", label=f"Hopf point, subcritical ({sub})")
    ax.plot([], [], "s", color="#27ae60", label=f"Hopf point, supercritical ({len(hb) - sub})")
    ax.plot([], [], "D", color="black", label="limit point (fold)")
    ax.legend(fontsize=9, loc="upper left" if zoom else "best")
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
