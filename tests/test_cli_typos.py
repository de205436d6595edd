"""A misspelt option, command or choice is named, with what it was probably meant to be.

argparse by itself reported ``--torqe 8`` as "the following arguments are required: --torque"
(the misspelt option is never mentioned) and a misspelt command by listing every command."""

import json

import pytest

from pydrill.cli import main

OP = ["--dof", "4", "--wob", "100", "--torque", "8.3"]


def refused(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    out, err = capsys.readouterr()
    assert exit_.value.code == 2 and out == ""
    return err.strip().splitlines()[-1]


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # the misspelt option, not the required one it left out
        (["simulate", "--dof", "4", "--wob", "100", "--torqe", "8"],
         "pydrill simulate: error: unrecognized argument --torqe (did you mean '--torque'?)"),
        (["simulate", *OP, "--tend", "10"],
         "pydrill simulate: error: unrecognized argument --tend (did you mean '--t-end'?)"),
        (["simulate", *OP, "--mehtod=bdf"],
         "pydrill simulate: error: unrecognized argument --mehtod (did you mean '--method'?)"),
        (["atlas", "query", "a.h5", "--wob", "1", "--torqe", "2"],
         "pydrill atlas query: error: unrecognized argument --torqe (did you mean '--torque'?)"),
        (["--verison"], "pydrill: error: unrecognized argument --verison (did you mean "
         "'--version'?)"),
        # nothing near it: named alone
        (["simulate", *OP, "--colour", "red"],
         "pydrill simulate: error: unrecognized argument --colour"),
        (["simulte", *OP], "pydrill: error: argument COMMAND: invalid choice: 'simulte' (did "
         "you mean 'simulate'?) (choose from 'simulate', 'hopf'"),
        (["atlas", "qurey", "a.h5"], "pydrill atlas: error: argument ACTION: invalid choice: "
         "'qurey' (did you mean 'query'?) (choose from 'info', 'query'"),
        (["simulate", *OP, "--initial", "rets"], "argument --initial: invalid choice: 'rets' "
         "(did you mean 'rest'?) (choose from 'rest', 'equilibrium')"),
        # a missing option alone is still said as argparse says it
        (["simulate", "--dof", "4", "--wob", "100"],
         "pydrill simulate: error: the following arguments are required: --torque"),
    ],
)  # fmt: skip
def test_a_typo_is_named_with_what_it_was_probably_meant_to_be(argv, said, capsys):
    assert said in refused(argv, capsys)


def test_abbreviations_and_values_that_look_like_options_are_not_typos(capsys):
    """argparse takes a unique prefix of an option (--t-e for --t-end); a negative number is
    a value. Neither is reported."""
    assert main(["simulate", *OP, "--t-e", "5", "--json"]) == 0
    capsys.readouterr()
    message = refused(["simulate", "--dof", "4", "--wob", "-100", "--torque", "8.3"], capsys)
    assert "unrecognized" not in message and "--wob" in message


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # argparse took the value for the command: "invalid choice: '100'"
        (["--wob", "100", "simulate", "--torque", "8.3"],
         "pydrill: error: --wob is an option of a command and goes after it: pydrill simulate "
         "--wob ... (commands that take --wob: simulate, stability, bifurcation, window, map, "
         "atlas query)"),
        (["--torque=3"], "pydrill: error: --torque is an option of a command and goes after "
         "it: pydrill simulate --torque ... (commands that take --torque: simulate, stability, "
         "bifurcation, map, atlas query)"),
        (["atlas", "--wob", "3", "query", "a.h5"], "pydrill atlas: error: --wob is an option "
         "of a command and goes after it: pydrill atlas query --wob ... (commands that take "
         "--wob: atlas query)"),
        (["--plot", "a.png"], "pydrill: error: --plot is an option of a command and goes "
         "after it: pydrill simulate --plot ... (commands that take --plot: simulate, hopf, "
         "stability, bifurcation, window, map, sweep)"),
        # no command has it: unknown, not "invalid choice: '3'"
        (["--frobnicate", "3"], "pydrill: error: unrecognized argument --frobnicate"),
    ],
)  # fmt: skip
def test_an_option_before_its_command_names_the_commands_that_take_it(argv, said, capsys):
    assert refused(argv, capsys) == said


def test_an_option_every_command_takes_is_said_so_in_json_too(capsys):
    with pytest.raises(SystemExit):
        main(["--json"])
    out, err = capsys.readouterr()
    said = "--json is an option of a command and goes after it: pydrill simulate --json ... "
    said += "(every command takes --json)"
    assert err.strip().splitlines()[-1] == f"pydrill: error: {said}"
    assert json.loads(out) == {"error": {"kind": "error", "message": said, "exit_status": 2}}


def test_an_option_after_its_command_is_not_sent_to_another_command(capsys):
    """Once the command is given, an option it lacks is a typo as before, not another
    command's option ("--omega" is stability's, not simulate's)."""
    said = refused(["simulate", *OP, "--omega", "3"], capsys)
    assert said.startswith("pydrill simulate: error: unrecognized argument --omega")


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # argparse's top parser said these, with its usage naming no command
        (["sweep", "a.toml", "--out", "a.h5", "--dashboard", ":0"],
         "pydrill sweep: error: unrecognized argument ':0' (--dashboard takes no value)"),
        (["simulate", *OP, "--json", "3"],
         "pydrill simulate: error: unrecognized argument '3' (--json takes no value)"),
        (["simulate", *OP, "extra"], "pydrill simulate: error: unrecognized argument 'extra'"),
        (["atlas", "info", "a.h5", "b.h5"],
         "pydrill atlas info: error: unrecognized argument 'b.h5'"),
        (["simulate", *OP, "a", "b"],
         "pydrill simulate: error: unrecognized arguments 'a', 'b'"),
    ],
)  # fmt: skip
def test_a_stray_value_is_said_by_its_command_with_the_flag_it_follows(argv, said, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    _, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert exit_.value.code == 2 and lines[-1] == said
    # the usage shown is the command's, not "pydrill [-h] [--version] COMMAND ..."
    assert lines[0].startswith(f"usage: {said.split(':')[0]} ")
