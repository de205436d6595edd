"""A point of a spec (SweepSpec.params_at, operating_point) given without one of its axes is
refused, naming the axis: it was built from the preset's default (dof 4, the full tally, the
preset's friction), another string than the grid's, or failed with a bare KeyError."""

from pathlib import Path

import pytest

import pydrill
from pydrill import load_spec, parse_spec

ROOT = Path(__file__).resolve().parents[1]

GRID = parse_spec(
    '[model]\npreset = "reduced-scale"\n[axes]\nwob = [50.0, 100.0]\ntorque = [6.0, 8.3]\n'
    "dof = [3, 6]\nmu_static = [0.85, 0.9]\n"
)


def test_a_whole_point_is_the_preset_built_at_it():
    # the reference: the string built directly from the preset, at each point's coordinates
    for i in range(GRID.size):
        c = GRID.coords(i)
        want = pydrill.preset("reduced-scale", dof=c["dof"], mu_static=c["mu_static"])
        assert GRID.params_at(c) == want
        assert GRID.operating_point(c) == (c["wob"], c["torque"])
    # W_ob and torque are not the string's: params_at does without them
    assert GRID.params_at({"dof": 6, "mu_static": 0.9}).dof == 6


@pytest.mark.parametrize(
    "coords, missing",
    [
        ({"wob": 50.0, "torque": 6.0, "mu_static": 0.9}, "dof"),  # was a dof-4 string
        ({"wob": 50.0, "torque": 6.0, "dof": 6}, "mu_static"),  # was the preset's 0.8
        ({"wob": 50.0}, "dof, mu_static"),
    ],
)
def test_params_at_refuses_a_point_without_a_size_or_parameter_axis(coords, missing):
    with pytest.raises(ValueError, match=f"lacks {missing}: .*axis of the spec "):
        GRID.params_at(coords)


def test_params_at_refuses_a_tally_point_without_its_depth():
    spec = load_spec(ROOT / "sweeps" / "paper-string-depth.toml")
    # the whole tally (5000 m) was built instead of the string at the point's depth
    assert spec.params_at({"depth": 500.0}) != spec.params_at({"depth": 5000.0})
    with pytest.raises(ValueError, match=r"lacks depth: .*\(depth, wob; held in \[model\]: "):
        spec.params_at({"wob": 5e4})


def test_operating_point_names_what_is_missing_and_takes_what_is_held():
    with pytest.raises(ValueError, match=r"lacks torque: .*\(wob, torque, dof, mu_static\)"):
        GRID.operating_point({"wob": 1.0})  # was KeyError: 'torque'
    held = parse_spec('[model]\npreset = "reduced-scale"\nwob = 50.0\n[axes]\ntorque = [6.0]\n')
    assert held.operating_point({"torque": 6.0}) == (50.0, 6.0)  # W_ob from [model]
    with pytest.raises(ValueError, match=r"lacks torque: .*\(torque; held in \[model\]: wob\)"):
        held.operating_point({})
