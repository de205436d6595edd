"""A torque axis through zero (u < 0: the string turned backwards, the mirror image Ω → −Ω),
and what an atlas's spec holds rather than sweeps. Checked against the analytic stuck torque,
the stability of the steady states computed apart from the figure, the per-point verdicts,
and the answer without the held value."""

import json

import numpy as np
import pytest

from pydrill.atlas import Atlas
from pydrill.atlas_grid import CoordinateError
from pydrill.cli import main
from pydrill.model import preset
from pydrill.spec import parse_spec
from pydrill.stability import stability
from pydrill.sweep import run_sweep

SPECS = {
    # (W_ob, u): the analytic curves, each half of the torque axis
    "signs": """
[model]
preset = "reduced-scale"
dof = 3
[axes]
wob = { start = 40.0, stop = 160.0, num = 7 }
torque = [-10.0, -8.3, -5.0, 5.0, 8.3, 10.0]
[simulation]
t_end = 30.0
initial = ["rest", "equilibrium"]
""",
    # safe either side of u = 0, with no grid point between
    "pair": """
[model]
preset = "reduced-scale"
dof = 3
[axes]
wob = [40.0, 60.0, 100.0]
torque = [-10.0, -8.3, 8.3, 10.0]
[simulation]
t_end = 30.0
initial = ["rest", "equilibrium"]
""",
    # (u, μ_sb): the stuck boundary from the grid
    "friction": """
[model]
preset = "reduced-scale"
dof = 3
wob = 100.0
[axes]
torque = [-12.0, -9.0, -6.0, -3.0, 3.0, 6.0, 9.0, 12.0]
mu_static = { start = 0.55, stop = 1.0, num = 4 }
[simulation]
t_end = 30.0
initial = ["rest"]
""",
    # torque held in [model], not swept
    "held": """
[model]
preset = "reduced-scale"
dof = 3
torque = 8.3
[axes]
wob = [40.0, 60.0, 100.0]
[simulation]
t_end = 30.0
initial = ["rest"]
""",
}

P3 = preset("reduced-scale", dof=3)


@pytest.fixture(scope="module")
def atlases(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("signs")
    out = {}
    for name, text in SPECS.items():
        out[name] = tmp / f"{name}.h5"
        run_sweep(parse_spec(text), out[name], serial=True)
    return out


def _lines(fig):
    """The figure's drawn lines by legend label (the analytic curves), NaN gaps dropped."""
    out = {}
    for line in fig.axes[0].get_lines():
        xy = np.asarray(line.get_xydata(), dtype=float)
        out[line.get_label()] = xy[np.isfinite(xy).all(axis=1)]
    return out


def test_the_analytic_curves_are_drawn_on_both_halves_with_true_legend_words(atlases):
    with Atlas(atlases["signs"]) as atlas:
        lines = _lines(atlas.plot())
    stuck = next(xy for label, xy in lines.items() if label.startswith("stuck boundary"))
    hopf_label, hopf = next((k, v) for k, v in lines.items() if k.startswith("first Hopf"))
    assert "$|u| =" in next(k for k in lines if k.startswith("stuck"))
    # the stuck torque, |u| = μ_sb W_ob R_b, on either half (it was drawn for u > 0 only)
    w, u = stuck.T
    np.testing.assert_allclose(np.abs(u), P3.static_torque(w), rtol=1e-12)
    assert u.min() < -9 and u.max() > 9
    # Past the Hopf curve, on the side the legend names, the fastest steady state is stable,
    # and just short of it unstable: stability computed apart, at negative torque too (the
    # words were "stable above", false for u < 0).
    assert hopf_label.endswith("stable at larger |u|)")
    for sign in (1.0, -1.0):
        half = hopf[(sign * hopf[:, 1] > 3) & (sign * hopf[:, 1] < 9)]
        assert len(half) > 10, sign
        for wk, uk in half[:: len(half) // 4]:
            for factor, stable in ((1.02, True), (0.98, False)):
                states = stability(P3, float(wk), torque=float(uk * factor))
                fastest = max(states, key=lambda s: abs(s.omega))
                assert fastest.stable is stable, (wk, uk, factor)


def test_the_stuck_boundary_from_the_grid_is_drawn_where_u_turns_negative_too(atlases):
    r_b = P3.bit_radius
    with Atlas(atlases["friction"]) as atlas:
        ax = atlas.plot().axes[0]
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(label.startswith("stuck boundary $|u| =") for label in labels)
    contours = [c for c in ax.collections if hasattr(c, "levels")]
    stuck = np.concatenate([p.vertices for p in contours[0].get_paths() if len(p.vertices)])
    u, mu = stuck.T
    np.testing.assert_allclose(np.abs(u), mu * 100.0 * r_b, rtol=1e-9)
    assert u.min() < -6 and u.max() > 6  # both halves (only u > 0 before)


def test_a_safe_window_does_not_run_across_zero_torque(atlases, capsys):
    with Atlas(atlases["pair"]) as atlas:
        safe = atlas.safe_region()
        torque = atlas.axes["torque"]
        rows = atlas.safe_windows("torque")
    assert safe[0].all()  # the reference: at 40 N every point is safe, -10 ... 10 N·m
    for row, verdicts in zip(rows, safe, strict=True):
        covered = [t for t in torque if any(lo <= t <= hi for lo, hi in row.windows)]
        assert covered == list(torque[verdicts])  # the windows hold the safe points, no more
        for lo, hi in row.windows:
            assert np.sign(lo) == np.sign(hi), row  # and none spans u = 0 (was -10 ... 10)
    assert rows[0].windows == [(-10.0, -8.3), (8.3, 10.0)]
    assert main(["atlas", "safe", str(atlases["pair"]), "--along", "torque", "--json"]) == 0
    said = json.loads(capsys.readouterr().out)["rows"][0]["windows"]
    assert said == [list(w) for w in rows[0].windows]


def test_what_the_spec_holds_is_taken_at_its_value_and_refused_at_another(atlases, capsys):
    with Atlas(atlases["held"]) as atlas:
        # the reference: the same question without the held value
        assert atlas.value(wob=60, torque=8.3) == atlas.value(wob=60)
        assert atlas.value(wob=60, torque="8.3 N·m", dof=3) == atlas.value(wob=60)
        assert atlas.index(wob=60, torque=8.3) == atlas.index(wob=60)
        assert atlas.sel(torque=8.3).identical(atlas.sel())
        assert atlas.safe_windows(torque=8.3) == atlas.safe_windows()
        for call in (
            lambda: atlas.value(wob=60, torque=9),
            lambda: atlas.sel(torque=9),
            lambda: atlas.safe_windows(torque=9),
            lambda: atlas.plot(at={"torque": 9}),
        ):
            with pytest.raises(CoordinateError, match=r"holds torque = 8\.3 N·m .*not 9 N·m"):
                call()
        coords = atlas.value(wob=60, torque=8.3)["coords"]
    # the CLI's answer, which took the held value before
    path = str(atlases["held"])
    assert main(["atlas", "query", path, "--wob", "60", "--torque", "8.3", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["coords"] == coords


def test_atlas_safe_says_when_set_is_not_a_grid_value(atlases, capsys):
    path = str(atlases["signs"])
    assert main(["atlas", "safe", path, "--set", "torque=8.3"]) == 0
    exact = capsys.readouterr()
    assert exact.err == ""  # on the grid: nothing to say
    assert main(["atlas", "safe", path, "--set", "torque=8.6"]) == 0
    near = capsys.readouterr()
    # answered for the nearest grid value, 8.3 N·m, as the exact one is; and said so
    assert near.out == exact.out
    assert near.err == (
        "pydrill atlas safe: note: --set torque=8.6 is not a grid value; answered at the "
        "nearest, torque = 8.3 N·m\n"
    )
