"""Operating-window charts in driller units: the window at one depth, and against depth."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .atlas_schema import FAILED
from .plot import REGIME_COLORS, place_legend, plt
from .plot_map import FAILED_COLOR, FAILED_LABEL, FAILED_MARKER
from .units import FT, LBF

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .window import DepthWindow, Limits

SAFE = "#82e0aa"
UNSTABLE = "#f5b041"
STALL = "#aab7b8"
HOPF_EDGE = "#922b21"
STALL_EDGE = "#1c2833"
KLBF = LBF  # kN per klbf (1 klbf = 4.448 kN)


def _curve_labels(fig, ax, curves) -> None:
    """Name each (text, x, depth, colour) curve of the depth chart by its foot, written
    upwards along it. Where neighbouring curves are closer than a label is wide, a label
    goes up its curve, above the labels it would touch (the leftmost curve's stays at the
    foot): no two touch. Lays the figure out first, to measure the labels as drawn."""
    if not curves:
        return
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    gap = 6 * fig.dpi / 72  # between two labels: clearly apart
    top = ax.get_window_extent(renderer).y1
    to_data = ax.transData.inverted()
    deepest = max(float(np.max(d)) for _, _, d, _ in curves)
    span = deepest - min(float(np.min(d)) for _, _, d, _ in curves)
    foot = ax.transData.transform((0.0, deepest - 0.02 * span))[1]

    def label(text, x, depth, color, y0):
        y = to_data.transform((0.0, y0))[1]
        order = np.argsort(depth)
        note = ax.annotate(
            text,
            (float(np.interp(y, depth[order], x[order])), y),
            xytext=(3, 0),
            textcoords="offset points",
            rotation=90,
            va="bottom",
            ha="left",
            fontsize=8.5,
            color=color,
            weight="bold",
            bbox=_BOX,
        )
        note.set_in_layout(False)
        return note, note.get_window_extent(renderer).padded(pad)

    pad = _BOX_PAD * 8.5 * fig.dpi / 72
    placed: list = []
    for text, x, depth, color in sorted(curves, key=lambda c: c[1][np.argmax(c[2])]):
        note, box = label(text, x, depth, color, foot)
        while clash := [b for b in placed if _beside(b, box, gap)]:
            note.remove()
            # Its box's foot (the text's less the padding) a gap above the highest it touches.
            note, box = label(text, x, depth, color, max(b.y1 for b in clash) + gap + pad + 1)
            if box.y1 > top:  # no room higher up: back to the foot
                note.remove()
                note, box = label(text, x, depth, color, foot)
                break
        placed.append(box)


def _beside(a, b, gap: float) -> bool:
    """Whether boxes ``a`` and ``b`` (display) overlap or are closer than ``gap``."""
    return a.padded(gap / 2).overlaps(b.padded(gap / 2))


def _klbf_axis(ax, where: str = "top"):
    """A second W_ob axis in klbf beside the kN one."""
    sec = ax.secondary_xaxis(where, functions=(lambda kn: kn / KLBF, lambda k: k * KLBF))
    sec.set_xlabel("weight on bit (klbf)")
    return sec


def window_figure(
    name: str,
    depth: float,
    limits: Limits,
    wob_max: float,
    rpm_max: float,
    checks=None,
    check_initial: str = "equilibrium",
    length: float | None = None,
) -> Figure:
    """The safe (W_ob, surface rpm) window of one string: exact edges, regions named in driller
    terms, steady surface torque contours inside the window, simulated sample points: ``checks``
    are (W_ob N, rpm, outcome), an outcome "failed" where the simulation failed (drawn as a
    grey question mark). ``length``: the string's (m, whole joints), said where not ``depth``."""
    p = limits.params
    rpm = np.linspace(0.0, rpm_max, 600)
    w_hopf = limits.wob_max_stable(rpm) / 1e3
    w_stall = limits.wob_max_unstuck(rpm) / 1e3
    w_safe = np.minimum(w_hopf, w_stall)
    x_max = wob_max / 1e3
    fig, ax = plt.subplots(figsize=(13.0, 7.0), layout="constrained")
    ax.fill_betweenx(rpm, 0, np.minimum(w_safe, x_max), color=SAFE, lw=0, zorder=0)
    ax.fill_betweenx(
        rpm, np.minimum(w_hopf, x_max), x_max, color=UNSTABLE, alpha=0.55, lw=0, zorder=0
    )
    ax.fill_betweenx(
        rpm,
        np.minimum(w_stall, x_max),
        x_max,
        facecolor=STALL,
        alpha=0.45,
        hatch="//",
        edgecolor="#7b7d7d",
        lw=0,
        zorder=0,
    )
    # What sets δ_c: the first Hopf, or on a short string the fold, which comes first there
    # (the legend said "first Hopf" at 300 m, where the fold is the edge).
    what = {"hopf": " (first Hopf)", "fold": " (fold)"}.get(limits.limit_type or "", "")
    ax.plot(w_hopf, rpm, color=HOPF_EDGE, lw=2.2, label=f"stick-slip edge{what}")
    ax.plot(w_stall, rpm, color=STALL_EDGE, lw=2.2, ls="--", label="stall edge (torque = $T_s$)")
    # Steady surface torque inside the window: what the torque gauge should read there.
    gw, gr = np.meshgrid(np.linspace(x_max / 300, x_max, 300), np.linspace(1.0, rpm_max, 300))
    tq = limits.torque(gw * 1e3, gr) / 1e3
    tq = np.where(
        gw <= np.minimum(limits.wob_max_stable(gr), limits.wob_max_unstuck(gr)) / 1e3, tq, np.nan
    )
    contoured = np.isfinite(tq).any() and np.nanmax(tq) > 0
    if contoured:
        cs = ax.contour(
            gw,
            gr,
            tq,
            levels=_nice_levels(np.nanmax(tq)),
            colors="#1e8449",
            linewidths=0.7,
            alpha=0.8,
        )
        ax.clabel(cs, fmt=lambda v: f"{v:g} kN·m", fontsize=7.5, inline_spacing=2)
    if checks:
        marks = {
            "steady": ("o", REGIME_COLORS["steady"]),
            "steady elsewhere": ("D", "#5dade2"),
            "stick-slip": ("X", REGIME_COLORS["stick-slip"]),
            "stuck": ("s", REGIME_COLORS["stuck"]),
            "oscillation": ("^", REGIME_COLORS["oscillation"]),
            # drawn, not left out: the text says why each failed
            FAILED: (FAILED_MARKER, FAILED_COLOR),
        }
        for regime, (marker, color) in marks.items():
            pts = [(w / 1e3, r) for w, r, g in checks if g == regime]
            if not pts:
                continue
            failed = regime == FAILED  # (a glyph, not a shape: no outline)
            said = FAILED_LABEL if failed else regime.replace("elsewhere", "at another rpm")
            ax.scatter(
                [pt[0] for pt in pts],
                [pt[1] for pt in pts],
                marker=marker,
                s=110 if failed else 46,
                zorder=5,
                color=color,
                edgecolors=None if failed else "black",
                linewidths=None if failed else 0.6,
                label=f"simulated from {check_initial}: {said}",
            )
    ax.set_xlim(0, x_max)
    ax.set_ylim(0, rpm_max)
    ax.set_xlabel("weight on bit (kN)")
    ax.set_ylabel("surface speed (rpm)")
    _klbf_axis(ax)
    ax.grid(alpha=0.35, lw=0.6)
    from matplotlib.patches import Patch

    handles, labels = ax.get_legend_handles_labels()
    handles = [
        Patch(color=SAFE),
        Patch(color=UNSTABLE, alpha=0.55),
        Patch(facecolor=STALL, alpha=0.45, hatch="//", edgecolor="#7b7d7d"),
        *handles,
    ]
    labels = [
        "SAFE: steady drilling is stable and the bit cannot stay stuck",
        "stick-slip: steady drilling unstable (any start)",
        "stall: torque at this rpm cannot break a stopped bit free",
        *labels,
    ]
    if contoured:  # (named only when drawn)
        ax.plot([], [], color="#1e8449", lw=0.7, label="steady surface torque")
        handles.append(ax.get_lines()[-1])
        labels.append("steady surface torque (kN·m)")
    ax.legend(
        handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8.5, framealpha=0.95
    )
    _label_regions(ax, limits, x_max, rpm_max)
    ax.text(
        1.02,
        0.0,
        "How to read it: pick W_ob on the bottom axis and go up;\n"
        "run faster than both edges. Heavier W_ob needs more rpm.\n"
        "The stall edge is the same at every depth; the stick-slip\n"
        "edge rises as the well deepens (the longer string damps its\n"
        "fundamental mode less). Surface torque held at the steady\n"
        "value: a check may settle at another rpm past the fold.",
        transform=ax.transAxes,
        fontsize=8.5,
        va="bottom",
        ha="left",
        color="#333333",
    )
    from .window import longer

    # the string is whole joints long: 4000 m asked, 4000.8 m built (said, not hidden)
    built = f"; string {length:,.6g} m" if length is not None and longer(depth, length) else ""
    ax.set_title(
        f"{name} at {depth:,.0f} m ({depth / FT:,.0f} ft{built}): operating window\n"
        f"lumped model {p.dof} inertias, bit {2 * p.bit_radius / 0.0254:.4g} in, "
        f"first destabilising slope $\\delta_c$ = {limits.delta_limit:.4g} N·m·s/rad",
        fontsize=10.5,
    )
    return fig


def _label_regions(ax, limits, x_max: float, rpm_max: float) -> None:
    """Name the regions on the chart itself, where each is widest."""
    box = {"boxstyle": "round,pad=0.3", "fc": "white", "ec": "none", "alpha": 0.75}
    style = {"ha": "center", "va": "center", "weight": "bold", "bbox": box}
    r = 0.8 * rpm_max
    w_edge = min(float(limits.wob_max(r)) / 1e3, x_max)
    ax.text(0.45 * w_edge, r, "SAFE", fontsize=16, color="#145a32", **style)
    x = 0.8 * x_max
    r_stall = float(limits.rpm_min_unstuck(x * 1e3))
    r_hopf = float(limits.rpm_min_stable(x * 1e3))
    if r_stall > r_hopf + 0.12 * rpm_max:
        y = min(0.5 * (r_stall + r_hopf), 0.9 * rpm_max)
        ax.text(x, y, "STALL\nbit can stay stuck", fontsize=11, color="#1c2833", **style)
    if r_hopf > 0.08 * rpm_max:
        ax.text(x, 0.45 * r_hopf, "STICK-SLIP", fontsize=11, color="#7e5109", **style)


def _nice_levels(top: float) -> list[float]:
    """Up to 12 round levels (1, 2 or 5 times a power of ten apart) below ``top`` > 0: a
    field string's kN·m and a laboratory string's thousandths of one alike (steps from 0.5
    up drew no contour below 0.5 kN·m, and the legend named the missing lines)."""
    base = 10.0 ** math.floor(math.log10(top))
    for m in (0.1, 0.2, 0.5, 1.0):
        step = m * base
        if top / step <= 12:
            # rounded: 3 x 0.05 is 0.15000000000000002, a label of many digits
            return [float(f"{v:.12g}") for v in np.arange(step, top, step)]
    return []  # (not reached: top / base < 10)


def window_depth_figure(
    dw: DepthWindow, wob_max: float, rpm_max: float, note: str | None = None
) -> Figure:
    """The window against depth, depth downwards as on a well plan: the heaviest safe W_ob at
    reference speeds (left) and the slowest safe speed at reference weights (right). Thick
    lines are the safe limits; thin lines show which edge sets them. ``note``, if given, is
    printed under the charts (``window --check``'s outcome at each depth)."""
    depth = dw.depth
    fig, (ax_w, ax_r) = plt.subplots(1, 2, figsize=(14, 8.2), sharey=True, layout="constrained")
    x_w = wob_max / 1e3
    names_w: list = []  # (text, x, depth, colour) of each curve: named once laid out
    names_r: list = []
    # A few depths: a dot on each one computed (two depths drew a straight line between them,
    # read off at depths never computed as if it were the window there).
    few = depth.size <= 12
    mark = {"marker": "o", "ms": 4.5, "clip_on": False} if few else {}  # end dots whole
    dots = "; dots: depths computed" if few else ""
    colors = plt.cm.viridis(np.linspace(0.0, 0.8, max(dw.rpm.size, 2)))
    for k, r in enumerate(dw.rpm):
        w = np.minimum(dw.wob_max[:, k] / 1e3, x_w)
        ax_w.fill_betweenx(depth, 0, w, color=SAFE, alpha=0.22, lw=0)
        ax_w.plot(w, depth, color=colors[k], lw=2.6, **mark)
        stable = dw.wob_max_stable[:, k] / 1e3
        ax_w.plot(np.where(stable < x_w, stable, np.nan), depth, color=colors[k], lw=0.9, ls=":")
        if w[-1] < 0.97 * x_w:
            names_w.append((f"{r:g} rpm", w, depth, colors[k]))
    safe = f"heaviest safe W_ob (left of it: safe){dots}"
    key = {"marker": "o", "ms": 4.5} if few else {}  # the legend's (an unclipped empty line
    # has an infinite extent, which collapsed the figure's layout)
    ax_w.plot([], [], color="#555555", lw=2.6, label=safe, **key)
    ax_w.plot([], [], color="#555555", lw=0.9, ls=":", label="stick-slip edge alone")
    ax_w.set_xlim(0, x_w)
    ax_w.set_xlabel("weight on bit (kN)")
    _klbf_axis(ax_w)
    ax_w.set_ylabel("bit depth (m)")
    ax_w.set_title("heaviest safe weight on bit at each surface speed", fontsize=10.5)
    colors = plt.cm.plasma(np.linspace(0.0, 0.8, max(dw.wob.size, 2)))
    for k, w in enumerate(dw.wob):
        r = np.minimum(dw.rpm_min[:, k], rpm_max)
        ax_r.fill_betweenx(depth, r, rpm_max, color=SAFE, alpha=0.22, lw=0)
        ax_r.plot(r, depth, color=colors[k], lw=2.6, **mark)
        ax_r.plot(
            np.minimum(dw.rpm_min_stable[:, k], rpm_max), depth, color=colors[k], lw=0.9, ls=":"
        )
        if r[-1] < 0.97 * rpm_max:
            names_r.append((f"{w / 1e3:g} kN ({w / LBF / 1e3:.3g} klbf)", r, depth, colors[k]))
    safe = f"slowest safe speed (right of it: safe){dots}"
    ax_r.plot([], [], color="#555555", lw=2.6, label=safe, **key)
    ax_r.plot([], [], color="#555555", lw=0.9, ls=":", label="stick-slip edge alone")
    ax_r.set_xlim(0, rpm_max)
    ax_r.set_xlabel("surface speed (rpm)")
    ax_r.set_title("slowest safe surface speed at each weight on bit", fontsize=10.5)
    sec = ax_r.secondary_yaxis("right", functions=(lambda m: m / FT, lambda f: f * FT))
    sec.set_ylabel("bit depth (ft)")
    for ax in (ax_w, ax_r):
        ax.grid(alpha=0.35, lw=0.6)
    ax_w.set_ylim(depth.max(), depth.min())
    fig.suptitle(
        f"{dw.name}: safe operating window, {depth.min():,.0f} m to {depth.max():,.0f} m "
        f"({depth.min() / FT:,.0f} to {depth.max() / FT:,.0f} ft)\n"
        "safe = steady drilling is stable (no stick-slip) and the bit cannot stay stuck; "
        "where a line bends, the stick-slip edge has taken over from the stall edge",
        fontsize=11.5,
    )
    # Clear of the curves (upper right hid the top of a 120 rpm line at 210 kN), else below;
    # once the axes are final (depth runs downwards).
    for ax in (ax_w, ax_r):
        place_legend(ax, fontsize=8.5, framealpha=0.95, outside="below")
    if note:
        fig.supxlabel(note, fontsize=9, color="#333333")
    _curve_labels(fig, ax_w, names_w)
    _curve_labels(fig, ax_r, names_r)
    return fig


_BOX_PAD = 0.15  #: of the labels' white boxes, in font sizes
_BOX = {"boxstyle": f"round,pad={_BOX_PAD}", "fc": "white", "ec": "none", "alpha": 0.8}
