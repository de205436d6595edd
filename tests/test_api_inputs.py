"""What the Python API takes: every argument of ``simulate``, ``preset`` and ``Params`` is
checked in Python and refused by name (``TypeError`` for a wrong type, ``ValueError`` for a
bad value) before anything is allocated or handed to the core; and what a
``SimulationResult`` gives back (intervals, energy balance, pickling, its inputs)."""

import copy
import json
import pickle

import numpy as np
import pytest

import pydrill
from pydrill import Params, preset, simulate
from pydrill.model import MAX_DOF

QUICK = {"wob": 100.0, "torque": 8.3, "t_end": 2.0, "n_out": 5}


def refused(kind, text, call, /, *args, **kwargs):
    """``call`` raises ``kind`` whose message holds ``text`` (the parameter's name); the
    message."""
    with pytest.raises(kind) as err:
        call(*args, **kwargs)
    message = str(err.value)
    assert text in message, message
    assert "incompatible function arguments" not in message, message
    return message


# 1. The size of the string: at most MAX_DOF inertias, integers only.


def test_max_dof_lives_with_the_model():
    from pydrill import spec_rules

    assert MAX_DOF == 100_000
    assert spec_rules.MAX_DOF is MAX_DOF


def test_a_string_longer_than_max_dof_is_refused_before_it_is_built():
    message = refused(ValueError, "dof = 100001", preset, dof=MAX_DOF + 1)
    assert "2 ... 100000" in message
    refused(ValueError, "pipes = 99998", preset, pipes=MAX_DOF - 2)
    refused(ValueError, "dof = 100001", simulate, dof=MAX_DOF + 1, **QUICK)
    refused(ValueError, "pipes = 99998", simulate, pipes=MAX_DOF - 2, **QUICK)
    p = preset(dof=4)
    fields = {**p.to_dict(), "inertias": [0.1] * (MAX_DOF + 1)}
    del fields["dof"]
    refused(ValueError, "inertias has 100001 entries", Params, **fields)


@pytest.mark.parametrize("key", ["dof", "pipes"])
@pytest.mark.parametrize(
    ("value", "kind"),
    [
        (float("nan"), TypeError),  # a float, as every integer argument refuses them
        (float("inf"), TypeError),
        (4.5, TypeError),
        (5.0, TypeError),
        (0, ValueError),
        ([4], TypeError),
        ("5", TypeError),
        (True, TypeError),
    ],
)
def test_a_bad_size_is_refused_by_name(key, value, kind):
    refused(kind, key, preset, **{key: value})
    refused(kind, key, simulate, **{key: value}, **QUICK)


def test_whole_sizes_of_any_integer_type_are_taken():
    for dof in (5, np.int64(5), np.uint8(5), np.array(5)):
        assert preset(dof=dof).dof == 5
    assert preset(pipes=np.int32(2)).dof == 5


# 2. Numbers: real numbers and 0-d arrays, not strings, bools or lists.

NUMBERS = [
    "wob",
    "torque",
    "t_end",
    "rtol",
    "atol",
    "max_step",
    "perturbation",
    "window_fraction",
    "max_switch_rate",
]


@pytest.mark.parametrize("key", NUMBERS)
@pytest.mark.parametrize("value", ["1", "abc", True, [1.0], np.array([1.0])])
def test_simulate_refuses_a_number_of_the_wrong_type(key, value):
    message = refused(TypeError, f"{key} must be a number", simulate, **{**QUICK, key: value})
    assert "got " + type(value).__name__ in message


def test_the_message_says_unit_and_value():
    message = refused(TypeError, "wob", simulate, **{**QUICK, "wob": "abc"})
    assert message == "wob must be a number (N), got str 'abc'"


def test_numpy_numbers_and_0d_arrays_are_numbers():
    for wob in (100, np.float32(100.0), np.int64(100), np.array(100.0)):
        r = simulate(**{**QUICK, "wob": wob, "t_end": np.array(2.0), "rtol": np.float64(1e-8)})
        assert r.wob == 100.0 and type(r.to_dict()["inputs"]["t_end"]) is float


@pytest.mark.parametrize(
    ("changes", "name"),
    [
        ({"bit_radius": "0.5"}, "bit_radius"),
        ({"mu_static": True}, "mu_static"),
        ({"top_damping": [0.18]}, "top_damping"),
        ({"inertias": [0.5, "0.1", 0.03, 0.03]}, "inertias[1]"),
        ({"dampings": [1e-4, True, 1e-4]}, "dampings[1]"),
        ({"stiffnesses": [0.073, [0.073], 0.073]}, "stiffnesses[1]"),
    ],
)
def test_params_refuses_a_field_of_the_wrong_type(changes, name):
    p = preset(dof=4)
    refused(TypeError, name, p.replace, **changes)
    refused(TypeError, name, preset, dof=4, **changes)
    fields = {**p.to_dict(), **changes}
    del fields["dof"]
    refused(TypeError, name, Params, **fields)


def test_params_takes_numpy_numbers():
    p = preset(dof=4, bit_radius=np.float32(0.5), inertias=np.array([0.5, 0.1, 0.03, 0.03]))
    assert p.bit_radius == 0.5 and type(p.bit_radius) is float
    assert p.inertias == (0.5, 0.1, 0.03, 0.03)


# 3. Values the core's binding cannot hold are refused in Python, by name.


@pytest.mark.parametrize(
    ("key", "value", "kind"),
    [
        ("n_out", 2**31, ValueError),
        ("n_out", 1, ValueError),
        ("n_out", 3001.0, TypeError),
        ("n_out", "3001", TypeError),
        ("max_order", 2**40, ValueError),
        ("max_order", -1, ValueError),
        ("max_steps", 2**63, ValueError),
        ("max_steps", True, TypeError),
        ("method", 5, TypeError),
        ("friction", None, TypeError),
    ],
)
def test_integers_and_choices_are_checked_before_the_core(key, value, kind):
    refused(kind, key, simulate, **{**QUICK, key: value})


def test_a_preset_name_must_be_a_string():
    refused(TypeError, "name must be a preset name", preset, None)
    refused(TypeError, "name must be a preset name", preset, 5)
    refused(TypeError, "preset must be a preset name", simulate, preset=5, **QUICK)
    assert simulate(preset=None, **QUICK).params.name == "reduced-scale"  # the default


# 4. params must be a Params.


@pytest.mark.parametrize(
    ("make", "got"),
    [
        (lambda p: p.to_dict(), "got dict"),
        (lambda p: "reduced-scale", "got str"),
        (lambda p: p.to_core(), "got pydrill._core.Params"),
    ],
)
def test_params_of_the_wrong_kind_is_refused(make, got):
    message = refused(
        TypeError,
        "params must be a pydrill.Params (from pydrill.preset or Params(...))",
        simulate,
        make(preset(dof=4)),
        **QUICK,
    )
    assert got in message


# 5. Conflicting or unknown arguments.


def test_pipes_and_preset_must_agree_with_params():
    p = preset(dof=4)
    refused(ValueError, "pipes = 10", simulate, p, pipes=10, **QUICK)
    refused(ValueError, "dof = 5", simulate, p, dof=5, **QUICK)
    assert simulate(p, pipes=1, **QUICK).dof == 4
    refused(ValueError, "preset = 'real-string'", simulate, p, preset="real-string", **QUICK)
    assert simulate(p, preset="reduced-scale", **QUICK).dof == 4  # the same: no conflict


def test_an_unknown_keyword_lists_simulate_options_too():
    message = refused(ValueError, "'tend'", simulate, tend=10.0, **QUICK)
    assert "t_end" in message and "not an option of simulate" in message
    assert "mu_static" in message  # the model parameters too


def test_name_is_refused_with_advice():
    message = refused(ValueError, "name", simulate, name="x", **QUICK)
    assert "preset=" in message


# 6. Results whose output times do not start at 0.


def test_stick_intervals_lie_within_the_output_span():
    full = simulate(wob=100.0, torque=8.3, dof=4, t_end=50.0)
    r = simulate(wob=100.0, torque=8.3, dof=4, t_end=50.0, t_out=[10.0, 20.0])
    intervals = r.stick_intervals()
    assert intervals
    for a, b in intervals:
        assert 10.0 <= a <= b <= 20.0
    clipped = [(max(a, 10.0), min(b, 20.0)) for a, b in full.stick_intervals() if b > 10 and a < 20]
    assert intervals == clipped


@pytest.mark.parametrize("k", [0, 1, 2, 3])
def test_stick_intervals_of_output_starting_on_a_switch(k):
    """Output from the very time of a switch: the core reports t[0]'s mode as the one before
    it, and the switch was skipped (from the stick at 20.2 s, the stick phase to 32.4 s was
    lost; from the slip at 15.2 s, the bit slipping was called held)."""
    full = simulate(wob=100.0, torque=8.3, dof=4, t_end=60.0)
    switch = full.switches[k]
    r = simulate(wob=100.0, torque=8.3, dof=4, t_end=60.0, t_out=np.linspace(switch.t, 60, 50))
    t0 = switch.t
    clipped = [(max(a, t0), b) for a, b in full.stick_intervals() if b > t0]
    assert r.stick_intervals() == clipped
    assert (r.stick_intervals()[0][0] == t0) == (switch.kind == "stick")


def test_energy_balance_counts_from_the_first_output():
    r = simulate(wob=100.0, torque=8.3, dof=4, t_end=50.0, t_out=[10.0, 20.0, 35.0, 50.0])
    error = r.energy_balance_error()
    assert type(error) is float
    assert error < 1e-8
    assert type(simulate(**QUICK).energy_balance_error()) is float


# 7. Pickling and deep copies: the data, not the core.


def test_a_result_pickles_and_deep_copies_with_its_data():
    r = simulate(wob=100.0, torque=8.3, dof=4, t_end=50.0, n_out=101)
    for copied in (pickle.loads(pickle.dumps(r)), copy.deepcopy(r)):
        assert isinstance(copied, pydrill.SimulationResult)
        np.testing.assert_array_equal(copied.states, r.states)
        np.testing.assert_array_equal(copied.energy, r.energy)
        assert not copied.states.flags.writeable
        assert copied.switches == r.switches
        assert copied.summary == r.summary and copied.stats == r.stats
        assert copied.params == r.params
        assert copied.stick_intervals() == r.stick_intervals()
        assert copied.to_dict() == r.to_dict()
        assert copied.modes == r.modes and copied.regime == r.regime


# 8. The inputs repeat the run.


def test_inputs_repeat_a_run_with_overrides():
    y0 = [1.0, 0.5, 1.0, 0.5, 1.0, 0.5, 1.0]
    r = simulate(
        wob=100.0,
        torque=8.3,
        dof=4,
        mu_static=0.9,
        bit_radius=0.12,
        dampings=[1e-4, 2e-4, 3e-4],
        t_end=30.0,
        t_out=np.linspace(0.0, 30.0, 31),
        initial=np.array(y0),
        window_fraction=0.3,
        max_step=0.5,
        perturbation=2e-3,
        max_switch_rate=1e3,
        method="dop853",
        rtol=1e-9,
    )
    inputs = json.loads(json.dumps(r.to_dict()["inputs"], allow_nan=False))
    assert inputs["mu_static"] == 0.9 and inputs["bit_radius"] == 0.12
    assert inputs["initial"] == y0 and inputs["t_out"][-1] == 30.0
    assert inputs["window_fraction"] == 0.3 and inputs["max_step"] == 0.5
    assert "mu_coulomb" not in inputs  # only what differs from the preset
    again = simulate(**inputs)
    assert again.params == r.params
    np.testing.assert_array_equal(again.states, r.states)
    assert again.summary == r.summary
    assert again.to_dict()["inputs"] == inputs == r.inputs()


def test_inputs_repeat_a_run_of_a_custom_string():
    base = preset(dof=3)
    fields = {**base.to_dict(), "inertias": [0.6, 0.04, 0.02], "name": "my rig"}
    del fields["dof"]
    p = Params(**fields)
    r = simulate(p, wob=60.0, torque=8.0, t_end=20.0, n_out=21, initial="equilibrium")
    inputs = json.loads(json.dumps(r.to_dict()["inputs"]))
    assert inputs["preset"] is None and inputs["inertias"] == [0.6, 0.04, 0.02]
    again = simulate(**inputs)
    assert again.params == p
    np.testing.assert_array_equal(again.states, r.states)
    # not relabelled as the reduced-scale rig it was not (its label is not an input: custom)
    assert again.params.name == "custom" and again.inputs() == r.inputs()
    # a preset's string with a few fields changed keeps its preset's name
    assert simulate(wob=60.0, torque=8.0, t_end=1.0, bit_radius=0.1).params.name == (
        "reduced-scale"
    )


# 9. Shapes of initial and t_out.


def test_initial_must_be_a_name_or_a_flat_state():
    refused(TypeError, "initial", simulate, dof=4, initial=None, **QUICK)
    refused(
        ValueError, "initial has shape (7, 1)", simulate, dof=4, initial=np.zeros((7, 1)), **QUICK
    )
    refused(TypeError, "initial", simulate, dof=4, initial=[True] * 7, **QUICK)
    refused(TypeError, "initial", simulate, dof=4, initial=["0"] * 7, **QUICK)
    refused(ValueError, "initial has 2 entries", simulate, dof=4, initial=[0.0, 1.0], **QUICK)
    # an entry that is not finite, by its name here (the core calls it state[3])
    bad = [0.0, 0.0, 0.0, np.inf, 0.0, 0.0, 0.0]
    refused(ValueError, "initial[3] = inf is not allowed", simulate, dof=4, initial=bad, **QUICK)


def test_t_out_must_be_a_flat_non_empty_list():
    run = {"wob": 100.0, "torque": 8.3, "t_end": 5.0}
    refused(ValueError, "t_out has shape (2, 2)", simulate, t_out=[[0, 1], [2, 3]], **run)
    refused(TypeError, "t_out", simulate, t_out=3.0, **run)
    refused(TypeError, "t_out", simulate, t_out="0 1 2", **run)
    refused(ValueError, "t_out is empty", simulate, t_out=[], **run)
    assert simulate(t_out=np.array([0.0, 2.5, 5.0]), **run).t.tolist() == [0.0, 2.5, 5.0]


# 10. The docstrings explain every option.


def test_help_explains_every_option():
    doc = simulate.__doc__
    for key in (
        "t_end",
        "t_out",
        "n_out",
        "rtol",
        "atol",
        "max_step",
        "max_order",
        "max_steps",
        "window_fraction",
        "max_switch_rate",
        "pipes",
        "perturbation",
    ):
        assert f"- ``{key}``" in doc or f", ``{key}``" in doc, key
    assert "``t_end`` (s)" in doc and "(switches/s)" in doc
    doc = preset.__doc__
    assert "- ``dof``" in doc and "- ``pipes``" in doc and "dof = pipes + 3" in doc


# 11. Friction coefficients: blame the one changed, in short numbers.


def test_the_friction_coefficient_changed_is_blamed():
    p = preset(dof=4)
    message = refused(ValueError, "mu_coulomb", p.replace, mu_coulomb=0.9)
    assert message.startswith("mu_coulomb = 0.9 is not allowed"), message
    assert "mu_static (0.8)" in message and "0.8000000" not in message
    message = refused(ValueError, "mu_static", p.replace, mu_static=0.4)
    assert message.startswith("mu_static = 0.4 is not allowed"), message
    assert "mu_coulomb (0.5)" in message
    message = refused(ValueError, "mu_coulomb", preset, dof=4, mu_coulomb=0.9)
    assert message.startswith("mu_coulomb = 0.9"), message


def test_no_switch_limit_is_null_in_the_inputs_and_runs_again():
    # max_switch_rate = inf put Infinity into inputs(), which strict JSON refuses
    r = simulate(**QUICK, max_switch_rate=float("inf"))
    inputs = r.inputs()
    assert inputs["max_switch_rate"] is None
    text = json.dumps(r.to_dict(), allow_nan=False)
    again = simulate(**json.loads(text)["inputs"])
    assert again.inputs() == inputs
    np.testing.assert_array_equal(again.bit_velocity, r.bit_velocity)
    assert simulate(**QUICK).inputs()["max_switch_rate"] == 1e4


@pytest.mark.parametrize("wob", [-1.7976931345e308, -np.finfo(float).max])
def test_a_weight_near_the_largest_float_is_refused_by_name(wob):
    # The message's shortest decimal read back beyond DBL_MAX and std::stod threw
    # out_of_range, which arrived as "IndexError: stod" (found by the property fuzz).
    refused(ValueError, "wob = -1.79769313", simulate, wob=wob, torque=0.0, t_end=1.0, dof=2)


@pytest.mark.parametrize(
    ("key", "value", "allowed"),
    [
        (
            "torque",
            1e300,
            "torque = 1e+300 is not allowed in a simulation: need |torque| <= 1e15 N·m",
        ),
        ("torque", -1e16, "torque = -1e+16 is not allowed in a simulation"),
        ("wob", 1e300, "wob = 1e+300 is not allowed in a simulation: must be <= 1e15 N"),
    ],
)
def test_a_load_that_would_overflow_the_run_is_refused_by_name(key, value, allowed):
    # torque = 1e300 overflowed the accelerations at t = 0, and the run failed with "step size
    # fell to 0 s at t = 0 s", naming neither the torque nor what is allowed.
    run = {"wob": 100.0, "torque": 8.3, "t_end": 1.0, key: value}
    refused(ValueError, allowed, simulate, **run)


def test_loads_up_to_the_bound_still_run():
    # 1e15 is ten orders of magnitude above a real string's loads and still simulates.
    assert simulate(wob=100.0, torque=1e15, t_end=50.0).regime == "steady"
    assert simulate(wob=1e15, torque=8.3, t_end=1.0).regime == "stuck"


# 12. Tolerances a double can resolve.


@pytest.mark.parametrize("method", ["auto", "dop853", "bdf", "adams", "erk"])
@pytest.mark.parametrize(
    ("key", "value", "allowed"),
    [
        ("rtol", 1e-300, "1e-14 <= rtol <= 0.01"),
        ("rtol", 1e-17, "1e-14 <= rtol <= 0.01"),
        ("atol", 1e-300, "1e-20 <= atol <= 0.001"),
    ],
)
def test_a_tolerance_finer_than_a_double_resolves_is_refused(method, key, value, allowed):
    # They were taken, then failed with NaN times ("h = nan", "t = nan s"), blamed the
    # solution ("not smooth"), or (DOP853 at rtol 1e-17) claimed success.
    message = refused(
        ValueError,
        f"{key} = {value:g} is not allowed",
        simulate,
        **{**QUICK, "method": method, key: value},
    )
    assert allowed in message, message


def test_the_tolerance_floors_run():
    for method in ("dop853", "bdf", "adams", "erk"):
        assert simulate(**QUICK, method=method, rtol=1e-14, atol=1e-20).t[-1] == 2.0


def test_an_erk_failure_reports_a_time_not_nan():
    # An overflowing start: ARKODE's step went to NaN and the error said "t = nan s".
    state = [1e150, 0, 0, 0, 0, 0, 0]
    with pytest.raises(pydrill.SolverError) as err:
        simulate(wob=100.0, torque=8.3, t_end=10.0, initial=state, method="erk")
    assert err.value.t_reached == 0.0
    assert "nan" not in str(err.value), str(err.value)
