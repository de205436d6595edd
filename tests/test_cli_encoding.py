"""Output under a locale that cannot write every character pydrill prints (N·m, Ω, δ, ≥):
``pydrill atlas info`` under PYTHONIOENCODING=ascii failed half-way with "'ascii' codec
can't encode character '\\xb7'", reported as an error of the input, exit 2."""

import io
import os
import subprocess
import sys

import pytest
from sweeping import CMD, SMALL

from pydrill import cli
from pydrill.cli_encoding import PLAIN
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

COMMANDS = ["simulate", "hopf", "stability", "bifurcation", "string", "window", "map", "sweep"]
COMMANDS += ["atlas", "reproduce"]


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("enc") / "small.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    return out


def _run(args, encoding):
    env = {**os.environ, "PYTHONIOENCODING": encoding, "PYTHONUTF8": "0"}
    proc = subprocess.run([*CMD, *map(str, args)], capture_output=True, env=env)
    return proc.returncode, proc.stdout.decode(encoding), proc.stderr.decode(encoding)


def _plain(text: str) -> str:
    return "".join(PLAIN.get(ch, ch) for ch in text)


@pytest.mark.parametrize(
    "args",
    [
        ["atlas", "info"],
        ["atlas", "query", "--wob", "100", "--torque", "8.3"],
        ["atlas", "safe"],
    ],
    ids=["info", "query", "safe"],
)
def test_atlas_commands_under_ascii_print_what_utf8_prints_in_plain_text(atlas, args):
    args = [*args[:2], atlas, *args[2:]] if args[0] == "atlas" else args
    code, utf8, _ = _run(args, "utf-8")
    assert code == 0 and "·" in utf8  # the test needs a character ASCII lacks
    code, ascii_out, err = _run(args, "ascii")
    assert (code, err) == (0, "")
    assert ascii_out == _plain(utf8)
    assert "N m" in ascii_out


def test_an_error_under_ascii_says_what_is_wrong_not_the_codec(atlas):
    code, out, err = _run(["atlas", "query", atlas, "--wob", "100", "--torque", "7"], "ascii")
    assert code == 2 and out == ""
    assert err.startswith("pydrill atlas query: error: torque = 7 N m is not on the grid")
    assert "codec" not in err


def test_latin1_keeps_the_characters_it_has(atlas):
    code, out, err = _run(["atlas", "info", atlas], "latin-1")
    assert (code, err) == (0, "")
    assert "N·m" in out  # U+00B7 is in Latin-1: nothing to replace


@pytest.mark.parametrize("command", COMMANDS)
def test_every_commands_help_prints_under_ascii(command):
    code, out, err = _run([command, "--help"], "ascii")
    assert (code, err) == (0, "")
    assert out.startswith("usage: pydrill " + command)


def test_a_program_calling_main_gets_its_streams_back_as_they_were(atlas, monkeypatch):
    raw = io.BytesIO()
    stream = io.TextIOWrapper(raw, encoding="ascii", errors="strict")
    monkeypatch.setattr(sys, "stdout", stream)
    assert cli.main(["atlas", "info", str(atlas)]) == 0
    assert stream.errors == "strict"  # the caller's own setting, after main
    with pytest.raises(UnicodeEncodeError):
        stream.write("·")
    stream.flush()
    assert b"N m" in raw.getvalue()
