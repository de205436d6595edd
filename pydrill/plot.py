"""Figures people would rather look at than read (matplotlib, no screen needed)."""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")  # files only: works on servers and in CI
import matplotlib.pyplot as plt
from matplotlib.patches import Patch
from matplotlib.ticker import Formatter

# Above KILO N (or N·m) a string is a real one: its forces in kN, torques in kN·m; one
# threshold for the figures and the commands' text.
from .cli_options import KILO

# Placing legends and insets, in their own module; the figures import them from here.
from .plot_place import clear_inset as clear_inset
from .plot_place import data_pixels as data_pixels
from .plot_place import place_legend as place_legend

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .simulate import SimulationResult

BIT = "#c0392b"
TOP = "#2c3e50"
STICK = "#f5b041"
HELD = "#9c640c"  #: the torque held by the rock, drawn over the stick shading
EQUILIBRIUM = "#27ae60"

REGIME_COLORS = {
    "steady": "#27ae60",
    "stick-slip": "#e67e22",
    "stuck": "#7f8c8d",
    "oscillation": "#8e44ad",
}


def unit_scale(values, unit: str) -> tuple[float, str]:
    """(1e3, "kN") for the forces of a real string (any above ``KILO`` N), (1.0, "N") for the
    laboratory string's; the same for "N·m"."""
    import numpy as np

    v = np.abs(np.asarray(values, dtype=float))
    big = v.size and np.isfinite(v).any() and np.nanmax(v) > KILO
    return (1e3, "k" + unit) if big else (1.0, unit)


def quantity(value: float, unit: str, scale: float | None = None) -> str:
    """``60000, "N"`` → "60 kN", ``8.1, "N·m"`` → "8.1 N·m": in the units of ``unit_scale``
    (of ``value`` alone unless ``scale`` is given)."""
    if scale is None:
        scale, shown = unit_scale(value, unit)
    else:
        shown = unit if scale == 1.0 else "k" + unit
    return f"{value / scale:g} {shown}"


class _Scaled(Formatter):
    """Tick labels of an axis in N shown in kN: the labels its own formatter would write (or
    leave out), divided by ``scale``."""

    def __init__(self, inner: Formatter, scale: float) -> None:
        self.inner, self.scale = inner, scale

    def set_axis(self, axis) -> None:
        super().set_axis(axis)
        self.inner.set_axis(axis)

    def set_locs(self, locs) -> None:
        super().set_locs(locs)
        self.inner.set_locs(locs)

    def __call__(self, x, pos=None) -> str:
        return f"{x / self.scale:g}" if self.inner(x, pos) else ""


def scale_ticks(axis, scale: float) -> None:
    """Label the ticks of ``axis`` (ax.xaxis, ...) whose data are in N (N·m) in kN (kN·m):
    the data stay in SI, only the numbers written change. Call after setting its scale."""
    if scale != 1.0:
        axis.set_major_formatter(_Scaled(axis.get_major_formatter(), scale))
        axis.set_minor_formatter(_Scaled(axis.get_minor_formatter(), scale))


#: rad/s per rpm: a turn is 2π rad, a minute 60 s
PER_RPM = math.pi / 30


def rpm_axis(ax, label: str, where: str = "top"):
    """A second axis on ``ax`` reading its angular velocity in rad/s in rpm, what a driller
    sets and reads: along the ``where`` "top" (or "bottom") of an x axis of Ω, on the "right"
    (or "left") of a y axis of it. Every string's, as in the hopf figure's. The axis made."""
    import numpy as np

    functions = (lambda w: np.divide(w, PER_RPM), lambda r: np.multiply(r, PER_RPM))
    if where in ("top", "bottom"):
        sec = ax.secondary_xaxis(where, functions=functions)
        sec.set_xlabel(label, fontsize=9)
    else:
        sec = ax.secondary_yaxis(where, functions=functions)
        sec.set_ylabel(label, fontsize=9)
    return sec


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
    # A steady state past the fold is unstable on any string (the bit cannot stay there): not
    # drawn as the one it may settle at (both were "steady state Ω", 4.7 rpm beside 64.5 rpm).
    said = set()
    for omega, past in zip(s.omega_equilibrium, result.past_fold(), strict=True):
        label = "unstable steady state (past the fold)" if past else "steady state $\\Omega$"
        ax_v.axhline(
            omega,
            color="0.45" if past else EQUILIBRIUM,
            ls=":" if past else "--",
            lw=1,
            label=None if label in said else label,
        )
        said.add(label)
    ax_v.set_ylabel("angular velocity (rad/s)")
    # Zero in view, as on the atlas profiles: from equilibrium, autoscaled to the data alone,
    # a decaying wobble of 0.02 rad/s about 33.16 rad/s filled the panel as if the bit shook.
    ax_v.update_datalim([(float(t[0]), 0.0)], updatex=False)
    ax_v.autoscale_view(scalex=False)
    handles, labels = ax_v.get_legend_handles_labels()
    if intervals:
        handles.append(Patch(color=STICK, alpha=0.4))
        labels.append("bit stuck")
    handles.append(Patch(color="0.5", alpha=0.15))
    labels.append("window judged for the regime")
    # The same velocities in rpm on the right, as the text gives them beside rad/s.
    rpm = rpm_axis(ax_v, "angular velocity (rpm)", "right")
    legends = [ax_v.legend(handles, labels, loc="upper left", fontsize=9)]

    te = result.reaction_torque
    held = result.mode_index >= 2  # stick or Karnopp band
    ax_t.plot(t, te, color=TOP, lw=1.1, label="reaction torque $T_e$")
    ax_t.axhline(s.static_torque, color=BIT, ls=":", lw=1.2, label="$T_s = \\mu_s W_{ob} R_b$")
    if te.min() < 0:  # the bit is pushed backwards too: show the lower limit
        ax_t.axhline(-s.static_torque, color=BIT, ls=":", lw=1.2, label="$-T_s$")
    ax_t.axhline(result.torque, color="0.4", ls="-.", lw=1, label="surface torque $u$")
    if held.any():
        # Darker than the stick shading it lies on (the shading's own orange was 1.6:1 on it).
        ax_t.plot(t[held], te[held], ".", color=HELD, ms=2, label="held by the rock")
    # A real string's torques in kN·m, even a light one's 3.8 kN·m beside its W_ob = 30 kN
    # (was "u = 3800 N·m" in the title beside "W_ob = 30 kN", and an axis in N·m).
    scale, unit = unit_scale([result.wob, result.torque, s.static_torque], "N·m")
    scale_ticks(ax_t.yaxis, scale)
    ax_t.set_ylabel(f"torque at the bit ({unit})")
    ax_t.set_xlabel("time (s)")
    legends.append(ax_t.legend(loc="upper left", fontsize=9))
    ax_t.set_xlim(t[0], t[-1])

    p = result.params
    period = f", period {s.period:.3g} s" if s.period else ""
    fig.suptitle(
        f"{s.regime.upper()} — {p.name}, dof {p.dof}, $W_{{ob}}$ = {quantity(result.wob, 'N')}, "
        f"$u$ = {quantity(result.torque, 'N·m', scale)}",
        color=REGIME_COLORS.get(s.regime, "black"),
        fontweight="bold",
    )
    changed = _changed_fields(result)
    ax_v.set_title(
        f"bit {s.bit_min:.3g}…{s.bit_max:.3g} rad/s (mean {s.bit_mean:.3g}), "
        f"stuck {100 * s.stuck_fraction:.0f} % of the judged window{period}; "
        f"{s.stick_events} stick events" + "".join(f"\n{line}" for line in changed),
        fontsize=9,
        color="0.3",
    )
    if s.note:  # the verdict is not to be trusted yet: say so under the big regime title
        from .atlas_format import CAVEAT_TEXT

        short = CAVEAT_TEXT.get(s.caveat) or s.note
        ax_v.annotate(
            f"caveat: {s.caveat} — {short}" if s.caveat else f"caveat: {short}",
            xy=(0.5, 1.0),
            xycoords="axes fraction",
            xytext=(0, 20 + 11 * len(changed)),  # above the lines of the title
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=10,
            fontweight="bold",
            color="#a04000",
        )
    _beside(fig, ax_v, rpm, legends)
    return fig


def _beside(fig: Figure, ax, sec, legends) -> None:
    """Put each of ``legends`` beside its axes, right of the tick labels and name of ``sec``
    (a secondary axis on the right of ``ax``), all at the same distance (the axes are one
    column): at 1.01 of the axes, a legend lay over the rpm labels."""
    from matplotlib.transforms import ScaledTranslation

    fig.draw_without_rendering()
    # inches from the spine to the end of the rpm axis's name, and 3 pt more
    clear = (sec.get_tightbbox().x1 - ax.get_window_extent().x1) / fig.dpi + 3 / 72
    for legend in legends:
        move = ScaledTranslation(clear, 0, fig.dpi_scale_trans)
        legend.set_bbox_to_anchor((1.0, 1.0), transform=legend.axes.transAxes + move)


def _changed_fields(result: SimulationResult) -> list[str]:
    """The fields of the run's string that differ from its preset's (what ``--set`` or
    ``preset(..., bit_damping=...)`` changed), as lines for the figure to say which string it
    was (none for a preset's own string, or one that is no preset's)."""
    import textwrap

    from .model import _LISTS, _SCALARS, _UNITS

    inputs = result.inputs()
    if inputs["preset"] is None:
        return []
    shown = []
    for key in _LISTS + _SCALARS:
        if key not in inputs:
            continue
        if key in _LISTS:
            shown.append(f"{key} ({len(inputs[key])} values)")
        else:
            unit = "" if key.startswith("mu_") or _UNITS[key] == "1" else f" {_UNITS[key]}"
            shown.append(f"{key} = {inputs[key]:.3g}{unit}")
    if not shown:
        return []
    # 115 characters: centred over the velocity axes, narrowed by the rpm axis on their right
    # (at 130 a line of every scalar changed began off the figure's left edge).
    return textwrap.wrap(f"changed from {result.params.name}: " + ", ".join(shown), 115)


def fit_suptitle(fig: Figure, text: str, **kwargs):
    """``fig.suptitle(text)``, wrapped onto more lines where one would be wider than the figure
    (a one-panel figure cut a long title off at both edges); the title's Text."""
    import textwrap

    title = fig.suptitle(text, **kwargs)
    # The Agg canvas pydrill draws on has a renderer; FigureCanvasBase's stub does not say so.
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    room = 0.96 * fig.bbox.width
    width = title.get_window_extent(renderer).width
    if width > room:
        chars = max(20, int(len(text) * room / width))
        title.set_text("\n".join(textwrap.wrap(text, chars)))
    return title


def save(fig: Figure, path: str | Path, dpi: int = 130) -> Path:
    """Write ``fig`` to ``path`` and close it, saved or not: pyplot keeps every figure it made
    until closed, and one whose save failed (a full disk, a parent that is a file) stayed
    open in the caller's session, drawn again by a notebook, counted towards pyplot's
    "more than 20 figures" warning."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with warnings.catch_warnings():
            # An axis of a range no tick can label (a window charted to 1e-300 rpm) collapses
            # matplotlib's layout, which it says in a UserWarning on stderr beside the notes;
            # the figure is saved without it, and the command has noted the range.
            warnings.filterwarnings("ignore", "constrained_layout not applied", UserWarning)
            fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
    return path
