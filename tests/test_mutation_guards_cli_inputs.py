"""How the command line reads what a user types, against the documented rules.

Found by a mutation audit of cli_parser, cli_options, cli_typos, suggest, cli_set,
cli_window_inputs, cli_checks and the option handling of cli_sweep and cli_string: no test held
the documented edges of the ranges (--t-end at most 1e10, --n-out 2 ... 1e8, --window 0 < F <= 1,
a load at most 1e15, window's bare kN up to 2000), window's bare numbers in kN and rpm, or which
option a refusal names. The expectations come from the --help texts and argparse's documented
exit status 2 for a usage error, the SI values from factors written out here.

An allowed value at its edge is shown accepted without running anything: argparse converts the
options left to right, so ``--t-end 1e10 --plot x.txt`` is refused for --plot, which it reaches
only once --t-end was taken.
"""

import json
import math

import pytest
from cli_running import notes, run
from sweeping import ROOT

TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"
SPEC = ROOT / "sweeps" / "minimal.toml"
KLBF = 4448.2216152605  # N, 1 klbf
RAD_S_PER_RPM = math.pi / 30
IN = 0.0254  # m
USAGE = 2  # argparse's documented exit status for a bad command line
OP = ["--dof", "4", "--wob", "100", "--torque", "8.3"]
BAD_PLOT = ["--plot", "figure.txt"]  # refused at parse time: a suffix no figure format has


def refused(capsys, *argv):
    """The error line of a refused command line (exit status 2, nothing on stdout)."""
    code, out, err = run(capsys, *argv)
    assert code == USAGE and out == "", (code, out, err)
    return err.strip().splitlines()[-1]


# --- the documented ranges, at their edges ---------------------------------------------------


@pytest.mark.parametrize(
    ("option", "allowed", "beyond", "said"),
    [
        ("--t-end", "1e10", "1.0000001e10", "need 0 < --t-end <= 1e10 s"),
        ("--t-end", "1e10", "0", "need 0 < --t-end <= 1e10 s"),
        ("--n-out", "2", "1", "need an integer 2 ... 1e8"),
        ("--n-out", "1e8", "100000001", "need an integer 2 ... 1e8"),
        ("--max-steps", "1e12", "1000000000001", "need an integer 1 ... 1e12"),
        ("--max-steps", "1", "0", "need an integer 1 ... 1e12"),
        ("--window", "1", "1.0001", "need 0 < --window <= 1"),
        ("--window", "1e-9", "0", "need 0 < --window <= 1"),
        ("--wob", "1e15", "1.0000001e15", "at most 1e15 N in size"),
        ("--torque", "-1e15", "-1.0000001e15", "at most 1e15 N m in size"),
        ("--torque", "1e15", "1.0000001e15", "at most 1e15 N m in size"),
        ("--wob", "1e-300", "0", "--wob must be a finite number > 0"),
    ],
)  # fmt: skip
def test_a_range_holds_its_documented_edge_and_refuses_beyond_it(
    option, allowed, beyond, said, capsys
):
    base = {"--wob": "100", "--torque": "8.3"}
    base.pop(option, None)
    fixed = [w for k, v in base.items() for w in (k, v)]
    # the edge is taken: the refusal is --plot's, reached after it
    message = refused(capsys, "simulate", "--dof", "4", *fixed, option, allowed, *BAD_PLOT)
    assert "figure.txt" in message and option not in message
    message = refused(capsys, "simulate", "--dof", "4", *fixed, option, beyond)
    assert message.startswith(f"pydrill simulate: error: argument {option}: ") and said in message


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (["--n-out", "2.5"], "--n-out must be a whole number 2 ... 1e8, got '2.5'"),
        (["--torque", "inf"], "--torque must be finite, got inf"),
        (["--inertias", "1,,2"], "(an entry is empty)"),
        (["--wob", "1e300"], "--wob = 1e300 is not allowed: at most 1e15 N"),
        # a value that starts with a minus and a point is a value (refused by the range
        # check), not an option that leaves --wob without one
        (["--wob", "-.5"], "--wob must be a finite number > 0, got -.5"),
    ],
)
def test_a_bad_value_is_refused_in_one_line_naming_the_option(argv, said, capsys):
    code, out, err = run(capsys, "simulate", *OP, *argv)
    assert code == USAGE and out == "" and said in err and "usage:" not in err, err


def test_a_figure_suffix_in_capitals_is_a_format(capsys):
    """FIGURE.PNG is a PNG (matplotlib takes the suffix in any case)."""
    message = refused(capsys, "simulate", *OP, "--plot", "FIG.PNG", "--t-end", "0")
    assert "--t-end" in message and "FIG.PNG" not in message


def test_an_invalid_choice_shows_the_usage_and_a_bad_value_does_not(capsys):
    """argparse's usage block helps when the command line is malformed (a choice not offered),
    not for a value out of range, whose check names option and range in one line."""
    code, _, err = run(capsys, "simulate", *OP, "--initial", "rets")
    assert code == USAGE and err.startswith("usage: pydrill simulate")
    assert "(did you mean 'rest'?)" in err
    code, _, err = run(capsys, "simulate", *OP, "--window", "2")
    assert code == USAGE and "usage:" not in err


def test_the_step_limit_is_said_in_the_options_words(capsys):
    """The API's max_steps and t_end are --max-steps and --t-end on the command line."""
    code, _, err = run(capsys, "simulate", *OP, "--max-steps", "10")
    assert code == 3 and "--max-steps = 10 internal steps" in err
    assert "raise --max-steps or shorten --t-end" in err and "max_steps" not in err


# --- misspelt options --------------------------------------------------------------------------


def test_an_abbreviation_is_no_typo_but_a_misspelling_after_it_is(capsys):
    """--wo is argparse's prefix of --wob; the typo to name is --torqe."""
    for wob in (["--wo", "100"], ["--wo=100"]):
        message = refused(capsys, "simulate", "--dof", "4", *wob, "--torqe", "8")
        assert message.endswith("unrecognized argument --torqe (did you mean '--torque'?)")


def test_after_a_double_dash_nothing_is_an_option_to_correct(capsys):
    """A bare -- ends the options: what follows is argparse's to report, not a typo."""
    message = refused(capsys, "simulate", *OP, "--", "--torqe")
    assert "did you mean" not in message and message.endswith("unrecognized arguments: -- --torqe")


def test_a_figure_path_that_is_a_folder_or_in_none_is_refused(capsys, tmp_path):
    folder = tmp_path / "run.png"
    folder.mkdir()
    message = refused(capsys, "simulate", *OP, "--plot", folder)
    assert message.endswith("is a directory; give a file name in it")
    message = refused(capsys, "simulate", *OP, "--plot", tmp_path / "no-such-folder" / "run.png")
    assert "there is no folder" in message and not (tmp_path / "no-such-folder").exists()


def test_a_typo_is_matched_whatever_its_case_and_a_far_name_is_not_offered(capsys):
    """BFD is bdf in capitals with two letters swapped: one edit. --wob is no typo of --dof
    (two letters of three differ): 'pydrill string' has no weight on bit, and offering --dof
    for it would name a wrong option."""
    message = refused(capsys, "simulate", *OP, "--method", "BFD")
    assert "invalid choice: 'BFD' (did you mean 'bdf'?)" in message
    message = refused(capsys, "string", TALLY, "--wob", "5")
    assert message == "pydrill string: error: unrecognized argument --wob"


# --- window: bare numbers are kN and rpm -------------------------------------------------------


def window(capsys, *extra):
    code, out, err = run(capsys, "window", TALLY, "--depth", "3000m", *extra, "--json")
    assert code == 0, err
    return json.loads(out), notes(err)


def test_window_reads_bare_numbers_in_kn_and_rpm_and_units_as_written(capsys):
    d, _ = window(
        capsys,
        *("--wob-max", "250", "--rpm-max", "20rad/s"),
        *("--at-wob", "10,2000,5klbf", "--at-rpm", "15,3rad/s"),
    )
    # the chart's last column and row are the maxima, in N and rpm
    assert d["wob"][-1] == pytest.approx(250e3, rel=1e-12)
    assert d["rpm"][-1] == pytest.approx(20 / RAD_S_PER_RPM, rel=1e-12)
    assert d["at_wob"] == pytest.approx([10e3, 2000e3, 5 * KLBF], rel=1e-12)
    assert d["at_rpm"] == pytest.approx([15.0, 3 / RAD_S_PER_RPM], rel=1e-12)
    d, _ = window(capsys, "--wob-max", "60klbf")
    assert d["wob"][-1] == pytest.approx(60 * KLBF, rel=1e-12)


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # bare numbers are kN up to 2000 (no bit takes more): above, newtons were meant
        (["--wob-max", "2001"], "--wob-max 2001: bare numbers are kN here"),
        (["--at-wob", "10,2001"], "--at-wob 2001: bare numbers are kN here"),
        (["--wob-max", "0"], "--wob-max must be a finite force > 0"),
        (["--wob-max", "1e300N"], "--wob-max = 1e300N is not allowed: at most 1e15 N"),
        (["--at-wob", "10,-5"], "--at-wob: give a comma-separated list of values > 0"),
        (["--at-wob", "10,1e300N"], "--at-wob = 10,1e300N is not allowed: at most 1e15 N"),
        (["--at-rpm", "15,0"], "--at-rpm must be a finite speed > 0 (rpm)"),
        (["--rpm-max", "0"], "--rpm-max must be a finite speed > 0 (rpm)"),
        (["--set", "karnopp_band=0.1"], "window's --set takes"),
        (["--set", "mu_static=0.1"], "--set mu_static = 0.1 is not allowed: need mu_static >"),
        # the coefficient --set gave is named, not the tally's it is compared with (this said
        # "mu_static = 0.8 is not allowed", of a value nobody typed)
        (["--set", "mu_coulomb=0.9"], "error: --set mu_coulomb = 0.9 is not allowed: need 0 <"),
    ],
)
def test_window_refuses_naming_the_option(argv, said, capsys):
    code, out, err = run(capsys, "window", TALLY, "--depth", "3000m", *argv)
    assert code == USAGE and out == "" and said in err, err


def test_window_notes_start_beyond_what_a_rig_does(capsys):
    """Some 300 rpm is the fastest top drive, 2000 kN the heaviest weight on bit: at those no
    note; beyond them (any one of a list, not only its first or last) a note naming it."""
    _, said = window(capsys, "--rpm-max", "300", "--at-rpm", "15,300", "--at-wob", "10,2000")
    assert said == []
    _, said = window(capsys, "--rpm-max", "300.5")
    assert len(said) == 1 and "--rpm-max 300.5 rpm is faster" in said[0]
    _, said = window(capsys, "--at-rpm", "15,400,20", "--at-wob", "10,2500kN,20")
    assert any("--at-rpm 400 rpm is faster" in n for n in said)
    assert any("--at-wob 2500 kN is heavier" in n for n in said)
    _, said = window(capsys, "--wob-max", "0.5")
    assert len(said) == 1 and "--wob-max 0.5 kN: the chart ends below 1 kN" in said[0]


def test_a_figure_that_could_not_be_saved_leaves_stdout_one_json_document(
    capsys, tmp_path, monkeypatch
):
    """The results came out before the save failed: stdout stays the one document a script
    parses (json.loads), the failure is said on stderr naming --plot, with exit status 2."""
    import errno

    import pydrill.plot

    def full_disk(figure, path):
        raise OSError(errno.ENOSPC, "No space left on device", path)

    monkeypatch.setattr(pydrill.plot, "save", full_disk)
    path = tmp_path / "run.png"
    code, out, err = run(capsys, "simulate", *OP, "--t-end", "1", "--plot", path, "--json")
    assert code == USAGE and f"--plot {path}: No space left on device" in err
    assert "error" not in json.loads(out) and "plot" not in json.loads(out)


def test_prose_is_refilled_without_breaking_an_option_at_its_hyphens():
    """A description's words come out whole at any width: "--dry-" then "run" is no option."""
    from pydrill.cli_parser import _Wrapped

    text = (
        "an interrupted sweep loses nothing: --resume computes only the missing points;\n"
        "--dry-run counts them, and --t-end sets each check's simulated time"
    )
    for width in range(8, 60):
        lines = _Wrapped("pydrill")._fill_text(text, width, "  ").splitlines()
        assert " ".join(lines).split() == text.split(), width


@pytest.mark.parametrize("flag", ["--js", "--jso", "--json"])
def test_an_abbreviated_json_still_gets_the_json_error_object(capsys, flag):
    """argparse takes --js for --json; a refused value then printed nothing on stdout, where
    a script parses the JSON error object (it did so for --json in full)."""
    code, out, err = run(capsys, "simulate", "--wob", "-1", "--torque", "8.3", flag)
    assert code == 2 and "--wob" in err
    doc = json.loads(out)
    assert "--wob" in json.dumps(doc)


def test_no_command_has_another_option_starting_with_j():
    """What makes --js (and --j...) mean --json alone, for argparse and for wants_json."""
    import argparse

    from pydrill.cli import build_parser

    def options(parser):
        for action in parser._actions:
            yield from action.option_strings
            if isinstance(action, argparse._SubParsersAction):
                for sub in action.choices.values():
                    yield from options(sub)

    found = set(options(build_parser()))
    assert "--json" in found
    assert {o for o in found if o.startswith("--j")} == {"--json"}


@pytest.mark.parametrize("spelling", ["separate", "equals", "trailing slash"])
def test_a_file_in_the_way_inside_reproduce_out_names_the_option_and_the_file(
    capsys, tmp_path, spelling
):
    # reproduce keeps its cache in DIR/cache; a file of that name stops it before any work. The
    # error comes from inside the folder given, so the option is found by the folder the path
    # lies in, not by the path itself (the surviving mutant compared paths for equality only).
    (tmp_path / "cache").write_text("not a folder")
    given = f"{tmp_path}/" if spelling == "trailing slash" else str(tmp_path)
    args = ["--out", given] if spelling != "equals" else [f"--out={given}"]
    code, out, err = run(capsys, "reproduce", *args, "--quick")
    assert code == USAGE and out == ""
    assert err.strip() == (
        f"pydrill reproduce: error: --out {given}: {tmp_path / 'cache'} is a file where pydrill "
        "keeps a folder; move it away or give another --out"
    )
    assert (tmp_path / "cache").read_text() == "not a folder"  # nothing lost
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cache"]  # nothing written


@pytest.mark.parametrize("words", [[], ["atlas"]])
def test_a_command_without_its_sub_command_lists_them_and_says_which_is_missing(capsys, words):
    # 'pydrill' alone said only "the following arguments are required: COMMAND" under a usage
    # line naming no command. Expected: the help listing every sub-command argparse knows of
    # (read from the parser itself), then one error line; exit status 2, stdout empty.
    from pydrill.cli import build_parser

    parser = build_parser()
    if words:
        parser = next(a.choices[words[0]] for a in parser._actions if isinstance(a.choices, dict))
    names = next(a.choices for a in parser._actions if isinstance(a.choices, dict))
    code, out, err = run(capsys, *words)
    assert code == USAGE and out == ""
    lines = err.splitlines()
    assert lines[0].startswith(f"usage: {parser.prog} ")
    listed = {line.split()[0] for line in lines if line.startswith("    ")}
    assert set(names) <= listed
    what, meta = ("action", "ACTION") if words else ("command", "COMMAND")
    assert lines[-1] == f"{parser.prog}: error: say which {what}: {parser.prog} {meta} ..."
    code, out, _ = run(capsys, *words, "--json")
    assert code == USAGE and json.loads(out)["error"]["exit_status"] == USAGE
