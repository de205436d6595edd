"""The public Python API fuzzed with hypothesis: ``pydrill.Atlas`` queries on a real small
atlas, the steady-state and stability functions and ``Params`` (``simulate`` and ``units``:
test_api_edges.py, sections 8 and 9). Bad input is a ValueError or TypeError (an atlas query's
miss a KeyError) that names the parameter; never another exception from inside, a warning, a
non-finite answer or a changed atlas file. Each example test is a case the fuzzing found,
failing before its fix."""

import hashlib
import math
import warnings

import numpy as np
import pytest
from fuzzing import FUZZ, values
from hypothesis import given
from hypothesis import strategies as st
from sweeping import SMALL

import pydrill
from pydrill import bifurcation
from pydrill import stability as stab
from pydrill.model import MAX_LOAD
from pydrill.sweep import run_sweep


def _digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def atlas_path(tmp_path_factory):
    out = tmp_path_factory.mktemp("fuzz") / "small.h5"
    run_sweep(pydrill.parse_spec(SMALL.replace("t_end = 200.0", "t_end = 50.0")), out, serial=True)
    return out


@pytest.fixture(scope="module")
def atlas(atlas_path):
    with pydrill.Atlas(atlas_path) as a:
        yield a


def _refused_or_done(call, *args, misses=(KeyError,), **kwargs):
    """The call's answer, or None for a refusal of the documented kinds (with a message): a
    ValueError or TypeError, or one of ``misses`` (an atlas query's KeyError off the grid)."""
    try:
        return call(*args, **kwargs)
    except (ValueError, TypeError, *misses) as exc:
        assert str(exc).strip("'\"")
        return None


# 1. Atlas queries


@FUZZ
@given(wob=values, torque=values, method=st.sampled_from(["exact", "nearest"]))
def test_atlas_queries_answer_or_refuse_by_name(atlas, atlas_path, wob, torque, method):
    before = _digest(atlas_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        point = _refused_or_done(atlas.value, method, wob=wob, torque=torque)
        if point is not None:
            assert point["status"] == "done" and set(point["regime"]) == {"rest", "equilibrium"}
        _refused_or_done(atlas.sel, "nearest" if method == "nearest" else None, wob=wob)
        _refused_or_done(atlas.safe_windows, torque=torque)
    assert _digest(atlas_path) == before


def test_a_coordinate_beyond_any_float_is_refused_by_name(atlas):
    """10**400 was an OverflowError from float() in every query."""
    for call in (
        lambda: atlas.value(wob=10**400, torque=8.3),
        lambda: atlas.value("nearest", wob=10**400, torque=8.3),
        lambda: atlas.sel(wob=10**400),
        lambda: atlas.safe_windows(torque=10**400),
    ):
        with pytest.raises(ValueError, match=r"wob|torque = 1000.*beyond the range of a float"):
            call()


@pytest.mark.parametrize("method", ["pad", "ffill", "backfill", "bfill", "bogus", 3])
def test_sel_takes_only_grid_values_or_nearest(atlas, method):
    """xarray's fill methods answered wob = 1e9 N with the 160 N column's data."""
    with pytest.raises(ValueError, match=rf"method = {method!r} is not allowed: None"):
        atlas.sel(method, wob=1e9)
    assert float(atlas.sel("exact", wob=100.0).wob) == 100.0


@pytest.mark.parametrize("initial", ["bogus", None, 1, math.nan, ["rest", "bogus"], {"rest"}])
def test_sel_names_an_unknown_start_and_the_atlas_s_own(atlas, initial):
    """xarray's "not all values found in index 'initial'" (or InvalidIndexError for a set)."""
    with pytest.raises(KeyError, match=r"initial = .* is not in this atlas: \['rest', 'equil"):
        atlas.sel(initial=initial)
    assert atlas.sel(initial=["rest"]).sizes["initial"] == 1


@pytest.mark.parametrize("empty", [[], (), np.array([])])
def test_an_empty_selection_is_refused_not_an_empty_slice(atlas, empty):
    with pytest.raises(ValueError, match=r"wob = .* selects nothing: give at least one value"):
        atlas.sel(wob=empty)
    with pytest.raises(ValueError, match=r"initial = .* selects nothing"):
        atlas.sel(initial=empty)


def test_safe_windows_refuse_an_empty_axis_name(atlas):
    """ "" was taken for the default axis, wob."""
    with pytest.raises(KeyError, match=r"is not an axis of this atlas; axes: wob, torque"):
        atlas.safe_windows("")


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"metric": ["severity"]}, TypeError, r"metric must be a name .* got \['severity'\]"),
        ({"initial": ""}, ValueError, r"initial = '' is not in this atlas"),  # (was "rest")
        ({"at": [1]}, TypeError, r"at must be a dict of axis values, .* got \[1\]"),
        ({"at": "torque"}, TypeError, r"at must be a dict .* got 'torque'"),
        ({"at": {"torque": None}}, TypeError, r"torque = None is not allowed: a number"),
        ({"at": {"torque": 1j}}, TypeError, r"torque = 1j is not allowed: a number"),
        ({"at": {"torque": 10**400}}, ValueError, r"torque = 1000.* beyond the range"),
    ],
)
def test_plot_refuses_bad_arguments_by_name(atlas, kwargs, error, message):
    with pytest.raises(error, match=message):
        atlas.plot(x="wob", **kwargs)


def test_plot_holds_an_axis_at_a_value_with_a_unit(atlas):
    """at={"torque": "8.3 N·m"} was float()'s "could not convert string to float"."""
    with_unit = atlas.plot(at={"torque": "8.3 N·m"})
    assert with_unit.axes[0].get_title() == atlas.plot(at={"torque": 8.3}).axes[0].get_title()


def test_the_map_of_a_steep_stribeck_law_draws(tmp_path):
    """stribeck_decay = 20: the first Hopf curve's W_ob overflowed a float by Ω = 36 rad/s and
    every (W_ob, u) map of the atlas failed ("wob = inf is not allowed")."""
    spec = SMALL.replace("dof = 4", "dof = 2\nstribeck_decay = 20.0")
    spec = spec.replace("t_end = 200.0", "t_end = 20.0").replace('"rest", "equilibrium"', '"rest"')
    run_sweep(pydrill.parse_spec(spec), tmp_path / "steep.h5", serial=True)
    with pydrill.Atlas(tmp_path / "steep.h5") as a:
        fig = a.plot()
    assert any("first Hopf curve" in line.get_label() for line in fig.axes[0].get_lines())


# 2. Steady states and stability

P4 = pydrill.preset("reduced-scale", dof=4)
REAL = pydrill.preset("real-string")


@FUZZ
@given(params=st.sampled_from([P4, REAL]), wob=values, torque=values, omega=values)
def test_steady_states_are_finite_within_max_load_or_refused(params, wob, torque, omega):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        u = _refused_or_done(pydrill.equilibrium_torque, params, wob, omega, misses=())
        omegas = _refused_or_done(pydrill.equilibrium_velocities, params, wob, torque, misses=())
    assert u is None or (math.isfinite(u) and abs(u) <= MAX_LOAD)
    assert omegas is None or all(math.isfinite(w) for w in omegas)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: pydrill.equilibrium_torque(REAL, 1e5, 1e308), r"omega = 1e\+308 .* MAX_LOAD"),
        (lambda: pydrill.equilibrium_torque(P4, 1e308, 1.0), r"wob = 1e\+308 .*: at most 1e15 N"),
        (lambda: pydrill.equilibrium_velocities(P4, 100, 1e308), r"torque = 1e\+308 .*: at most"),
        (lambda: pydrill.equilibrium_velocities(P4, 1e16, 8.3), r"wob = 1e\+16 .*: at most 1e15"),
    ],
)
def test_steady_states_beyond_max_load_are_refused(call, message):
    """The real string at 1e308 rad/s needed a torque of inf (returned); 1e308 N·m had a
    steady state at 1.3e308 rad/s. simulate and stability refuse loads beyond MAX_LOAD."""
    with pytest.raises(ValueError, match=message):
        call()


positive = st.one_of(
    st.sampled_from([5e-324, 1e-300, 1.0, 1e100, 1e300, 1e308]), st.floats(0, 1e308)
)


@FUZZ
@given(delta=positive.filter(lambda d: d > 0), omega=positive)
def test_boundary_wob_is_finite_or_refused_by_name(delta, omega):
    """A W_ob past a float's range was inf, with a RuntimeWarning (an error here)."""
    try:
        w = stab.boundary_wob(P4, delta, [0.0, omega])
    except ValueError as exc:
        assert "is beyond the range of a float" in str(exc) and "omega = " in str(exc)
        return
    assert np.all(np.isfinite(w)) and np.all(w >= 0)


@FUZZ
@given(delta=st.one_of(st.sampled_from([1e308, -1e308, 1e200, 1e-300]), st.floats(-1e308, 1e308)))
def test_the_linearisation_is_finite_or_refused_by_name(delta):
    """delta = 1e308 gave a Jacobian and a polynomial of inf, and a LinAlgError from
    eigenvalues."""
    for call in (stab.jacobian, stab.characteristic_polynomial, stab.eigenvalues):
        try:
            out = call(P4, delta)
        except ValueError as exc:
            assert str(exc).startswith("delta = ")  # (the core may refuse it first)
            continue
        assert np.all(np.isfinite(out))


@FUZZ
@given(
    st.lists(
        st.one_of(st.sampled_from([1e300, -1e300, 1e-300]), st.floats(-1e300, 1e300)),
        min_size=2,
        max_size=6,
    )
)
def test_hurwitz_determinants_are_finite_or_refused(ascending):
    """1e300 coefficients gave determinants of inf and nan."""
    try:
        dets = stab.hurwitz_determinants(ascending)
    except ValueError as exc:
        assert "ascending" in str(exc) or "coefficient" in str(exc)
        return
    assert np.all(np.isfinite(dets))


def test_hurwitz_determinants_beyond_a_float_are_refused():
    with pytest.raises(ValueError, match=r"ascending|coefficient"):
        stab.hurwitz_determinants([1e300, 1e300, 1e300, 1e300, 1.0])


@pytest.mark.parametrize(
    ("l1", "expected"),
    [(np.array(1.0), "subcritical"), (np.array(-2), "supercritical"), (10**400, "subcritical")],
)
def test_criticality_takes_0d_arrays_and_any_integer(l1, expected):
    """A 0-d array was refused as "not a number", 10**400 an OverflowError."""
    assert stab.criticality(l1) == expected


@FUZZ
@given(delta=positive.filter(lambda d: d > 0), frequency=positive.filter(lambda w: w > 0))
def test_a_crossing_s_lyapunov_coefficient_is_finite_or_refused(delta, frequency):
    """A Crossing made by hand (frequency = 1e200 rad/s) had a coefficient of NaN."""
    try:
        l1 = stab.Crossing("hopf", delta, frequency, 1, 2).lyapunov(P4)
    except ValueError as exc:
        assert "delta" in str(exc) or "frequency" in str(exc)  # (or the core refuses it)
        return
    assert math.isfinite(l1)


def test_a_branch_whose_torque_passes_max_load_is_refused():
    """omega_max = 1e308 overflowed (RuntimeWarning) to a branch of inf N·m."""
    with pytest.raises(ValueError, match=r"omega_max = 1e\+308 .* beyond MAX_LOAD"):
        bifurcation.branch(REAL, vary="torque", wob=100.0, omega_max=1e308)
    assert bifurcation.branch(REAL, vary="torque", wob=1e5, omega_max=1e3, samples=20).points


# 3. Params and presets


def test_preset_reads_an_iterator_of_entries_once():
    """A generator was read to find dof, then found empty ("inertias has 0 entries")."""
    p = pydrill.preset(inertias=(j for j in [0.5, 0.03]), stiffnesses=iter([0.07]))
    assert p.inertias == (0.5, 0.03) and p.stiffnesses == (0.07,)


def test_a_set_of_entries_has_no_order_and_is_refused():
    """{0.5, 0.03} was taken in the set's own order, whatever the caller meant."""
    for make in (lambda v: pydrill.preset(inertias=v), lambda v: P4.replace(dampings=v)):
        with pytest.raises(
            TypeError, match=r"(inertias|dampings) must be a list of numbers, got set"
        ):
            make({0.5, 0.03, 0.1})


@pytest.mark.parametrize(
    ("data", "error", "message"),
    [
        ([1, 2], TypeError, r"data must be a dict, as Params.to_dict writes, got list"),
        (None, TypeError, r"data must be a dict, .* got NoneType None"),
        ("abc", TypeError, r"data must be a dict, .* got str 'abc'"),
        ({"inertias": [1.0, 1.0]}, ValueError, r"stiffnesses is missing: Params.from_dict"),
    ],
)
def test_from_dict_names_what_is_wrong_with_its_data(data, error, message):
    with pytest.raises(error, match=message):
        pydrill.Params.from_dict(data)
    assert pydrill.Params.from_dict(P4.to_dict()) == P4


@pytest.mark.parametrize(
    ("wob", "error"), [(math.nan, ValueError), (-1.0, ValueError), ("a", TypeError)]
)
def test_static_torque_refuses_a_bad_weight_by_name(wob, error):
    """NaN gave NaN; "a" was str's "can't multiply sequence by non-int of type 'float'"."""
    with pytest.raises(error, match=r"wob = .* is not allowed"):
        P4.static_torque(wob)
    assert P4.static_torque(100.0) == pytest.approx(8.0)
    np.testing.assert_allclose(P4.static_torque(np.array([0.0, 100.0])), [0.0, 8.0])


scales = st.sampled_from([1e-300, 1e-100, 1e-3, 1.0, 1e3, 1e100, 1e200, 1e300, 1e308])


@FUZZ
@given(
    field=st.sampled_from(["bit_radius", "mu_static", "stribeck_decay", "stribeck_velocity"]),
    value=scales,
    other=st.sampled_from(["bit_radius", "mu_static", "stribeck_decay"]),
    scale=scales,
)
def test_an_accepted_friction_law_stays_finite_up_to_max_load(field, value, other, scale):
    """mu_static = 1e308 was accepted: a run at 1e15 N had a static_torque of inf, and
    static_torque and stability_map overflowed (a RuntimeWarning)."""
    try:
        p = pydrill.preset(dof=2, **{field: value}).replace(**{other: scale})
    except ValueError as exc:
        assert field in str(exc) or other in str(exc)
        return
    assert math.isfinite(p.static_torque(MAX_LOAD))
    assert np.all(np.isfinite(stab.stribeck_slope(p, MAX_LOAD, 0.0)))
    assert stab.stability_map(p, [0.0, 1.0], [1.0, MAX_LOAD]).shape == (2, 2)


def test_a_friction_torque_past_a_float_at_max_load_is_refused():
    with pytest.raises(ValueError, match=r"mu_static = 1e\+308, bit_radius = 0.1 are not allowed"):
        pydrill.preset(dof=2, mu_static=1e308)
