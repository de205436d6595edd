"""How the command line reads the string's options, --set, and sweep's options.

Found by a mutation audit of cli_set, cli_string, cli_checks and cli_sweep's option handling:
no test held a --set value with a unit in SI, the friction notes at their documented edge
("above 2"), which combinations of --preset/--tally/--pipes/--lump are refused, the notes on
a real string's loads at their sign, the simulate line a failed check advises (read back by
the parser), or sweep's --workers range 1 ... 256 and its dashboard options. The expectations
come from the --help texts and the documented rules; SI values from factors written out here.
"""

import json
import shlex
from argparse import Namespace

import pytest
from cli_running import notes, run
from sweeping import ROOT

from pydrill import SolverError
from pydrill.cli import build_parser
from pydrill.cli_checks import failure_lines, say_failed_checks
from pydrill.cli_set import set_params
from pydrill.cli_string import point_command

TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"
SPEC = ROOT / "sweeps" / "minimal.toml"
IN = 0.0254  # m, 1 inch
USAGE = 2  # argparse's documented exit status for a bad command line
OP = ["--dof", "4", "--wob", "100", "--torque", "8.3"]
# a run that ends at once (done, or at its step limit), after the string was built and its
# notes said
SHORT = ["--t-end", "0.01", "--max-steps", "10"]


def refused(capsys, *argv):
    code, out, err = run(capsys, *argv)
    assert code == USAGE and out == "", (code, out, err)
    return err.strip().splitlines()[-1]


# --- --set -------------------------------------------------------------------------------------


def test_set_values_with_a_unit_are_read_in_si(capsys):
    args = build_parser().parse_args(
        ["simulate", *OP, "--set", "bit_radius=4.5 in", "--set", "bit_damping = 0.05"]
    )
    assert set_params(args) == pytest.approx({"bit_radius": 4.5 * IN, "bit_damping": 0.05})


@pytest.mark.parametrize(
    ("sets", "said"),
    [
        (["bit_damping="], "--set 'bit_damping=': expected NAME=VALUE"),
        (["bit_damping=1", "bit_damping=2"], "bit_damping is given twice"),
        # the string's refusal, naming the option that gave the value
        (["mu_static=0.1"], "error: --set mu_static = 0.1 is not allowed: need mu_static >"),
    ],
)
def test_set_refusals_name_the_option(sets, said, capsys):
    argv = [w for s in sets for w in ("--set", s)]
    assert said in refused(capsys, "simulate", *OP, *argv)


def test_friction_notes_start_above_two(capsys):
    """A friction coefficient above 2 is most likely mistyped (0.8 as 8); one of 20 or less
    is a tenth of it meant; 2 itself draws no note. Both coefficients are looked at."""
    code, _, err = run(capsys, "simulate", *OP, *SHORT, "--set", "mu_static=2")
    assert code != USAGE and notes(err) == []
    sets = ["--set", "mu_static=20", "--set", "mu_coulomb=8"]
    code, _, err = run(capsys, "simulate", *OP, *SHORT, *sets)
    said = notes(err)
    assert code != USAGE and len(said) == 2
    assert "--set mu_static = 20:" in said[0] and said[0].endswith("; 2 meant?)")
    assert "--set mu_coulomb = 8:" in said[1] and said[1].endswith("; 0.8 meant?)")


# --- the string's options ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (["--pipes", "1e9"], "error: --pipes = 1000000000 is not allowed: need an integer 1 ..."),
        (["--lump", "2"], "error: --lump needs --tally"),
        (["--preset", "real-string", "--tally", TALLY], "give --preset or --tally, not both"),
        (["--tally", TALLY, "--pipes", "3"], "--pipes is not allowed with --tally"),
        (["--tally", TALLY, "--lump", "0"], "error: --lump = 0 is not allowed: >= 1"),
        # the default --lump 1 makes too many inertias of a 1000 km string (some 9 m a joint)
        (["--tally", TALLY, "--depth", "1000km"], "error: --lump = 1: the string (1e+06 m) has"),
        # a tally's string of 3 inertias has 2 links
        (["--tally", TALLY, "--dof", "3", "--stiffnesses", "1,2,3"], "give 2 (one per link)"),
    ],
)
def test_string_options_refused_naming_the_option(argv, said, capsys):
    assert said in refused(capsys, "simulate", "--wob", "1", "--torque", "1", *argv)


def test_a_tallys_lump_is_echoed_as_its_default_one(capsys):
    code, out, err = run(
        capsys,
        *("stability", "--tally", TALLY, "--dof", "2", "--wob", "60kN", "--omega", "10"),
        "--json",
    )
    assert code == 0, err
    assert json.loads(out)["tally"]["lump"] == 1  # --help: "(default 1)"


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # a speed typed with its unit: no advice to write its unit; the speed is too fast
        (["--omega", "600rpm"], "--omega is 600 rpm, faster than any top drive"),
        (["--omega", "600"], "a bare number is rad/s; for rpm write 600rpm"),
        # a light torque of either sign
        (["--torque", "-50"], "--torque is -50 N m, light for a real string"),
        (["--wob", "500", "--torque", "10kN*m"], "--wob is 500 N, light for a real string"),
        (["--wob", "3000kN", "--torque", "10kN*m"], "--wob is 3000 kN, heavier than any"),
    ],
)
def test_real_string_notes(argv, said, capsys):
    wob = [] if "--wob" in argv else ["--wob", "60kN"]
    code, _, err = run(capsys, "stability", "--preset", "real-string", *wob, *argv)
    assert code == 0 and [said in n for n in notes(err)] == [True], err


def test_a_real_strings_torque_on_the_laboratory_string_is_noted_at_either_sign(capsys):
    code, _, err = run(capsys, "stability", "--wob", "100", "--torque", "-6000")
    assert code == 0 and "--torque is -6 kN m, on the reduced-scale laboratory" in err


def test_a_run_longer_than_a_day_is_noted_and_a_day_is_not(capsys):
    code, _, err = run(capsys, "simulate", *OP, "--t-end", "86400", "--max-steps", "10")
    assert code == 3 and notes(err) == []
    code, _, err = run(capsys, "simulate", *OP, "--t-end", "86401", "--max-steps", "10")
    assert code == 3 and len(notes(err)) == 1 and "--t-end is 86401 s (1 day) of" in err


def test_the_simulate_line_of_a_failed_check_reads_back_as_its_point():
    """The line a failed check advises, read by the command line's own parser: the same string,
    load and options (a real string's loads written in kN and kN m)."""
    args = Namespace(
        tally=str(TALLY), depth="3000m", lump=None, dof=4, set_params=["bit_damping=0.05"]
    )
    line = point_command(args, 60e3, -12e3, initial="equilibrium", max_steps=1000)
    back = build_parser().parse_args(shlex.split(line)[1:])
    assert back.wob == pytest.approx(60e3) and back.torque == pytest.approx(-12e3)
    assert (back.tally, back.depth, back.dof, back.max_steps) == (str(TALLY), "3000m", 4, 1000)
    assert back.initial == "equilibrium" and set_params(back) == {"bit_damping": 0.05}


# --- checks that failed ------------------------------------------------------------------------


def test_failed_checks_are_listed_five_then_counted():
    msgs = [f"m{k}" for k in range(7)]
    assert failure_lines(msgs[:5]) == [f"  m{k}" for k in range(5)]
    lines = failure_lines(msgs)
    assert lines[:5] == [f"  m{k}" for k in range(5)] and len(lines) == 6
    assert lines[5].startswith("  ... and 2 more")


def test_every_check_failed_is_a_solver_failure(capsys):
    with pytest.raises(SolverError, match=r"every check failed \(2 of 2\)"):
        say_failed_checks("map", ["a", "b"], 2, json=False)
    say_failed_checks("map", ["a"], 2, json=False)
    assert "1 of 2 checks failed" in capsys.readouterr().err


# --- sweep's options ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # --workers 1 ... 256: 1 and 256 are taken (the refusal is of the dashboard's port,
        # checked after them)
        (["--workers", "256", "--dashboard-address", ":99999"], "the port 0 ... 65535"),
        (["--workers", "1", "--dashboard-address", ":99999"], "the port 0 ... 65535"),
        (["--serial", "--out", "{missing}"], "--out '{missing}': there is no folder"),
        (["--workers", "257"], "--workers = 257 is not allowed: 1 ... 256"),
        (["--workers", "0"], "--workers = 0 is not allowed: 1 ... 256"),
        # the dashboard is the local cluster's (--dashboard-address implies --dashboard)
        (["--dashboard-address", ":8787", "--serial"], "a --serial sweep has no Dask"),
        (["--dashboard", "--scheduler", "tcp://127.0.0.1:1"], "an existing cluster"),
        (["--part", "0/3"], "error: --part '0/3' is not allowed"),
    ],
)
def test_sweep_options_refused_naming_the_option(argv, said, capsys, tmp_path):
    missing = str(tmp_path / "no-such-folder" / "a.h5")
    argv = [a.format(missing=missing) for a in argv]
    assert said.format(missing=missing) in refused(capsys, "sweep", SPEC, *argv)
    assert not (tmp_path / "no-such-folder").exists()
