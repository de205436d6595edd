"""Figures of the reproduction's simulations: the paper's Figs. 4, 5, 7, 8 and 9.

Each shows what the paper's figure shows (same quantities, same projections of the state
space) with labels, units, the paper's markers (● x_in, ◆ x_out, ★ quasi-equilibrium) and the
numbers pydrill computed in the title.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .plot import plt, save

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
    label = STYLE[key]["label"]
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


def _sigma_strip(ax, params, wob: float, w_range, theta_shift: float = 0.0) -> None:
    """Σ̃ on the plane ω_b = 0: k θ + c ω_l within ±T_s (Eq. 22), θ the collar (or string)
    twist against ω_l (or ω_r)."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    k, c = params.stiffnesses[-1], params.dampings[-1]
    ts = params.static_torque(wob)
    w0, w1 = w_range
    corners = [(ts - c * w0) / k, (ts - c * w1) / k, (-ts - c * w1) / k, (-ts - c * w0) / k]
    verts = [
        [
            (corners[0] + theta_shift, w0, 0),
            (corners[1] + theta_shift, w1, 0),
            (corners[2] + theta_shift, w1, 0),
            (corners[3] + theta_shift, w0, 0),
        ]
    ]
    ax.add_collection3d(Poly3DCollection(verts, color=SIGMA, alpha=0.25))
    for e, sign in ((corners[:2], "+"), (corners[2:][::-1], "-")):
        ax.plot(
            [e[0] + theta_shift, e[1] + theta_shift],
            [w0, w1],
            [0, 0],
            color="#b9770e",
            lw=1.2,
            ls="--" if sign == "-" else "-",
        )


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
    for i, w in enumerate(wobs):
        r = runs["orbits"][w]
        keep = r.t >= r.t[-1] - 40.0
        color = cmap(i / max(len(wobs) - 1, 1))
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
    ax.plot([qe], [0], [0], "*", color="black", ms=14, label="quasi-equilibrium (u/$k_t$, 0, 0)")
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
        f"stuck above ($W^*_{{ob}}$ = u/(μ_sb R_b) = {iv['wob_star']:.2f} N)",
        fontsize=10,
    )
    fig.suptitle(
        "Fig. 5 — n = 4 (dof 2), u = 8.1 N·m, $W_{ob}$ from 90 to 150 N: larger $W_{ob}$, "
        "longer sticking, then a stuck bit",
        fontweight="bold",
    )
    return save(fig, out / "fig05_wob_steps.png")


def fig7(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    from .reproduce_sims import lab

    r = runs["loaded"]
    p = lab(4)
    fig = plt.figure(figsize=(14, 6.2), layout="constrained")
    ax = _axes3d(
        fig,
        121,
        (
            "$\\varphi_l - \\varphi_b$ (rad)",
            "$\\dot\\varphi_l$ (rad/s)",
            "$\\dot\\varphi_b$ (rad/s)",
        ),
    )
    ax.plot(r.twist[:, -1], r.omega[:, -2], r.omega[:, -1], color=BIT, lw=1.2, label="trajectory")
    w = r.omega[:, -2]
    _sigma_strip(ax, p, 160.0, (min(w.min(), -5), max(w.max(), 5)))
    i_in = _switch_points(r, "in")[0]
    ax.plot([r.twist[i_in, -1]], [w[i_in]], [0], "o", color="black", ms=7, label="$x_{in}$")
    ax.plot(
        [n["quasi_equilibrium_twist"]],
        [0],
        [0],
        "*",
        color="black",
        ms=14,
        label="quasi-equilibrium $\\tilde x$ = (u/k_tb, 0, 0)",
    )
    ax.plot([], [], color=SIGMA, lw=8, alpha=0.4, label="sliding region $\\tilde\\Sigma$ (Eq. 22)")
    ax.legend(fontsize=8, loc="upper left")
    ax.view_init(elev=25, azim=-55)
    ax.set_title("(a) the trajectory enters $\\tilde\\Sigma$ once and stays", fontsize=10)
    ax_b = fig.add_subplot(122)
    keep = r.t <= 60
    ax_b.plot(r.t[keep], r.reaction_torque[keep], color=TOP, label="reaction torque $T_e$")
    ax_b.axhline(n["static_torque"], color=BIT, ls=":", label="$T_s = \\mu_{sb} W_{ob} R_b$")
    ax_b.axhline(8.3, color="0.4", ls="-.", label="surface torque u")
    ax_b.set_xlabel("time (s)")
    ax_b.set_ylabel("torque at the bit (N·m)")
    ax_b.grid(alpha=0.3)
    ax2 = ax_b.twinx()
    ax2.plot(r.t[keep], r.omega[keep, -1], color=BIT, lw=1, label="bit velocity")
    ax2.set_ylabel("bit velocity (rad/s)", color=BIT)
    h1, l1 = ax_b.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax_b.legend(h1 + h2, l1 + l2, fontsize=9, loc="center right")
    ax_b.set_title(
        f"(b) stuck at t = {n['t_in']:.2f} s; $T_e$ settles to u = 8.3 < $T_s$ = "
        f"{n['static_torque']:.3g} N·m",
        fontsize=10,
    )
    fig.suptitle(
        "Fig. 7 — permanently stuck bit, n = 8 (dof 4), $W_{ob}$ = 160 N, u = 8.3 N·m "
        "(drilling at 100 N, then loaded to 160 N)",
        fontweight="bold",
    )
    return save(fig, out / "fig07_stuck.png")


def fig8(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    from .reproduce_sims import lab

    r = runs["run"]
    p = lab(4)
    k, c = p.stiffnesses[-1], p.dampings[-1]
    ts = p.static_torque(100.0)
    phi = r.angles
    fig = plt.figure(figsize=(14, 6.2), layout="constrained")
    ax = fig.add_subplot(121)
    colors = ["#1f618d", "#b03a2e", "#7d3c98"]
    t_end = n["visits"][-1]["t_out"] + 2
    for i, v in enumerate(n["visits"]):
        held = (r.t >= v["t_in"]) & (r.t <= v["t_out"])
        w = np.linspace(-1, 1, 2) * max(1.0, np.abs(r.omega[held, -2]).max() * 1.3)
        lo, hi = v["phi_b"] + (-ts - c * w) / k, v["phi_b"] + (ts - c * w) / k
        ax.fill_betweenx(w, lo, hi, color=colors[i], alpha=0.12)
        ax.plot(hi, w, color=colors[i], lw=1)
        ax.plot(lo, w, color=colors[i], lw=1, ls="--")
        ax.plot(
            phi[held, -2],
            r.omega[held, -2],
            color=colors[i],
            lw=1.6,
            label=f"visit {i + 1}: stuck {v['t_in']:.1f}–{v['t_out']:.1f} s, "
            f"$\\bar\\varphi_b$ = {v['phi_b']:.0f} rad",
        )
        j_in, j_out = np.flatnonzero(held)[[0, -1]]
        ax.plot(phi[j_in, -2], r.omega[j_in, -2], "o", color="black", ms=6)
        ax.plot(phi[j_out, -2], r.omega[j_out, -2], "D", color="black", ms=6)
        ax.plot(v["phi_b"] + 8.3 / k, 0, "*", color="black", ms=12)
    ax.plot([], [], "o", color="black", label="$x_{in}$")
    ax.plot([], [], "D", color="black", label="$x_{out}$ (on $\\partial\\tilde\\Sigma_i^+$)")
    ax.plot([], [], "*", color="black", label="$\\tilde x$ (virtual: u > $T_s$)")
    ax.plot(
        [],
        [],
        color="0.3",
        label="$\\partial\\tilde\\Sigma_i^+$ (solid), $\\partial\\tilde\\Sigma_i^-$ (dashed)",
    )
    ax.set_xlabel("collar angle $\\varphi_l$ (rad)")
    ax.set_ylabel("collar velocity $\\dot\\varphi_l$ (rad/s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
    ax.set_title(
        "(a) on $\\tilde\\Sigma_i$ only: each visit has its own strip, shifted by "
        "the held bit angle",
        fontsize=10,
    )
    ax3 = _axes3d(
        fig, 122, ("$\\varphi_l$ (rad)", "$\\dot\\varphi_l$ (rad/s)", "$\\varphi_b$ (rad)")
    )
    keep = r.t <= t_end
    ax3.plot(phi[keep, -2], r.omega[keep, -2], phi[keep, -1], color="0.6", lw=0.8, label="slipping")
    for i, v in enumerate(n["visits"]):
        held = (r.t >= v["t_in"]) & (r.t <= v["t_out"])
        ax3.plot(
            phi[held, -2],
            r.omega[held, -2],
            phi[held, -1],
            color=colors[i],
            lw=2,
            label=f"on $\\tilde\\Sigma_{i + 1}$",
        )
    ax3.legend(fontsize=8, loc="upper left")
    ax3.view_init(elev=20, azim=-60)
    ax3.set_title(
        "(b) $(\\varphi_l, \\dot\\varphi_l, \\varphi_b)$: the bit angle is constant on each visit",
        fontsize=10,
    )
    fig.suptitle(
        "Fig. 8 — the first three visits to the sliding region, n = 8 (dof 4), "
        "$W_{ob}$ = 100 N, u = 8.3 N·m",
        fontweight="bold",
    )
    return save(fig, out / "fig08_sliding_visits.png")


def fig9(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    from .reproduce_sims import lab

    r = runs["run"]
    p = lab(4)
    fig = plt.figure(figsize=(14, 6.2), layout="constrained")
    ax = fig.add_subplot(121)
    for key in ("top", "pipe", "collar", "bit"):
        _chain(r, key, ax, 300.0, velocity=True)
    ax.axhline(
        n["omega"],
        color="#27ae60",
        ls="--",
        lw=1.2,
        label=f"steady state Ω = {n['omega']:.4g} rad/s",
    )
    ax.set_xlabel("time (s)")
    ax.set_ylabel("angular velocity (rad/s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=9, loc="lower right")
    ax.set_title(
        f"(a) the bit breaks free at t = {n['first_slip']:.2f} s and never sticks "
        f"again; within 1 % of Ω after {n['settled_1pct']:.0f} s",
        fontsize=10,
    )
    ax3 = _axes3d(
        fig,
        122,
        (
            "$\\varphi_l - \\varphi_b$ (rad)",
            "$\\dot\\varphi_l$ (rad/s)",
            "$\\dot\\varphi_b$ (rad/s)",
        ),
    )
    ax3.plot(r.twist[:, -1], r.omega[:, -2], r.omega[:, -1], color=BIT, lw=0.9)
    _sigma_strip(ax3, p, 40.0, (-5, 75))
    theta_e = float(r.twist[-1, -1])  # converged: h(Ω)/k_tb
    ax3.plot(
        [theta_e],
        [n["omega"]],
        [n["omega"]],
        "o",
        color="#27ae60",
        ms=9,
        label="standard equilibrium $\\bar x_e$",
    )
    ax3.plot(
        [8.3 / p.stiffnesses[-1]],
        [0],
        [0],
        "*",
        color="black",
        ms=13,
        label="$\\tilde x$ (virtual: u > $T_s$ = 3.2 N·m)",
    )
    ax3.plot([], [], color=SIGMA, lw=8, alpha=0.4, label="sliding region $\\tilde\\Sigma$")
    ax3.legend(fontsize=8, loc="upper left")
    ax3.view_init(elev=22, azim=-58)
    ax3.set_title(
        "(b) the trajectory leaves $\\tilde\\Sigma$ and spirals into $\\bar x_e$", fontsize=10
    )
    fig.suptitle(
        f"Fig. 9 — steady drilling, n = 8 (dof 4), $W_{{ob}}$ = 40 N, u = 8.3 N·m: "
        f"stable (δ = {n['delta']:.2g} ≪ δ₁ = {n['delta_1']:.4g} N·m·s/rad)",
        fontweight="bold",
    )
    return save(fig, out / "fig09_steady.png")


def draw_simulations(out: Path, numbers: dict[str, Any], runs: dict[str, Any]) -> list[Path]:
    return [
        fig4(out, numbers["fig04"], runs["fig04"]),
        fig5(out, numbers["fig05"], runs["fig05"]),
        fig7(out, numbers["fig07"], runs["fig07"]),
        fig8(out, numbers["fig08"], runs["fig08"]),
        fig9(out, numbers["fig09"], runs["fig09"]),
    ]
