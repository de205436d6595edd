"""Figures of the stability analysis: the Hopf boundaries in (Ω, W_ob), the eigenvalues of a
steady state, bifurcation diagrams. The (W_ob, u) operating map is drawn by
:mod:`pydrill.plot_map`."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .plot import clear_inset, place_legend, plt, quantity, rpm_axis, scale_ticks, unit_scale
from .plot_labels import place_labels

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def hopf_figure(params, crossings, omega_max: float | None = None, n: int = 400) -> Figure:
    """Stability boundaries in (Ω, W_ob) — the paper's Fig. 10 for any dof: regions coloured by
    the number of unstable eigenvalues, the Hopf curves W_ob(Ω) = δ_k e^{γΩ/v_f}/(…) on top,
    for Ω up to ``omega_max`` rad/s (None: 20)."""
    asked = omega_max is not None  # the title says whose Ω_max it falls short of
    omega_max = 20.0 if omega_max is None else omega_max
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D

    from .stability import boundary_wob, stability_map

    # Crossings at δ = 0 (no damping at the ends, or none at all) lie on the axis W_ob = 0:
    # every W_ob drawn is past them, and they set no scale.
    drawn = [c for c in crossings if c.delta > 0]
    at_zero = sum(c.multiplicity for c in crossings if c.delta == 0 and c.direction > 0)
    first = next((c for c in drawn if c.direction > 0), drawn[0] if drawn else None)
    # The first Hopf curve at Ω = 0; with none above δ = 0, a W_ob range of real bits (10 kN
    # to 2000 kN below), uniformly unstable.
    w0 = float(boundary_wob(params, first.delta, 0.0)) if first is not None else 3e4
    w_lo = w0 / 3.0
    # ln W_ob grows by γ/v_f per rad/s along a Hopf curve: in log space, as e^{γΩ/v_f}
    # overflows past Ω ≈ 700 v_f/γ.
    rate = params.stribeck_decay / params.stribeck_velocity
    # Up to the boundary at Ω_max, but no more than four decades: beyond, no drill string goes.
    log_hi = math.log(3.0 * w0) + rate * omega_max
    w_hi = math.exp(min(max(log_hi, math.log(30.0 * w_lo)), math.log(1e4 * w_lo)))
    # Nor past 2000 kN, which no bit takes: the paper's tally drew up to 19 400 kN, its
    # 10 ... 300 kN a strip at the foot (a laboratory string's 1.3 kN is far below).
    w_hi = min(w_hi, max(2e6, 30.0 * w_lo))
    # Where the first Hopf curve leaves the top of the map, every W_ob drawn has a smaller
    # slope than δ_1: the map is one colour from there on. Draw a little past it, not on to
    # an Ω_max thousands of times further (an empty map).
    omega_top = math.log(w_hi / w0) / rate if rate > 0 else math.inf
    omega_shown = min(omega_max, 1.25 * omega_top) if first is not None else omega_max
    omega = np.linspace(0.0, omega_shown, n)
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
    for c in drawn:
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
    ax.set_xlim(0, omega_shown)
    ax.set_ylim(w_lo, w_hi)
    scale, unit = unit_scale(w_hi, "N")
    scale_ticks(ax.yaxis, scale)
    ax.set_xlabel("steady bit velocity $\\Omega$ (rad/s)")
    ax.set_ylabel(f"weight on bit $W_{{ob}}$ ({unit})")
    rpm_axis(ax, "steady bit speed (rpm)", "top")
    cbar = fig.colorbar(mesh, ax=ax, ticks=range(0, top + 1, max(1, top // 10)))
    cbar.set_label("unstable eigenvalues of the steady state")
    legend = (
        []
        if first is None
        else [
            Line2D(
                [],
                [],
                color="#7b241c",
                lw=2.2,
                label=f"first Hopf: $\\delta_1$ = {first.delta:.4g} N·m·s/rad, "
                f"{(first.frequency or 0):.3g} rad/s{_criticality_note(params, first)}",
            )
        ]
    )
    if sum(c.type == "hopf" for c in drawn) > 1:  # (a kind with no curve drawn is not listed)
        legend.append(Line2D([], [], color="#922b21", lw=0.8, label="further Hopf crossings"))
    if any(c.type == "fold" for c in drawn):
        legend.append(
            Line2D([], [], color="#1f618d", ls="--", label="fold ($\\delta = c_r + c_b$)")
        )
    if legend:
        ax.legend(handles=legend, loc="lower right", fontsize=9, framealpha=0.95)
    n_hopf = sum(c.type == "hopf" for c in crossings)
    cut = (
        f"\nΩ up to {omega_shown:.3g} rad/s of the {omega_max:g} "
        f"{'asked' if asked else 'by default (--omega-max)'}: further on, the first Hopf "
        f"curve is above the largest $W_{{ob}}$ drawn, {w_hi / scale:.4g} {unit}"
        if omega_shown < omega_max
        else ""
    )
    if at_zero == 0:
        verdict = (
            f"steady drilling is stable below the first Hopf curve ({n_hopf} Hopf crossings in all)"
        )
    else:  # the whole map is past them: say why no part of it is stable
        verdict = (
            "steady drilling is unstable at every $W_{ob}$\n"
            f"{at_zero} eigenvalue{'s cross' if at_zero > 1 else ' crosses'} at $\\delta$ = 0: "
            f"the string has no damping {'at all' if first is None else 'at the top or the bit'} "
            f"({n_hopf} Hopf crossings in all)"
        )
    ax.set_title(f"{params.name}, dof {params.dof}: {verdict}{cut}", fontsize=10)
    return fig


def eigenvalue_figure(params, points) -> Figure:
    """Eigenvalues of each steady state in the complex plane, the unstable half-plane shaded."""
    fig, ax = plt.subplots(figsize=(9.5, 5.5), layout="constrained")
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
    size = sorted(abs(r) for r in re if r != 0)
    if size and size[-1] > 100 * size[0]:
        # One eigenvalue far from the axis (Re 14 against 0.04 and -3e-5): on a linear axis
        # all the others sat on Re = 0, and which side of it each lies on (the plot's point)
        # could not be seen. Logarithmic on either side of zero, linear within the least |Re|.
        linthresh = max(size[0] / 2, size[-1] * 1e-9)
        ax.set_xscale("symlog", linthresh=linthresh, linscale=0.4)
        neg = [-r for r in re if r < 0]
        pos = [r for r in re if r > 0]
        ax.set_xlim(-3 * max(neg or [linthresh * 10]), 3 * max(pos or [linthresh * 10]))
        # Zero and whole decades clear of the linear band (whose edge labels ran into "0"), at
        # most about a dozen of them.
        first = math.floor(math.log10(linthresh)) + 1
        if 10.0**first < 5 * linthresh:  # -0.1 beside 0 at linthresh 0.03: their labels touched
            first += 1
        tops = [math.floor(math.log10(-ax.get_xlim()[0])), math.floor(math.log10(ax.get_xlim()[1]))]
        step = max(1, math.ceil((tops[0] + tops[1] - 2 * first + 2) / 12))
        ticks = [0.0]
        for sign, top in zip((-1, 1), tops, strict=True):
            ticks += [sign * 10.0**d for d in range(top, first - 1, -step)]
        ax.set_xticks(sorted(ticks))
        xlabel = f"Re λ (1/s; logarithmic beyond ±{linthresh:.1g}, linear within)"
    else:
        lo = min([*re, -0.1])
        hi = max([*re, 0.0])
        span = hi - lo
        ax.set_xlim(lo - 0.05 * span, max(hi + 0.15 * span, 0.1 * span))
        xlabel = "Re λ (1/s)"
    # All of Re λ > 0 that the axes show, drawn under the points (the limits are fixed now).
    ax.axvspan(
        0, ax.get_xlim()[1], color="#f5b7b1", alpha=0.5, lw=0, zorder=0, label="unstable half-plane"
    )
    ax.axvline(0, color="black", lw=0.8)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("Im λ (rad/s)")
    ax.grid(alpha=0.3)
    # Beside the axes: eigenvalues may sit anywhere in the plane, the legend covers none.
    ax.legend(fontsize=9, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    if points:
        # The operating point whole: W_ob and the surface torque that holds the steady state
        # (the title said W_ob alone, and the figure could be of any u).
        pt = points[0]
        scale, _ = unit_scale([pt.wob, pt.torque], "N·m")
        ax.set_title(
            f"{params.name}, dof {params.dof}, $W_{{ob}}$ = {quantity(pt.wob, 'N', scale)}, "
            f"$u$ = {quantity(pt.torque, 'N·m', scale)}",
            fontsize=10,
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
    an inset zooms in on them. A real string's forces are in kN (torques in kN·m)."""
    import numpy as np

    fig, ax = plt.subplots(figsize=(9, 5.8), layout="constrained")
    x = branch.wob if branch.vary == "wob" else branch.torque
    # kN and kN·m if either the branch or the value held is a real string's, as in the text
    # (a light W_ob = 20 kN held beside torques in N·m, or the reverse, mixed the two).
    scale, unit = unit_scale(np.append(x, branch.fixed), "N" if branch.vary == "wob" else "N·m")
    hb = sorted((pt for pt in branch.points if pt.type == "HB"), key=lambda pt: -pt.omega)
    few = len(hb) <= 4
    # (axes, text, (x, y), colour) of each label: placed once the figure is laid out
    labels: list[tuple] = []

    def draw(ax, label: bool, short: bool = False, into: list | None = None) -> None:
        """The branch on ``ax``; with ``label``, the names of its points go ``into`` a list
        (``labels`` by default) for ``place_labels``."""
        names = labels if into is None else into
        stable = branch.unstable == 0
        for mask, style, name in (
            (stable, "-", "stable steady state"),
            (~stable, "--", "unstable steady state"),
        ):
            y = np.where(mask, branch.omega, np.nan)
            color = "#1f618d" if style == "-" else "#922b21"
            ax.plot(x, y, style, color=color, lw=2, label=name)
        for i, pt in enumerate(hb):
            px = pt.wob if branch.vary == "wob" else pt.torque
            color = "#27ae60" if pt.criticality == "supercritical" else "#c0392b"
            ax.plot(px, pt.omega, "s", color=color, ms=8 if few else 5, zorder=5)
            if label and (few or i == 0):
                # pt.label: the name the table and --json give it (bifurcation.point_labels)
                text = (
                    pt.label
                    if short
                    else f"{pt.label} ({pt.criticality[:3]}), frequency {pt.frequency:.3g} rad/s"
                )
                names.append((ax, text, (px, pt.omega), color))
        for pt in branch.points:
            if pt.type == "LP":
                px = pt.wob if branch.vary == "wob" else pt.torque
                ax.plot(px, pt.omega, "D", color="black", ms=7, zorder=5)
                if label:
                    names.append((ax, pt.label, (px, pt.omega), "black"))

    xs = np.array([pt.wob if branch.vary == "wob" else pt.torque for pt in branch.points])
    zoom = len(xs) > 1 and np.ptp(xs) < 0.15 * np.ptp(x)
    draw(ax, label=not zoom)
    scale_ticks(ax.xaxis, scale)
    if branch.vary == "wob":
        ax.set_xlabel(f"weight on bit $W_{{ob}}$ ({unit})")
        fixed = f"$u$ = {quantity(branch.fixed, 'N·m', scale)}"
    else:
        ax.set_xlabel(f"surface torque $u$ ({unit})")
        fixed = f"$W_{{ob}}$ = {quantity(branch.fixed, 'N', scale)}"
    ax.set_ylabel("steady bit velocity $\\Omega$ (rad/s)")
    ax.set_ylim(bottom=0)
    rpm_axis(ax, "steady bit speed (rpm)", "right")  # the same Ω as the text gives it
    ax.grid(alpha=0.3)
    ax.set_title(f"{params.name}, dof {params.dof}, {fixed}", fontsize=10)
    if zoom:
        # The special points sit within a few per cent of the range: zoom in on them.
        pad = max(0.15 * np.ptp(xs), 0.01 * xs.max())
        top = max(pt.omega for pt in branch.points)
        # Where it hides none of the branch: the lower left when W_ob varies (the branch falls
        # from the upper left; at (0.5, 0.4) the inset hid the stable branch's middle).
        spots = [
            (x0, y0, w, h)
            for w, h in ((0.47, 0.42), (0.4, 0.36), (0.34, 0.3))
            for x0 in ((0.97 - w, 0.08) if branch.vary == "torque" else (0.08, 0.97 - w))
            for y0 in (0.4, 0.08, 0.92 - h)
        ]

        def decorate(ins) -> list[tuple]:
            names: list[tuple] = []
            draw(ins, label=True, short=True, into=names)
            ins.set_xlim(xs.min() - pad, xs.max() + 2 * pad)
            ins.set_ylim(0, top * 1.25 + 0.3)
            scale_ticks(ins.xaxis, scale)
            ins.tick_params(labelsize=7)
            ins.grid(alpha=0.3)
            # HB1's place on the axis (Ω) and its oscillation's frequency: both in rad/s.
            first = (
                f"; {hb[0].label} at Ω = {hb[0].omega:.3g} rad/s\n"
                f"(frequency {hb[0].frequency:.3g} rad/s, {hb[0].criticality})"
                if hb
                else ""
            )
            ins.set_title(f"{len(hb)} Hopf point{'s' if len(hb) != 1 else ''}{first}", fontsize=8)
            return names

        ins, names = clear_inset(ax, spots, decorate)
        labels.extend(names)
        ax.indicate_inset_zoom(ins, edgecolor="0.4")
    sub = sum(pt.criticality == "subcritical" for pt in hb)
    # Only the kinds there are ("supercritical (0)" named a marker the figure has not).
    if sub:
        ax.plot([], [], "s", color="#c0392b", label=f"Hopf point, subcritical ({sub})")
    if len(hb) > sub:
        ax.plot([], [], "s", color="#27ae60", label=f"Hopf point, supercritical ({len(hb) - sub})")
    if any(pt.type == "LP" for pt in branch.points):
        ax.plot([], [], "D", color="black", label="limit point (fold)")
    # Clear of the branch and the inset (upper left hid the stable branch's start at W_ob = 0).
    place_legend(ax, fontsize=9)
    # Varying the torque, the stable branch leaves HB1 to the upper right: labels go left.
    place_labels(fig, labels, right=branch.vary == "wob")
    return fig
