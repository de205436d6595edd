"""The figure of a one-axis atlas: what it draws is what the atlas holds."""

import subprocess

import h5py
import numpy as np
import pytest
from sweeping import CMD

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.plot_atlas import MAP_COLORS
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

LINE = """
[model]
preset = "reduced-scale"
dof = 4
torque = 8.3
[axes]
wob = { start = 40.0, stop = 160.0, num = 13 }
[simulation]
t_end = 200.0
initial = ["rest", "equilibrium"]
"""


@pytest.fixture(scope="module")
def line_atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("line") / "line.h5"
    run_sweep(parse_spec(LINE), out, serial=True)
    return out


def _raw(atlas, name):
    with h5py.File(atlas, "r") as f:
        return f[name][...]


def test_the_profile_draws_each_starts_bit_velocities_and_the_steady_state(line_atlas):
    with Atlas(line_atlas) as atlas:
        fig = atlas.plot()
    ax, strip = fig.axes
    wob = _raw(line_atlas, "wob")
    lines = {line.get_label(): line for line in ax.get_lines()}
    for j, start in enumerate(["rest", "equilibrium"]):
        line = lines[f"from {start}: mean (band: least to largest)"]
        np.testing.assert_array_equal(line.get_xdata(), wob)
        np.testing.assert_array_equal(line.get_ydata(), _raw(line_atlas, "bit_mean")[:, j])
    # The band of each start spans its least to its largest bit velocity.
    bands = ax.collections
    assert len(bands) == 2
    for j, band in enumerate(bands):
        top = band.get_paths()[0].vertices[:, 1]
        assert np.isclose(top.max(), np.nanmax(_raw(line_atlas, "bit_max")[:, j]))
        assert np.isclose(top.min(), np.nanmin(_raw(line_atlas, "bit_min")[:, j]))
    # The fastest steady state, split by the sign of its spectral abscissa.
    omega, abscissa = (
        _raw(line_atlas, "omega_eq")[:, 0],
        _raw(line_atlas, "spectral_abscissa")[:, 0],
    )
    stable = lines["fastest steady state, stable"].get_ydata()
    np.testing.assert_array_equal(np.isfinite(stable), abscissa < 0)
    np.testing.assert_array_equal(stable[abscissa < 0], omega[abscissa < 0])
    assert (abscissa >= 0).any() == ("fastest steady state, unstable" in lines)
    # The strip: a row per start, coloured by the regime the atlas holds there.
    regimes = _raw(line_atlas, "regime")
    colors = list(MAP_COLORS)
    drawn = strip.collections[0].get_array().reshape(2, -1)
    for j in range(2):
        names = [colors[int(k)] for k in drawn[j]]
        assert names == [fmt.REGIME_NAMES[int(c)] for c in regimes[:, j]]
    assert {"steady", "stick-slip", "stuck"} <= set(
        fmt.REGIME_NAMES[int(c)] for c in regimes.ravel()
    )  # the grid crosses the regimes, so the test sees each colour
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend == [n for n in MAP_COLORS if fmt.REGIMES[n] in np.unique(regimes)]
    assert strip.get_xlabel() == "weight on bit $W_{ob}$ (N)"
    assert "torque = 8.3 N·m" in ax.get_title() and "(13 points)" in ax.get_title()


def test_a_profile_of_a_metric_from_each_start(line_atlas):
    with Atlas(line_atlas) as atlas:
        fig = atlas.plot(metric="stick_events")
        steady = atlas.plot(metric="spectral_abscissa")
    ax = fig.axes[0]
    counts = _raw(line_atlas, "stick_events").astype(float)
    counts[counts < 0] = np.nan  # a count not measured (no steady state to start from)
    for j, line in enumerate(ax.get_lines()):
        np.testing.assert_array_equal(line.get_ydata(), counts[:, j])
    assert ax.get_ylabel() == "stick_events"
    (line,) = [x for x in steady.axes[0].get_lines() if x.get_label() == "fastest steady state"]
    np.testing.assert_array_equal(line.get_ydata(), _raw(line_atlas, "spectral_abscissa")[:, 0])
    assert steady.axes[0].get_ylabel() == "spectral_abscissa (1/s)"


def test_a_profile_refuses_a_second_axis_by_name(line_atlas):
    with Atlas(line_atlas) as atlas:
        with pytest.raises(ValueError, match=r"y = 'torque': this atlas has one axis, wob"):
            atlas.plot(y="torque")
        with pytest.raises(ValueError, match=r"x = 'dof' is not an axis of this atlas; axes: wob"):
            atlas.plot(x="dof")


def test_atlas_plot_command_draws_a_one_axis_atlas(line_atlas, tmp_path):
    out = tmp_path / "line.png"
    proc = subprocess.run(
        [*CMD, "atlas", "plot", str(line_atlas), "--out", str(out)], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert out.stat().st_size > 20_000


def test_a_profile_of_a_map_is_the_sweep_of_its_row(line_atlas, tmp_path):
    """A (W_ob, u) atlas's profile along W_ob at u = 8.3 draws what a sweep of W_ob alone at
    u = 8.3 (LINE) computed: the same points, simulated apart."""
    out = tmp_path / "map.h5"
    run_sweep(
        parse_spec(
            LINE.replace("torque = 8.3\n", "").replace(
                "[simulation]", "torque = [6.0, 8.3]\n[simulation]"
            )
        ),
        out,
        serial=True,
    )
    with Atlas(out) as atlas, Atlas(line_atlas) as line:
        cut = atlas.plot(profile=True, x="wob", at={"torque": 8.3})
        alone = line.plot()
        metric = atlas.plot("stuck_fraction", profile=True, at={"torque": 8.3})
        with pytest.raises(ValueError, match=r"y = 'torque' with --profile: a profile is drawn"):
            atlas.plot(profile=True, y="torque")
    for a, b in zip(cut.axes[0].get_lines(), alone.axes[0].get_lines(), strict=True):
        assert a.get_label() == b.get_label()
        np.testing.assert_array_equal(a.get_xdata(), b.get_xdata())
        np.testing.assert_array_equal(a.get_ydata(), b.get_ydata())
    np.testing.assert_array_equal(
        cut.axes[1].collections[0].get_array(), alone.axes[1].collections[0].get_array()
    )
    assert "torque = 8.3 N·m" in cut.axes[0].get_title()
    assert "(13 points of an atlas of 26 points)" in cut.axes[0].get_title()
    with h5py.File(out, "r") as f:
        k = list(f["torque"][...]).index(8.3)
        np.testing.assert_array_equal(
            metric.axes[0].get_lines()[0].get_ydata(), f["stuck_fraction"][:, k, 0]
        )
    proc = subprocess.run(
        [
            *CMD,
            "atlas",
            "plot",
            str(out),
            "--out",
            str(tmp_path / "p.png"),
            "--profile",
            "--set",
            "torque=8.3",
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0 and (tmp_path / "p.png").stat().st_size > 20_000, proc.stderr


DEPTH = """
[model]
tally = "{tally}"
dof = 6
torque = "9 kN·m"
[axes]
depth = [1000.0, 3000.0]
wob = ["40 kN", "70 kN", "100 kN"]
[simulation]
t_end = 50.0
initial = ["rest"]
"""


def test_titles_give_held_depths_in_metres_and_fit_the_figure(tmp_path):
    """'depth = 3000' had no unit; a real string's title ran past both edges of a profile."""
    from pathlib import Path

    tally = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"
    out = tmp_path / "depth.h5"
    run_sweep(parse_spec(DEPTH.format(tally=tally), base=tmp_path), out, serial=True)
    with Atlas(out) as atlas:
        figures = [
            atlas.plot(profile=True, x="wob", at={"depth": 3000.0}),
            atlas.plot("severity", x="depth", y="wob"),
            atlas.plot(x="wob", y="depth"),
        ]
    for fig in figures:
        text = fig.axes[0].get_title()
        assert "torque = 9 kN·m" in text and all(len(line) <= 95 for line in text.split("\n"))
        fig.canvas.draw()  # the title inside the figure, as saved
        box = fig.axes[0].title.get_window_extent()
        assert box.x0 >= 0 and box.x1 <= fig.bbox.width
    assert "depth = 3000 m:" in figures[0].axes[0].get_title()
    assert figures[0].axes[1].get_xlabel() == "weight on bit $W_{ob}$ (kN)"


# Steady from rest at every point: the bit's velocity barely varies along the row.
STEADY = """
[model]
preset = "reduced-scale"
dof = 4
torque = 8.3
[axes]
wob = [20.0, 30.0, 40.0]
[simulation]
t_end = 100.0
initial = ["rest"]
"""


def test_a_profile_shows_zero_with_every_value_so_small_changes_stay_small(tmp_path):
    """Autoscaled to the data alone, a profile of steady points (9.1185 ... 9.1203 rad/s) filled
    the plot with the last 1e-4 of the start-up's wobble, as if the bit shook: zero is in view,
    beside every value drawn (read from the raw datasets)."""
    out = tmp_path / "steady.h5"
    run_sweep(parse_spec(STEADY), out, serial=True)
    assert (_raw(out, "regime") == fmt.REGIMES["steady"]).all()
    with Atlas(out) as atlas:
        figures = {"bit": atlas.plot(), "period": atlas.plot("bit_top_ratio")}
    drawn = {
        "bit": np.concatenate([_raw(out, n)[..., 0] for n in ("bit_min", "bit_max", "omega_eq")]),
        "period": _raw(out, "bit_top_ratio")[..., 0],
    }
    for what, fig in figures.items():
        low, high = fig.axes[0].get_ylim()
        values = drawn[what][np.isfinite(drawn[what])]
        assert low <= 0.0 < values.min() and values.max() <= high, what
        # and the values fill a visible part of it: from zero to the largest, not the plot's top
        assert values.max() >= 0.8 * high


def test_a_title_over_a_map_narrowed_by_its_legend_stays_inside_the_figure():
    """Centred over a map that a wide legend beside it narrows, a title of 80 characters ran
    past the figure's left edge and was cut; it is shifted inside, by the overflow only."""
    from pydrill.plot import plt
    from pydrill.plot_atlas_title import keep_title_inside

    fig, ax = plt.subplots(figsize=(9.5, 6.2), layout="constrained")
    ax.plot([0, 1], [0, 1], label="a legend entry as wide as half the figure " * 2)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title("string paper-eq53, dof 24, torque = 9 kN·m: regime from rest after 100 s (3969)")
    fig.draw_without_rendering()
    assert ax.title.get_window_extent().x0 < 0  # as it was: cut at the left
    keep_title_inside(fig, ax)
    fig.canvas.draw()
    box = ax.title.get_window_extent()
    assert 0 <= box.x0 and box.x1 <= fig.bbox.width
    assert box.x0 < 10  # moved by the overflow (and a few pixels), not re-centred elsewhere
    plt.close(fig)
