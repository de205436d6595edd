"""A tally string held at one depth in [model] (``depth = "3000 m"``), as W_ob or the torque
can be held: it was refused ("model.depth: unknown parameter"), and a one-value depth axis
was the only way."""

import json

import h5py
import numpy as np
import pytest
from sweeping import ROOT

from pydrill import load_tally
from pydrill.atlas import Atlas
from pydrill.spec import SpecError, parse_spec
from pydrill.sweep import run_sweep

TALLY_PATH = ROOT / "examples" / "tallies" / "paper-eq53.toml"
TALLY = TALLY_PATH.read_text()

HELD = """
[model]
tally = "paper-eq53.toml"
dof = 8
depth = "3000 m"
[axes]
wob = ["40 kN", "60 kN", "80 kN"]
torque = ["8 kN·m", "9 kN·m"]
[simulation]
t_end = 60.0
initial = ["rest", "equilibrium"]
"""

# The same sweep with the depth as an axis of one value
AXIS = HELD.replace('depth = "3000 m"\n', "").replace(
    'wob = ["40 kN"', 'depth = ["3000 m"]\nwob = ["40 kN"'
)


def test_the_string_is_the_tally_at_that_depth():
    spec = parse_spec(HELD, tally_text=TALLY)
    assert spec.fixed["depth"] == 3000.0 and "depth" not in spec.axes
    want = load_tally(TALLY_PATH).at_depth(3000.0).to_params(dof=8)
    for k in (0, spec.size - 1):
        got = spec.params_at(spec.coords(k))
        np.testing.assert_array_equal(got.inertias, want.inertias)
        np.testing.assert_array_equal(got.stiffnesses, want.stiffnesses)
    # at another depth the string differs: the depth held is not ignored
    other = parse_spec(HELD.replace("3000 m", "1000 m"), tally_text=TALLY)
    assert sum(other.params_at(other.coords(0)).inertias) != sum(want.inertias)
    assert other.digest != spec.digest


def test_held_depth_computes_what_a_one_value_depth_axis_does(tmp_path):
    held, axis = tmp_path / "held.h5", tmp_path / "axis.h5"
    run_sweep(parse_spec(HELD, tally_text=TALLY), held, serial=True)
    run_sweep(parse_spec(AXIS, tally_text=TALLY), axis, serial=True)
    with h5py.File(held, "r") as a, h5py.File(axis, "r") as b:
        assert "depth" not in json.loads(a.attrs["axes"])
        k = json.loads(b.attrs["axes"]).index("depth")
        for name in ("regime", "bit_mean", "stuck_fraction", "omega_eq", "unstable"):
            np.testing.assert_array_equal(a[name][...], np.take(b[name][...], 0, axis=k))
    with Atlas(held) as atlas:
        info = atlas.summary()["model"]
        assert info["held"] == {"depth": 3000.0} and info["inertias"] == 8
        fig = atlas.plot()
        assert "depth = 3000 m" in fig.axes[0].get_title()


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (('depth = "3000 m"', 'depth = "-5 m"'), "model.depth: '-5 m' is not allowed: a depth > 0"),
        (('depth = "3000 m"', 'depth = "3000 rpm"'), "model.depth: '3000 rpm': unit 'rpm' is not"),
        (('depth = "3000 m"', "depth = true"), "model.depth: True is not allowed"),
        (
            ('wob = ["40 kN"', 'depth = [1000.0]\nwob = ["40 kN"'),
            "model.depth: depth is also an axis: give it in one place only",
        ),
    ],
)
def test_a_bad_held_depth_is_refused_naming_the_key(change, words):
    with pytest.raises(SpecError) as e:
        parse_spec(HELD.replace(*change), tally_text=TALLY)
    assert words in str(e.value)


def test_a_preset_has_no_depth_to_hold():
    text = HELD.replace('tally = "paper-eq53.toml"\n', 'preset = "reduced-scale"\n')
    text = text.replace("kN·m", "N·m").replace("kN", "N")
    with pytest.raises(SpecError) as e:
        parse_spec(text)
    assert str(e.value).startswith("model.depth: needs a tally string")
