"""What a message of a single-run command tells its user to do, that user can do: every option
a message (error or note) names is an option of the command that printed it, or of the command
it names (``pydrill simulate --max-steps ...``), and no message names simulate()'s parameters
by their Python names (``max_steps``, ``t_end``), which no command line takes. ``map --check``
said "raise max_steps or shorten t_end", and map has neither spelling.

The options are read from the parser itself, not listed here: an option renamed or removed
makes the messages that still name it fail."""

import argparse
import functools
import json
import re
import shlex
from pathlib import Path

import pytest

import pydrill
from pydrill.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
PAPER = str(ROOT / "examples" / "tallies" / "paper-eq53.toml")

#: simulate()'s parameters that its command line spells otherwise
API_NAMES = (
    "max_steps",
    "t_end",
    "n_out",
    "window_fraction",
    "max_step",
    "t_out",
    "max_switch_rate",
)


def commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def advice_faults(command: str, text: str) -> list[str]:
    """The options ``text`` names that its command lacks, and the API names it uses. Within
    a sentence, from "pydrill OTHER" on, the options are OTHER's (a suggested command line)."""
    parsers = commands()
    faults = []
    for line in text.splitlines():
        for sentence in re.split(r"[;()]", line):
            current, prev = command, None
            for word in sentence.split():
                word = word.strip("'\",.:")
                if word in parsers and prev == "pydrill":
                    current = word
                prev = word
                if re.fullmatch(r"--[a-z][a-z-]*", word.split("=")[0]):
                    option = word.split("=")[0]
                    if option not in parsers[current]._option_string_actions:
                        faults.append(f"{option} (not an option of {current}): {line}")
        for name in API_NAMES:
            if re.search(rf"(?<![\w-]){name}(?!\w)", line):
                faults.append(f"{name} (simulate()'s name, no option): {line}")
    return faults


def test_the_walk_finds_what_it_is_for():
    """The checker itself: an option the command lacks, an API name, and a suggested command's
    own option are told apart."""
    assert advice_faults("map", "pydrill map: error: raise max_steps or shorten --t-end") == [
        "max_steps (simulate()'s name, no option): pydrill map: error: raise max_steps or "
        "shorten --t-end"
    ]
    assert advice_faults("map", "give --max-steps 10") == [
        "--max-steps (not an option of map): give --max-steps 10"
    ]
    assert advice_faults("map", "run it alone: pydrill simulate --max-steps 10") == []
    assert advice_faults("map", "see 'pydrill simulate'; --max-steps 10") != []


T = ["--tally", PAPER]
# Bad and implausible command lines of the single-run commands: each error path and each note.
CASES = [
    ["map", "--dof", "4", "--t-end", "50"],
    ["map", "--dof", "4", "--check", "41"],
    ["map", "--dof", "4", "--wob-max", "-1"],
    ["map", "--dof", "4", "--wob-max", "100kN"],
    ["map", "--dof", "4", "--depth", "3000m"],
    ["map", "--preset", "real-string", *T],
    ["map", *T, "--pipes", "10"],
    ["map", *T, "--depth", "30000"],
    ["map", *T, "--depth", "3000m", "--wob-max", "100"],
    ["map", *T, "--depth", "3000m", "--wob-max", "3000kN", "--torque-max", "200kN*m"],
    ["map", *T, "--depth", "3000rpm"],
    ["map", *T, "--depth", "3000m", "--lump", "0"],
    # past a day (LONG_RUN, 86400 s): the note on a long run; 1e5 s, not 1e6, keeps the checks short
    ["map", "--dof", "2", "--check", "2", "--t-end", "1e5"],
    ["stability", "--dof", "4", "--wob", "40"],
    ["stability", "--dof", "4", "--wob", "40", "--omega", "0"],
    ["stability", "--dof", "4", "--wob", "60kN", "--torque", "9kN*m"],
    ["stability", *T, "--depth", "3000m", "--wob", "60", "--omega", "60"],
    ["stability", *T, "--depth", "3000m", "--wob", "3000kN", "--omega", "400rpm"],
    ["stability", *T, "--depth", "3000m", "--wob", "60kN", "--torque", "9"],
    ["stability", "--dof", "4", "--wob", "40", "--torque", "1", "--plot", "x.png"],
    ["stability", "--dof", "4", "--wob", "40", "--omega", "1e300"],
    ["hopf", "--dof", "4", "--omega-max", "30"],
    ["hopf", "--dof", "1"],
    ["hopf", "--pipes", "0"],
    ["hopf", *T, "--dof", "1"],
    ["bifurcation", "--dof", "2", "--vary", "wob"],
    ["bifurcation", "--dof", "2", "--vary", "torque"],
    ["bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8", "--wob", "100"],
    ["bifurcation", "--dof", "2", "--vary", "torque", "--wob", "100", "--torque", "8"],
    ["bifurcation", "--dof", "2", "--vary", "torque", "--wob", "60kN"],
    ["window", PAPER, "--depth", "3000m", "--t-end", "5"],
    ["window", PAPER, "--depth", "3000m", "--check-dof", "12"],
    ["window", PAPER, "--depth", "3000m", "--check", "1", "--check-dof", "1"],
    ["window", PAPER, "--depth", "3000m", "--wob-max", "3000"],
    ["window", PAPER, "--depth", "3000m", "--rpm-max", "400", "--at-rpm", "400"],
    ["window", PAPER, "--depth", "10m"],
    ["window", PAPER, "--depth", "30000"],
    ["window", PAPER, "--depth", "3000m", "--at-wob", "3000"],
    ["window", PAPER, "--depth", "3000m", "--lump", "0"],
    ["string", PAPER, "--depth", "30000"],
    ["string", PAPER, "--dof", "1"],
]


@pytest.mark.parametrize("argv", CASES, ids=lambda argv: " ".join(argv).replace(PAPER, "T"))
def test_messages_name_only_options_the_command_has(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    try:
        main(argv)
    except SystemExit:  # argparse's refusals
        pass
    err = capsys.readouterr().err
    assert err, "no message: the case no longer tests a message"
    assert "Traceback" not in err
    assert advice_faults(argv[0], err) == []


def _limited(monkeypatch, **limits):
    """pydrill.simulate, which map and window call for their checks, with ``limits`` (the
    core's own failures, its own messages)."""
    monkeypatch.setattr(pydrill, "simulate", functools.partial(pydrill.simulate, **limits))


@pytest.mark.parametrize(
    "argv",
    [
        ["map", "--dof", "4", "--check", "2"],
        ["map", *T, "--depth", "1000m", "--lump", "3", "--check", "2", "--t-end", "50"],
        ["window", PAPER, "--depth", "1000m", "--check", "1", "--check-dof", "10"],
        ["window", PAPER, "--depth", "1000m", "--check", "1", "--check-from", "rest"],
    ],
    ids=["map", "map-tally", "window", "window-rest"],
)
def test_a_check_at_its_step_limit_says_what_this_command_can_do(argv, capsys, monkeypatch):
    """The failed check names its point and a ``pydrill simulate`` line that runs that point
    alone with more steps; run as given (with the step limit), that line fails as the check
    did, at the same time; the limit lifted, it runs. Every check fails at 20 steps: exit
    status 3, the first failure's message last on stderr (each one's in the output)."""
    _limited(monkeypatch, max_steps=20)
    assert main(argv) == 3
    out, err = capsys.readouterr()
    assert advice_faults(argv[0], out) == advice_faults(argv[0], err) == []
    assert "every check failed" in err and "the check at " in err and "shorten --t-end" in err
    assert err.strip().splitlines()[-1].split("the first: ")[1] in out  # listed in the output
    reached = re.search(r"steps reached at t = (\S+) s;", err).group(1)
    line = re.search(r"(pydrill simulate .*)$", err.strip()).group(1)
    words = shlex.split(line)
    assert words[words.index("--max-steps") + 1] == "100000000"
    i = words.index("--max-steps")
    alone = [*words[1:i], "--max-steps", "20", *words[i + 2 :]]
    monkeypatch.undo()
    assert main(alone) == 3  # the very point (to 8 digits): it fails where the check did
    alone_reached = re.search(r"reached t = (\S+) s\)", capsys.readouterr().err).group(1)
    assert float(alone_reached) == pytest.approx(float(reached), rel=1e-4)
    assert main([*words[1:], "--n-out", "2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["regime"]


def test_a_check_that_fails_otherwise_gives_the_line_to_run_it_alone(capsys, monkeypatch):
    """Some checks chatter, the others are computed: exit status 0, the failed ones listed in
    the output with their messages, counted on stderr."""
    _limited(monkeypatch, max_switch_rate=1e-3)  # stick-slip is "chattering" at once
    assert main(["map", "--dof", "4", "--check", "3", "--t-end", "3000"]) == 0
    out, err = capsys.readouterr()
    assert "chattering" in out and "to run that point alone: pydrill simulate --dof 4" in out
    assert re.search(r"pydrill map: \d of 9 checks failed", err)
    assert advice_faults("map", out) == advice_faults("map", err) == []


#: a value with a unit of each kind, as a help text would show one
UNIT_SAMPLES = ("100kN", "12kN*m", "120rpm", "3000m", "60klbf", "2rad/s")
SINGLE_RUN = ("simulate", "map", "stability", "hopf", "bifurcation", "window", "string")


def _takes(action: argparse.Action, text: str) -> bool:
    try:
        action.type(text)  # type: ignore[misc]
    except (argparse.ArgumentTypeError, ValueError, TypeError):
        return False
    return True


@pytest.mark.parametrize("command", SINGLE_RUN)
def test_an_option_that_takes_units_shows_one_in_its_help(command):
    """map's --wob-max took 200kN, and its help said "N" alone: an engineer typed 200000. Each
    option whose type takes a value with a unit shows such a value in its help, and each such
    value shown, the option takes."""
    faults = []
    for action in commands()[command]._actions:
        if action.type is None or not action.help or not callable(action.type):
            continue
        takes = [s for s in UNIT_SAMPLES if _takes(action, s)]
        shown = re.findall(
            r"(?<![\w.])\d+(?:\.\d+)?(?:kN\*m|kNm|kN|kft\*lbf|klb-ft|ft-lbs?|klbf|lbf|rpm|rad/s|ft|m)(?![\w*-])",
            action.help,
        )
        name = action.option_strings[0] if action.option_strings else action.dest
        if takes and not shown:
            faults.append(f"{name} takes {takes[0]}, its help shows no unit")
        faults += [f"{name} shows {s} and refuses it" for s in shown if not _takes(action, s)]
    assert faults == []


@pytest.mark.parametrize(
    ("limit", "words"),
    [
        (["--max-steps", "20"], "--max-steps = 20 internal steps reached"),
        (["--max-switch-rate", "0.001", "--t-end", "3000"], "(limit --max-switch-rate = 0.001 /s)"),
    ],
)
def test_simulate_at_a_limit_names_the_option_that_sets_it(limit, words, capsys):
    """simulate's chattering guard said "limit max_switch_rate = ...", a parameter of the
    Python API the command line did not take; --max-switch-rate now sets it. Both limits are
    the core's own failures, at the values given."""
    argv = ["simulate", "--wob", "100", "--torque", "8.3", *limit]
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert words in err
    assert advice_faults("simulate", err) == []
    # the same run within the default limits runs
    assert main([*argv[:5], "--t-end", "3000"] if "3000" in argv else argv[:5]) == 0
