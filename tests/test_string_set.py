"""``pydrill string --set``: the lumped string of a tally with some of its values changed, as
the other commands build it from the same tally and --set, said in the text and the JSON, and a
bad value refused before anything is printed; and ``--preset``, the paper's strings."""

import dataclasses
import json

import pytest
from sweeping import ROOT

from pydrill.cli import main
from pydrill.tally import load_tally

PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
STRING = ["string", str(PAPER), "--depth", "3000m", "--dof", "3"]


def string_json(*options: str, capsys) -> dict:
    assert main([*STRING, *options, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_the_changed_string_is_the_tally_built_with_the_changed_values(capsys):
    """Changed on the tally before its chain is built (dataclasses.replace, the tally's own
    path) or on the built string (what the command does): the same string."""
    sets = {"bit_damping": 100.0, "bit_radius": 0.1524, "mu_static": 0.9, "top_damping": 50.0}
    expected = dataclasses.replace(load_tally(PAPER), **sets).at_depth(3000.0).to_params(dof=3)
    d = string_json(
        *("--set", "bit_damping=100", "--set", "bit_radius=6in"),
        *("--set", "mu_static=0.9", "--set", "top_damping=50 N*m*s/rad"),
        capsys=capsys,
    )
    assert d["set"] == pytest.approx(sets)
    assert d["bit_damping"] == expected.bit_damping == 100.0
    assert d["bit_radius"] == pytest.approx(expected.bit_radius)
    assert d["top_damping"] == expected.top_damping == 50.0
    assert d["friction"]["mu_static"] == expected.mu_static == 0.9
    assert d["friction"]["mu_coulomb"] == expected.mu_coulomb
    assert d["inertias"] == pytest.approx(list(expected.inertias), rel=1e-12)
    assert d["stiffnesses"] == pytest.approx(list(expected.stiffnesses), rel=1e-12)
    assert d["units"]["friction"]["stribeck_velocity"] == "rad/s"
    # The chain itself is the tally's: --set leaves the pipe alone.
    own = string_json(capsys=capsys)
    assert own["inertias"] == d["inertias"] and own["dampings"] == d["dampings"]
    assert "set" not in own and own["bit_damping"] != 100.0


def test_simulate_with_the_same_set_runs_the_string_that_string_shows(capsys):
    shown = string_json("--set", "bit_damping=77", "--set", "mu_coulomb=0.4", capsys=capsys)
    argv = ["simulate", "--tally", str(PAPER), "--depth", "3000m", "--dof", "3"]
    argv += ["--set", "bit_damping=77", "--set", "mu_coulomb=0.4"]
    assert main([*argv, "--wob", "60kN", "--torque", "9kNm", "--t-end", "5", "--json"]) == 0
    ran = json.loads(capsys.readouterr().out)["inputs"]
    assert ran["bit_damping"] == shown["bit_damping"] == 77.0
    assert ran["mu_coulomb"] == shown["friction"]["mu_coulomb"] == 0.4
    assert ran["inertias"] == pytest.approx(shown["inertias"], rel=1e-12)


def test_the_text_says_what_changed_and_the_friction_law(capsys):
    assert main([*STRING, "--set", "stribeck_velocity=2", "--set", "bit_radius=6in"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "changed         stribeck_velocity = 2 rad/s, bit_radius = 0.1524 m"
    assert "R_b = 0.1524 m" in lines[-2]
    assert lines[-1] == "  friction    mu_s = 0.8, mu_c = 0.5, gamma_b = 0.9, v_f = 2 rad/s"


@pytest.mark.parametrize(
    ("item", "said"),
    [
        ("mu_static=0.1", "--set mu_static = 0.1 is not allowed: need mu_static > mu_coulomb"),
        ("bit_dampng=100", "bit_dampng is not one of the string's parameters (did you mean "
         "'bit_damping'?)"),
        ("inertias=3", "inertias is a list, one value per inertia; --set takes top_damping"),
        ("bit_radius=3 kg", "unit 'kg' is not a length unit"),
        ("bit_damping=-1", "bit_damping"),
    ],
)  # fmt: skip
def test_a_bad_set_is_refused_in_one_line_and_nothing_printed(item, said, capsys):
    assert main([*STRING, "--set", item]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert said in err and len(err.strip().splitlines()) == 1, err


def preset_json(*options: str, capsys) -> dict:
    assert main(["string", *options, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_a_preset_is_shown_with_the_papers_values(capsys):
    """'pydrill string --preset': the paper's strings as DESIGN.md section 4 gives them (Eq. 14
    at dof 4, Eq. 53), --pipes P as --dof P+3, and --set applied, as the other commands build
    them."""
    lab = preset_json("--preset", "reduced-scale", "--dof", "4", capsys=capsys)
    assert list(lab)[:3] == ["preset", "name", "dof"] and lab["preset"] == "reduced-scale"
    assert lab["inertias"] == [0.518, 0.025, 0.0318, 0.0318]  # J_r, J, J_l = J_b, J_b
    assert lab["stiffnesses"] == [0.073] * 3 and lab["dampings"] == [1e-4] * 3
    assert (lab["top_damping"], lab["bit_damping"], lab["bit_radius"]) == (0.18, 0.01, 0.1)
    assert lab["friction"] == {
        "mu_static": 0.8, "mu_coulomb": 0.5, "stribeck_decay": 0.9, "stribeck_velocity": 1.0
    }  # fmt: skip
    assert lab["length"] is None and lab["bha_length"] is None
    real = preset_json("--preset", "real-string", capsys=capsys)
    assert real["inertias"] == [2122.0, 471.9698] and real["stiffnesses"] == [861.5336]
    assert real["dampings"] == [172.3067] and real["bit_radius"] == 0.155575
    pipes = preset_json("--preset", "reduced-scale", "--pipes", "2", capsys=capsys)
    assert pipes == preset_json("--preset", "reduced-scale", "--dof", "5", capsys=capsys)
    changed = preset_json(
        "--preset", "reduced-scale", "--set", "bit_damping=0.05", "--set", "mu_static=0.9",
        capsys=capsys,
    )  # fmt: skip
    assert changed["set"] == {"bit_damping": 0.05, "mu_static": 0.9}
    assert changed["bit_damping"] == 0.05 and changed["friction"]["mu_static"] == 0.9
    assert main(["string", "--preset", "reduced-scale"]) == 0
    text = capsys.readouterr().out.splitlines()
    assert text[0] == "reduced-scale: dof 4 (a preset: a lumped model, no pipe lengths)"
    assert text[1] == "  top drive   J = 0.518 kg m^2, c_r = 0.18 N m s/rad"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "give a TALLY.toml (a real string, e.g. examples/tallies/paper-eq53.toml) or"),
        ([str(PAPER), "--preset", "reduced-scale"], "give TALLY.toml or --preset, not both"),
        (["--preset", "reduced-scale", "--depth", "3000m"], "--depth needs a TALLY.toml"),
        (["--preset", "reduced-scale", "--lump", "2"], "--lump needs a TALLY.toml"),
        ([str(PAPER), "--pipes", "3"], "--pipes needs --preset"),
    ],
)  # fmt: skip
def test_a_string_needs_a_tally_or_a_preset_and_options_of_its_kind(args, message, capsys):
    assert main(["string", *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and message in captured.err
