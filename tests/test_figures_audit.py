"""The figures show what their data say: checked on the drawn artists (patch extents, text
boxes, marker positions), against the plotted values and the axis limits."""

import warnings
from itertools import combinations, pairwise
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.axes._secondary_axes import SecondaryAxis

matplotlib.use("Agg")

import pydrill

ROOT = Path(__file__).resolve().parents[1]


def _drawn(fig):
    """Lay the figure out and draw it once: the positions below are the saved ones."""
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def _marker_boxes(ax):
    """Display-space boxes of the single-point markers drawn by ``ax.plot``."""
    from matplotlib.transforms import Bbox

    boxes = []
    for line in ax.get_lines():
        if line.get_marker() in ("None", "", None) or len(line.get_xdata()) != 1:
            continue
        (x, y) = ax.transData.transform((line.get_xdata()[0], line.get_ydata()[0]))
        half = (line.get_markersize() / 2 + line.get_markeredgewidth()) * ax.figure.dpi / 72
        boxes.append(Bbox.from_extents(x - half, y - half, x + half, y + half))
    return boxes


def test_eigenvalue_plot_shades_all_of_re_above_zero_and_its_legend_hides_no_eigenvalue():
    from pydrill.plot_analysis import eigenvalue_figure
    from pydrill.stability import stability

    p = pydrill.preset("reduced-scale", dof=4)
    points = stability(p, 100.0, torque=5.9)
    ev = np.array([z for pt in points for z in pt.eigenvalues])
    assert ev.real.max() > 10  # the audit's eigenvalue far to the right (Re 14.7)
    fig = eigenvalue_figure(p, points)
    ax = fig.axes[0]
    _drawn(fig)
    (shade,) = [a for a in ax.patches if a.get_label() == "unstable half-plane"]
    box = shade.get_window_extent()
    zero, right = ax.transData.transform([(0.0, 0.0), (ax.get_xlim()[1], 0.0)])[:, 0]
    assert box.x0 == pytest.approx(zero, abs=1.0)
    assert box.x1 >= right - 1.0  # up to the right edge of the axes, whatever it is
    shown = ax.transData.transform(np.column_stack([ev.real, ev.imag]))
    unstable = shown[ev.real > 0]
    assert np.all((unstable[:, 0] >= box.x0) & (unstable[:, 0] <= box.x1))
    # No eigenvalue (nor the marker around it) under the legend.
    legend = ax.get_legend().get_window_extent().padded(6 * fig.dpi / 72)
    assert not [xy for xy in shown if legend.contains(*xy)]


def test_severity_map_hatches_exactly_the_stuck_cells(tmp_path):
    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    spec = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 10 }
torque = { start = 4.0, stop = 14.0, num = 8 }
[simulation]
t_end = 200.0
initial = ["rest"]
"""
    out = tmp_path / "small.h5"
    run_sweep(parse_spec(spec), out, serial=True)
    with Atlas(out) as atlas:
        stuck = (atlas.regimes("rest") == "stuck").T  # (torque, wob), as the map's rows
        fig = atlas_figure(atlas, metric="severity")
    assert stuck.any() and not stuck.all()
    ax = fig.axes[0]
    corners = ax.collections[0].get_coordinates()  # the cells the colour mesh draws
    hatched = [a for a in [*ax.collections, *ax.patches] if a.get_hatch()]
    assert hatched
    covered = np.zeros(stuck.shape, dtype=int)
    for i in range(stuck.shape[0]):
        for j in range(stuck.shape[1]):
            (x0, y0), (x1, y1) = corners[i, j], corners[i + 1, j + 1]
            # The centre and near each corner: a cell is hatched whole or not at all.
            fx = np.array([0.5, 0.05, 0.95, 0.05, 0.95])
            fy = np.array([0.5, 0.05, 0.05, 0.95, 0.95])
            pts = ax.transData.transform(
                np.column_stack([x0 + fx * (x1 - x0), y0 + fy * (y1 - y0)])
            )
            inside = np.zeros(len(pts), dtype=bool)
            for artist in hatched:
                paths = artist.get_paths() if hasattr(artist, "get_paths") else [artist.get_path()]
                for path in paths:
                    inside |= path.contains_points(pts, transform=artist.get_transform())
            covered[i, j] = inside.sum()
    np.testing.assert_array_equal(covered, np.where(stuck, 5, 0))


def test_bifurcation_inset_names_the_hopf_velocity_and_its_labels_clear_markers_and_labels():
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    p = pydrill.preset("reduced-scale", dof=2)
    b = branch(p, vary="wob", torque=8.1)
    hb1 = max((pt for pt in b.points if pt.type == "HB"), key=lambda pt: pt.omega)
    fig = bifurcation_figure(p, b)
    (inset,) = [a for a in fig.axes[0].child_axes if not isinstance(a, SecondaryAxis)]
    title = inset.get_title()
    assert f"Ω = {hb1.omega:.3g} rad/s" in title  # where it is on the axis: 6.49 rad/s
    assert f"frequency {hb1.frequency:.3g} rad/s" in title  # and how fast it oscillates
    renderer = _drawn(fig)
    labels = [t for t in inset.texts if t.get_text() in ("HB1", "HB2", "LP")]
    assert len(labels) == 3
    boxes = [t.get_window_extent(renderer) for t in labels]
    markers = _marker_boxes(inset)
    assert len(markers) == 3
    frame = inset.get_window_extent(renderer)
    for text, box in zip(labels, boxes, strict=True):
        assert not [m for m in markers if box.overlaps(m)], text.get_text()
        assert frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1), text
    for a, b_ in combinations(boxes, 2):
        assert not a.overlaps(b_)


def test_depth_window_curve_labels_do_not_touch_and_sit_by_their_curves():
    from pydrill.plot_window import window_depth_figure
    from pydrill.tally import load_tally
    from pydrill.window import parse_depths, window_against_depth

    tally = load_tally(ROOT / "examples/tallies/paper-eq53.toml")
    rpm = [15, 20, 25, 30, 40, 60, 90, 120, 150]  # the command's defaults
    wob = [10e3, 20e3, 30e3, 50e3, 100e3]
    dw = window_against_depth(tally, parse_depths("500m:5000m:10"), rpm, wob)
    fig = window_depth_figure(dw, 3e5, 200.0)
    renderer = _drawn(fig)
    for ax, unit in zip(fig.axes[:2], ("rpm", "kN"), strict=True):
        labels = [t for t in ax.texts if unit in t.get_text()]
        assert len(labels) >= 4
        boxes = [t.get_bbox_patch().get_window_extent(renderer) for t in labels]
        for a, b in combinations(boxes, 2):
            assert not a.padded(1.0).overlaps(b), (ax.get_title(), a, b)
        for text, box in zip(labels, boxes, strict=True):
            # Beside the thick line of its own colour, at the label's height.
            (curve,) = [
                ln
                for ln in ax.get_lines()
                if ln.get_linewidth() > 2
                and ln.get_color() is not None
                and np.allclose(matplotlib.colors.to_rgba(ln.get_color()), text.get_color())
                and len(ln.get_xdata())
            ]
            xy = ax.transData.transform(np.column_stack([curve.get_xdata(), curve.get_ydata()]))
            order = np.argsort(xy[:, 1])
            x = np.interp(box.y0, xy[order, 1], xy[order, 0])
            assert 0 <= box.x0 - x <= 8 * fig.dpi / 72, text.get_text()


def test_operating_map_markers_on_the_edges_are_drawn_whole():
    from matplotlib.collections import PathCollection

    from pydrill.operating import operating_map
    from pydrill.plot_map import operating_figure
    from pydrill.stability import critical_deltas

    p = pydrill.preset("reduced-scale", dof=4)
    wob, torque = np.linspace(1.25, 250.0, 40), np.linspace(0.125, 25.0, 40)
    crossings = critical_deltas(p)
    omap = operating_map(p, wob, torque, crossings)
    regimes = ["steady", "stick-slip", "stuck", "oscillation"]
    k = np.linspace(50.0, 250.0, 5)  # the command's --check 5 grid: its last row and column
    checks = [
        (w, u, regimes[(i + j) % 4])
        for i, w in enumerate(k)
        for j, u in enumerate(np.linspace(5.0, 25.0, 5))
    ]
    fig = operating_figure(p, omap, crossings, checks)
    ax = fig.axes[0]
    _drawn(fig)
    scatters = [c for c in ax.collections if isinstance(c, PathCollection)]
    assert sum(len(c.get_offsets()) for c in scatters) == len(checks)
    for c in scatters:
        if not c.get_clip_on():
            continue
        clip = c.get_clip_box()
        half = np.sqrt(c.get_sizes()[0]) / 2 * fig.dpi / 72
        for x, y in ax.transData.transform(c.get_offsets()):
            assert clip.x0 <= x - half and x + half <= clip.x1
            assert clip.y0 <= y - half and y + half <= clip.y1


def test_hopf_map_far_past_the_boundary_warns_not_and_shows_the_boundary():
    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    p = pydrill.preset("reduced-scale", dof=4)
    crossings = critical_deltas(p)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an overflow in exp is an error here
        fig = hopf_figure(p, crossings, omega_max=1e6)
        _drawn(fig)
    ax = fig.axes[0]
    mesh = ax.collections[0]
    counts = np.asarray(mesh.get_array()).ravel()
    centres = mesh.get_coordinates()[:-1, :-1].reshape(-1, 2)  # a corner of each cell
    x0, x1 = ax.get_xlim()
    shown = counts[(centres[:, 0] >= x0) & (centres[:, 0] < x1)]
    assert 0.05 < np.mean(shown > 0) < 0.95  # both sides of the first Hopf curve are in view
    first = max(ax.get_lines(), key=lambda ln: ln.get_linewidth())
    y = np.asarray(first.get_ydata())
    lo, hi = ax.get_ylim()
    assert np.any((y > lo) & (y < hi))
    assert "1e+06" in ax.get_title()  # says the range asked for is not the range shown


def test_real_string_figures_are_in_kilonewtons_and_the_laboratory_string_in_newtons():
    from pydrill.bifurcation import branch
    from pydrill.plot import simulation_figure
    from pydrill.plot_analysis import bifurcation_figure

    real = pydrill.preset("real-string")
    b = branch(real, vary="wob", torque=7662.0)
    fig = bifurcation_figure(real, b)
    ax = fig.axes[0]
    _drawn(fig)
    assert ax.get_xlabel().endswith("(kN)")
    assert "7.662 kN·m" in ax.get_title()
    lo, hi = ax.get_xlim()
    ticks = [
        (at, float(t.get_text().replace("−", "-")))
        for at, t in zip(ax.get_xticks(), ax.get_xticklabels(), strict=True)
        if lo <= at <= hi
    ]
    assert len(ticks) >= 3 and hi > 5e4  # data in N, labels the same values in kN
    assert all(shown == pytest.approx(at / 1e3) for at, shown in ticks)
    r = pydrill.simulate(real, wob=60000.0, torque=7662.0, t_end=30.0, n_out=301)
    fig = simulation_figure(r)
    assert "60 kN" in fig._suptitle.get_text() and "7.662 kN·m" in fig._suptitle.get_text()
    assert fig.axes[1].get_ylabel().endswith("(kN·m)")
    lab = pydrill.preset("reduced-scale", dof=2)
    fig = bifurcation_figure(lab, branch(lab, vary="wob", torque=8.1))
    assert fig.axes[0].get_xlabel().endswith("(N)") and "8.1 N·m" in fig.axes[0].get_title()


def test_regime_map_dots_exactly_the_cells_judged_with_a_caveat(tmp_path):
    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    spec = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [50.0, 100.0, 145.0, 165.0]
torque = [3.5, 8.3, 8.5, 9.5]
[simulation]
t_end = 300.0
initial = ["rest", "equilibrium"]
"""
    out = tmp_path / "caveats.h5"
    run_sweep(parse_spec(spec), out, serial=True)
    with Atlas(out) as atlas:
        # Reference: each point's own query, not the array the figure reads.
        noted = np.array(
            [
                [
                    atlas.value(wob=w, torque=u)["caveat"]["equilibrium"] is not None
                    for u in atlas.axes["torque"]
                ]
                for w in atlas.axes["wob"]
            ]
        ).T  # (torque, wob), as the map's rows
        fig = atlas_figure(atlas, initial="equilibrium")
    assert noted.any() and not noted.all()
    ax = fig.axes[0]
    corners = ax.collections[0].get_coordinates()
    dotted = [a for a in [*ax.collections, *ax.patches] if a.get_hatch() == ".."]
    assert dotted
    hits = np.zeros(noted.shape, dtype=bool)
    for i in range(noted.shape[0]):
        for j in range(noted.shape[1]):
            (x0, y0), (x1, y1) = corners[i, j], corners[i + 1, j + 1]
            centre = ax.transData.transform([[(x0 + x1) / 2, (y0 + y1) / 2]])
            hits[i, j] = any(
                path.contains_points(centre, transform=a.get_transform()).any()
                for a in dotted
                for path in a.get_paths()
            )
    np.testing.assert_array_equal(hits, noted)
    assert any("caveat" in t.get_text() for t in ax.get_legend().get_texts())


def _tally_atlas(tmp_path):
    """A 2 x 2 atlas of the paper's real string (a tally) at a fixed torque of 9 kN·m."""
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    spec = f"""
[model]
tally = "{(ROOT / "examples/tallies/paper-eq53.toml").as_posix()}"
dof = 4
torque = "9 kN·m"
[axes]
depth = [500.0, 1000.0]
wob = [20000.0, 40000.0]
[simulation]
t_end = 5.0
initial = ["rest"]
"""
    out = tmp_path / "tally.h5"
    run_sweep(parse_spec(spec), out, serial=True)
    return out


def test_tally_atlas_map_titles_say_kilo_once(tmp_path):
    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure

    with Atlas(_tally_atlas(tmp_path)) as atlas:
        fig = atlas_figure(atlas)
    title = fig.axes[0].get_title()
    assert "torque = 9 kN·m" in title and "kkN" not in title
    assert fig.axes[0].get_ylabel().endswith("(kN)")  # wob, the second axis


def _wu_atlas(tmp_path):
    """A 3 x 3 (W_ob, u) atlas of the laboratory string: steady, unstable and no steady state."""
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    spec = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [40.0, 120.0, 200.0]
torque = [2.0, 7.0, 16.0]
[simulation]
t_end = 5.0
initial = ["rest"]
"""
    out = tmp_path / "wu.h5"
    run_sweep(parse_spec(spec), out, serial=True)
    return out


@pytest.mark.parametrize("x, y", [("wob", "torque"), ("torque", "wob")])
def test_hopf_curve_legend_names_the_side_the_steady_state_is_stable_on(tmp_path, x, y):
    """With the axes swapped the stable side is another: the legend said "above" on both."""
    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure
    from pydrill.stability import stability

    with Atlas(_wu_atlas(tmp_path)) as atlas:
        fig = atlas_figure(atlas, x=x, y=y)
    ax = fig.axes[0]
    _drawn(fig)
    (label,) = [t.get_text() for t in ax.get_legend().get_texts() if "Hopf" in t.get_text()]
    side = label.split("stable ")[1].rstrip(")")
    step = {"above": (0, 1), "below": (0, -1), "to the right": (1, 0), "to the left": (-1, 0)}
    assert side in step
    (curve,) = [line for line in ax.get_lines() if "Hopf" in line.get_label()]
    (lo, hi) = ax.get_xlim()
    data = np.column_stack([curve.get_xdata(), curve.get_ydata()])
    shown = data[(data[:, 0] > lo) & (data[:, 0] < hi)]
    p = pydrill.preset("reduced-scale", dof=4)
    for xy in shown[:: max(1, len(shown) // 5)]:
        at = ax.transData.transform(xy)
        for sign, stable in ((1, True), (-1, False)):  # 15 px to the named side, and away
            px = at + sign * 15 * np.array(step[side])
            px, py = ax.transData.inverted().transform(px)
            wob, torque = (px, py) if x == "wob" else (py, px)
            points = stability(p, wob, torque=torque)
            fastest = max(points, key=lambda pt: pt.omega).stable if points else False
            assert fastest == stable, (side, wob, torque)


def test_unstable_count_map_greys_out_no_steady_state_with_a_whole_number_colour_bar(tmp_path):
    """-1 (no steady state) came out on the colour bar, nearly the colour of 0 (stable)."""
    from matplotlib.colors import BoundaryNorm

    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure

    with Atlas(_wu_atlas(tmp_path)) as atlas:
        unstable = atlas._f["unstable"][..., 0].T  # (torque, wob), as the map's rows
        fig = atlas_figure(atlas, metric="unstable")
    none = unstable < 0
    assert none.any() and (unstable == 0).any() and (unstable > 0).any()
    ax, bar = fig.axes
    mesh = ax.collections[0]
    np.testing.assert_array_equal(np.ma.getmaskarray(mesh.get_array()), none)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(t.startswith("no steady state") for t in labels)
    # One colour per whole number, with a tick on each: 0 and 1 are told apart.
    assert isinstance(mesh.norm, BoundaryNorm)
    ticks = bar.get_yticks()
    assert ticks.min() == 0 and unstable.max() in ticks and np.all(ticks == np.round(ticks))
    colours = {tuple(mesh.cmap(mesh.norm(k))) for k in range(int(unstable.max()) + 1)}
    assert len(colours) == int(unstable.max()) + 1


def test_simulation_figure_says_a_caveat_under_its_regime_and_only_then():
    """The CLI printed "note: ... too short to judge the regime"; the figure said STEADY alone."""
    from pydrill.plot import simulation_figure

    def texts(fig):
        return [t.get_text() for ax in fig.axes for t in ax.texts]

    short = pydrill.simulate(pipes=10, wob=40.0, torque=8.3, t_end=100.0, initial="equilibrium")
    assert short.summary.caveat == "short-window"
    fig = simulation_figure(short)
    (line,) = [t for t in texts(fig) if t.startswith("caveat:")]
    assert "short-window" in line and "simulate longer" in line
    _drawn(fig)  # the line is on the figure, clear of the title and the axes
    (text,) = [t for t in fig.axes[0].texts if t.get_text() == line]
    box = text.get_window_extent()
    assert box.y0 >= fig.axes[0].get_window_extent().y1
    assert box.y1 <= fig._suptitle.get_window_extent().y0 and box.y1 <= fig.bbox.y1
    longer = pydrill.simulate(pipes=10, wob=40.0, torque=8.3, t_end=200.0, initial="equilibrium")
    assert not longer.summary.note
    assert not [t for t in texts(simulation_figure(longer)) if t.startswith("caveat")]


def test_stuck_hatching_of_an_equilibrium_severity_map_covers_whole_cells_visibly(tmp_path):
    """The audit saw the "bit stuck" hatch on triangular slivers of the cells: grey lines on
    viridis' dark purple (a severity of 0) could hardly be seen, the few that could made
    slivers. Each stuck cell is hatched whole, as the cell, and in every quarter of it the
    lines stand out from its colour."""
    from matplotlib.transforms import Bbox

    from pydrill.atlas import Atlas
    from pydrill.plot_atlas import atlas_figure, contrast
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    spec = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [60.0, 80.0, 100.0, 120.0]
torque = [4.0, 5.0, 6.0, 7.0]
[simulation]
t_end = 300.0
initial = ["equilibrium"]
"""
    out = tmp_path / "eq.h5"
    run_sweep(parse_spec(spec), out, serial=True)
    with Atlas(out) as atlas:
        stuck = (atlas.regimes("equilibrium") == "stuck").T  # (torque, wob), the map's rows
        fig = atlas_figure(atlas, initial="equilibrium", metric="severity")
    assert stuck.sum() >= 3
    ax = fig.axes[0]
    mesh = ax.collections[0]
    corners = mesh.get_coordinates()
    faces = mesh.to_rgba(mesh.get_array())
    hatched = [a for a in ax.collections if a.get_hatch()]
    # The hatched patches are the stuck cells, exactly.
    drawn = sorted(
        tuple(np.round(p.get_extents().get_points().ravel(), 9))
        for a in hatched
        for p in a.get_paths()
    )
    cells = sorted(
        tuple(np.round(np.r_[corners[i, j], corners[i + 1, j + 1]], 9))
        for i, j in zip(*np.nonzero(stuck), strict=True)
    )
    assert drawn == cells
    # And the lines are seen on every quarter of each.
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())[::-1, :, :3] / 255.0  # row 0 at the bottom
    for i, j in zip(*np.nonzero(stuck), strict=True):
        (x0, y0), (x1, y1) = ax.transData.transform([corners[i, j], corners[i + 1, j + 1]])
        # The part in view (edge cells show half), inside its borders.
        box = Bbox.intersection(Bbox.from_extents(x0, y0, x1, y1), ax.bbox)
        box = Bbox.from_extents(box.x0 + 2, box.y0 + 2, box.x1 - 2, box.y1 - 2)
        xm, ym = (box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2
        for qx0, qx1, qy0, qy1 in (
            (box.x0, xm, box.y0, ym),
            (xm, box.x1, box.y0, ym),
            (box.x0, xm, ym, box.y1),
            (xm, box.x1, ym, box.y1),
        ):
            quarter = image[int(qy0) : int(qy1), int(qx0) : int(qx1)].reshape(-1, 3)
            seen = [contrast(px, faces[i, j]) >= 3 for px in quarter]
            assert sum(seen) >= 0.05 * len(seen), ((i, j), sum(seen), len(seen))


def test_long_string_fig12_of_one_panel_keeps_its_whole_title_on_the_figure(tmp_path, monkeypatch):
    """``reproduce --quick`` draws one panel; its title was cut off at both edges."""
    from pydrill import reproduce_plots_long
    from pydrill.reproduce_analysis import hopf_curves, string_summary
    from pydrill.stability import critical_deltas

    numbers = {}
    for key, p in (
        ("dof2", pydrill.preset("reduced-scale", dof=2)),
        ("pipes10", pydrill.preset("reduced-scale", pipes=10)),
    ):
        crossings = critical_deltas(p)
        numbers[key] = {"summary": string_summary(p, crossings), "fig12": hopf_curves(p, crossings)}
    numbers["strings"] = {"dof2": numbers.pop("dof2")}
    drawn = []
    monkeypatch.setattr(reproduce_plots_long, "save", lambda fig, path: drawn.append(fig))
    reproduce_plots_long.fig12_long(tmp_path, numbers, (10,))
    (fig,) = drawn
    _drawn(fig)
    title = fig._suptitle
    box = title.get_window_extent()
    assert box.x0 >= fig.bbox.x0 and box.x1 <= fig.bbox.x1 and box.y1 <= fig.bbox.y1
    words = "Fig. 12 for long strings: the first Hopf curve bounds stable drilling; the others"
    assert " ".join(title.get_text().split()).startswith(words)
    assert title.get_text().rstrip().endswith("lie just beyond it")
    # Clear of the panel's own title below it.
    assert box.y0 >= fig.axes[0].title.get_window_extent().y1


@pytest.mark.parametrize("wob, point", [(100.0, {"omega": 2.0}), (140.0, {"torque": 8.1})])
def test_eigenvalue_plot_shows_each_eigenvalue_clear_of_the_axis_on_its_side(wob, point):
    """One eigenvalue at Re 14 (or 20) set a linear axis on which all the oscillating modes
    (Re 0.04, 0.003, -3e-5) sat on Re = 0: which side each lies on could not be seen."""
    from pydrill.plot_analysis import eigenvalue_figure
    from pydrill.stability import stability

    p = pydrill.preset("reduced-scale", dof=4)
    points = stability(p, wob, **point)
    ev = np.array([z for pt in points for z in pt.eigenvalues])
    assert ev.real.max() > 10 and np.abs(ev.real).min() < 1e-2
    fig = eigenvalue_figure(p, points)
    ax = fig.axes[0]
    _drawn(fig)
    zero = ax.transData.transform([(0.0, 0.0)])[0, 0]
    shown = ax.transData.transform(np.column_stack([ev.real, ev.imag]))[:, 0]
    radius = np.sqrt(28) / 2 * fig.dpi / 72  # the markers' (s = 28 pt²)
    # Each marker whole on the side of its eigenvalue, and inside the axes.
    assert np.all(np.sign(shown - zero) == np.sign(ev.real))
    assert np.all(np.abs(shown - zero) > radius + 2), np.abs(shown - zero)
    box = ax.get_window_extent()
    assert np.all((shown - radius > box.x0) & (shown + radius < box.x1))
    # Tick labels do not run into each other.
    labels = [t.get_window_extent() for t in ax.get_xticklabels() if t.get_text()]
    assert all(a.x1 < b.x0 for a, b in pairwise(labels))
