"""Figures of the reproduction's simulations: the paper's Figs. 4, 5, 7, 8 and 9.

Each shows what the paper's figure shows (same quantities, same projections of the state
space) with labels, units, the paper's markers (● x_in, ◆ x_out, ★ quasi-equilibrium) and the
numbers pydrill computed in the title. Figs. 7, 8 and 9, of the sliding region, are drawn in
:mod:`pydrill.reproduce_figures_sliding` with this module's styles.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .plot import plt, save
from .reproduce_figures_sliding import fig7, fig8, fig9

TOP, PIPE, COLLAR, BIT = "#2c3e50", "#2874a6", "#239b56", "#c0392b"
SIGMA = "#f5b041"
STYLE = {  # the paper's line styles: top dotted, pipe dashed, collars and bit solid
    "top": dict(color=TOP, ls=":", lw=1.6, label="top rotary system $\\varphi_r$"),
    "pipe": dict(color=PIPE, ls="--", lw=1.3, label="drill pipe $\\varphi_1$"),
    "collar": dict(color=COLLAR, ls="-", lw=1.3, label="drill collars $\\varphi_l$"),
    "bit": dict(color=BIT, ls="-", lw=1.6, label="bit $\\varphi_b$"),
}


def _switch_points(run, which: str) -> list[int]:
    kinds = ("stick",) if which == "in" else ("slip",)
    return [int(np.searchsorted(run.t, s.t)) for s in run.switches if s.kind in kinds]


def _chain(run, key: str, ax, t_max: float, velocity: bool) -> None:
    k = {"top": 0, "pipe": 1, "collar": -2, "bit": -1}[key]
    keep = run.t <= t_max
    label = str(STYLE[key]["label"])
    y = run.omega if velocity else run.angles
    if velocity:
        label = label.replace("\\varphi", "\\dot\\varphi")
    ax.plot(run.t[keep], y[keep, k], **{**STYLE[key], "label": label})


def _mark_switches(ax, run, y: np.ndarray, t_max: float) -> None:
    for which, marker, label in (
        ("in", "o", "$x_{in}$ (bit sticks)"),
        ("out", "D", "$x_{out}$ (bit slips)"),
    ):
        idx = [i for i in _switch_points(run, which) if run.t[min(i, len(run.t) - 1)] <= t_max]
        idx = [min(i, len(run.t) - 1) for i in idx]
        if which == "in":
            idx = [0, *idx] if run.mode_index[0] >= 2 else idx
        ax.plot(run.t[idx], y[idx], marker, color="black", ms=6, ls="none", label=label, zorder=5)


def fig4(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    run = runs["exact"]
    ex = n["exact"]
    t_max = 100.0
    fig, (ax_a, ax_b) = plt.subplots(2, 1, figsize=(11, 8), sharex=True, layout="constrained")
    phi = run.angles
    for key in ("top", "pipe", "collar", "bit"):
        _chain(run, key, ax_a, t_max, velocity=False)
        _chain(run, key, ax_b, t_max, velocity=True)
    _mark_switches(ax_a, run, phi[:, -1], t_max)
    _mark_switches(ax_b, run, run.omega[:, -1], t_max)
    for a, b in run.stick_intervals():
        if a < t_max:
            for ax in (ax_a, ax_b):
                ax.axvspan(a, min(b, t_max), color=SIGMA, alpha=0.18, lw=0)
    ax_a.set_ylabel("angular displacement (rad)")
    ax_b.set_ylabel("angular velocity (rad/s)")
    ax_b.set_xlabel("time (s)")
    ax_b.set_xlim(0, t_max)
    ax_a.set_title("(a) angular displacements — the bit advances in steps", fontsize=10, loc="left")
    ax_b.set_title(
        f"(b) angular velocities — the bit is stuck {100 * ex['stuck_fraction']:.0f} % of "
        "the time (shaded), then spins up to "
        f"{ex['bit_max']:.3g} rad/s = {ex['bit_top_ratio']:.2g}× the mean top speed",
        fontsize=10,
        loc="left",
    )
    for ax in (ax_a, ax_b):
        ax.grid(alpha=0.3)
    ax_a.legend(fontsize=9, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax_b.legend(fontsize=9, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(
        f"Fig. 4 — stick-slip, n = 8 (dof 4), $W_{{ob}}$ = 100 N, u = 8.3 N·m: period "
        f"{ex['period']:.4g} s\n(pydrill, exact friction, from rest; the paper's Karnopp "
        f"model, Eq. 9: {n['karnopp']['period']:.4g} s)",
        fontweight="bold",
    )
    return save(fig, out / "fig04_stick_slip.png")


def _axes3d(fig, pos, labels):
    ax = fig.add_subplot(pos, projection="3d")
    for setter, lab in zip((ax.set_xlabel, ax.set_ylabel, ax.set_zlabel), labels, strict=True):
        setter(lab, fontsize=9)
    ax.tick_params(labelsize=8)
    return ax


def fig5(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    fig = plt.figure(figsize=(14, 6.2), layout="constrained")
    ax = _axes3d(
        fig,
        121,
        (
            "$\\varphi_r - \\varphi_b$ (rad)",
            "$\\dot\\varphi_r$ (rad/s)",
            "$\\dot\\varphi_b$ (rad/s)",
        ),
    )
    cmap = plt.cm.viridis
    wobs = sorted(runs["orbits"])
    # The whole colour map over the orbits drawn (a stuck bit's is the point ★, drawn grey):
    # spread over all seven W_ob, 90 N and 100 N were two near-identical purples.
    moving = [w for w in wobs if runs["orbits"][w].summary.regime != "stuck"]
    for i, w in enumerate(wobs):
        r = runs["orbits"][w]
        keep = r.t >= r.t[-1] - 40.0
        k = moving.index(w) if w in moving else None
        color = "0.55" if k is None else cmap(0.85 * k / max(len(moving) - 1, 1))
        reg = r.summary.regime
        ax.plot(
            r.twist[keep, 0],
            r.omega[keep, 0],
            r.omega[keep, -1],
            color=color,
            lw=1.1,
            label=f"$W_{{ob}}$ = {w:g} N: {reg}"
            + (f", period {r.summary.period:.3g} s" if r.summary.period else " (at ★)"),
        )
        for which, marker in (("in", "o"), ("out", "D")):
            idx = [min(i, len(r.t) - 1) for i in _switch_points(r, which)]
            idx = [i for i in idx if keep[i]]
            x, y, z = r.twist[idx, 0], r.omega[idx, 0], r.omega[idx, -1]
            ax.plot(x, y, z, marker, color="black", ms=5, ls="none")
    qe = n["quasi_equilibrium_twist"]
    ax.plot([qe], [0], [0], "*", color="black", ms=14, label="quasi-equilibrium ($u/k_t$, 0, 0)")
    ax.plot([], [], "o", color="black", ms=5, ls="none", label="$x_{in}$")
    ax.plot([], [], "D", color="black", ms=5, ls="none", label="$x_{out}$")
    # Beside the 3-D box, not on it: inside the axes it hid the box's upper corner.
    fig.legend(*ax.get_legend_handles_labels(), fontsize=8, loc="outside lower left", ncol=5)
    ax.set_title("(a) each $W_{ob}$'s attractor from rest (last 40 s)", fontsize=10)
    ax.view_init(elev=22, azim=-62)
    ax_b = fig.add_subplot(122)
    for t0, w, r in runs["segments"]:
        ax_b.plot(r.t + t0, r.omega[:, -1], color=BIT, lw=0.9)
        ax_b.plot(r.t + t0, r.omega[:, 0], color=TOP, ls="--", lw=1.0)
        ax_b.axvline(t0, color="0.6", lw=0.8)
        ax_b.text(t0 + 3, 66, f"{w:g} N", fontsize=8, color="0.25")
    ax_b.plot([], [], color=BIT, label="bit $\\dot\\varphi_b$")
    ax_b.plot([], [], color=TOP, ls="--", label="top $\\dot\\varphi_r$")
    ax_b.set_ylim(-2, 72)
    ax_b.set_xlabel("time (s); $W_{ob}$ raised every 100 s, the motion carried over")
    ax_b.set_ylabel("angular velocity (rad/s)")
    ax_b.grid(alpha=0.3)
    ax_b.legend(fontsize=9, loc="center right")
    iv = n["interval"]
    ax_b.set_title(
        f"(b) stick-slip from rest for {iv['lower']:.1f} < $W_{{ob}}$ < {iv['upper']:.1f} N, "
        "stuck above\n(a start-up overshoots the static limit "
        f"$W^*_{{ob}} = u/(\\mu_{{sb}} R_b)$ = {iv['wob_star']:.2f} N)",
        fontsize=10,
    )
    fig.suptitle(
        "Fig. 5 — n = 4 (dof 2), u = 8.1 N·m, $W_{ob}$ from 90 to 150 N: larger $W_{ob}$, "
        "longer sticking, then a stuck bit",
        fontweight="bold",
    )
    return save(fig, out / "fig05_wob_steps.png")


def draw_simulations(out: Path, numbers: dict[str, Any], runs: dict[str, Any]) -> list[Path]:
    return [
        fig4(out, numbers["fig04"], runs["fig04"]),
        fig5(out, numbers["fig05"], runs["fig05"]),
        fig7(out, numbers["fig07"], runs["fig07"]),
        fig8(out, numbers["fig08"], runs["fig08"]),
        fig9(out, numbers["fig09"], runs["fig09"]),
    ]
