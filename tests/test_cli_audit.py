"""Command-line edges found by a newcomer's audit: options that were silently ignored, units
that meant something else than the help said, figures of nothing, outputs that could not be
written found out only after the work."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from sweeping import SMALL

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
CMD = [sys.executable, "-m", "pydrill"]


def run(*args):
    return subprocess.run([*CMD, *map(str, args)], capture_output=True, text=True)


def refused(proc, *words):
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    assert not proc.stdout and "Traceback" not in proc.stderr
    for w in words:
        assert w in proc.stderr, proc.stderr
    return True


@pytest.mark.parametrize(
    "args, words",
    [
        # simulate took --depth/--lump without a tally and ran the laboratory rig
        (("simulate", "--depth", "3000m", "--wob", "100", "--torque", "8.3"), ["--depth needs"]),
        (("simulate", "--lump", "5", "--wob", "100", "--torque", "8.3"), ["--lump needs"]),
        # the branch varies W_ob: a fixed --wob beside it was dropped
        (
            ("bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1", "--wob", "100"),
            ["--wob is not allowed with --vary wob"],
        ),
        (
            ("bifurcation", "--dof", "2", "--vary", "torque", "--wob", "100", "--torque", "8"),
            ["--torque is not allowed with --vary torque"],
        ),
        # options of the check alone, with no check
        (("map", "--dof", "4", "--t-end", "50"), ["--t-end needs --check"]),
        (("window", PAPER, "--depth", "3000m", "--t-end", "5"), ["--t-end needs --check"]),
        (("window", PAPER, "--depth", "3000m", "--check-dof", "12"), ["--check-dof needs --check"]),
    ],
)
def test_options_that_would_be_ignored_are_refused(args, words):
    assert refused(run(*args), *words)


def test_a_bare_weight_on_bit_in_window_is_kilonewtons_as_the_help_says():
    def at_wob(text):
        proc = run("window", PAPER, "--depth", "3000m", "--at-wob", text, "--json")
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout)

    bare, with_unit = at_wob("60,20"), at_wob("60kN,20000N")
    assert bare["at_wob"] == with_unit["at_wob"] == [60e3, 20e3]
    assert bare["windows"][0]["rpm_min"] == with_unit["windows"][0]["rpm_min"]
    assert run("window", PAPER, "--depth", "3000m", "--wob-max", "0").returncode == 2


def test_no_figure_is_written_where_there_is_nothing_to_draw(tmp_path):
    png = tmp_path / "stab.png"
    proc = run("stability", "--dof", "4", "--wob", "150", "--torque", "8.3", "--plot", png)
    assert refused(proc, "no steady rotation", "no figure")
    assert not png.exists()
    # Without --plot the same point is a verdict, not an error.
    assert run("stability", "--dof", "4", "--wob", "150", "--torque", "8.3").returncode == 0


def test_an_output_that_cannot_be_written_is_refused_before_the_work(tmp_path):
    blocker = tmp_path / "sim.json"
    blocker.write_text("{}")
    proc = run("simulate", "--wob", "100", "--torque", "8.3", "--plot", blocker / "a.png")
    assert refused(proc, "is a file, not a directory")
    spec = tmp_path / "one.toml"  # W_ob swept, the torque held fixed: one axis
    spec.write_text(
        SMALL.replace("torque = [6.0, 8.3]\n", "").replace("dof = 4", "dof = 4\ntorque = 8.3")
    )
    out = tmp_path / "one.h5"
    # one axis: the sweep draws its profile (it was refused)
    proc = run("sweep", spec, "--out", out, "--serial", "--plot", tmp_path / "map.png")
    assert proc.returncode == 0 and (tmp_path / "map.png").stat().st_size > 20_000, proc.stderr
    assert proc.stdout.endswith(f"figure: {tmp_path / 'map.png'}\n")
    proc = run("sweep", spec, "--out", blocker / "x.h5", "--serial")
    assert refused(proc, "--out", "is a file, not a directory")


def test_export_onto_the_atlas_itself_is_refused(tmp_path):
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    out = tmp_path / "a.nc"
    run_sweep(parse_spec(SMALL.replace("t_end = 200.0", "t_end = 20.0")), out, serial=True)
    before = out.read_bytes()
    assert refused(run("atlas", "export", out, "--out", out), "is the atlas itself")
    assert out.read_bytes() == before


def test_simulate_takes_max_steps_as_its_solver_message_advises():
    proc = run("simulate", "--wob", "100", "--torque", "8.3", "--max-steps", "1000")
    assert proc.returncode == 3 and "--max-steps = 1000" in proc.stderr
    assert "--max-steps" in run("simulate", "--help").stdout


@pytest.mark.parametrize(
    "args, regime, note",
    [
        # 3 s of a 17.5 s stick-slip cycle read as an oscillation, and 0.3 us as steady: the
        # verdicts stay what the window shows, but the note says the window cannot tell.
        (["--window", "0.01"], "oscillation", "shorter than the string's slowest period"),
        (["--window", "1e-9"], "steady", "shorter than the string's slowest period"),
        # 18 s: the first break-away, no second stick yet.
        (["--t-end", "18"], "stick-slip", "broke free once"),
        ([], "stick-slip", None),  # 300 s, window 150 s: judged, no caveat
    ],
)
def test_a_verdict_from_too_little_of_the_run_carries_a_note(args, regime, note):
    proc = run("simulate", "--wob", "100", "--torque", "8.3", *args, "--json")
    data = json.loads(proc.stdout)
    assert data["regime"] == regime
    if note is None:
        assert data["note"] is None
    else:
        assert note in data["note"]


@pytest.mark.parametrize(
    "args, words",
    [
        # argparse took "-1e9" and "-1,1,1" for options: "expected one argument"
        (("simulate", "--wob", "-1e9", "--torque", "8.3"), ["--wob must be a finite number > 0"]),
        (("simulate", "--wob", "100", "--torque", "8.3", "--dampings", "-1,1,1"), ["dampings[0]"]),
    ],
)
def test_a_negative_value_after_a_space_reaches_the_range_check(args, words):
    assert refused(run(*args), *words)


def test_a_depth_axis_without_a_tally_says_what_it_needs(tmp_path):
    spec = tmp_path / "d.toml"
    spec.write_text(
        '[model]\npreset = "reduced-scale"\ndof = 4\ntorque = 8.3\n'
        "[axes]\ndepth = [1000.0, 2000.0]\nwob = [50.0, 100.0]\n"
    )
    assert refused(run("sweep", spec, "--dry-run"), "axes.depth: needs a tally string")


def test_a_bad_value_is_one_line_and_a_malformed_command_shows_the_usage():
    bad_value = run("simulate", "--wob", "-5", "--torque", "8.3")
    assert refused(bad_value, "--wob must be a finite number > 0")
    assert bad_value.stderr.count("\n") == 1  # not the ten-line usage block first
    missing = run("simulate", "--torque", "8.3")
    assert refused(missing, "the following arguments are required: --wob", "usage: pydrill")


def test_a_bare_weight_on_bit_too_large_for_kilonewtons_is_refused():
    # 20000 meant in newtons would otherwise be a 20 MN column needing 18766 rpm
    for option in ("--at-wob", "--wob-max"):
        proc = run("window", PAPER, "--depth", "3000m", option, "20000")
        assert refused(proc, "bare numbers are kN", "20000N")


def _strict(text):
    def refuse(name):
        raise AssertionError(f"{name} in --json output: not JSON")

    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize(
    "args",
    [
        ("simulate", "--wob", "100", "--torque", "8.3", "--t-end", "20"),
        ("stability", "--wob", "100", "--torque", "8.3"),
        ("hopf", "--dof", "4"),
        ("bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1"),
        ("map", "--dof", "2"),
        ("string", PAPER, "--depth", "3000m"),
    ],
    ids=lambda a: a[0],
)
def test_every_json_output_is_one_indented_strict_document(args):
    # bifurcation, map and string printed one long line while the others were indented
    proc = run(*args, "--json")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("{\n  "), proc.stdout[:80]
    assert isinstance(_strict(proc.stdout), dict)


def test_sweep_and_atlas_json_are_indented_too(tmp_path):
    spec, out = tmp_path / "s.toml", tmp_path / "s.h5"
    spec.write_text(SMALL)
    sweep = run("sweep", spec, "--out", out, "--serial", "--json")
    assert sweep.returncode == 0, sweep.stderr
    for proc in (
        sweep,
        run("sweep", spec, "--dry-run", "--json"),
        run("atlas", "info", out, "--json"),
        run("atlas", "query", out, "--nearest", "--wob", "100", "--torque", "8.3", "--json"),
    ):
        assert proc.returncode == 0, proc.stderr
        assert proc.stdout.startswith("{\n  "), proc.stdout[:80]
        _strict(proc.stdout)


@pytest.mark.parametrize(
    "option, words",
    [
        (("--window", "1.5"), "--window = 1.5 is not allowed: need 0 < --window <= 1"),
        (("--n-out", "1"), "--n-out = 1 is not allowed: need an integer 2 ... 1e8"),
        (("--max-steps", "0"), "--max-steps = 0 is not allowed: need an integer 1 ... 1e12"),
        (("--rtol", "2"), "--rtol = 2 is not allowed: need "),
    ],
)
def test_simulate_errors_name_the_option_as_typed_with_a_sensible_range(option, words):
    """They said window_fraction, n_out and max_steps, and a range up to 4611686018427387904."""
    proc = run("simulate", "--wob", "100", "--torque", "8.3", *option)
    assert refused(proc, words)
    for internal in ("window_fraction", "n_out", "max_steps", "4611686018427387904"):
        assert internal not in proc.stderr


def test_simulate_solver_failure_names_the_options_to_change():
    proc = run("simulate", "--wob", "100", "--torque", "8.3", "--t-end", "1e4", "--max-steps", 50)
    assert proc.returncode == 3, proc.stderr
    assert "raise --max-steps or shorten --t-end" in proc.stderr and "max_steps" not in proc.stderr


def test_a_reproduce_out_that_is_a_file_is_one_line_naming_the_option(tmp_path):
    existing = tmp_path / "small.toml"
    existing.write_text("")
    proc = run("reproduce", "--out", existing, "--quick")
    assert refused(proc, f"--out {existing}: a file of that name exists; give a folder")
    assert "Errno" not in proc.stderr and proc.stderr.count("\n") == 1


@pytest.mark.parametrize(
    "args, option",
    [
        (("simulate", "--wob", "100", "--torque", "8.3", "--plot", "/proc/x.png"), "--plot"),
        (("atlas", "export", "ATLAS", "--out", "/proc/x.csv"), "--out"),
    ],
)
def test_an_output_the_os_refuses_is_one_line_naming_the_option_and_path(tmp_path, args, option):
    """They said "[Errno 2] No such file or directory: '/proc/x.png'"."""
    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    atlas = tmp_path / "small.h5"
    if "ATLAS" in args:
        run_sweep(parse_spec(SMALL.replace("t_end = 200.0", "t_end = 10.0")), atlas, serial=True)
    proc = run(*[atlas if a == "ATLAS" else a for a in args])
    path = args[-1]
    assert proc.returncode == 2 and "Errno" not in proc.stderr, proc.stderr
    assert proc.stderr.startswith(f"pydrill {args[0]}")
    assert option in proc.stderr and path in proc.stderr and proc.stderr.count("\n") == 1


def test_simulate_prints_its_results_before_saying_its_figure_could_not_be_saved(
    monkeypatch, capsys, tmp_path
):
    from pydrill import cli, plot

    def refuse(fig, path):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(plot, "save", refuse)
    png = tmp_path / "x.png"
    assert cli.main(["simulate", "--wob", "100", "--torque", "8.3", "--plot", str(png)]) == 2
    out, err = capsys.readouterr()
    assert out.startswith("regime          stick-slip") and "figure" not in out
    assert err == f"pydrill simulate: error: --plot {png}: Permission denied\n"
    assert cli.main(["simulate", "--wob", "100", "--torque", "8.3", "--plot", str(png), "--json"])
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert data["regime"] == "stick-slip" and "plot" not in data and "--plot" in err


@pytest.mark.parametrize(
    "args",
    [
        ("simulate", "--wob", "100", "--torque", "8.3", "--plot", "OUT.png"),
        ("atlas", "export", "ATLAS", "--out", "OUT.csv"),
        ("atlas", "plot", "ATLAS", "--out", "OUT.png"),
        ("sweep", ROOT / "sweeps" / "minimal.toml", "--out", "OUT.h5", "--serial"),
    ],
)
def test_an_output_file_in_a_folder_that_does_not_exist_is_refused_and_no_folder_made(
    tmp_path, args
):
    """--plot /nonexistent/dir/x.png made /nonexistent/dir."""
    atlas = tmp_path / "a.h5"
    if "ATLAS" in args:
        (tmp_path / "a.h5").write_bytes(b"")  # refused before it is read
    missing = tmp_path / "no" / "such"
    argv = [atlas if a == "ATLAS" else missing / a if str(a).startswith("OUT") else a for a in args]
    proc = run(*argv)
    assert refused(proc, f"there is no folder {missing}; make it first")
    assert not (tmp_path / "no").exists()


def test_sweeping_again_into_a_complete_atlas_says_it_is_complete(tmp_path):
    """It said "use --resume to complete it" of an atlas with nothing left to complete."""
    spec, out = ROOT / "sweeps" / "minimal.toml", tmp_path / "m.h5"
    assert run("sweep", spec, "--out", out, "--serial", "--no-progress").returncode == 0
    before = out.read_bytes()
    proc = run("sweep", spec, "--out", out, "--serial")
    assert refused(proc, f"{out} already holds this sweep, complete: 57 points; nothing to resume")
    assert "delete it or give another --out" in proc.stderr and "complete it" not in proc.stderr
    assert out.read_bytes() == before
    again = run("sweep", spec, "--out", out, "--serial", "--resume", "--no-progress")
    assert again.returncode == 0 and "0 computed now" in again.stdout


@pytest.mark.parametrize(
    "command, words",
    [
        (
            ["simulate"],
            [
                "relative tolerance (default 1e-8;",
                "absolute tolerance (rad and rad/s; default 1e-8;",
            ],
        ),
        (["simulate"], ["number of output times (default 3001; 2 ... 1e8)", "at most 1e12"]),
        (["bifurcation"], ["where W_ob reaches 0; with --vary torque, 40)"]),
        (["map"], ["(K <= 40; default 0"]),
        (["window"], ["(K <= 20; default 0"]),
        (["atlas", "plot"], ["--initial {rest,equilibrium}"]),
    ],
)
def test_help_shows_defaults_limits_and_choices(command, words):
    """--rtol, --atol, --n-out and bifurcation --omega-max showed no default; the limits of
    map/window --check were found out by trying; atlas plot --initial listed no choices."""
    proc = subprocess.run(
        [*CMD, *command, "--help"],
        capture_output=True,
        text=True,
        env={**os.environ, "COLUMNS": "200"},
    )
    assert proc.returncode == 0
    for w in words:
        assert w in proc.stdout, proc.stdout


@pytest.mark.parametrize(
    "args, words",
    [
        (("map", "--check", "41"), "argument --check: --check = 41 is not allowed"),
        (("window", PAPER, "--check", "21"), "argument --check: --check = 21 is not allowed"),
    ],
)
def test_check_beyond_its_limit_is_refused_when_read(args, words):
    assert refused(run(*args), words)


def test_the_time_reproduce_takes_is_stated_in_one_place():
    """The README said 56 s, reproduce --help about 75 s and tools/main.sh about 75 s: the
    time measured is the README's alone (its run), the others say roughly what to expect."""
    import re

    proc = subprocess.run([*CMD, "reproduce", "--help"], capture_output=True, text=True)
    assert proc.returncode == 0
    time_part = proc.stdout.partition("time:")[2].partition("examples:")[0]
    assert "a minute or two on 2 cores" in " ".join(time_part.split()), time_part
    assert not re.search(r"\d\s*s\b", time_part), time_part
    main_sh = (ROOT / "tools" / "main.sh").read_text()
    assert not re.search(r"\d\s*s\b", main_sh.partition("pydrill reproduce")[0].split("\n\n")[-1])
    readme = (ROOT / "README.md").read_text()
    section = readme.partition("## Reproducing the paper")[2].partition("\n## ")[0]
    shown = re.findall(r"paper/report\.md: \d+ figures, (\d+) s", section)
    assert len(shown) == 1, "the README shows one run of reproduce, with its time"
    assert "from scratch on 2 cores" in " ".join(section.split())
    scratch = [m for m in re.findall(r"(\d+) s\b", section) if m == shown[0]]
    assert len(scratch) == 1, "the time measured is given once, in the run shown"


def test_no_progress_drops_the_progress_not_the_notices(tmp_path):
    """--no-progress once silenced where the sweep ran too (and, with --dashboard, the link
    the help promises): a batch log then showed nothing while a sweep waited for workers."""
    spec, out = ROOT / "sweeps" / "minimal.toml", tmp_path / "m.h5"
    proc = run("sweep", spec, "--out", out, "--workers", "1", "--no-progress")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert re.fullmatch(r"sweep: 1 Dask worker, scheduler tcp://\S+", lines[0])
    # then only what to run next (a notice too), no progress
    assert lines[1].startswith(f"next: pydrill atlas safe {out}"), lines
    assert len(lines) == 3 and f"pydrill atlas plot {out} --out" in lines[2], lines
