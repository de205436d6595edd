"""The bifurcation diagrams of the reproduction (the paper's Fig. 11 and its long-string
analogues): a branch with its Hopf and fold points, the attractors simulated along it, and an
inset on the special points placed where it hides none of them."""

from __future__ import annotations

from typing import Any

import numpy as np

SUB, SUPER, FOLD = "#c0392b", "#27ae60", "#1f618d"


def _draw_branch(ax, b: dict[str, Any], labels: bool) -> list[tuple]:
    """Steady states (stable thick, unstable thin dashed) with their HB and LP points; with
    ``labels``, the (axes, text, point, colour) of their names, for ``place_labels``."""
    x = np.array(b["branch"]["x"])
    omega = np.array(b["branch"]["omega"])
    stable = np.array(b["branch"]["unstable"]) == 0
    ax.plot(x, np.where(stable, omega, np.nan), color=FOLD, lw=3, label="stable steady state")
    ax.plot(
        x,
        np.where(~stable, omega, np.nan),
        "--",
        color="#922b21",
        lw=1.2,
        label="unstable steady state",
    )
    from .bifurcation import point_labels

    key = "wob" if b["vary"] == "wob" else "torque"
    # The names pydrill bifurcation gives them (the stored points may predate its "label")
    named = point_labels([(pt["type"], pt["omega"]) for pt in b["points"]])
    hb = sorted(
        ((pt, name) for pt, name in zip(b["points"], named, strict=True) if pt["type"] == "HB"),
        key=lambda q: -q[0]["omega"],
    )
    names: list[tuple] = []
    for i, (pt, name) in enumerate(hb):
        color = SUB if pt["criticality"] == "subcritical" else SUPER
        ax.plot(pt[key], pt["omega"], "s", color=color, ms=6, zorder=6)
        if labels and (i == 0 or b["dof"] <= 4):
            names.append((ax, name, (pt[key], pt["omega"]), color))
    if b["fold"]:
        ax.plot(b["fold"][key], b["fold"]["omega"], "D", color="black", ms=6, zorder=6)
        if labels:
            names.append((ax, "LP", (b["fold"][key], b["fold"]["omega"]), "black"))
    return names


def _branch_panel(
    ax, b: dict[str, Any], atlas: dict[str, Any] | None, letter: str
) -> tuple[list, bool]:
    """One bifurcation diagram: the branch, the attractors the simulations found (the paper's
    circles), and an inset around the Hopf and fold points, where it hides none of them.
    Returns the names of the inset's points and whether W_ob varies, for ``name_points`` once
    the figure is whole."""
    from .plot import clear_inset

    _draw_branch(ax, b, labels=False)
    key = "wob" if b["vary"] == "wob" else "torque"
    names: list = []
    if atlas is not None:
        ax_x = np.array(atlas["axes"][key])
        for init, marker, label in (("rest", "o", "from rest"), ("equilibrium", "^", "from Ω")):
            reg = np.array(atlas[init]["regime"], dtype=object)
            top = np.array(atlas[init]["bit_max"], dtype=float)
            osc = (reg == "stick-slip") | (reg == "oscillation")
            ax.plot(
                ax_x[osc],
                top[osc],
                marker,
                mfc="none",
                mec="#d35400",
                ms=6,
                label=f"periodic orbit {label}: max $\\dot\\varphi_b$",
            )
            stuck = reg == "stuck"
            ax.plot(
                ax_x[stuck],
                np.zeros(stuck.sum()),
                marker,
                color="0.45",
                ms=4,
                label=f"stuck bit {label}" if stuck.any() else None,
            )
        ax.set_xlim(ax_x.min(), ax_x.max())
    ax.set_ylim(bottom=-1.5)
    ax.set_xlabel("weight on bit $W_{ob}$ (N)" if key == "wob" else "surface torque $u$ (N·m)")
    ax.set_ylabel("bit velocity (rad/s)")
    ax.grid(alpha=0.3)
    fixed = f"$u$ = {b['fixed']:g} N·m" if key == "wob" else f"$W_{{ob}}$ = {b['fixed']:g} N"
    first = b["first_hopf"]
    text = ""
    if first:
        text = (
            f"; HB1 at {first[key]:.5g} {'N' if key == 'wob' else 'N·m'}, "
            f"$l_1$ = {first['lyapunov']:.2g}"
            if first["lyapunov"] is not None
            else ""
        )
    ax.set_title(f"({letter}) n' = {2 * b['dof'] - 1} (dof {b['dof']}), {fixed}{text}", fontsize=10)
    special = [pt for pt in b["points"]] + ([b["fold"]] if b["fold"] else [])
    if special:
        xs = [pt[key] for pt in special]
        pad = max(0.15 * (max(xs) - min(xs)), 0.01 * max(xs))
        top = max(pt["omega"] for pt in special)
        # Clear of the branch and of the periodic orbits: at a fixed place, the inset of
        # Fig. 11(b) and (d) hid the first orbits found from rest.
        # Large first; on the right first when W_ob varies (the branch falls to the right).
        spots = [
            (x0, y0, w, h)
            for w, h in ((0.47, 0.42), (0.4, 0.36), (0.32, 0.3))
            for x0 in ((0.97 - w, 0.08, 0.3) if key == "wob" else (0.08, 0.97 - w, 0.3))
            for y0 in (0.4, 0.9 - h, 0.1, 0.25)
        ]

        def decorate(ins) -> list[tuple]:
            names = _draw_branch(ins, b, labels=True)
            ins.set_xlim(min(xs) - 2 * pad, max(xs) + 2 * pad)  # room for names either side
            ins.set_ylim(-0.3, top * 1.25 + 0.3)
            ins.tick_params(labelsize=7)
            ins.grid(alpha=0.3)
            ins.set_title("Hopf and fold points", fontsize=7)
            return names

        ins, names = clear_inset(ax, spots, decorate)
        ax.indicate_inset_zoom(ins, edgecolor="0.4")
    ax.plot([], [], "s", color=SUB, label="Hopf point, subcritical ($l_1$ > 0)")
    if any(pt["criticality"] == "supercritical" for pt in b["points"]):
        ax.plot([], [], "s", color=SUPER, label="Hopf point, supercritical ($l_1$ < 0)")
    ax.plot([], [], "D", color="black", label="limit point (fold)")
    return names, key == "wob"


def name_points(fig, panels: list) -> None:
    """Write the names of each panel's points (``_branch_panel``'s) where they clear the
    markers and one another: HB2 and LP, 0.1 N apart, were written over one another at fixed
    offsets. Last, once the legend is in: the layout moves the insets until then."""
    from .plot_labels import place_labels

    for names, wob in panels:
        if names:  # W_ob varying, the stable branch leaves HB1 to the upper left: names right
            place_labels(fig, names, right=wob)
