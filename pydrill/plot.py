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
