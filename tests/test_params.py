"""Parameter sets, overrides and their validation."""

import dataclasses
import math
import pickle

import pytest

import pydrill
from pydrill import preset


def test_reduced_scale_chain_matches_eq14():
    p = preset("reduced-scale", dof=4)
    assert p.inertias == (0.518, 0.025, 0.0318, 0.0318)
    assert p.stiffnesses == (0.073,) * 3
    assert p.dampings == (1e-4,) * 3
    assert (p.top_damping, p.bit_damping, p.bit_radius) == (0.18, 0.01, 0.1)
    assert (p.mu_coulomb, p.mu_static, p.stribeck_decay) == (0.5, 0.8, 0.9)
    assert preset("reduced-scale", dof=2).inertias == (0.518, 0.0318)
    assert preset("reduced-scale", dof=3).inertias == (0.518, 0.0318, 0.0318)


def test_pipes_means_dof_plus_three():
    p = preset("reduced-scale", pipes=10)
    assert p.dof == 13 and p.pipes == 10
    assert p.inertias[1:11] == (0.025,) * 10
    with pytest.raises(ValueError, match="disagree"):
        preset("reduced-scale", dof=5, pipes=10)
    with pytest.raises(ValueError, match="pipes"):
        preset("reduced-scale", pipes=0)


def test_real_string_is_eq53():
    p = preset("real-string")
    assert p.dof == 2
    assert p.inertias == (2122.0, 471.9698)
    assert p.stiffnesses == (861.5336,)
    assert p.dampings == (172.3067,)
    assert p.bit_radius == 0.155575
    with pytest.raises(ValueError, match="real-string"):
        preset("real-string", dof=4)


def test_unknown_preset_is_named():
    with pytest.raises(ValueError, match="'granite'"):
        preset("granite", dof=4)


def test_non_uniform_overrides():
    p = preset("reduced-scale", dof=4, inertias=[0.6, 0.03, 0.04, 0.02], dampings=[0, 1e-3, 2e-4])
    assert p.inertias == (0.6, 0.03, 0.04, 0.02)
    assert p.dampings == (0.0, 1e-3, 2e-4)
    # A full list of inertias sets the length of the string.
    assert preset("reduced-scale", inertias=[0.5, 0.1, 0.03]).dof == 3


@pytest.mark.parametrize(
    ("changes", "name", "allowed"),
    [
        ({"inertias": [0.5, -0.1, 0.03, 0.03]}, "inertias[1]", "> 0"),
        ({"stiffnesses": [0.07, 0.0, 0.07]}, "stiffnesses[1]", "> 0"),
        ({"dampings": [1e-4, -1e-4, 1e-4]}, "dampings[1]", ">= 0"),
        ({"top_damping": -0.1}, "top_damping", ">= 0"),
        ({"bit_radius": 0.0}, "bit_radius", "> 0"),
        ({"stribeck_decay": math.nan}, "stribeck_decay", "finite"),
        ({"stribeck_velocity": math.inf}, "stribeck_velocity", "finite"),
        ({"mu_static": 0.3}, "mu_static", "mu_coulomb"),
        ({"mu_coulomb": 0.0}, "mu_coulomb", "0 < mu_coulomb"),
        ({"karnopp_band": 0.0}, "karnopp_band", "> 0"),
    ],
)
def test_bad_parameter_is_refused_with_name_value_and_range(changes, name, allowed):
    with pytest.raises(ValueError) as err:
        preset("reduced-scale", dof=4).replace(**changes)
    message = str(err.value)
    assert message.startswith(name), message
    assert allowed in message, message


def test_wrong_list_length_and_unknown_key():
    with pytest.raises(ValueError, match="stiffnesses has 2 entries: dof = 4 needs 3"):
        preset("reduced-scale", dof=4, stiffnesses=[0.1, 0.1])
    with pytest.raises(ValueError, match="stiffnesses has 1 entry: dof = 4 needs 3"):
        preset("reduced-scale", dof=4, stiffnesses=[0.1])
    with pytest.raises(ValueError, match="unknown parameter 'spring': allowed are inertias"):
        preset("reduced-scale", dof=4).replace(spring=3)  # nothing near it: no guess
    with pytest.raises(ValueError, match=r"'stifnesses' \(did you mean 'stiffnesses'\?\)"):
        preset("reduced-scale", dof=4).replace(stifnesses=[1, 1, 1])
    with pytest.raises(ValueError, match=r"'top_dampng' \(did you mean 'top_damping'\?\)"):
        preset("reduced-scale", dof=4, top_dampng=0.1)
    with pytest.raises(ValueError, match=r"'t_ned' \(did you mean 't_end'\?\)"):
        pydrill.simulate(preset="reduced-scale", dof=4, wob=100, torque=8.3, t_ned=10)
    with pytest.raises(TypeError, match="list of numbers"):  # a wrong type, as documented
        preset("reduced-scale", dof=4, inertias="heavy")


def test_dof_below_two_is_refused():
    with pytest.raises(ValueError, match="dof = 1"):
        preset("reduced-scale", dof=1)


def test_params_round_trip_through_the_core():
    p = preset("reduced-scale", dof=6, dampings=[1e-4, 2e-4, 3e-4, 4e-4, 5e-4])
    core = p.to_core()
    assert tuple(core.dampings) == p.dampings
    assert p.to_dict()["dof"] == 6
    assert p.static_torque(100.0) == pytest.approx(8.0)


def test_equilibrium_torque_inverts_velocities():
    p = preset("reduced-scale", dof=4)
    for wob in (20.0, 100.0, 200.0):
        for omega in (0.5, 3.0, 20.0):
            u = pydrill.equilibrium_torque(p, wob, omega)
            assert any(
                abs(w - omega) < 1e-12 * omega for w in pydrill.equilibrium_velocities(p, wob, u)
            )


def test_to_dict_and_from_dict_round_trip_through_json():
    import json

    for p in (
        pydrill.preset("reduced-scale", dof=7),
        pydrill.preset("reduced-scale", dof=3).replace(inertias=[1.0, 2.0, 3.0], name="mine"),
    ):
        back = pydrill.Params.from_dict(json.loads(json.dumps(p.to_dict())))
        assert back == p and back.name == p.name and back.dof == p.dof
    d = pydrill.preset("reduced-scale", dof=4).to_dict()
    with pytest.raises(ValueError, match="dof = 5 does not match the 4 inertias"):
        pydrill.Params.from_dict({**d, "dof": 5})
    with pytest.raises(ValueError, match="unknown parameter 'mu_dynamic'"):
        pydrill.Params.from_dict({**d, "mu_dynamic": 0.5})


def test_params_pickle_after_a_run_without_the_cores_copy():
    """A run builds the core's copy of the string once and keeps it on the Params (the core's
    Params cannot be pickled): a Params that was run still pickles, to an equal one, which
    runs to the same result."""
    p = preset("reduced-scale", dof=4)
    before = pydrill.simulate(p, wob=60.0, torque=8.3, t_end=20.0)
    back = pickle.loads(pickle.dumps(p))
    assert back == p and back is not p
    after = pydrill.simulate(back, wob=60.0, torque=8.3, t_end=20.0)
    assert after.summary == before.summary
    assert (after.states == before.states).all()


@pytest.mark.parametrize("name", [5, None, b"rig", ["rig"]])
def test_a_name_that_is_not_text_is_refused(name):
    """A Params' name labels results, --json and atlases as text: 5 was taken as it was."""
    p = pydrill.preset(dof=2)
    with pytest.raises(TypeError, match=r"name = .* is not allowed: a label, must be a str"):
        dataclasses.replace(p, name=name)
    with pytest.raises(TypeError, match=r"name = .* is not allowed: a label"):
        pydrill.Params.from_dict({**p.to_dict(), "name": name})
    assert dataclasses.replace(p, name="rig 2").name == "rig 2"
