"""Figures of the reproduction's analysis: the paper's Figs. 6b, 10, 11, 12, and their analogues
for long strings with the multiple Hopf crossings and their criticality."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .model import preset
from .operating import hopf_curve_wu, operating_map
from .plot import place_legend, plt, save
from .plot_atlas import MAP_COLORS
from .reproduce_plots_branch import FOLD, SUB, SUPER, _branch_panel, name_points
from .stability import boundary_wob

SLIDE = "black"
REGIME_ORDER = ("steady", "stick-slip", "stuck", "oscillation", "no-steady-state")


def _regime_image(ax, x, y, regimes) -> None:
    from matplotlib.colors import ListedColormap

    codes = np.vectorize(lambda r: REGIME_ORDER.index(r) if r in REGIME_ORDER else 4)(
        np.asarray(regimes, dtype=object)
    )
    # The colours of `pydrill atlas plot`'s maps, opaque: the same regimes looked different in
    # the two figures of the same atlas, and REGIME_COLORS at 55 % left steady and stuck 13
    # CIELAB units apart to a deuteranope (21 or more apart now).
    colors = [MAP_COLORS[r] for r in REGIME_ORDER]
    ax.pcolormesh(
        x,
        y,
        codes.T,
        cmap=ListedColormap(colors),
        vmin=-0.5,
        vmax=4.5,
        shading="nearest",
        rasterized=True,
    )


def fig6b(out: Path, numbers: dict[str, Any]) -> Path:
    from matplotlib.patches import Patch

    a = numbers["atlas_fig06b"]
    wob, torque = np.array(a["axes"]["wob"]), np.array(a["axes"]["torque"])
    p = preset("reduced-scale", dof=4)
    fig, axes = plt.subplots(1, 2, figsize=(14, 6), layout="constrained", sharey=True)
    for ax, init, title in zip(
        axes,
        ("rest", "equilibrium"),
        ("(a) started from rest", "(b) started near the steady state"),
        strict=True,
    ):
        _regime_image(ax, wob, torque, a[init]["regime"])
        w = np.linspace(0, wob.max() * 1.02, 100)
        ax.plot(
            w,
            p.static_torque(w),  # broadcasts over W_ob
            color=SLIDE,
            lw=2,
            label="$u^+ = \\mu_{sb} R_b W_{ob}$ (Eq. 38)",
        )
        for case, (ww, uu) in {
            "Fig. 9": (40, 8.3),
            "Fig. 4": (100, 8.3),
            "Fig. 7": (160, 8.3),
        }.items():
            ax.plot(ww, uu, "o", mfc="white", mec="black", ms=8)
            # On a white ground: the line u+ ran through "Fig. 4".
            ax.annotate(
                case,
                (ww, uu),
                xytext=(6, 7),
                textcoords="offset points",
                fontsize=9,
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85},
            )
        ax.set_xlim(wob.min() - 2.5, wob.max() + 2.5)
        ax.set_ylim(torque.min() - 0.25, torque.max() + 0.25)
        ax.set_xlabel("weight on bit $W_{ob}$ (N)")
        ax.set_title(title, fontsize=10)
    axes[0].set_ylabel("surface torque $u$ (N·m)")
    handles = [Patch(color=MAP_COLORS[r], label=r) for r in REGIME_ORDER[:4]]
    blank = MAP_COLORS["no-steady-state"]
    handles.append(Patch(color=blank, label="no steady state to start from"))
    handles += axes[0].get_legend_handles_labels()[0]
    axes[1].legend(handles=handles, fontsize=9, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    s = numbers["fig06b_band"]
    fig.suptitle(
        "Fig. 6(b) — where the bit sticks and slips: a band along $u^+ = \\mu_{sb} R_b W_{ob}$ "
        f"(n = 8, {len(wob) * len(torque)} simulations × 2 starts; at u = 8.3 N·m stick-slip "
        f"for {s['wob_lo']:g}–{s['wob_hi']:g} N, $W^*_{{ob}}$ = {s['wob_star']:.2f} N)",
        fontweight="bold",
        fontsize=11,
    )
    return save(fig, out / "fig06b_regime_map.png")


def fig10_title(typo_roots: list[float]) -> str:
    """Fig. 10's title, with what the paper's printed Δ₂ = a₁ − a₂ − a₀ gives for Eq. (14):
    its root in δ (linear) is negative, so no positive root (the title once said "no root")."""
    typo = "has no positive root" if not typo_roots else f"has its root at δ = {typo_roots[0]:.4g}"
    return (
        "Fig. 10 — (Ω, $W_{ob}$) where steady drilling is stable, n' = 3: below $\\mathcal{H}_2$ "
        f"(Δ₂ = a₂a₁ − a₀ = 0; the paper's printed Δ₂ = a₁ − a₂ − a₀ {typo})"
    )


def fig10(out: Path, numbers: dict[str, Any], pipes: tuple[int, ...]) -> Path:
    fig, axes = plt.subplots(1, 2, figsize=(14, 6), layout="constrained")
    for ax, key, name, w_max in (
        (axes[0], "fig10a", "reduced-scale", 10.0),
        (axes[1], "fig10b", "real-string", 6.0),
    ):
        n = numbers[key]
        p = preset(name, dof=2)
        omega = np.linspace(0, w_max, 400)
        h2 = boundary_wob(p, n["h2_delta"], omega)
        h1 = boundary_wob(p, n["h1_delta"], omega)
        fold = boundary_wob(p, n["fold_delta"], omega)
        scale = 1e-3 if name == "real-string" else 1.0
        ax.fill_between(
            omega, h2 * 1e-6 * scale, h2 * scale, color="#abebc6", label="stable steady state"
        )
        ax.plot(
            omega,
            h2 * scale,
            color=SUB,
            lw=2.4,
            label=f"$\\mathcal{{H}}_2$: Hopf locus, δ = {n['h2_delta']:.5g} "
            f"({n['h2_frequency']:.3g} rad/s, "
            f"{'subcritical' if n['lyapunov_h2'] > 0 else 'supercritical'})",
        )
        ax.plot(
            omega,
            fold * scale,
            ":",
            color=FOLD,
            lw=1.6,
            label=f"$a_0 = 0$ (fold): δ = $c_r + c_b$ = {n['fold_delta']:.4g}",
        )
        ax.plot(
            omega,
            h1 * scale,
            "--",
            color="#7d3c98",
            lw=1.6,
            label=f"$\\mathcal{{H}}_1$: Δ₂ = 0 outside $\\mathcal{{H}}_+$, δ = {n['h1_delta']:.4g}",
        )
        if name == "reduced-scale":
            for k, pp in enumerate(pipes):
                d = numbers[f"pipes{pp}"]["summary"]["first"]["delta"]
                ax.plot(
                    omega,
                    boundary_wob(p, d, omega),
                    color="0.35",
                    lw=0.9,
                    ls=(0, (1 + k, 2)),
                    label=f"first Hopf curve, {pp} pipes: δ = {d:.4g}",
                )
        ax.set_yscale("log")
        ax.set_xlim(0, w_max)
        ax.set_ylim(h2[0] * scale / 3, h2[-1] * scale * 3)
        ax.set_xlabel("steady rotary velocity Ω (rad/s)")
        ax.set_ylabel("weight on bit $W_{ob}$ (" + ("kN" if scale != 1.0 else "N") + ")")
        ax.grid(alpha=0.3, which="both")
        # Clear of the curves: in the upper left the fold and H1 lines of (a) ran under it.
        place_legend(ax, fontsize=8)
        ax.set_title(
            "(a) laboratory string, Eq. (14)"
            if name == "reduced-scale"
            else "(b) real string, Eq. (53)",
            fontsize=10,
        )
    fig.suptitle(
        fig10_title(numbers["fig10a"]["typo_roots"]),
        fontweight="bold",
        fontsize=11,
    )
    return save(fig, out / "fig10_stability_region.png")


def fig11(out: Path, numbers: dict[str, Any]) -> Path:
    fig, axes = plt.subplots(2, 2, figsize=(15, 10.5), layout="constrained")
    panels = [
        _branch_panel(ax, numbers[f"fig11{letter}"], numbers.get(f"atlas_fig11{letter}"), letter)
        for ax, letter in zip(axes.ravel(), "abcd", strict=True)
    ]
    axes[0, 1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(
        "Fig. 11 — bifurcation diagrams of steady drilling (Eq. 14): Hopf points (squares) with "
        "their criticality;\nstick-slip (circles) coexists with the stable branch below HB1",
        fontweight="bold",
    )
    name_points(fig, panels)
    return save(fig, out / "fig11_bifurcation.png")


def _hopf_wu(ax, p, curves, fold_delta, wob_max, torque_max, first_only=False) -> None:
    omega = np.linspace(1e-4, 80.0, 4000)
    shown = 0
    for c in curves:
        w, u = hopf_curve_wu(p, c["delta"], omega)
        keep = (w <= wob_max * 1.1) & (u <= torque_max * 1.1)
        if not keep.any():
            continue
        first = shown == 0 and c["direction"] > 0
        if first_only and not first:
            ax.plot(w[keep], u[keep], color="#922b21", lw=0.5, alpha=0.4)
            continue
        color = SUB if (c["lyapunov"] or 0) > 0 else (SUPER if c["lyapunov"] else "0.5")
        l1 = f", $l_1$ = {c['lyapunov']:.2g}" if c["lyapunov"] is not None else ""
        ax.plot(
            w[keep],
            u[keep],
            color=color,
            lw=2.4 if first else 1.2,
            ls="-" if c["direction"] > 0 else "-.",
            label=f"HB{shown + 1}: δ = {c['delta']:.4g}, {c['frequency']:.3g} rad/s{l1}"
            + ("" if c["direction"] > 0 else " (restabilising)"),
        )
        shown += 1
    if fold_delta:
        w, u = hopf_curve_wu(p, fold_delta, omega)
        keep = (w <= wob_max * 1.1) & (u <= torque_max * 1.1)
        ax.plot(w[keep], u[keep], ":", color=FOLD, lw=2, label="fold (LP): δ = $c_r + c_b$")
    wob = np.linspace(0, wob_max, 50)
    ax.plot(
        wob,
        p.static_torque(wob),
        color=SLIDE,
        lw=1.5,
        label="$u^+ = \\mu_{sb} R_b W_{ob}$ (Fig. 6b)",
    )
    ax.set_xlim(0, wob_max)
    ax.set_ylim(0, torque_max)
    ax.set_xlabel("weight on bit $W_{ob}$ (N)")
    ax.set_ylabel("surface torque $u$ (N·m)")
    ax.grid(alpha=0.3)


def fig12(out: Path, numbers: dict[str, Any]) -> Path:
    fig, axes = plt.subplots(1, 2, figsize=(15, 6.2), layout="constrained", sharey=True)
    for ax, dof, letter in ((axes[0], 2, "a"), (axes[1], 4, "b")):
        p = preset("reduced-scale", dof=dof)
        f12 = numbers["strings"][f"dof{dof}"]["fig12"]
        wob, torque = np.linspace(1, 200, 160), np.linspace(0.1, 16, 160)
        om = operating_map(p, wob, torque)
        stable = (om.category <= 1).astype(float)
        ax.contourf(wob, torque, stable, levels=[0.5, 1.5], colors=["#d5f5e3"])
        if dof == 4 and "atlas_fig06b" in numbers:
            a = numbers["atlas_fig06b"]
            reg = np.array(a["rest"]["regime"], dtype=object)
            ww, uu = np.meshgrid(a["axes"]["wob"], a["axes"]["torque"], indexing="ij")
            ss = reg == "stick-slip"
            ax.plot(
                ww[ss],
                uu[ss],
                ".",
                color="#e67e22",
                ms=4,
                label="stick-slip from rest (atlas of Fig. 6b)",
            )
        _hopf_wu(ax, p, f12["curves"], f12["fold_delta"], 200, 16)
        ax.plot([], [], color="#d5f5e3", lw=8, label="a stable steady state exists")
        ax.set_title(f"({letter}) n' = {2 * dof - 1} (dof {dof})", fontsize=10)
    fig.suptitle(
        "Fig. 12 — ($W_{ob}$, $u$) at which a Hopf point appears (Eq. 14): one curve per "
        "critical slope $\\delta_k$, each of one criticality",
        fontweight="bold",
    )
    for ax in axes:  # upper left, (b)'s hid the stick-slip points of W_ob 90-103 N above 10.6 N·m
        place_legend(ax, fontsize=8)
    return save(fig, out / "fig12_hopf_wob_torque.png")


def draw_analysis(out: Path, numbers: dict[str, Any], pipes: tuple[int, ...]) -> list[Path]:
    from .reproduce_plots_long import fig11_long, fig12_long, multiple_hopf

    paths = [
        fig6b(out, numbers),
        fig10(out, numbers, pipes),
        fig11(out, numbers),
        fig12(out, numbers),
    ]
    paths += [fig11_long(out, numbers, pp) for pp in pipes]
    paths += [fig12_long(out, numbers, pipes), multiple_hopf(out, numbers, pipes)]
    return paths
