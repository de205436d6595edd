"""A newcomer's audit of the command line: whole numbers written as 1e8 are integers; a unit on
--t-end is refused saying it takes seconds; 'atlas safe' places no edges of windows that do not
exist; a value of what an atlas's spec holds fixed is taken if it is that value and refused
otherwise, saying so; the units the commands print are read back; a friction coefficient of 8
(for 0.8) is noted. Expected values come from the definitions, the raw atlas datasets or a
second run of the same command, not from the code under test."""

import json
import re
from pathlib import Path

import h5py
import numpy as np
import pytest
from cli_running import notes, run

from pydrill import atlas_format as fmt
from pydrill import cli, units
from pydrill.atlas_schema import axis_units
from pydrill.cli_sweep import spec_notes
from pydrill.spec import parse_spec
from pydrill.spec_rules import KINDS
from pydrill.sweep import run_sweep

ROOT = Path(__file__).resolve().parents[1]
PAPER = str(ROOT / "examples" / "tallies" / "paper-eq53.toml")


# 1. whole numbers in a float's form


@pytest.mark.parametrize(
    "argv, dest, text",
    [
        (["simulate", "--wob", "100", "--torque", "8"], "n_out", "--n-out"),
        (["simulate", "--wob", "100", "--torque", "8"], "max_steps", "--max-steps"),
        (["map"], "check", "--check"),
        (["window", PAPER, "--depth", "3000m"], "check", "--check"),
        (["window", PAPER, "--depth", "3000m"], "check_dof", "--check-dof"),
        (["simulate", "--wob", "100", "--torque", "8"], "dof", "--dof"),
        (["hopf"], "pipes", "--pipes"),
        (["sweep", "x.toml"], "workers", "--workers"),
    ],
)
def test_a_whole_number_in_a_float_s_form_is_an_integer(argv, dest, text):
    """1e1 and 10.0 are the integer 10 (an int, as "10" gives), for every integer option; it
    said "must be an integer, got '1e1'"."""
    parser = cli.build_parser()
    for written in ("10", "1e1", "10.0", "1.0e+01"):
        value = getattr(parser.parse_args([*argv, text, written]), dest)
        assert value == 10 and type(value) is int, (text, written, value)


@pytest.mark.parametrize(
    "argv, option, allowed",
    [
        (["simulate", "--wob", "100", "--torque", "8"], "--n-out", "2 ... 1e8"),
        (["simulate", "--wob", "100", "--torque", "8"], "--max-steps", "1 ... 1e12"),
        (["map"], "--check", "0 ... 40"),
        (["simulate", "--wob", "100", "--torque", "8"], "--dof", "2 ... 100000"),
    ],
)
@pytest.mark.parametrize("bad", ["1.5", "1e400", "-1e400", "nan", "ten"])
def test_a_number_that_is_not_whole_is_refused_with_the_range(capsys, argv, option, allowed, bad):
    code, out, err = run(capsys, *argv, option, bad)
    assert code == 2 and not out
    assert f"{option} must be a whole number" in err and allowed in err, err
    assert repr(bad) in err


def test_a_whole_number_out_of_range_is_refused_as_typed(capsys):
    # 1e13 steps: whole, but past the limit (10^12); the message shows what was typed
    code, _, err = run(capsys, "simulate", "--wob", "100", "--torque", "8", "--max-steps", "1e13")
    assert code == 2
    assert "--max-steps = 1e13 is not allowed: need an integer 1 ... 1e12" in err
    # a size past the string's limit names its option (it said "dof = 1000000000 ...")
    code, _, err = run(capsys, "simulate", "--wob", "100", "--torque", "8", "--dof", "1e9")
    assert code == 2 and "error: --dof = 1000000000 is not allowed" in err, err


# 2. a unit on --t-end


@pytest.mark.parametrize("command", [["simulate", "--wob", "100", "--torque", "8"], ["map"]])
@pytest.mark.parametrize("bad", ["10s", "10 min", "1h"])
def test_a_unit_on_t_end_is_refused_saying_it_takes_seconds(capsys, command, bad):
    code, out, err = run(capsys, *command, "--t-end", bad)
    assert code == 2 and not out
    assert (
        f"--t-end must be a number of seconds without a unit, e.g. 600 for 10 min, got {bad!r}"
        in err
    )


# 3 and 4: an atlas with a torque and mu_coulomb held by its spec, swept over W_ob and mu_static

HELD = """
[model]
preset = "reduced-scale"
dof = 4
torque = 10.0
mu_coulomb = 0.4
[axes]
wob = [20.0, 60.0, 200.0]
mu_static = [0.8, 0.9]
[simulation]
t_end = 50.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def held(tmp_path_factory):
    out = tmp_path_factory.mktemp("newcomer") / "held.h5"
    run_sweep(parse_spec(HELD), out, serial=True)
    return out


def _safe(path) -> np.ndarray:
    """Safe points straight from the file (wob, mu_static): steady, and the fastest steady
    state with no eigenvalue in the right half-plane."""
    with h5py.File(path, "r") as f:
        steady = np.all(f["regime"][...] == fmt.REGIMES["steady"], axis=-1)
        return steady & (f["unstable"][..., 0] == 0)


def test_no_note_on_window_edges_where_there_is_no_window(held, capsys):
    safe = _safe(held)
    assert safe[:2].any() and not safe[2].any()  # W_ob 20, 60 N: some safe; 200 N: none
    # along mu_static: a window at the lighter weights, and the note on where its edges lie
    code, out, _ = run(capsys, "atlas", "safe", held, "--along", "mu_static")
    assert code == 0 and "(the true edges lie within a grid step" in out
    # held at 200 N, where no point is safe: no window, so no edges to place (it said "the
    # true edges lie within a grid step beyond each window's ends" of none)
    code, out, _ = run(capsys, "atlas", "safe", held, "--along", "mu_static", "--set", "wob=200")
    assert code == 0
    assert out.splitlines()[-1] == "  none (0 of 2 points)", out
    assert "edges" not in out


def test_a_held_value_is_taken_if_it_is_the_spec_s(held, capsys):
    """Giving what the spec holds at every point changes nothing: the same output as without
    it, whichever way the value is written (to rounding: 6 digits, as printed)."""
    point = ["atlas", "query", held, "--wob", "60", "--set", "mu_static=0.9"]
    code, plain, _ = run(capsys, *point)
    assert code == 0
    for extra in (
        ["--torque", "10"],
        ["--torque", "0.01 kN·m"],
        ["--torque", f"{10 / (0.3048 * 4.4482216152605)!r}ft·lbf"],  # 10 N·m in ft·lbf
        ["--torque", "10.000001"],
        ["--set", "torque=10N*m"],
        ["--set", "mu_coulomb=0.4"],
        ["--set", "dof=4"],
    ):
        code, out, err = run(capsys, *point, *extra)
        assert (code, out) == (0, plain), (extra, err)
    for command in (["atlas", "safe", held], ["atlas", "safe", held, "--json"]):
        code, plain, _ = run(capsys, *command)
        code, out, err = run(capsys, *command, "--set", "torque=10", "--set", "mu_coulomb=0.4")
        assert (code, out) == (0, plain), err


@pytest.mark.parametrize(
    "command",
    [
        ["atlas", "query", "{atlas}", "--wob", "60", "--set", "mu_static=0.9"],
        ["atlas", "safe", "{atlas}"],
        ["atlas", "plot", "{atlas}", "--out", "{png}"],
    ],
)
def test_another_value_of_what_the_spec_holds_is_refused_saying_so(held, tmp_path, capsys, command):
    """It said "torque is not an axis of this atlas", as if the atlas knew no torque."""
    argv = [a.format(atlas=held, png=tmp_path / "m.png") for a in command]
    for given, want in [
        (
            ["--set", "torque=9"],
            "--set torque=9: its spec holds torque = 10 N·m at every point, not 9 N·m",
        ),
        (["--set", "torque=10.001"], "holds torque = 10 N·m at every point, not 10.001 N·m"),
        (["--set", "mu_coulomb=0.5"], "--set mu_coulomb=0.5: its spec holds mu_coulomb = 0.4 at"),
    ]:
        code, out, err = run(capsys, *argv, *given)
        assert code == 2 and not out, err
        assert want in err and err.rstrip().endswith("; leave it out"), err
    assert not (tmp_path / "m.png").exists()
    if argv[1] == "query":  # an option of its own, named as such
        code, _, err = run(capsys, *argv, "--torque", "9kN*m")
        assert code == 2 and "error: --torque: its spec holds torque = 10 N·m" in err, err
        assert "not 9 kN·m; leave it out" in err
    # what is neither an axis nor held: each command names the --set that gave it
    code, _, err = run(capsys, *argv, "--set", "depth=3")
    assert code == 2
    assert "--set depth=3: depth is not an axis of this atlas; axes: wob, mu_static" in err, err


# 5. the units the commands print are read back


def test_the_damping_and_inertia_units_printed_are_read(capsys):
    """'pydrill string' prints c_r in "N m s/rad" and J in "kg m^2": --set top_damping with
    the unit as printed gives the string that value (it said "unit 'N m s/rad' is not a damping
    unit")."""
    code, out, _ = run(capsys, "string", "--preset", "reduced-scale")
    assert code == 0
    damping = re.search(r"c_r = (\S+) (N m s/rad)\n", out)
    inertia = re.search(r"J = (\S+) (kg m\^2)", out)
    assert damping and inertia, out
    assert units.parse(f"{inertia[1]} {inertia[2]}", "inertia") == float(inertia[1])
    twice = 2 * float(damping[1])
    code, out, err = run(
        capsys,
        "string",
        "--preset",
        "reduced-scale",
        "--set",
        f"top_damping={twice!r} {damping[2]}",
    )
    assert code == 0, err
    assert f"c_r = {twice:g} N m s/rad" in out


def test_damping_is_spelt_as_torque_is():
    """Every way a torque's N·m may be written (N m, N*m, N.m, N-m, Nm) makes a damping's
    N·m·s/rad written the same way; and kg·m² as in the tallies' comments."""
    for sep in (" ", "*", ".", "-", "·", ""):
        assert units.parse(f"3 N{sep}m", "torque") == 3.0
        assert units.parse(f"3 N{sep}m{sep}s/rad", "damping") == 3.0, sep
    assert units.parse("2122 kg·m²", "inertia") == 2122.0
    with pytest.raises(ValueError, match="not a damping unit"):
        units.parse("3 N m", "damping")  # a torque is no damping


def test_every_axis_unit_an_atlas_writes_is_read_back(tmp_path, capsys):
    """An atlas's axes carry UDUNITS units for CF readers ("N m s rad-1", "rad s-1"); a value
    written with the unit read from the file picks the point of that value (it said "unit
    'N m s rad-1' is not a damping unit")."""
    for name, kind in KINDS.items():
        unit = axis_units(name)
        assert units.parse(f"2.5 {unit}", kind) == 2.5, (name, unit)
    spec = HELD.replace("mu_static = [0.8, 0.9]", "bit_damping = [0.01, 0.05]")
    run_sweep(parse_spec(spec), tmp_path / "d.h5", serial=True)
    with h5py.File(tmp_path / "d.h5", "r") as f:
        unit = f["bit_damping"].attrs["units"]
        regimes = f["regime"][...]
    assert unit == "N m s rad-1"
    for j, value in enumerate((0.01, 0.05)):
        code, out, err = run(
            capsys, "atlas", "query", tmp_path / "d.h5", "--wob", "60",
            "--set", f"bit_damping={value} {unit}", "--json",
        )  # fmt: skip
        assert code == 0, err
        answer = json.loads(out)
        assert answer["coords"] == {"wob": 60.0, "bit_damping": pytest.approx(value)}
        assert answer["regime"] == fmt.REGIME_NAMES[regimes[1, j, 0]]


# 6. a friction coefficient most likely mistyped


@pytest.mark.parametrize(
    "sets, noted",
    [
        (["mu_static=8"], ["mu_static = 8"]),
        (["mu_static=2.01"], ["mu_static = 2.01"]),
        (["mu_coulomb=3", "mu_static=4"], ["mu_static = 4", "mu_coulomb = 3"]),
        (["mu_static=1.99"], []),  # high, but a bit's friction may be
        (["mu_static=0.9"], []),
    ],
)
def test_a_friction_coefficient_above_two_is_noted_not_refused(capsys, sets, noted):
    args = [a for s in sets for a in ("--set", s)]
    for command in (
        ["string", "--preset", "reduced-scale"],
        ["string", PAPER],
        ["simulate", "--wob", "100", "--torque", "9", "--t-end", "0.5"],
    ):
        code, out, err = run(capsys, *command, *args)
        assert code == 0 and out, err
        said = notes(err)
        assert len(said) == len(noted), err
        for note, what in zip(said, noted, strict=True):
            assert note.startswith(f"pydrill: note: --set {what}: a friction coefficient above")


def test_a_tally_s_and_a_spec_s_friction_above_two_is_noted(tmp_path, capsys):
    text = Path(PAPER).read_text()
    assert text.count("mu_static = 0.8\n") == 1
    tally = tmp_path / "t.toml"
    tally.write_text(text.replace("mu_static = 0.8\n", "mu_static = 8\n"))
    code, _, err = run(capsys, "string", tally)
    assert code == 0
    assert notes(err) == [
        f"pydrill: note: {tally}: bit.mu_static = 8: a friction coefficient above any bit's on "
        "rock (some 0.1 ... 1; most likely mistyped above 2; 0.8 meant?)"
    ]
    for spec, want in [
        (HELD.replace("mu_coulomb = 0.4", "mu_coulomb = 0.4\nbit_damping = 0.05"), []),
        (HELD.replace("[0.8, 0.9]", "[0.8, 9.0]"), ["axes.mu_static reaches 9"]),
    ]:
        spec_notes(parse_spec(spec))
        said = notes(capsys.readouterr().err)
        assert [n.removeprefix("pydrill: note: ").split(": ")[0] for n in said] == want
    held_high = HELD.replace("mu_coulomb = 0.4", "mu_coulomb = 4.0").replace(
        "mu_static = [0.8, 0.9]", "mu_static = [5.0, 6.0]"
    )
    spec_notes(parse_spec(held_high))
    said = [
        n.removeprefix("pydrill: note: ").split(": ")[0] for n in notes(capsys.readouterr().err)
    ]
    assert said == ["axes.mu_static reaches 6", "model.mu_coulomb = 4"]


# 7. the paper's real string at another size


@pytest.mark.parametrize(
    "size, named",
    [(["--dof", "3"], "--dof 3"), (["--pipes", "10"], "--pipes 10"), (["--inertias", "1,2,3"], "")],
)
def test_the_real_string_at_another_size_points_to_its_tally(capsys, size, named):
    """The core's refusal spoke to C++ ("Params::inertias, stiffnesses, dampings"); the command
    names the option typed and the tally that holds the paper's string pipe by pipe, and what
    it suggests runs."""
    base = ["--wob", "100kN", "--torque", "10kN*m", "--t-end", "5"]
    code, out, err = run(capsys, "simulate", "--preset", "real-string", *size, *base)
    assert (code, out) == (2, "")
    assert err.startswith(f"pydrill simulate: error: {named}")
    assert "Params::" not in err and "--tally TALLY.toml [--depth D] [--dof N]" in err
    tally = re.search(r"\((examples/tallies/\S+\.toml) is the paper's\)", err)
    assert tally, err
    code, out, err = run(capsys, "simulate", "--tally", ROOT / tally[1], "--dof", "3", *base)
    assert code == 0, err
    assert "paper-eq53 at" in out and "3 inertias" in out
