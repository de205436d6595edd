"""Guards from a mutation audit of what the operating-map and window figures show (plot_map,
plot_window): the drawn data compared with the paper's torques by hand (T_s = μ_sb W_ob R_b,
the steady torque (c_t + c_b) Ω + W_ob R_b μ(Ω) with μ(Ω) = μ_cb + Δμ e^{-γΩ/v_f}), with
pydrill.stability at points of a drawn curve, and with unit conversions by hand."""

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from pydrill.model import preset
from pydrill.operating import CATEGORIES, operating_map
from pydrill.plot import plt
from pydrill.stability import critical_deltas, stability
from pydrill.window import Limits

P = preset("reduced-scale")  # μ_sb 0.8, μ_cb 0.5, R_b 0.1 m, γ 0.9, v_f 1, c_t 0.18, c_b 0.01
RPM = 2 * np.pi / 60  # rad/s per rpm, by hand
KLBF = 4.4482216152605  # kN per klbf, by hand


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _stable_fastest(wob, torque):
    pts = stability(P, float(wob), torque=float(torque))
    return bool(pts) and max(pts, key=lambda p: p.omega).stable


def test_operating_map_draws_each_category_in_its_place_and_the_curves_where_they_are():
    """The colour mesh is the category grid (u vertical); its stable categories are the green
    ones the title speaks of; the legend names each category shown in its mesh colour; the
    sliding line is T_s by hand; the Hopf curve separates stable from unstable steady states
    (stability()) and stays in view; the checks sit at their (W_ob, u)."""
    from matplotlib.collections import QuadMesh

    from pydrill.plot_map import operating_figure

    wob, torque = np.linspace(10.0, 200.0, 20), np.linspace(1.0, 20.0, 16)
    crossings = critical_deltas(P)
    omap = operating_map(P, wob, torque, crossings)
    checks = [(100.0, 4.0, "stuck"), (150.0, 14.0, "stick-slip"), (40.0, 15.0, "steady")]
    fig = operating_figure(P, omap, crossings, checks)
    ax = fig.axes[0]
    mesh = next(c for c in ax.collections if isinstance(c, QuadMesh))
    cat = np.asarray(mesh.get_array()).reshape(len(torque), len(wob))
    np.testing.assert_array_equal(cat, omap.category)
    faces = mesh.to_rgba(mesh.get_array()).reshape(len(torque), len(wob), 4)
    colour = {}
    for k in range(4):
        where = omap.category == k
        if where.any():
            colour[k] = faces[where][0]
            r, g, b, _ = colour[k]
            # "safe drilling = stable steady state (green)": categories 0 and 1 alone green
            assert (g > r and g > b) == (k in (0, 1)), (k, colour[k])
    assert len(colour) >= 3
    legend = ax.get_legend()
    for text, handle in zip(legend.get_texts(), legend.legend_handles, strict=True):
        if text.get_text() in CATEGORIES:
            k = CATEGORIES.index(text.get_text())
            np.testing.assert_allclose(handle.get_facecolor(), colour.pop(k))
    assert not colour, "a category shown but not in the legend"
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    sliding = next(ln for lab, ln in lines.items() if "sliding boundary" in lab)
    np.testing.assert_allclose(sliding.get_ydata(), 0.8 * 0.1 * sliding.get_xdata())
    hopf = lines["first Hopf curve"]
    w, u = hopf.get_data()
    assert w.max() <= 1.05 * 200.0 and u.max() <= 1.05 * 20.0
    seen = np.flatnonzero((w > 20) & (w < 190) & (u > 2) & (u < 19))
    assert len(seen) > 5
    for i in seen[:: max(1, len(seen) // 5)]:
        assert _stable_fastest(w[i], u[i] * 1.02) != _stable_fastest(w[i], u[i] * 0.98)
    for w0, u0, regime in checks:
        (dots,) = [c for c in ax.collections if c.get_label() == f"simulated from rest: {regime}"]
        np.testing.assert_allclose(dots.get_offsets(), [[w0, u0]])
    assert ax.get_xlabel() == "weight on bit $W_{ob}$ (N)"
    assert ax.get_ylabel() == "surface torque $u$ (N·m)"


def test_window_edges_are_the_paper_s_stick_slip_and_stall_weights_in_kilonewtons():
    """On the (W_ob kN, rpm) window: the stick-slip edge is W = δ_c e^{γΩ/v_f} / (R_b Δμ γ/v_f)
    with δ_c the first Hopf crossing's slope; on the stall edge the steady torque equals T_s;
    the green fill reaches the nearer edge alone; the torque contours are the steady torque
    in kN·m; checks sit at W_ob/1000; the second axis is in klbf."""
    from pydrill.plot_window import SAFE, window_figure

    limits = Limits.of(P)
    wob_max, rpm_max = 400.0, 200.0
    checks = [(150.0, 100.0, "steady"), (300.0, 30.0, "stuck")]
    fig = window_figure("lab", 1.0, limits, wob_max, rpm_max, checks)
    ax = fig.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    delta_c = next(c.delta for c in critical_deltas(P) if c.type == "hopf" and c.direction > 0)
    g, a = 0.9 / 1.0, 0.1 * (0.8 - 0.5)
    w, rpm = lines["stick-slip edge (first Hopf)"].get_data()
    np.testing.assert_allclose(w * 1e3, delta_c * np.exp(g * rpm * RPM) / (a * g), rtol=1e-9)
    w, rpm = lines["stall edge (torque = $T_s$)"].get_data()
    om, wn = rpm[1:] * RPM, w[1:] * 1e3
    steady = 0.19 * om + wn * 0.1 * (0.5 + 0.3 * np.exp(-g * om))
    np.testing.assert_allclose(steady, 0.8 * 0.1 * wn, rtol=1e-9)
    # the green fill: right edge at min(both edges, W_ob max) at each rpm
    (fill,) = [
        c
        for c in ax.collections
        if len(c.get_facecolor()) and np.allclose(c.get_facecolor()[0][:3], _rgb(SAFE))
    ]
    verts = fill.get_paths()[0].vertices
    r = verts[:, 1]
    hand = np.minimum.reduce(
        [
            delta_c * np.exp(g * r * RPM) / (a * g) / 1e3,
            np.where(r > 0, 0.19 * r * RPM / (a * -np.expm1(-g * r * RPM) + 1e-300), 0.19 / (a * g))
            / 1e3,
            np.full_like(r, wob_max / 1e3),
        ]
    )
    assert np.all(verts[:, 0] <= hand + 1e-9)
    assert verts[:, 0].max() > 0.9 * np.nanmax(hand[r > 1])  # reaches it, not short of it
    # the torque contours: steady torque by hand, in kN·m, at the level they are drawn for
    sets = [c for c in ax.collections if hasattr(c, "levels")]
    assert sets
    for level, path in zip(sets[0].levels, sets[0].get_paths(), strict=False):
        v = path.vertices
        if not len(v):
            continue
        om = v[:, 1] * RPM
        tq = (0.19 * om + v[:, 0] * 1e3 * 0.1 * (0.5 + 0.3 * np.exp(-g * om))) / 1e3
        np.testing.assert_allclose(tq, level, rtol=2e-2)
    for w0, r0, outcome in checks:
        (dots,) = [c for c in ax.collections if str(c.get_label()).endswith(f": {outcome}")]
        np.testing.assert_allclose(dots.get_offsets(), [[w0 / 1e3, r0]])
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("weight on bit (kN)", "surface speed (rpm)")
    (sec,) = ax.child_axes
    assert sec.get_xlabel() == "weight on bit (klbf)"
    np.testing.assert_allclose(sec._functions[0](KLBF), 1.0)  # kN -> klbf
    assert "1 m (3 ft)" in ax.get_title()


def _rgb(hex_colour):
    from matplotlib.colors import to_rgb

    return to_rgb(hex_colour)


def test_depth_window_lines_are_the_safe_limits_with_depth_downwards():
    """Thick lines: min(stick-slip, stall) weight (kN) and max(both) rpm at each depth, from
    each depth's string (Limits of tally.at_depth); depth runs downwards; the right chart's
    curves are named in kN."""
    from pathlib import Path

    from pydrill.plot_window import window_depth_figure
    from pydrill.tally_parse import load_tally
    from pydrill.window import window_against_depth

    tally = load_tally(Path(__file__).resolve().parents[1] / "examples/tallies/paper-eq53.toml")
    depths, rpm, wob = [1000.0, 3000.0], [40.0, 120.0], [30e3, 100e3]
    fig = window_depth_figure(window_against_depth(tally, depths, rpm, wob, lump=10), 300e3, 200.0)
    ax_w, ax_r = fig.axes[:2]
    lims = [Limits.of(tally.at_depth(d).to_params(lump=10)) for d in depths]
    thick_w = [ln for ln in ax_w.get_lines() if ln.get_linewidth() == 2.6 and len(ln.get_xdata())]
    thick_r = [ln for ln in ax_r.get_lines() if ln.get_linewidth() == 2.6 and len(ln.get_xdata())]
    for k, r in enumerate(rpm):
        hand = [min(lim.wob_max_stable(r), lim.wob_max_unstuck(r), 300e3) / 1e3 for lim in lims]
        np.testing.assert_allclose(thick_w[k].get_xdata(), hand, rtol=1e-9)
        np.testing.assert_allclose(thick_w[k].get_ydata(), depths)
    for k, w in enumerate(wob):
        hand = [min(max(lim.rpm_min_stable(w), lim.rpm_min_unstuck(w)), 200.0) for lim in lims]
        np.testing.assert_allclose(thick_r[k].get_xdata(), hand, rtol=1e-9)
    assert ax_w.yaxis_inverted()
    notes = {t.get_text() for t in ax_r.texts}
    for w in wob:
        if any(f"{w / 1e3:g} kN" in n for n in notes):
            break
    else:
        raise AssertionError(f"no curve named in kN: {notes}")
