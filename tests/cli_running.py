"""Running ``pydrill`` in the test's own process, for tests of what it prints."""

import json
import subprocess
import sys

from pydrill import cli


def run(capsys, *args):
    """Exit status, stdout and stderr of ``pydrill ARGS`` (a bad option value exits at once)."""
    try:
        code = cli.main([str(a) for a in args])
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def notes(err: str) -> list[str]:
    """The notes among a command's stderr lines."""
    return [line for line in err.splitlines() if line.startswith("pydrill: note: ")]


def ok_text(capsys, *args) -> str:
    """What ``pydrill ARGS`` prints on stdout; its exit status must be 0."""
    code, out, err = run(capsys, *args)
    assert code == 0, err
    return out


def ok_json(capsys, *args):
    """The document ``pydrill ARGS --json`` prints; its exit status must be 0."""
    return json.loads(ok_text(capsys, *args, "--json"))


def spawn(*args):
    """``pydrill ARGS`` run as a new process (``python -m pydrill``), as a shell runs it: its
    completed process, stdout and stderr as text."""
    cmd = [sys.executable, "-m", "pydrill", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def spawn_json(*args):
    """The document ``pydrill ARGS --json`` prints as a new process; its exit status must be 0."""
    proc = spawn(*args, "--json")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)
