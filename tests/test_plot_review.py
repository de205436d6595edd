"""A reviewer's checks of pydrill's figures, on the drawn artists rather than the pixels: every
text on the canvas, no legend or inset over the data it explains, names that do not overlap,
regime colours a colour-blind reader tells apart, one meaning per colour across figures."""

from __future__ import annotations

import itertools
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.axes._secondary_axes import SecondaryAxis

matplotlib.use("Agg")

import pydrill

SMALL = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 6 }
torque = { start = 3.0, stop = 15.0, num = 5 }
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
[record]
stability = true
"""


def drawn(fig):
    """Draw ``fig`` on an Agg canvas (tests/conftest.py closes the figures after each test,
    which leaves the module's figures a bare canvas) and return its renderer."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not hasattr(fig.canvas, "get_renderer"):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def outside_canvas(fig) -> list[str]:
    """What ``fig`` draws (partly) off its canvas, after a draw: each axes with its tick
    labels, axis labels and title (a colour bar's label too), legend and figure text that is
    not wholly on it, named; [] when everything is."""
    renderer = drawn(fig)
    frame = fig.bbox.padded(1.0)
    off = []
    for artist in fig.get_default_bbox_extra_artists():
        box = artist.get_tightbbox(renderer)
        if box is None or box.width == 0 or not np.isfinite(box.extents).all():
            continue  # nothing drawn (an empty collection's box is infinite)
        if not (frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)):
            name = getattr(artist, "get_title", lambda: "")() or getattr(artist, "get_text", str)()
            off.append(f"{type(artist).__name__} {name!r}: {box.extents.round()}")
    return off


def data_points(ax, step: float = 2.0) -> np.ndarray:
    """Display pixels where ``ax`` draws data: line vertices, points along line segments every
    ``step`` pixels, and scatter points."""
    from matplotlib.collections import PathCollection

    out = [np.empty((0, 2))]
    for line in ax.get_lines():
        xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
        if not len(xy):
            continue
        px = line.get_transform().transform(xy)
        good = np.isfinite(px).all(axis=1)
        out.append(px[good])
        if line.get_linestyle() in ("None", "", " "):
            continue
        for a, b, ok in zip(px[:-1], px[1:], good[:-1] & good[1:], strict=True):
            if ok:
                n = int(np.hypot(*(b - a)) // step) + 1
                out.append(a + (b - a) * (np.arange(n)[:, None] / n))
    for c in ax.collections:
        if isinstance(c, PathCollection) and len(c.get_offsets()):
            out.append(c.get_offset_transform().transform(np.asarray(c.get_offsets(), float)))
    return np.concatenate(out)


def hidden_by(box, points) -> int:
    """How many of ``points`` (display pixels) lie inside ``box``."""
    return int(
        np.sum(
            (points[:, 0] > box.x0)
            & (points[:, 0] < box.x1)
            & (points[:, 1] > box.y0)
            & (points[:, 1] < box.y1)
        )
    )


# Machado, Oliveira & Fernandes (2009), full severity, on linear RGB.
CVD = {
    "deuteranopia": [
        [0.367322, 0.860646, -0.227968],
        [0.280085, 0.672501, 0.047413],
        [-0.011820, 0.042940, 0.968881],
    ],
    "protanopia": [
        [0.152286, 1.052583, -0.204868],
        [0.114503, 0.786281, 0.099216],
        [-0.003882, -0.048116, 1.051998],
    ],
    "tritanopia": [
        [1.255528, -0.076749, -0.178779],
        [-0.078411, 0.930809, 0.147602],
        [0.004733, 0.691367, 0.303900],
    ],
}


def _lab(color, vision: str | None = None) -> np.ndarray:
    """CIELAB (D65) of an sRGB colour, as a reader with ``vision`` sees it."""
    from matplotlib.colors import to_rgb

    c = np.array(to_rgb(color))
    c = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    if vision:
        c = np.clip(np.array(CVD[vision]) @ c, 0, 1)
    xyz = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    x = xyz @ c / np.array([0.95047, 1.0, 1.08883])
    f = np.where(x > 0.008856, np.cbrt(x), 7.787 * x + 16 / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


@pytest.mark.parametrize("vision", [None, *CVD])
def test_regime_colours_differ_for_colour_blind_readers(vision):
    from pydrill.plot import REGIME_COLORS
    from pydrill.plot_atlas import MAP_COLORS

    for palette in (MAP_COLORS, REGIME_COLORS):
        regimes = [r for r in palette if r not in ("missing", "failed")]
        for a, b in itertools.combinations(regimes, 2):
            gap = np.linalg.norm(_lab(palette[a], vision) - _lab(palette[b], vision))
            assert gap > 15, (vision, a, b, gap)  # CIELAB units: 2.3 is just noticeable


def test_operating_map_gives_no_category_the_colour_of_no_steady_state():
    from matplotlib.colors import to_rgba

    from pydrill.operating import CATEGORIES, operating_map
    from pydrill.plot_atlas import MAP_COLORS
    from pydrill.plot_map import operating_figure
    from pydrill.stability import critical_deltas

    p = pydrill.preset("reduced-scale", dof=4)
    omap = operating_map(p, np.linspace(1, 250, 60), np.linspace(0.1, 25, 60))
    omap.category[omap.category == 2] = 3  # a map without one of the categories
    fig = operating_figure(p, omap, critical_deltas(p))
    cmap = fig.axes[0].collections[0].get_cmap()
    drawn = [tuple(cmap(k)) for k in range(cmap.N)]
    # "stable steady state, can stay stuck" was the light blue that means "no steady state"
    # on the atlas maps.
    assert to_rgba(MAP_COLORS["no-steady-state"]) not in drawn
    assert outside_canvas(fig) == []
    # The grid starts at 1/250 of its range: the axes start at zero, with a 0 written there.
    ax = fig.axes[0]
    assert ax.get_xlim()[0] == 0.0 and ax.get_ylim()[0] == 0.0
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    for k, name in enumerate(CATEGORIES):  # a category in the legend only where it is drawn
        assert (name in labels) == bool((omap.category == k).any()), name


def test_bifurcation_figure_legend_and_inset_hide_none_of_the_branch():
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    for dof, vary, fixed in ((2, "wob", 8.1), (4, "torque", 60.0)):
        p = pydrill.preset("reduced-scale", dof=dof)
        b = branch(p, vary=vary, **({"torque": fixed} if vary == "wob" else {"wob": fixed}))
        fig = bifurcation_figure(p, b)
        ax = fig.axes[0]
        renderer = drawn(fig)
        points = data_points(ax)
        # Upper left, the legend hid where the stable branch starts (W_ob = 0, Ω = 43 rad/s);
        # at (0.5, 0.4), the inset hid the stable branch's middle.
        assert hidden_by(ax.get_legend().get_window_extent(), points) == 0, (dof, vary)
        (inset,) = [a for a in ax.child_axes if not isinstance(a, SecondaryAxis)]  # not rpm
        assert hidden_by(inset.get_tightbbox(renderer), points) == 0, (dof, vary)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert not [t for t in labels if t.endswith("(0)")], labels  # no kind it has not
        assert outside_canvas(fig) == []


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    out = tmp_path_factory.mktemp("atlas") / "small.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    return out


def test_every_metric_map_and_profile_keeps_its_text_on_the_canvas(small_atlas):
    import matplotlib.pyplot as plt

    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import METRICS, WORDS, atlas_figure

    with Atlas(small_atlas) as atlas:
        for initial in ("rest", "equilibrium"):
            for metric in [None, *METRICS]:
                fig = atlas_figure(atlas, initial=initial, metric=metric)
                # bit_top_ratio's colour-bar label (110 characters) ran off the top.
                assert outside_canvas(fig) == [], (initial, metric)
                if metric in WORDS:  # "spectral_abscissa of ..." said nothing to a driller
                    assert f"{WORDS[metric]} ({metric})" in fig.axes[0].get_title()
                plt.close(fig)
        for metric in (None, "severity", "spectral_abscissa"):
            fig = atlas_figure(atlas, metric=metric, profile=True, at={"torque": 9.0})
            assert outside_canvas(fig) == [], metric
            plt.close(fig)


def test_a_metric_profile_crosses_out_the_stuck_points(small_atlas):
    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure

    with Atlas(small_atlas) as atlas:
        fig = atlas_figure(atlas, metric="severity", profile=True, at={"torque": 9.0})
        k = list(atlas.axes["torque"]).index(9.0)
        stuck = atlas.regimes("rest")[:, k] == "stuck"
        wob = np.asarray(atlas.axes["wob"])
    assert stuck.any() and not stuck.all()
    ax = fig.axes[0]
    # A stuck bit's severity is 0, as steady drilling's: it was drawn as a plain point there.
    (cross,) = [c for c in ax.collections if c.get_label() == "from rest: bit stuck"]
    np.testing.assert_array_equal(np.asarray(cross.get_offsets())[:, 0], wob[stuck])
    assert "from rest: bit stuck" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_eigenvalue_figure_names_the_whole_operating_point():
    from pydrill.plot_analysis import eigenvalue_figure
    from pydrill.stability import stability

    p = pydrill.preset("reduced-scale", dof=4)
    title = eigenvalue_figure(p, stability(p, 40.0, torque=8.3)).axes[0].get_title()
    assert "$W_{ob}$ = 40 N" in title and "$u$ = 8.3 N·m" in title  # u was missing
    real = pydrill.preset("real-string", dof=2)
    title = eigenvalue_figure(real, stability(real, 60e3, torque=9e3)).axes[0].get_title()
    assert "$W_{ob}$ = 60 kN" in title and "$u$ = 9 kN·m" in title


def test_depth_window_dots_the_depths_computed_and_its_legends_hide_no_curve():
    from pydrill.plot_window import window_depth_figure
    from pydrill.tally_parse import load_tally
    from pydrill.window import window_against_depth

    tally = load_tally(Path(__file__).resolve().parents[1] / "examples/tallies/paper-eq53.toml")
    rpm, wob = [40.0, 120.0], [10e3, 30e3, 100e3]
    for depths in ([1524.0, 4572.0], np.linspace(500.0, 5000.0, 30)):
        fig = window_depth_figure(window_against_depth(tally, depths, rpm, wob), 300e3, 200.0)
        drawn(fig)
        for ax in fig.axes[:2]:
            lines = ax.get_lines()
            thick = [x for x in lines if x.get_linewidth() > 2 and len(x.get_ydata())]
            assert thick
            # Two depths drew a bare straight line between them, read as the window between.
            for line in thick:
                assert (line.get_marker() not in ("None", "", None)) == (len(depths) <= 12)
            frame = ax.get_window_extent().padded(-1.5)
            points = data_points(ax)
            inside = points[
                (points[:, 0] > frame.x0)
                & (points[:, 0] < frame.x1)
                & (points[:, 1] > frame.y0)
                & (points[:, 1] < frame.y1)
            ]
            # Upper right, the legend hid the top of the 120 rpm line (at 210 kN).
            assert hidden_by(ax.get_legend().get_window_extent(), inside) == 0
        assert outside_canvas(fig) == []


def test_simulation_figure_torque_held_stands_out_on_the_stick_shading():
    from matplotlib.colors import to_rgb

    from pydrill.plot import simulation_figure
    from pydrill.plot_atlas import contrast

    r = pydrill.simulate(preset="reduced-scale", dof=4, wob=100.0, torque=8.3, t_end=60.0)
    fig = simulation_figure(r)
    ax_t = fig.axes[1]
    (held,) = [x for x in ax_t.get_lines() if x.get_label() == "held by the rock"]
    shade = next(p for p in ax_t.patches if p.get_alpha() and p.get_alpha() > 0.2)
    ground = shade.get_alpha() * np.array(shade.get_facecolor()[:3]) + (1 - shade.get_alpha())
    # Drawn in the shading's own orange, the held torque was 1.6:1 on it.
    assert contrast(to_rgb(held.get_color()), ground) >= 3.0
    assert outside_canvas(fig) == []


def test_simulation_figure_of_steady_drilling_keeps_zero_velocity_in_view():
    from pydrill.plot import simulation_figure

    r = pydrill.simulate(
        preset="reduced-scale", dof=4, wob=40.0, torque=8.3, t_end=60.0, initial="equilibrium"
    )
    assert r.regime == "steady"
    lo, hi = simulation_figure(r).axes[0].get_ylim()
    # Autoscaled to the data alone, a wobble of 0.02 rad/s about 33.16 filled the panel.
    assert lo <= 0.0 < r.summary.bit_mean < hi
