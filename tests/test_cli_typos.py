"""A misspelt option, command or choice is named, with what it was probably meant to be.

argparse by itself reported ``--torqe 8`` as "the following arguments are required: --torque"
(the misspelt option is never mentioned) and a misspelt command by listing every command."""

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
