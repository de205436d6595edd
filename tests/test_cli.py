"""The pydrill command as a user and a script meet it: real subprocesses."""

import itertools
import json
import subprocess
import sys
from pathlib import Path

import pytest

CMD = [sys.executable, "-m", "pydrill"]
MINIMAL = Path(__file__).resolve().parents[1] / "sweeps" / "minimal.toml"


def run(*args, check=True):
    proc = subprocess.run([*CMD, *args], capture_output=True, text=True, timeout=300)
    if check and proc.returncode != 0:
        raise AssertionError(f"exit {proc.returncode}: {proc.stderr}")
    return proc


def test_simulate_json_has_the_documented_fields(tmp_path):
    png = tmp_path / "fig4.png"
    proc = run(
        "simulate",
        "--preset",
        "reduced-scale",
        "--dof",
        "4",
        "--wob",
        "100",
        "--torque",
        "8.3",
        "--t-end",
        "300",
        "--json",
        "--plot",
        str(png),
    )
    data = json.loads(proc.stdout)  # exactly one JSON object
    assert data["regime"] == "stick-slip"
    for key in ("bit_velocity", "top_velocity"):
        assert set(data[key]) == {"min", "max", "mean"}
    for key in ("severity", "stuck_fraction", "period", "stick_events", "omega_equilibrium"):
        assert key in data
    assert data["period"] > 0
    assert data["omega_equilibrium"] == [pytest.approx(17.368418484246266, rel=1e-12)]
    solver = data["solver"]
    for key in ("method", "steps", "rhs_evals", "jac_evals", "switches", "wall_time"):
        assert key in solver
    assert solver["switches"] > 10 and solver["wall_time"] > 0
    assert data["units"]["bit_velocity"] == "rad/s"
    assert data["units"]["period"] == "s"
    assert png.stat().st_size > 20_000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_pipes_is_dof_plus_three():
    a = json.loads(
        run(
            "simulate", "--pipes", "2", "--wob", "160", "--torque", "8.3", "--t-end", "20", "--json"
        ).stdout
    )
    b = json.loads(
        run(
            "simulate", "--dof", "5", "--wob", "160", "--torque", "8.3", "--t-end", "20", "--json"
        ).stdout
    )
    assert a["inputs"]["dof"] == b["inputs"]["dof"] == 5
    assert a["regime"] == b["regime"] == "stuck"
    assert a["period"] is None


def test_stuck_json_is_strict_json():
    proc = run("simulate", "--wob", "160", "--torque", "8.3", "--json", "--friction", "karnopp")
    data = json.loads(proc.stdout)
    assert data["regime"] == "stuck"
    assert data["solver"]["method"] in ("adams", "bdf", "erk", "dop853")


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--wob", "-5", "--torque", "8.3"], "--wob must be a finite number > 0"),
        (["--wob", "abc", "--torque", "8.3"], "--wob must be a number"),
        (["--wob", "100", "--torque", "nan"], "--torque must be finite"),
        (["--wob", "100", "--torque", "8.3", "--dof", "1"], "dof = 1"),
        (
            ["--wob", "100", "--torque", "8.3", "--preset", "real-string", "--dof", "5"],
            "real-string",
        ),
        (["--wob", "100", "--torque", "8.3", "--dampings", "1,-1,1"], "dampings[1] = -1"),
        (["--wob", "100", "--torque", "8.3", "--initial", "sideways"], "invalid choice"),
        (["--wob", "160", "--torque", "8.3", "--initial", "equilibrium"], "no steady rotation"),
        (["--torque", "8.3"], "--wob"),
    ],
)
def test_bad_input_exits_2_without_traceback(args, needle):
    proc = run("simulate", *args, check=False)
    assert proc.returncode == 2
    assert needle in proc.stderr
    assert "Traceback" not in proc.stderr
    assert proc.stdout == ""


@pytest.mark.parametrize("method", ["bdf", "dop853"])
def test_solver_failure_exits_3_naming_the_limit_and_the_time_reached(method):
    """A run that cannot finish (here: 50 internal steps for 300 s) exits 3 with one line that
    says where it stopped and what to change, never a traceback; --json scripts get one object
    on stdout, the error alone (nothing to mistake for a result), with the same message and the
    time reached as a number."""
    proc = run(
        "simulate",
        *("--wob", "100", "--torque", "8.3", "--t-end", "300"),
        *("--method", method, "--max-steps", "50", "--json"),
        check=False,
    )
    assert proc.returncode == 3, proc.stderr
    err = proc.stderr.strip()
    assert err.startswith("pydrill simulate: solver failed (reached t = ") and "\n" not in err
    t = float(err.split("reached t = ")[1].split(" s")[0])
    assert 0 < t < 300
    assert "--max-steps = 50" in err and "raise --max-steps or shorten --t-end" in err
    doc = json.loads(proc.stdout)
    assert list(doc) == ["error"]
    assert doc["error"]["kind"] == "solver failed" and doc["error"]["exit_status"] == 3
    assert err.endswith(": " + doc["error"]["message"])
    assert f"{doc['error']['t_reached']:g}" == f"{t:g}"


def test_help_teaches():
    text = run("simulate", "--help").stdout
    for needle in ("--wob", "weight on bit", "stick-slip", "examples:", "units:"):
        assert needle in text
    assert "simulate" in run("--help").stdout


def _commands():
    """Every command's words, the top one's ([]) and each atlas action's included."""
    import argparse

    from pydrill.cli import build_parser

    def walk(parser, words):
        yield words
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    yield from walk(sub, [*words, name])

    return list(walk(build_parser(), []))


def help_stubs(lines: list[str], columns: int) -> list[tuple[str, str]]:
    """The lines of prose that end before a word of the next one would have filled them
    (argparse fills to COLUMNS - 2): "top_mean," alone on a line where the source broke it.
    The next line continues the paragraph when it is unindented too, or indented under a line
    that does not end in ":" (a hanging paragraph, "JSON fields: ..." then "  severity, ...");
    under a header ("examples:") an indented line is an example or a table row."""
    stubs, hanging = [], None  # hanging: the indent of the paragraph's continuation lines
    for a, b in itertools.pairwise(lines):
        lead = len(b) - len(b.lstrip())
        if not (a.strip() and b.strip()):
            hanging = None
            continue
        if not a[:1].isspace():  # a line of prose, or a header
            prose = not (a.startswith("usage:") or a.endswith(":"))
            hanging = lead if prose and lead else None
            follows = prose and (lead == 0 or hanging is not None)
        else:  # indented: within a hanging paragraph only
            follows = hanging is not None and lead == hanging
            hanging = hanging if follows else None
        if follows and len(a) + 1 + len(b.split()[0]) <= columns - 2:
            stubs.append((a, b))
    return stubs


def test_help_stubs_are_found():
    """The check below fails on the glitches it was written for (pydrill atlas query --help)."""
    glitch = [
        "JSON fields: regime, caveat and the metrics (bit_min, bit_max, bit_mean,",
        "top_mean,",
        "  severity, stuck_fraction, period, stick_events, wall_time, top_min, top_max,",
        "  bit_top_ratio) from the first initial",
        "  condition; coords, status",
    ]
    assert help_stubs(glitch, 80) == [(glitch[1], glitch[2]), (glitch[3], glitch[4])]
    kept = ["examples:", "  pydrill atlas query paper.h5", "", "usage: pydrill", "  [-h]"]
    assert help_stubs(kept, 80) == []


@pytest.mark.parametrize("columns", [60, 80, 120])
@pytest.mark.parametrize("command", _commands(), ids=lambda words: " ".join(words) or "pydrill")
def test_help_prose_fits_the_terminal_and_examples_stay_whole(
    command, columns, monkeypatch, capsys
):
    """On a narrow, an 80-column and a wide terminal no line of prose runs past it (map's
    description was one line of 404 characters) or stops short, a stub (a paragraph refilled,
    not cut line by line); an example command (indented) is kept on its one line, to copy."""
    from pydrill.cli import main

    def shown(columns: int) -> list[str]:
        monkeypatch.setenv("COLUMNS", str(columns))
        with pytest.raises(SystemExit):
            main([*command, "--help"])
        return capsys.readouterr().out.splitlines()

    lines = shown(columns)
    assert [line for line in lines if len(line) > columns and not line[:1].isspace()] == []
    assert help_stubs(lines, columns) == []
    examples = [line for line in lines if line.strip().startswith("pydrill ")]
    if command:  # the top --help lists the commands; each command's shows examples
        assert examples, "an example command in every command's --help"
    # the same lines on a terminal wide enough for any: not cut to fit
    assert [line for line in shown(400) if line.strip().startswith("pydrill ")] == examples


def test_driller_units_on_the_command_line():
    si = json.loads(
        run(
            "stability",
            "--preset",
            "real-string",
            "--wob",
            "60000",
            "--omega",
            "12.566370614359172",
            "--json",
        ).stdout
    )
    driller = json.loads(
        run(
            "stability", "--preset", "real-string", "--wob", "60kN", "--omega", "120rpm", "--json"
        ).stdout
    )
    assert driller["equilibria"][0]["torque"] == pytest.approx(si["equilibria"][0]["torque"])
    klbf = json.loads(
        run("simulate", "--wob", "0.02248klbf", "--torque", "8.3", "--t-end", "20", "--json").stdout
    )
    assert klbf["inputs"]["wob"] == pytest.approx(100.0, rel=1e-3)
    bad = run("simulate", "--wob", "3 furlong", "--torque", "8.3", check=False)
    assert bad.returncode == 2 and "not a force unit" in bad.stderr


def test_ctrl_c_in_any_command_ends_with_one_line_and_status_130(monkeypatch, capsys):
    import pydrill
    from pydrill import cli

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(pydrill, "simulate", interrupted)
    assert cli.main(["simulate", "--wob", "100", "--torque", "8.3"]) == 130
    assert capsys.readouterr().err.strip() == "pydrill simulate: interrupted"


def test_an_output_that_cannot_be_written_is_one_line_not_a_traceback(tmp_path):
    proc = run(
        "simulate", "--wob", "100", "--torque", "8.3", "--plot", "/proc/pydrill/x.png", check=False
    )
    assert proc.returncode == 2
    assert proc.stderr.startswith("pydrill simulate: error: ") and "Traceback" not in proc.stderr


def test_an_atlas_in_a_folder_that_does_not_exist_is_refused_like_every_other_output_file(
    tmp_path,
):
    """A typo in the folder made a tree of folders (at / if need be); now it is refused, as for
    every output file (--plot, atlas plot/export --out). reproduce --out DIR still makes its
    folder: it is one."""
    out = tmp_path / "new" / "dir" / "m.h5"
    spec = Path(__file__).resolve().parents[1] / "sweeps" / "minimal.toml"
    proc = run("sweep", str(spec), "--out", str(out), "--serial", check=False)
    assert proc.returncode == 2 and f"there is no folder {out.parent}" in proc.stderr
    assert not (tmp_path / "new").exists()


def test_sweep_progress_in_a_log_is_a_plain_line_now_and_then(capsys):
    from pydrill.cli_sweep_report import LogProgress, duration

    log = LogProgress(1000, every=0.0)
    log.update(250)
    log.update(750)  # finished: the summary line says the rest
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("sweep: 250/1000 points (25 %), ")
    assert lines[0].endswith(" left") and "\r" not in lines[0]
    quiet = LogProgress(1000)  # every 30 s: a short sweep prints nothing
    quiet.update(999)
    assert capsys.readouterr().err == ""
    assert [duration(x) for x in (7.4, 75, 3725)] == ["7 s", "1 min 15 s", "1 h 02 min"]


@pytest.mark.parametrize(
    "command",
    [
        ["simulate", "--wob", "100", "--torque", "8.3", "--plot"],
        ["stability", "--wob", "100", "--torque", "8.3", "--plot"],
        ["hopf", "--plot"],
        ["sweep", str(MINIMAL), "--out", "never.h5", "--plot"],
    ],
)
def test_a_figure_format_matplotlib_cannot_write_is_refused_before_any_work(tmp_path, command):
    """Refused when the command line is read: a sweep of an hour used to end in matplotlib's
    "Format 'txt' is not supported", its figure lost."""
    proc = subprocess.run(
        [*CMD, *command, str(tmp_path / "figure.txt")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=60,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "argument --plot: " in proc.stderr and "one of .png, .pdf, .svg" in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_commands_without_a_figure_do_not_load_matplotlib(tmp_path):
    """Loading the plotting stack takes longer than a simulation (0.6 s of a 0.9 s command,
    measured), so only --plot pays for it."""
    code = (
        "import sys; from pydrill.cli import main\n"
        "for argv in (['simulate', '--wob', '100', '--torque', '8.3', '--json'],\n"
        "             ['stability', '--wob', '100', '--torque', '8.3', '--json'],\n"
        f"             ['sweep', {str(MINIMAL)!r},\n"
        "              '--out', 'm.h5', '--serial', '--json']):\n"
        "    assert main(argv) == 0, argv\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib')[:3])\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[-1] == "[]"


TALLY = str(Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml")


@pytest.mark.parametrize(
    ("args", "notes"),
    [
        # bare numbers on a real string: 60 N and 573 rpm, where 60 kN and 60 rpm were meant
        (["stability", "--tally", TALLY, "--wob", "60", "--omega", "60"], ["60kN", "60rpm"]),
        (
            [
                "simulate",
                "--preset",
                "real-string",
                "--wob",
                "50",
                "--torque",
                "9kN*m",
                "--t-end",
                "5",
            ],
            ["50kN"],
        ),
        # in units, or plausible: nothing to say
        (["stability", "--tally", TALLY, "--wob", "60kN", "--omega", "60rpm"], []),
        (["stability", "--dof", "4", "--wob", "60", "--omega", "60"], []),  # laboratory scale
    ],
)
def test_a_bare_number_implausible_for_a_real_string_gets_a_note(args, notes):
    """A bare number is SI, and the command still runs as typed; stderr says what it took."""
    r = subprocess.run([*CMD, *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    said = [line for line in r.stderr.splitlines() if line.startswith("pydrill: note:")]
    assert len(said) == len(notes)
    for line, fix in zip(said, notes, strict=True):
        assert f"write {fix}" in line
