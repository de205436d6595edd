"""Figures of the reproduction beyond the paper: Figs. 11 and 12 for long strings, and the
multiple Hopf crossings with their criticality."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .model import preset
from .operating import hopf_curve_wu
from .plot import fit_suptitle, plt, save
from .reproduce_plots import FOLD, SUPER, _branch_panel, _hopf_wu, name_points


def fig11_long(out: Path, numbers: dict[str, Any], pipes: int) -> Path:
    n = numbers[f"pipes{pipes}"]
    fig, axes = plt.subplots(1, 2, figsize=(15, 5.8), layout="constrained")
    panels = [
        _branch_panel(
            ax, n[f"fig11{letter}"], numbers.get(f"atlas_pipes{pipes}-fig11{letter}"), letter
        )
        for ax, letter in zip(axes, "cd", strict=True)
    ]
    axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    s = n["summary"]
    fig.suptitle(
        f"Fig. 11 (c, d) for {pipes} drill pipes (dof {s['dof']}, n' = {s['n_prime']}): "
        f"{s['hopf']} Hopf crossings, up to {s['max_unstable']} unstable eigenvalues",
        fontweight="bold",
    )
    name_points(fig, panels)
    return save(fig, out / f"fig11_pipes{pipes}.png")


def fig12_long(out: Path, numbers: dict[str, Any], pipes: tuple[int, ...]) -> Path:
    fig, axes = plt.subplots(
        1, len(pipes), figsize=(6 * len(pipes), 6), layout="constrained", sharey=True, squeeze=False
    )
    base = numbers["strings"]["dof2"]["fig12"]["curves"][0]["delta"]
    for ax, pp in zip(axes[0], pipes, strict=True):
        n = numbers[f"pipes{pp}"]
        p = preset("reduced-scale", pipes=pp)
        _hopf_wu(ax, p, n["fig12"]["curves"], n["fig12"]["fold_delta"], 200, 16, first_only=True)
        w, u = hopf_curve_wu(p, base, np.linspace(1e-4, 80, 4000))
        keep = (w < 220) & (u < 17.6)
        ax.plot(w[keep], u[keep], "--", color="0.2", lw=1.2, label="first Hopf curve of n' = 3")
        ax.plot([], [], color="#922b21", lw=0.5, label="further Hopf curves")
        ax.legend(fontsize=8, loc="upper left")
        s = n["summary"]
        ax.set_title(f"{pp} pipes (n' = {s['n_prime']}): {s['hopf']} Hopf curves", fontsize=10)
    fit_suptitle(  # one panel (--quick) is narrower than the title
        fig,
        "Fig. 12 for long strings: the first Hopf curve bounds stable drilling; the "
        "others lie just beyond it",
        fontweight="bold",
    )
    return save(fig, out / "fig12_long_strings.png")


def multiple_hopf(out: Path, numbers: dict[str, Any], pipes: tuple[int, ...]) -> Path:
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(15, 6), layout="constrained")
    strings = [("dof 4 (n' = 7)", numbers["strings"]["dof4"])]
    strings += [
        (f"{pp} pipes (n' = {numbers[f'pipes{pp}']['summary']['n_prime']})", numbers[f"pipes{pp}"])
        for pp in pipes
    ]
    markers = "osD^v"
    n_sub = n_all = 0
    for k, (label, d) in enumerate(strings):
        curves = d["fig12"]["curves"]
        delta = np.array([c["delta"] for c in curves])
        freq = np.array([c["frequency"] for c in curves])
        l1 = np.array([np.nan if c["lyapunov"] is None else c["lyapunov"] for c in curves])
        destab = np.array([c["direction"] > 0 for c in curves])
        color = ("#1f618d", "#d35400", "#7d3c98", "#117a65", "#b7950b")[k % 5]
        ax.scatter(
            delta[destab],
            freq[destab],
            marker=markers[k],
            color=color,
            s=18,
            label=f"{label}: {len(curves)} Hopf",
        )
        ax.scatter(
            delta[~destab],
            freq[~destab],
            marker=markers[k],
            facecolor="none",
            edgecolor=color,
            s=18,
        )
        pos, neg = np.isfinite(l1) & (l1 > 0), np.isfinite(l1) & (l1 < 0)
        ax2.scatter(freq[pos], l1[pos], marker=markers[k], color=color, s=18, label=label)
        ax2.scatter(
            freq[neg], -l1[neg], marker=markers[k], facecolor="none", edgecolor=SUPER, s=60, lw=1.5
        )
        n_sub += int(pos.sum())
        n_all += int(pos.sum() + neg.sum())
    ax.axvline(
        numbers["fig10a"]["fold_delta"],
        color=FOLD,
        ls=":",
        lw=1.5,
        label="fold: δ = $c_r + c_b$ (every string)",
    )
    ax.set_xscale("log")
    ax.set_xlabel("critical Stribeck slope $\\delta_k$ (N·m·s/rad)")
    ax.set_ylabel("Hopf frequency $\\omega_k$ (rad/s)")
    ax.grid(alpha=0.3, which="both")
    # Below the axes: every corner of either panel holds crossings of some string.
    ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3)
    ax.set_title(
        "(a) every Hopf crossing (filled: destabilising as δ grows, open: restabilising)",
        fontsize=10,
    )
    ax2.set_yscale("log")
    ax2.set_xlabel("Hopf frequency $\\omega_k$ (rad/s)")
    ax2.set_ylabel("first Lyapunov coefficient |$l_1$| (filled: $l_1$ > 0, subcritical)")
    ax2.grid(alpha=0.3, which="both")
    ax2.scatter(
        [],
        [],
        marker="o",
        facecolor="none",
        edgecolor=SUPER,
        s=60,
        lw=1.5,
        label="open, in green: |l₁| of a supercritical crossing (l₁ < 0), same shapes",
    )
    ax2.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
    ax2.set_title(
        f"(b) criticality: {n_sub} of {n_all} computed Hopf crossings are subcritical", fontsize=10
    )
    fig.suptitle(
        "Multiple Hopf crossings for n' > 3 (the paper: 'untractable') and their "
        "criticality (not in the paper)",
        fontweight="bold",
    )
    return save(fig, out / "hopf_multiple_criticality.png")
