"""The boundaries drawn on an atlas's regime maps.

On (W_ob, u) they are the analytic ones of the string at the held values: the stuck boundary
u = μ_sb W_ob R_b and the first Hopf curve (the paper's Figs. 6b and 12). On any other pair
of axes (a model parameter, the string's size or depth against W_ob or u, two parameters)
there is no such closed form to draw; there the stuck boundary is the zero of u − μ_sb W_ob
R_b evaluated at every grid point (exact where it is linear along the axes, as it is in each
of W_ob, u, μ_sb and R_b), and the stability boundary of the fastest steady state is the zero
of the spectral abscissa the atlas recorded, interpolated between grid points.

A negative torque turns the string the other way: the map is its mirror image (Ω → −Ω), so
on a torque axis below zero the curves are drawn mirrored too, the stuck one as |u| = μ_sb
W_ob R_b and the legend's side of the Hopf curve said in |u|.
"""

from __future__ import annotations

from typing import Any

from .plot_atlas import _edges, _extent

#: the curves' looks: the stuck boundary in black, the stability boundary in dark red
STUCK = {"color": "black", "linestyles": "-", "linewidths": 2}
#: its label: the static balance; a start from rest winds the string up past u, and can free
#: the bit a little beyond it (the stick-slip or steady cells on its stuck side)
STUCK_LABEL = "stuck boundary $u = \\mu_{sb} W_{ob} R_b$\n(static: a start-up can overshoot it)"
#: ... on a torque axis below zero (turned backwards: the mirror image)
STUCK_LABEL_ABS = STUCK_LABEL.replace("$u =", "$|u| =")
UNSTABLE: dict[str, Any] = {"colors": "#922b21", "linestyles": "--", "linewidths": 2}


def boundaries(atlas, ax, xname: str, yname: str, held: dict[str, float], index: list) -> list:
    """Draw the boundaries of the map of ``atlas`` on (``xname``, ``yname``), its other axes
    at ``held`` (grid positions ``index``, as the map read them); return the legend handles."""
    if {xname, yname} == {"wob", "torque"}:
        return _analytic(atlas, ax, xname, yname, held)
    return _from_grid(atlas, ax, xname, yname, held, index)


def _analytic(atlas, ax, xname: str, yname: str, held: dict[str, float]) -> list:
    import numpy as np

    from .stability import critical_deltas, unstable_count

    x, y = atlas.axes[xname], atlas.axes[yname]
    params = atlas.spec.params_at(held)  # the string at the held values (dof, depth, ...)
    wob = np.linspace(
        x.min() if xname == "wob" else y.min(), x.max() if xname == "wob" else y.max(), 200
    )
    torques = np.asarray(y if xname == "wob" else x, dtype=float)
    # Each half of the torque axis its curves: u > 0's, and u < 0's mirrored (Ω → −Ω, u → −u)
    signs = [s for s, there in ((1.0, torques.max() > 0), (-1.0, torques.min() < 0)) if there]
    signs = signs or [1.0]  # (u = 0 alone: stuck everywhere, the curves out of view)

    def halves(w, u):  # both halves one line (a NaN between): one legend entry
        return np.concatenate([np.append(w, np.nan) for _ in signs])[:-1], np.concatenate(
            [np.append(s * u, np.nan) for s in signs]
        )[:-1]

    ts = params.static_torque(wob)
    crossings = critical_deltas(params)
    first = next((c for c in crossings if c.type == "hopf" and c.direction > 0), None)
    curves = [(*halves(wob, ts), "black", "-", STUCK_LABEL if signs == [1.0] else STUCK_LABEL_ABS)]
    # A stability boundary only where nothing is unstable before it: a string without damping
    # at its ends has its fold at δ = 0 (on the axis W_ob = 0), and its steady states are
    # stable on neither side of its first Hopf curve (the legend would say "stable below").
    if first is not None and first.delta > 0 and unstable_count(crossings, first.delta) == 0:
        from .operating import hopf_curve_wu

        w, u = hopf_curve_wu(params, first.delta, np.linspace(1e-3, 80, 3000))
        # which side in the u > 0 half (in the other, mirrored: the same side in |u|)
        magnitude = np.abs(torques)
        seen = (0.0 if len(signs) == 2 else magnitude.min(), magnitude.max())
        lims = (_extent(x), seen) if xname == "wob" else (seen, _extent(y))
        side = _stable_side(params, crossings, w, u, xname, *lims)
        if signs == [-1.0]:  # the mirror image alone: above is below
            side = _MIRRORED[side]
        elif len(signs) == 2:  # both halves: one side in words true for either
            side = "at larger |u|" if side in ("above", "to the right") else "at smaller |u|"
        curves.append(
            (*halves(w, u), "#922b21", "--", f"first Hopf curve (steady state stable {side})")
        )
    handles = []
    for cw, cu, color, style, lab in curves:
        px, py = (cw, cu) if xname == "wob" else (cu, cw)
        handles += ax.plot(px, py, style, color=color, lw=2, label=lab)
    ax.set_xlim(*_extent(x))
    ax.set_ylim(*_extent(y))
    return handles


def _from_grid(atlas, ax, xname: str, yname: str, held: dict[str, float], index: list) -> list:
    import numpy as np
    from matplotlib.lines import Line2D

    x = np.asarray(atlas.axes[xname], dtype=float)
    y = np.asarray(atlas.axes[yname], dtype=float)
    if len(x) < 2 or len(y) < 2:  # a line of cells: no curve to find across it
        return []
    handles = []
    # On the grid and out to its cells' outer edges (exact: the margin is the closed form at
    # any coordinate): a contour of the grid points alone stopped half a cell short of each
    # side of a map whose cells are drawn whole (a (depth, W_ob) map's line ran 1000-5000 m
    # across cells from 750 to 5250 m).
    xe, ye = (np.concatenate([e[:1], v, e[-1:]]) for v, e in ((x, _edges(x)), (y, _edges(y))))
    # A torque axis of both signs: u = 0 a grid line too, where |u| turns (exact there as well)
    xe, ye = (
        np.union1d(v, [0.0]) if n == "torque" and v.min() < 0 < v.max() else v
        for n, v in ((xname, xe), (yname, ye))
    )
    margin = _stuck_margin(atlas, xname, yname, xe, ye, held)
    if _crosses(margin):
        ax.contour(xe, ye, margin.T, levels=[0.0], colors=STUCK["color"], linewidths=2)
        drawn = "torque" in (xname, yname)
        u = atlas.axes["torque"] if drawn else held.get("torque", atlas.spec.fixed.get("torque"))
        label = STUCK_LABEL_ABS if np.min(u) < 0 else STUCK_LABEL
        handles.append(Line2D([], [], color="black", lw=2, label=label))
    if atlas.spec.record["stability"]:
        order = list(atlas.axes)
        abscissa = np.asarray(atlas._f["spectral_abscissa"][..., 0][tuple(index)], dtype=float)
        if order.index(xname) > order.index(yname):
            abscissa = abscissa.T
        if _crosses(abscissa):
            ax.contour(x, y, np.ma.masked_invalid(abscissa).T, levels=[0.0], **UNSTABLE)
            label = "stability boundary of the fastest steady state\n(from the atlas's eigenvalues)"
            handles.append(Line2D([], [], color=UNSTABLE["colors"], ls="--", lw=2, label=label))
    return handles


def _stuck_margin(atlas, xname, yname, x, y, held) -> Any:
    """|u| − μ_sb W_ob R_b at every grid point (x, y): negative where the rock can hold the bit
    (either way round: u < 0 turns the string backwards). Each of the four is swept on x or y,
    held, fixed by the spec, or the string's own."""
    import numpy as np

    spec = atlas.spec
    # params_at needs every axis: x's and y's at any grid value (they are drawn, not read here;
    # what is read, μ_sb and R_b, is the string's own only where no axis sets it)
    params = spec.params_at(spec.coords(0) | held)
    own = {"mu_static": params.mu_static, "bit_radius": params.bit_radius}

    def value(name: str):
        if name == xname:
            return x[:, None]
        if name == yname:
            return y[None, :]
        if name in held:
            return held[name]
        return spec.fixed[name] if name in spec.fixed else own[name]

    margin = np.abs(value("torque")) - value("mu_static") * value("wob") * value("bit_radius")
    return np.broadcast_to(margin, (len(x), len(y)))


#: a side of a curve in the legend's words, and that side in the mirror image (u → −u)
_MIRRORED = {
    "above": "below",
    "below": "above",
    "to the right": "to the left",
    "to the left": "to the right",
}


def _crosses(values) -> bool:
    """Whether a grid of values has a zero to draw: both signs among its finite values."""
    import numpy as np

    finite = np.asarray(values)[np.isfinite(values)]
    return bool(finite.size) and finite.min() < 0 < finite.max()


def _stable_side(params, crossings, w, u, xname: str, xlim, ylim) -> str:
    """On which side of the Hopf curve ``(w, u)`` the map shows the steady state stable, in
    the legend's words ("above", "to the right", ...): found by the stability of the fastest
    steady state just past the curve's middle point in view, towards higher torque, and said
    for the axes drawn (torque vertical or horizontal)."""
    import numpy as np

    from .stability import stability

    wlim, ulim = (xlim, ylim) if xname == "wob" else (ylim, xlim)
    seen = np.flatnonzero(
        (w >= wlim[0]) & (w <= wlim[1]) & (u >= ulim[0]) & (u <= ulim[1]) & np.isfinite(w)
    )
    k = seen[len(seen) // 2] if len(seen) else int(np.nanargmin(np.abs(w - np.mean(wlim))))
    step = 0.01 * (ulim[1] - ulim[0]) or 0.01 * abs(u[k])
    past = stability(params, float(w[k]), torque=float(u[k] + step), crossings=crossings)
    # Stable on the side of the higher torque? (0, 1 or 2 steady states there: the fastest)
    higher = bool(past) and max(past, key=lambda pt: pt.omega).stable
    if xname == "wob":  # torque vertical
        return "above" if higher else "below"
    return "to the right" if higher else "to the left"


#: the safe region's outline: white, with a dark edge, to stand out on every regime's colour
SAFE_LABEL = "safe: steady from {starts}, stable"


def safe_outline(atlas, ax, mesh, index: list, swap: bool) -> list:
    """Outline on a regime map the cells of ``atlas.safe_region()`` (every start steady, the
    fastest steady state stable), along the cell edges the colour ``mesh`` draws: on the map
    from equilibrium it marks the part of the steady region that a start from rest reaches
    too. ``index``: the map's grid positions; ``swap``: the map's axes are in the atlas's
    reverse order. Returns the legend handle, or none without stability or safe points."""
    import numpy as np
    from matplotlib import patheffects
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    if not atlas.spec.record["stability"]:
        return []
    safe = atlas.safe_region()[tuple(index)]
    safe = safe.T if swap else safe  # (x, y)
    if not safe.any():
        return []
    edges = mesh.get_coordinates()  # (len(y) + 1, len(x) + 1, 2): cell corners
    ex, ey = edges[0, :, 0], edges[:, 0, 1]
    # Beyond the grid as at its edge: no line along the grid's own border, which the frame
    # draws, or shows half a cell inside where the axes end at the grid's values.
    pad = np.pad(safe, 1, mode="edge")
    segments = []
    # Where a cell and its neighbour along x differ: the edge between them, at ex[i]
    for i, j in zip(*np.nonzero(pad[:-1, 1:-1] != pad[1:, 1:-1]), strict=True):
        segments.append([(ex[i], ey[j]), (ex[i], ey[j + 1])])
    # and along y, at ey[j]
    for i, j in zip(*np.nonzero(pad[1:-1, :-1] != pad[1:-1, 1:]), strict=True):
        segments.append([(ex[i], ey[j]), (ex[i + 1], ey[j])])
    halo = [patheffects.Stroke(linewidth=4, foreground="#1b2631"), patheffects.Normal()]
    lines = LineCollection(segments, colors="white", linewidths=2, zorder=3.5)
    lines.set_path_effects(halo)
    ax.add_collection(lines)
    starts = "both starts" if len(atlas.initials) == 2 else atlas.initials[0]
    handle = Line2D([], [], color="white", lw=2, path_effects=halo)
    handle.set_label(SAFE_LABEL.format(starts=starts))
    return [handle]
