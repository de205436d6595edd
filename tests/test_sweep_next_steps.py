"""What ``pydrill sweep`` says after a complete sweep: the commands to run next (on stderr,
a line each, the command first). Each command it names must run as named, and give what the
line says: the safe windows (one row per value of one other axis, the rest held at a grid
value), and a regime map."""

import shlex
import subprocess

import h5py
import pytest
from sweeping import CMD, ROOT

TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"

# Three axes: one row per (depth, torque) pair without --set, a wall of lines on a real grid.
SPEC = f"""
[model]
tally = "{TALLY}"
dof = 6
[axes]
depth = ["1000 m", "3000 m"]
wob = ["40 kN", "80 kN"]
torque = ["6 kN·m", "9 kN·m", "12 kN·m"]
[simulation]
t_end = 50.0
initial = ["rest"]
"""


def _sweep(tmp_path, text, *options):
    spec = tmp_path / "study.toml"
    spec.write_text(text)
    out = tmp_path / "my study.h5"  # a space: the commands named must quote it
    proc = subprocess.run(
        [*CMD, "sweep", str(spec), "--out", str(out), "--serial", *options],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    return out, proc


def _next(stderr):
    """The commands of the ``next:`` lines, each split as a shell would."""
    lines = stderr.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("next: "))
    block = [lines[first][len("next: ") :]]
    block += [line[6:] for line in lines[first + 1 :] if line.startswith("      pydrill")]
    return [shlex.split(line, comments=True) for line in block]


def test_a_finished_sweep_names_the_safe_windows_and_a_map_and_they_run(tmp_path):
    out, proc = _sweep(tmp_path, SPEC)
    assert "next:" not in proc.stdout  # the stdout summary stays as scripts read it
    safe, plot = _next(proc.stderr)
    assert safe[:4] == ["pydrill", "atlas", "safe", str(out)]
    assert plot[:4] == ["pydrill", "atlas", "plot", str(out)]
    # The safe windows, as named: one row per depth, the torque held at a grid value.
    run = subprocess.run([*CMD, *safe[1:]], capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    with h5py.File(out, "r") as f:
        depths, torques = f["depth"][...], f["torque"][...]
    rows = [line for line in run.stdout.splitlines() if "depth = " in line]
    assert len(rows) == len(depths)
    held = safe[safe.index("--set") + 1]
    assert held.startswith("torque=") and held.endswith("kN·m")
    assert float(held[len("torque=") : -len("kN·m")]) * 1e3 in torques.tolist()
    # The map, as named.
    figure = tmp_path / plot[plot.index("--out") + 1]
    run = subprocess.run([*CMD, *plot[1:]], capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_without_stability_no_safe_windows_are_offered_and_a_plot_drawn_is_not_offered(tmp_path):
    text = SPEC + "[record]\nstability = false\n"
    out, proc = _sweep(tmp_path, text, "--plot", "map.png")
    (info,) = _next(proc.stderr)  # the map is drawn: only what the atlas holds is offered
    assert info[:3] == ["pydrill", "atlas", "info"]
    run = subprocess.run([*CMD, *info[1:]], capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0 and "12 points" in run.stdout
    # as atlas safe would have refused it
    refused = subprocess.run([*CMD, "atlas", "safe", str(out)], capture_output=True, text=True)
    assert refused.returncode == 2 and "did not record stability" in refused.stderr


@pytest.mark.parametrize("option", ["--json"])
def test_json_output_says_nothing_next(tmp_path, option):
    _, proc = _sweep(tmp_path, SPEC, option)
    assert "next:" not in proc.stderr and "next:" not in proc.stdout


def test_a_plot_of_a_three_axis_sweep_says_which_slice_it_draws(tmp_path):
    """sweep --plot of (depth, wob, torque) drew the map at the first torque without a word."""
    out, proc = _sweep(tmp_path, SPEC, "--plot", "map.png")
    with h5py.File(out, "r") as f:
        torques = f["torque"][...]
    (note,) = [line for line in proc.stderr.splitlines() if "the map holds" in line]
    assert f"the map holds torque at its first value, {torques[0] / 1e3:g} kN·m, of 3" in note
    assert f"'pydrill atlas plot {out} --out FILE.png --set torque=VALUE'" in note
