"""Python API edges found by an audit: sweeps' workers and specs, the plan's limits, frozen
axes, atlas coordinates in float32, closed and pickled atlases, stability's inputs, units'
refusals and the exported TallyError; and simulate and units.parse fuzzed with hypothesis (as
test_api_fuzz.py fuzzes the rest of the API), with the output times and quantities the
fuzzing found wrong."""

import copy
import math
import pickle

import numpy as np
import pytest
from fuzzing import FUZZ, values
from hypothesis import given
from hypothesis import strategies as hst
from sweeping import SMALL

import pydrill
from pydrill import stability as st
from pydrill import units
from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import AtlasError, run_sweep
from pydrill.sweep_plan import SweepPlan, plan_sweep

# Six quick points; two W_ob 4e-7 N apart (a step far finer than 1e-6 of them).
CLOSE = """
[model]
preset = "reduced-scale"
dof = 2
[axes]
wob = [40.0, 100.0, 100.0000004]
torque = [6.0, 8.3]
[simulation]
t_end = 20.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def spec():
    return parse_spec(SMALL)


@pytest.fixture(scope="module")
def close_atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("close") / "c.h5"
    run_sweep(parse_spec(CLOSE), out, serial=True)
    return out


# 1. run_sweep: workers and spec, refused before anything is written


@pytest.mark.parametrize(
    ("workers", "error", "shown"),
    [
        (0, ValueError, "workers = 0"),
        (257, ValueError, "workers = 257"),
        (True, TypeError, "workers = True"),
        ("2", TypeError, "workers = '2'"),
        (2.5, TypeError, "workers = 2.5"),
        (-1, ValueError, "workers = -1"),  # last: it hung before the fix
    ],
)
def test_run_sweep_refuses_bad_workers_before_writing(spec, tmp_path, workers, error, shown):
    out = tmp_path / "new" / "w.h5"
    with pytest.raises(error, match=rf"{shown} is not allowed: None \(one per core\) or an "):
        run_sweep(spec, out, workers=workers)
    assert list(tmp_path.iterdir()) == []  # no atlas, no journal, no directory


@pytest.mark.parametrize("call", [run_sweep, plan_sweep])
def test_sweeps_refuse_a_path_for_a_spec(tmp_path, call):
    args = (tmp_path / "w.h5",) if call is run_sweep else ()
    refused = r"spec = 'small.toml' \(str\) is not a SweepSpec: read one with pydrill.load_spec"
    with pytest.raises(TypeError, match=refused):
        call("small.toml", *args)
    assert list(tmp_path.iterdir()) == []


# 2. A spec's axes are read-only


def test_spec_axes_are_read_only(spec):
    assert not spec.axes["wob"].flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        spec.axes["wob"][0] = 50.0
    assert spec.axes["wob"][0] == 40.0


@pytest.mark.parametrize(
    "change",
    [
        lambda s: s.axes.__setitem__("wob", np.array([1.0])),  # the whole axis replaced
        lambda s: s.axes.pop("torque"),
        lambda s: s.simulation.update(t_end=1.0),
        lambda s: s.overrides.setdefault("bit_damping", 1.0),
        lambda s: s.record.clear(),
        lambda s: s.fixed.__setitem__("wob", 1.0),
    ],
)
def test_spec_tables_are_read_only_and_its_digest_stays(spec, change):
    digest, shape = spec.digest, spec.shape
    with pytest.raises(TypeError, match="read-only"):
        change(spec)
    assert spec.digest == digest and spec.shape == shape
    again = pickle.loads(pickle.dumps(spec))  # as it travels to a worker
    assert again.digest == digest and list(again.axes) == list(spec.axes)
    assert copy.deepcopy(spec).digest == digest


# 3. plan_sweep's limits and SweepPlan.wall_seconds


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"most": 0}, ValueError, r"most = 0 is not allowed: an integer >= 1"),
        ({"most": 2.5}, TypeError, r"most = 2.5 is not allowed"),
        ({"least": -1}, ValueError, r"least = -1 is not allowed: an integer >= 0"),
        ({"budget": -1}, ValueError, r"budget = -1 is not allowed: a finite number of seconds"),
        ({"budget": 0.0}, ValueError, r"budget = 0.0 is not allowed"),
        ({"budget": math.inf}, ValueError, r"budget = inf is not allowed"),
        ({"budget": "1"}, TypeError, r"budget = '1' is not allowed"),
    ],
)
def test_plan_sweep_refuses_bad_limits(spec, kwargs, error, message):
    with pytest.raises(error, match=message):
        plan_sweep(spec, **kwargs)


def test_wall_seconds_needs_a_worker():
    plan = SweepPlan(10, 10, "none", 3, 0, "", 2.0, 1.0, 3.0, 0, 0)
    assert plan.wall_seconds(4) == (2.5, 5.0, 7.5)
    for bad, error in ((0, ValueError), (-1, ValueError), ("2", TypeError), (True, TypeError)):
        with pytest.raises(error, match=rf"workers = {bad!r} is not allowed: an integer >= 1"):
            plan.wall_seconds(bad)


# 4. Atlas: float32 coordinates, reads after close, pickling


def test_atlas_matches_float32_coordinates(close_atlas):
    with Atlas(close_atlas) as atlas:
        point = atlas.value(wob=np.float32(40.0), torque=np.float32(8.3))
        assert point["coords"] == {"wob": 40.0, "torque": 8.3}
        assert atlas.index(wob=40.0 * (1 + 3e-7), torque=8.3) == (0, 1)
        # Two grid values 4e-7 apart: each is found, and a value between them is neither.
        assert atlas.index(wob=100.0, torque=6.0) == (1, 0)
        assert atlas.index(wob=100.0000004, torque=6.0) == (2, 0)
        with pytest.raises(KeyError, match=r"wob = 100.0000002 N is not on the grid"):
            atlas.index(wob=100.0000002, torque=6.0)


def test_atlas_miss_shows_the_difference(close_atlas):
    with Atlas(close_atlas) as atlas:
        # Both print as 40 and 100 with 6 digits ({:g}): in full, they differ.
        with pytest.raises(
            KeyError, match=r"wob = 40.000045 N is not on the grid \(nearest 40.0 N\)"
        ):
            atlas.value(wob=40.000045, torque=8.3)
        with pytest.raises(
            KeyError, match=r"wob = 100.00004 N is outside the atlas \(40 N ... 100.0000004 N\)"
        ):
            atlas.value(wob=100.00004, torque=8.3)
        with pytest.raises(
            KeyError, match=r"torque = 8.4 N·m is not on the grid \(nearest 8.3 N·m\)"
        ):
            atlas.value(wob=40.0, torque=8.4)


def test_atlas_reads_after_close_are_refused(close_atlas):
    atlas = Atlas(close_atlas)
    atlas.close()
    assert atlas.closed
    for read in (
        lambda: atlas.value(wob=40.0, torque=8.3),
        lambda: atlas.summary(),
        lambda: atlas.regimes(),
        lambda: atlas.safe_region(),
        lambda: atlas.to_xarray(),
    ):
        with pytest.raises(AtlasError, match=r"c\.h5: this Atlas is closed"):
            read()


def test_atlas_pickles_as_its_path(close_atlas):
    with Atlas(close_atlas) as atlas:
        again = pickle.loads(pickle.dumps(atlas))
        try:
            assert again.path == close_atlas.absolute() and not again.closed
            assert again.value(wob=40.0, torque=6.0) == atlas.value(wob=40.0, torque=6.0)
        finally:
            again.close()


# 5. stability's inputs


P = pydrill.preset("reduced-scale", dof=2)
CROSSINGS = st.critical_deltas(P)


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: st.stability_map(P, [math.nan], [100.0]), ValueError, r"omega\[0\] = nan"),
        (lambda: st.stability_map(P, [1.0], [-100.0]), ValueError, r"wob\[0\] = -100 is not"),
        (lambda: st.stability_map(P, [[1.0]], [100.0]), ValueError, r"omega has shape \(1, 1\)"),
        (lambda: st.stribeck_slope(P, -100, 1), ValueError, r"wob = -100 is not allowed: .* > 0"),
        (lambda: st.stribeck_slope(P, 100, -1), ValueError, r"omega = -1 is not allowed: .* >= 0"),
        (lambda: st.stribeck_slope(P, "100", 1), TypeError, r"wob = '100' is not allowed"),
        (lambda: st.boundary_wob(P, -1, 1), ValueError, r"delta = -1 is not allowed: .* >= 0"),
        (lambda: st.boundary_wob(P, 1, [0, math.inf]), ValueError, r"omega\[1\] = inf"),
        (lambda: st.unstable_count(CROSSINGS, math.nan), ValueError, r"delta = nan is not"),
        (lambda: st.criticality(math.nan), ValueError, r"l1 = nan is not allowed"),
        (lambda: st.criticality("0.1"), TypeError, r"l1 = '0.1' is not allowed"),
        (
            lambda: st.stability(P, 100.0, torque=8.3, crossings=[]),
            ValueError,
            r"crossings are not this string's \(no fold; its own have one at c_r",
        ),
        (
            lambda: st.stability(
                P, 100.0, torque=8.3, crossings=st.critical_deltas(pydrill.preset("real-string"))
            ),
            ValueError,
            r"crossings are not this string's \(a fold at delta",
        ),
    ],
)
def test_stability_refuses_bad_inputs(call, error, message):
    with pytest.raises(error, match=message):
        call()


def test_stability_map_takes_numbers_as_one_value_axes():
    counts = st.stability_map(P, 5.0, 100.0)
    assert counts.shape == (1, 1)
    assert counts[0, 0] == st.unstable_count(CROSSINGS, st.stribeck_slope(P, 100.0, 5.0))
    # The string's own crossings pass, also for one without damping at its ends (fold at 0).
    undamped = P.replace(top_damping=0.0, bit_damping=0.0)
    own = st.critical_deltas(undamped)
    assert st.stability_map(undamped, [1.0], [100.0], own).shape == (1, 1)


# 6. units


def test_units_name_unknown_units_and_kinds():
    assert units.convert(1.0, "velocity", "RPM") == pytest.approx(60 / (2 * math.pi))
    assert units.convert(1.0, "torque", "kft-lbf") == units.convert(1.0, "torque", "kft·lbf")
    with pytest.raises(ValueError, match=r"unit = 'rps' is not a velocity unit; use one of rad/s"):
        units.convert(1.0, "velocity", "rps")
    with pytest.raises(ValueError, match=r"kind 'foo'; use one of length, force, torque"):
        units.convert(1.0, "foo", "m")
    with pytest.raises(TypeError, match=r"si_value = '1' is not allowed: a number"):
        units.convert("1", "force", "N")
    with pytest.raises(ValueError, match=r"kind 'wob'; use one of length, force, torque"):
        units.parse("100 kN", "wob")
    with pytest.raises(ValueError, match=r"unit 'kg' is not an inertia unit; use one of kg·m2"):
        units.parse("3 kg", "inertia")
    with pytest.raises(ValueError, match=r"'fast' is not a rate: write a number and a unit"):
        units.parse("fast", "rate")


# 7. TallyError


def test_tally_error_is_exported():
    from pydrill.tally import TallyError

    assert pydrill.TallyError is TallyError and "TallyError" in pydrill.__all__


@pytest.mark.parametrize(
    ("l1", "expected"),
    [(-1e-300, "supercritical"), (0.0, "degenerate"), (-0.0, "degenerate"), (2.5, "subcritical")],
)
def test_criticality_follows_the_sign_of_l1_and_names_zero(l1, expected):
    # l1 = 0 used to be called "subcritical": the first coefficient decides nothing there
    assert st.criticality(l1) == expected


# 8. Fuzzed (tests/test_api_fuzz.py has the rest): simulate


@FUZZ
@given(
    key=hst.sampled_from(
        [
            "wob",
            "torque",
            "t_end",
            "rtol",
            "max_step",
            "window_fraction",
            "perturbation",
            "bit_radius",
            "stribeck_velocity",
            "n_out",
            "dof",
        ]
    ),
    value=values,
)
def test_simulate_answers_finitely_or_refuses_by_name(key, value):
    kwargs = {"wob": 100.0, "torque": 8.3, "dof": 2, "t_end": 5.0, "n_out": 11, key: value}
    try:
        r = pydrill.simulate(**kwargs, max_steps=200_000)
    except (ValueError, TypeError) as exc:
        assert key in str(exc) or "initial" in str(exc) or "mu_" in str(exc)
        return
    except pydrill.SolverError:
        return
    assert np.all(np.isfinite(r.states)) and np.all(np.diff(r.t) > 0)


@FUZZ
@given(
    t_end=hst.one_of(
        hst.sampled_from([5e-324, 1e-320, 1e-310, 1e-305, 3e-308]), hst.floats(5e-324, 1e-290)
    ),
    n_out=hst.integers(2, 4000),
)
def test_output_times_increase_or_the_run_is_refused(t_end, n_out):
    """The core flushes subnormal numbers to 0: t_end = 5e-324 s was judged "steady" from
    rest, and 1e-305 s gave 3001 output times of 0."""
    try:
        r = pydrill.simulate(wob=100.0, torque=8.3, dof=2, t_end=t_end, n_out=n_out)
    except ValueError as exc:
        assert f"t_end = {t_end:g} is not allowed with n_out = {n_out}" in str(exc)
        return
    assert np.all(np.diff(r.t) > 0) and r.t[-1] == t_end and r.regime == "stuck"


def test_a_subnormal_output_time_is_refused():
    """t_out = [0, 1e-320, 1] came back as times [0, 0, 1]."""
    with pytest.raises(ValueError, match=r"t_out\[1\] = .* is not allowed: an output time is 0 or"):
        pydrill.simulate(wob=100.0, torque=8.3, dof=2, t_end=1.0, t_out=[0.0, 1e-320, 1.0])


# 9. units, fuzzed


@FUZZ
@given(
    number=hst.one_of(
        hst.sampled_from(["1e400", "9" * 400, "1e308", "-1e309"]), hst.floats().map(repr)
    ),
    unit=hst.sampled_from(["", " N", " kN", " klbf", " tf", " kips"]),
)
def test_a_quantity_with_its_unit_is_finite_or_refused(number, unit):
    """ "1e400 N" and "1e308 kN" were inf (where inf itself is refused)."""
    try:
        value = pydrill.units.parse(number + unit, "force")
    except ValueError as exc:
        assert "is not a finite force" in str(exc) or "is not a force" in str(exc)
        return
    assert math.isfinite(value)
