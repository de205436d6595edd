"""A real-string preset of another size than its 2 inertias is refused in its caller's words.

``pydrill.preset("real-string", dof=4)`` said "(Params::inertias, stiffnesses, dampings; in
Python, from a pipe tally)": the C++ core's advice, with a C++ name and no Python call. It
now names ``pydrill.Params(inertias=...)`` and ``pydrill.load_tally(path).to_params(dof=...)``
(what docs/api.md documents), and a sweep spec names its own ``[model] tally`` key; the C++
wording stays the C++ caller's (cpp/tests/test_params.cpp)."""

import dataclasses
from pathlib import Path

import pytest

import pydrill

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"


@pytest.mark.parametrize(
    ("size", "named"),
    [
        ({"dof": 4}, "dof = 4"),
        ({"pipes": 1}, "pipes = 1 (dof = 4)"),
        (
            {"inertias": [2122.0, 100.0, 471.9698]},
            "a string of 3 inertias (inertias has 3 entries)",
        ),
    ],
)
def test_python_names_python_calls(size, named):
    with pytest.raises(ValueError) as info:
        pydrill.preset("real-string", **size)
    message = str(info.value)
    assert message.startswith(f"{named} is not allowed for preset 'real-string'"), message
    assert "Params::" not in message and "in Python" not in message, message
    assert "pydrill.Params(inertias=" in message
    dof = 3 if "inertias" in size else 4
    assert f"pydrill.load_tally(path).to_params(dof={dof})" in message
    # the advice works as written: the tally it names gives that string
    params = pydrill.load_tally(PAPER).to_params(dof=dof)
    assert params.dof == dof
    fields = {f.name: getattr(params, f.name) for f in dataclasses.fields(pydrill.Params)}
    assert pydrill.Params(**fields).dof == dof


def test_a_sweep_spec_names_its_tally_key():
    text = "[model]\npreset = 'real-string'\n[axes]\npipes = [50]\nwob = [1.0]\ntorque = [1.0]\n"
    with pytest.raises(pydrill.SpecError) as info:
        pydrill.parse_spec(text)
    message = str(info.value)
    assert "dof = 53 is not allowed for preset 'real-string'" in message
    assert '[model] tally = "TALLY.toml"' in message, message
    assert "pydrill." not in message and "Params::" not in message, message
    # the key it names builds such a string
    tally = f'[model]\ntally = "{PAPER}"\ndof = 53\n[axes]\nwob = [6e4]\ntorque = [9e3]\n'
    assert pydrill.parse_spec(tally).params_at({}).dof == 53
