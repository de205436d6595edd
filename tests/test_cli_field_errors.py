"""A drilling engineer's audit of bad input to the single-run commands on a real string: every
refusal is one line that names the file or the option at fault (it said "section[0].odd:
unknown" of no file, "dof = 1 is not allowed" of --check-dof, "'3000rpm': unit 'rpm' is not
a length unit" of no option). A section is named as the file lists it, from 1."""

from pathlib import Path

import pytest

from pydrill import cli

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
POINT = ["--wob", "60kN", "--torque", "9kN*m"]


def refused(capsys, *args):
    """The one-line message of a refusal (exit status 2, nothing on stdout)."""
    code = cli.main([str(a) for a in args])
    out = capsys.readouterr()
    assert code == 2 and not out.out and "Traceback" not in out.err, out
    (line,) = out.err.splitlines()
    return line


@pytest.mark.parametrize(
    "typo, found",
    [
        (('od = "5 in"', 'odd = "5 in"'), "section 1 (drill-pipe), odd: unknown"),
        (("count = 100", "count = 1OO"), "not valid TOML"),
        (("[bit]", "[bitt]"), "bitt: unknown"),
    ],
)
@pytest.mark.parametrize(
    "command",
    [
        ["simulate", "--tally", "{}", *POINT],
        ["stability", "--tally", "{}", "--wob", "60kN", "--omega", "60rpm"],
        ["hopf", "--tally", "{}"],
        ["string", "{}"],
        ["window", "{}", "--depth", "3000m"],
    ],
)
def test_a_typo_in_a_tally_is_said_with_the_file_name(capsys, tmp_path, typo, found, command):
    bad = tmp_path / "my-well.toml"
    text = PAPER.read_text()
    assert typo[0] in text
    bad.write_text(text.replace(typo[0], typo[1], 1))
    line = refused(capsys, *(str(bad) if a == "{}" else a for a in command))
    assert f"error: {bad}: " in line and found in line, line


@pytest.mark.parametrize(
    "command",
    [
        ["simulate", "--tally", PAPER, *POINT],
        ["stability", "--tally", PAPER, "--wob", "60kN", "--omega", "60rpm"],
        ["string", PAPER],
        ["window", PAPER],
    ],
)
@pytest.mark.parametrize(
    "depth, words",
    [
        ("3000rpm", ["--depth", "'rpm' is not a length unit"]),
        ("-3000m", ["--depth", "> 0"]),
        # 49.5 m of BHA in paper-eq53.toml (2 collars of 18.6 m, 9.3 + 1.5 + 1.5 m)
        ("10m", ["--depth 10 m is shallower than the BHA", f"({2 * 18.6 + 9.3 + 3.0:g} m)"]),
    ],
)
def test_a_bad_depth_is_refused_naming_depth(capsys, command, depth, words):
    line = refused(capsys, *command, f"--depth={depth}")
    for w in words:
        assert w in line, line


@pytest.mark.parametrize(
    "args, words",
    [
        # 105 elements + the top drive: 2 ... 106 inertias
        (["simulate", "--tally", PAPER, *POINT, "--dof", "1"], ["--dof = 1", "2 ... 106"]),
        (["hopf", "--tally", PAPER, "--dof", "107"], ["--dof = 107", "2 ... 106"]),
        # 334 inertias at 3000 m
        (
            ["window", PAPER, "--depth", "3000m", "--check", "2", "--check-dof", "1"],
            ["--check-dof = 1", "2 ... 334"],
        ),
        (["window", PAPER, "--depth", "3000m", "--at-wob", "5kN*m"], ["--at-wob", "force unit"]),
        (["window", PAPER, "--depth", "3000m", "--at-rpm", "5kN"], ["--at-rpm", "velocity unit"]),
    ],
)
def test_a_bad_string_size_or_list_names_its_option(capsys, args, words):
    line = refused(capsys, *args)
    for w in words:
        assert w in line, line
