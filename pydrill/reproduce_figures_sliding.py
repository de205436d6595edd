"""Figures of the reproduction's sliding-region simulations: the paper's Figs. 7, 8 and 9."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .plot import place_legend, plt, save

# The line styles, markers and 3-D axes come from reproduce_figures, imported inside each
# figure: that module imports these figures at its top (to draw and re-export them).


def _sigma_strip(ax, params, wob: float, w_range, theta_shift: float = 0.0) -> None:
    """Σ̃ on the plane ω_b = 0: k θ + c ω_l within ±T_s (Eq. 22), θ the collar (or string)
    twist against ω_l (or ω_r)."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from .reproduce_figures import SIGMA

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


def fig7(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    from .reproduce_figures import BIT, SIGMA, TOP, _axes3d, _switch_points
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
        label="quasi-equilibrium $\\tilde x$ = ($u/k_{tb}$, 0, 0)",
    )
    ax.plot([], [], color=SIGMA, lw=8, alpha=0.4, label="sliding region $\\tilde\\Sigma$ (Eq. 22)")
    ax.legend(fontsize=8, loc="upper left")
    ax.view_init(elev=25, azim=-55)
    ax.set_title("(a) the trajectory enters $\\tilde\\Sigma$ once and stays", fontsize=10)
    ax_b = fig.add_subplot(122)
    keep = r.t <= 60
    ax_b.plot(r.t[keep], r.reaction_torque[keep], color=TOP, label="reaction torque $T_e$")
    ax_b.axhline(n["static_torque"], color=BIT, ls=":", label="$T_s = \\mu_{sb} W_{ob} R_b$")
    ax_b.axhline(8.3, color="0.4", ls="-.", label="surface torque $u$")
    ax_b.set_xlabel("time (s)")
    ax_b.set_ylabel("torque at the bit (N·m)")
    ax_b.grid(alpha=0.3)
    ax2 = ax_b.twinx()
    ax2.plot(r.t[keep], r.omega[keep, -1], color=BIT, lw=1, label="bit velocity")
    ax2.set_ylabel("bit velocity (rad/s)", color=BIT)
    h1, l1 = ax_b.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax_b.set_title(
        f"(b) stuck at t = {n['t_in']:.2f} s; $T_e$ settles to u = 8.3 < $T_s$ = "
        f"{n['static_torque']:.3g} N·m",
        fontsize=10,
    )
    # Clear of both axes' curves: at "center right" it hid the reaction torque's last swings.
    place_legend(ax_b, h1 + h2, l1 + l2, twins=(ax2,), fontsize=9)
    fig.suptitle(
        "Fig. 7 — permanently stuck bit, n = 8 (dof 4), $W_{ob}$ = 160 N, u = 8.3 N·m "
        "(drilling at 100 N, then loaded to 160 N)",
        fontweight="bold",
    )
    return save(fig, out / "fig07_stuck.png")


def fig8(out: Path, n: dict[str, Any], runs: dict[str, Any]) -> Path:
    from .reproduce_figures import _axes3d
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
    from .reproduce_figures import BIT, SIGMA, _axes3d, _chain
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
