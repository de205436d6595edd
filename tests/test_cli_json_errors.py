"""--json promises scripts one JSON object on stdout: on a failure too, the error alone."""

import json
import subprocess
import sys

import pytest

CMD = [sys.executable, "-m", "pydrill"]


def run(*args):
    return subprocess.run([*CMD, *args], capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize(
    ("args", "prog"),
    [
        (["simulate", "--wob", "-1", "--torque", "8.3"], "simulate"),  # a range, in argparse
        (["simulate", "--wob", "100", "--torqe", "8.3"], "simulate"),  # a misspelt option
        (["simulate", "--wob", "100", "--torque", "8.3", "--set", "mu_static=0.1"], "simulate"),
        (["atlas", "info", "{tmp}/no-such-atlas.h5"], "atlas info"),  # a file
        (["stability", "--wob", "0", "--torque", "8.3"], "stability"),
    ],
)
def test_bad_input_with_json_prints_the_error_as_json(args, prog, tmp_path):
    """Every bad input, wherever it is caught (argparse, the model, a file), reaches a --json
    script as one object, ``{"error": ...}``, holding the message said on stderr and exit
    status 2; the same command without --json leaves stdout empty and says the same."""
    args = [a.format(tmp=tmp_path) for a in args]
    plain = run(*args)
    proc = run(*args, "--json")
    assert plain.returncode == proc.returncode == 2 and plain.stdout == ""
    doc = json.loads(proc.stdout)
    assert list(doc) == ["error"]
    assert doc["error"]["exit_status"] == 2 and doc["error"]["kind"] == "error"
    last = proc.stderr.strip().splitlines()[-1]
    assert last == f"pydrill {prog}: error: {doc['error']['message']}"
    assert last == plain.stderr.strip().splitlines()[-1]


def test_json_after_a_double_dash_is_not_the_option():
    """After "--" every token is a value, so a "--json" there asks for nothing: the error stays
    on stderr alone."""
    proc = run("atlas", "info", "--", "--json")
    assert proc.returncode == 2 and proc.stdout == ""
    assert "--json" in proc.stderr


def test_ctrl_c_with_json_is_an_interrupted_error(monkeypatch, capsys):
    """Ctrl-C still ends with one line and status 130; a --json script reads why."""
    import pydrill
    from pydrill import cli

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(pydrill, "simulate", interrupted)
    assert cli.main(["simulate", "--wob", "100", "--torque", "8.3", "--json"]) == 130
    out, err = capsys.readouterr()
    assert err.strip() == "pydrill simulate: interrupted"
    assert json.loads(out) == {
        "error": {"kind": "interrupted", "message": "stopped by Ctrl-C", "exit_status": 130}
    }
