"""A list of spring stiffnesses must agree with the string's length, as a list of spring
dampings does; only a list of inertias says how long the string is (docs/api.md, `preset`:
dof defaults to 4 "or the length of a full `inertias` list"; `pydrill simulate --help`:
--stiffnesses is "one fewer than the inertias").

Two stiffnesses given for the 4-inertia laboratory string (an entry left out, most likely) were
taken as a 3-inertia string without a word, by `preset`, `simulate`, every command and a sweep
spec, while two dampings were refused; the text output of `pydrill simulate` does not even
show the dof. Both lists are refused alike now, naming the count the string needs."""

import subprocess
import sys

import pytest

import pydrill
from pydrill.spec import SpecError, parse_spec

CMD = [sys.executable, "-m", "pydrill"]
TWO = [0.073, 0.2]  # two springs: three inertias, not the default four


@pytest.mark.parametrize("key", ["stiffnesses", "dampings"])
def test_preset_refuses_a_spring_list_of_another_length_whichever_list(key):
    with pytest.raises(
        ValueError, match=rf"^{key} has 2 entries: dof = 4 needs 3 \(one per spring\)"
    ):
        pydrill.preset("reduced-scale", **{key: TWO})
    # Given the length, the same list is taken as it is.
    assert getattr(pydrill.preset("reduced-scale", dof=3, **{key: TWO}), key) == tuple(TWO)


def test_inertias_still_set_the_length_and_the_springs_then_follow_them():
    p = pydrill.preset("reduced-scale", inertias=[0.5, 0.03, 0.03], stiffnesses=TWO)
    assert p.dof == 3 and p.stiffnesses == tuple(TWO)


def test_simulate_refuses_two_stiffnesses_for_the_default_string():
    with pytest.raises(ValueError, match="stiffnesses has 2 entries: dof = 4 needs 3"):
        pydrill.simulate(wob=100.0, torque=8.3, t_end=1.0, stiffnesses=TWO)


@pytest.mark.parametrize("option", ["--stiffnesses", "--dampings"])
def test_the_command_refuses_both_lists_alike_with_exit_status_2(option):
    proc = subprocess.run(
        [*CMD, "simulate", "--wob", "100", "--torque", "8.3", "--t-end", "1", option, "0.073,0.2"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stdout
    assert "has 2 entries: dof = 4 needs 3 (one per spring)" in proc.stderr
    assert proc.stdout == ""


@pytest.mark.parametrize("key", ["stiffnesses", "dampings"])
def test_a_sweep_spec_refuses_both_lists_alike(key):
    text = f"[model]\n{key} = [0.073, 0.2]\n[axes]\nwob = [100.0]\ntorque = [8.3]\n"
    with pytest.raises(SpecError, match=f"{key} has 2 entries: dof = 4 needs 3"):
        parse_spec(text)
    assert parse_spec(text.replace("[model]\n", "[model]\ndof = 3\n")).dof == 3
