"""Atlas lookups against brute force and the documented rules, not against pydrill's own code.

Found by a mutation audit of pydrill/atlas_grid.py, atlas.py and atlas_merge.py: which grid
point a coordinate names (nearest, exact within float32's resolution but never nearer than a
quarter step to a neighbour, refused beyond half a step past either end), slices inclusive at
both ends, and the safe region (every start steady, the fastest steady state stable) could
each be changed without any other test failing.
"""

import itertools
import shutil

import h5py
import numpy as np
import pytest

from pydrill.atlas import Atlas
from pydrill.atlas_grid import CoordinateError, grid_index, on_grid, selection
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

TINY = """
[model]
preset = "reduced-scale"
dof = 2
[axes]
wob = [40.0, 100.0, 130.0, 160.0]
torque = [6.0, 8.3]
[simulation]
t_end = 20.0
initial = ["rest", "equilibrium"]
"""

ONE_TORQUE = """
[model]
preset = "reduced-scale"
dof = 2
[axes]
wob = [40.0, 100.0]
torque = [8.3]
[simulation]
t_end = 20.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("guards") / "tiny.h5"
    run_sweep(parse_spec(TINY), path, serial=True)
    return path


# -- which grid point a value names -----------------------------------------------------------


def _brute_nearest(values, v):
    """The index of the grid value nearest v, by looking at every one."""
    best = None
    for i, g in enumerate(values):
        if best is None or abs(g - v) < abs(values[best] - v):
            best = i
    return best


def test_nearest_is_the_nearest_grid_value_on_uneven_grids():
    rng = np.random.default_rng(7)
    for _ in range(40):
        values = np.sort(rng.choice(np.arange(1.0, 200.0, 0.5), size=6, replace=False))
        ends = values[0] - 0.45 * (values[1] - values[0]), values[-1]
        for v in rng.uniform(*ends, size=25):
            assert grid_index("wob", values, v, "nearest") == _brute_nearest(values, v)


def test_reach_is_half_of_the_end_step_at_each_end():
    """Beyond half a grid step past either end is outside the atlas, whatever the method; the
    step is the one at that end (an uneven list axis: 1 at the low end, 8 at the high)."""
    values = np.array([1.0, 2.0, 10.0])
    assert grid_index("wob", values, 0.55, "nearest") == 0
    assert grid_index("wob", values, 13.9, "nearest") == 2
    for v in (0.45, 14.1):
        with pytest.raises(CoordinateError, match="outside the atlas"):
            grid_index("wob", values, v, "nearest")


def test_a_one_value_axis_answers_for_that_value_only():
    values = np.array([8.3])
    assert grid_index("torque", values, 8.3, "nearest") == 0
    with pytest.raises(CoordinateError, match="outside the atlas"):
        grid_index("torque", values, 8.4, "nearest")


def test_exact_takes_float32_resolution_and_no_more():
    values = np.array([6.0, 8.3, 10.0])
    assert grid_index("torque", values, float(np.float32(8.3)), "exact") == 1
    assert grid_index("torque", values, 8.3 * (1 + 5e-7), "exact") == 1
    for off in (8.3 * (1 + 1e-5), 8.3 * (1 - 1e-4), 8.31):
        with pytest.raises(CoordinateError, match="not on the grid"):
            grid_index("torque", values, off, "exact")


def test_exact_never_names_a_point_nearer_its_neighbour_than_a_quarter_step():
    """Grid values 1e-7 apart: the 1e-6 tolerance would take a value halfway between for
    either; a quarter of the step (2.5e-8) decides."""
    values = np.array([1.0, 1.0 + 1e-7, 2.0])
    assert on_grid(values, 0, 1.0 + 2e-8)
    assert not on_grid(values, 0, 1.0 + 5e-8)
    assert not on_grid(values, 1, 1.0 + 5e-8)
    with pytest.raises(CoordinateError, match="not on the grid"):
        grid_index("wob", values, 1.0 + 5e-8, "exact")


# -- sel: lists, exact values and slices ------------------------------------------------------

AXES = {"wob": np.array([40.0, 100.0, 130.0, 160.0]), "torque": np.array([6.0, 8.3])}


def test_a_slice_keeps_both_of_its_ends():
    chosen = selection(AXES, ("rest",), None, {"wob": slice(40.0, 130.0)})
    assert chosen["wob"] == [40.0, 100.0, 130.0]
    chosen = selection(AXES, ("rest",), None, {"wob": slice("100 N", None)})
    assert chosen["wob"] == [100.0, 130.0, 160.0]
    assert selection(AXES, ("rest",), None, {"torque": slice(8.3, 8.3)})["torque"] == [8.3]


def test_an_exact_selection_answers_with_the_grid_value_itself():
    """What xarray then selects by equality: the grid's 8.3, not the 8.3000004 asked."""
    asked = 8.3 * (1 + 5e-8)
    chosen = selection(AXES, ("rest",), None, {"torque": asked, "wob": [40.0 * (1 + 1e-8)]})
    assert chosen["torque"] == 8.3
    assert chosen["wob"] == [40.0]


def test_sel_with_an_asked_value_near_the_grid_value(tiny):
    with Atlas(tiny) as atlas:
        ds = atlas.sel(torque=8.3 * (1 + 5e-8), initial="rest")
        assert ds["wob"].values.tolist() == [40.0, 100.0, 130.0, 160.0]
        assert list(ds.regime_name.values) == list(atlas.regimes("rest")[:, 1])
        ds = atlas.sel(wob=slice(100.0, 160.0))
        assert ds["wob"].values.tolist() == [100.0, 130.0, 160.0]


# -- regimes and the safe region --------------------------------------------------------------


def test_regimes_of_each_start_are_that_starts(tiny):
    with Atlas(tiny) as atlas:
        for start in atlas.initials:
            names = atlas.regimes(start)
            for i, wob in enumerate(atlas.axes["wob"]):
                for j, torque in enumerate(atlas.axes["torque"]):
                    point = atlas.value(wob=wob.item(), torque=torque.item())
                    assert names[i, j] == point["regime"][start]
        # the starts disagree somewhere on this grid, so a start's own codes matter
        assert (atlas.regimes("rest") != atlas.regimes("equilibrium")).any()


def _safe_by_definition(atlas):
    """Every start steady and the fastest steady state stable, point by point from value()."""
    safe = np.zeros(atlas.shape, dtype=bool)
    for i, wob in enumerate(atlas.axes["wob"]):
        for j, torque in enumerate(atlas.axes["torque"]):
            point = atlas.value(wob=wob.item(), torque=torque.item())
            steady = all(r == "steady" for r in point["regime"].values())
            unstable = point["stability"]["unstable"]
            safe[i, j] = steady and bool(unstable) and unstable[0] == 0
    return safe


def test_safe_region_is_its_definition(tiny):
    with Atlas(tiny) as atlas:
        safe = atlas.safe_region()
        assert safe.tolist() == _safe_by_definition(atlas).tolist()
        # one start steady and the other not: not safe (this grid has such a point)
        rest, equilibrium = atlas.regimes("rest"), atlas.regimes("equilibrium")
        assert ((rest == "steady") != (equilibrium == "steady")).any()
        assert safe.any()


def test_an_unstable_steady_state_is_not_safe(tiny, tmp_path):
    """The fastest steady state with one eigenvalue (or more) in the right half-plane: not
    safe, though every start settled (a short run may not have seen it grow)."""
    copy = tmp_path / "unstable.h5"
    shutil.copy(tiny, copy)
    with Atlas(copy) as atlas:
        safe = atlas.safe_region()
    i, j = np.argwhere(safe)[0]
    with h5py.File(copy, "r+") as f:
        f["unstable"][i, j, 0] = 1
    with Atlas(copy) as atlas:
        point = atlas.value(wob=atlas.axes["wob"][i].item(), torque=atlas.axes["torque"][j].item())
        assert point["stability"]["unstable"][0] == 1  # the point as written
        changed = atlas.safe_region()
        assert not changed[i, j]
        assert changed.sum() == safe.sum() - 1
        assert changed.tolist() == _safe_by_definition(atlas).tolist()


def test_an_axis_of_one_value_may_be_left_out(tmp_path):
    path = tmp_path / "one.h5"
    run_sweep(parse_spec(ONE_TORQUE), path, serial=True)
    with Atlas(path) as atlas:
        assert atlas.index(wob=100.0) == (1, 0)
        assert atlas.index("nearest", wob=45.0) == (0, 0)
        assert atlas.value(wob=40.0)["coords"] == {"wob": 40.0, "torque": 8.3}


# -- branches of steady states (pydrill.bifurcation) ------------------------------------------


def test_special_points_are_labelled_hb1_and_lp_even_when_alone():
    """Hopf points are HB1, HB2, ... from the highest Ω down, even a single one (the table,
    --json and the figures call the end of the stable branch HB1); a single fold is LP."""
    from pydrill.bifurcation import point_labels

    assert point_labels([("LP", 2.0), ("HB", 5.0)]) == ["LP", "HB1"]
    assert point_labels([("HB", 1.0), ("HB", 3.0), ("LP", 2.0)]) == ["HB2", "HB1", "LP"]
    assert point_labels([("LP", 1.0), ("LP", 3.0)]) == ["LP2", "LP1"]


def test_a_branch_samples_low_speeds_whatever_its_top():
    """Half the samples geometric from 1e-6 v_f/γ_b up: with omega_max = 1e5 rad/s the
    laboratory string's Hopf and fold points (1.6 ... 6.5 rad/s) are sampled as finely as
    with omega_max = 40."""
    from pydrill.bifurcation import FLOOR, branch
    from pydrill.model import preset

    p = preset("reduced-scale", dof=2)
    b = branch(p, vary="torque", wob=100.0, omega_max=1e5, samples=2000)
    assert len(b.omega) == 2000 and np.all(np.diff(b.omega) > 0)
    scale = p.stribeck_velocity / p.stribeck_decay
    assert b.omega[0] == pytest.approx(FLOOR * scale, rel=1e-9)
    # 1000 geometric samples over the decades from there to 1e5: those below 10 rad/s
    low = 1000 * np.log(10.0 / b.omega[0]) / np.log(1e5 / b.omega[0])  # 634.8
    assert abs(np.count_nonzero(b.omega < 10.0) - low) <= 2
    # and the other half evenly spaced up to the top: 100, 200, ... 1e5 rad/s
    assert b.omega[-1] == pytest.approx(1e5, rel=1e-8)
    even = 100.0 * np.arange(1, 1001)
    nearest = b.omega[np.abs(b.omega[:, None] - even[None, :]).argmin(axis=0)]
    assert nearest == pytest.approx(even, rel=1e-8)


def test_crossings_of_a_string_damped_otherwise_are_refused():
    """Every string's fold is at δ = c_r + c_b: crossings whose fold is 0.5 % away are
    another string's, and a branch drawn with them would be that string's stability."""
    from pydrill.bifurcation import branch
    from pydrill.model import preset
    from pydrill.stability import critical_deltas

    p = preset("reduced-scale", dof=2)
    other = p.replace(top_damping=p.top_damping * 1.005)
    (fold,) = [c.delta for c in critical_deltas(other) if c.type == "fold"]
    assert fold == pytest.approx(other.top_damping + other.bit_damping, rel=1e-12)
    with pytest.raises(ValueError, match="not this string's"):
        branch(p, vary="torque", wob=100.0, crossings=critical_deltas(other))
    without_fold = [c for c in critical_deltas(p) if c.type != "fold"]
    with pytest.raises(ValueError, match="no fold"):
        branch(p, vary="torque", wob=100.0, crossings=without_fold)
    own = branch(p, vary="torque", wob=100.0, crossings=critical_deltas(p))
    assert own == branch(p, vary="torque", wob=100.0)


def test_unstable_counts_are_the_eigenvalues_right_of_the_axis():
    """unstable_count from the crossings alone, against the Jacobian's eigenvalues (LAPACK) at
    slopes between and beyond the crossings; crossings out of order are refused, as the
    counts they give would be wrong."""
    from pydrill.model import preset
    from pydrill.stability import critical_deltas, eigenvalues, unstable_count

    p = preset("reduced-scale", dof=3)
    crossings = critical_deltas(p)
    deltas = sorted(c.delta for c in crossings)
    probes = [0.0, *(0.5 * (a + b) for a, b in itertools.pairwise(deltas)), 2 * deltas[-1] + 1]
    counts = unstable_count(crossings, probes)
    for delta, count in zip(probes, counts, strict=True):
        assert count == np.count_nonzero(eigenvalues(p, delta).real > 0), delta
    assert len(set(counts.tolist())) > 1
    with pytest.raises(ValueError, match="not finite deltas in increasing order"):
        unstable_count(crossings[::-1], probes)
