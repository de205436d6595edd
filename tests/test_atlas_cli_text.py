"""What ``atlas info`` and ``atlas query`` print for a real string: every value in its axis's
unit, the string the atlas is of, and why each steady state is stable or not."""

import json
import math
import subprocess

import h5py
import pytest
from sweeping import CMD, ROOT, SMALL

from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

TALLY = (ROOT / "examples" / "tallies" / "paper-eq53.toml").read_text()

# The paper's real string, lumped to 6 inertias, on a torque axis that reads in kN·m
FIELD = """
[model]
tally = "paper-eq53.toml"
dof = 6
[axes]
wob = ["40 kN", "80 kN"]
torque = ["6 kN·m", "9 kN·m", "12 kN·m"]
[simulation]
t_end = 30.0
initial = ["rest", "equilibrium"]
"""

# The same string held at one torque, with one parameter changed from the tally's
HELD = """
[model]
tally = "paper-eq53.toml"
dof = 6
torque = "9 kN·m"
bit_damping = 60.0
[axes]
wob = ["40 kN", "80 kN"]
[simulation]
t_end = 30.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def field(tmp_path_factory):
    out = tmp_path_factory.mktemp("field") / "field.h5"
    run_sweep(parse_spec(FIELD, tally_text=TALLY), out, serial=True)
    return out


def _run(*args: str) -> str:
    return subprocess.run([*CMD, *args], capture_output=True, text=True, check=True).stdout


def test_a_point_reads_in_its_axis_unit(field):
    """9000 N·m on an axis of 6 ... 12 kN·m was printed '9000 N·m' (its own size alone chose
    the unit), beside '80 kN' and the axis line's kN·m."""
    text = _run("atlas", "query", str(field), "--wob", "80kN", "--torque", "9 kN·m")
    assert text.splitlines()[0] == "wob = 80 kN, torque = 9 kN·m: done"
    info = _run("atlas", "info", str(field))
    assert "axis torque            3 values, 6 kN·m ... 12 kN·m" in info
    moved = _run("atlas", "query", str(field), "--wob", "80kN", "--torque", "9.4kN·m", "--nearest")
    assert "(the grid point nearest torque = 9.4 kN·m)" in moved
    off = subprocess.run(
        [*CMD, "atlas", "query", str(field), "--wob", "80kN", "--torque", "9.4kN·m"],
        capture_output=True,
        text=True,
    )
    assert off.returncode == 2
    assert "torque = 9.4 kN·m is not on the grid (nearest 9 kN·m)" in off.stderr


def test_query_says_why_each_steady_state_is_stable_or_not(field):
    """The text gave 'unstable (3)': now the count of eigenvalues with Re > 0, the spectral
    abscissa and the Hopf margin, as the JSON holds them, and the speed in rpm too."""
    seen_unstable = False
    for wob in ("40kN", "80kN"):
        for torque in ("6kN·m", "9kN·m", "12kN·m"):
            args = ["atlas", "query", str(field), "--wob", wob, "--torque", torque]
            text = _run(*args).splitlines()
            st = json.loads(_run(*args, "--json"))["stability"]
            lines = [n for n, line in enumerate(text) if "steady state Omega" in line]
            assert len(lines) == len(st["omega_eq"])
            for k, n in enumerate(lines):
                omega, count = st["omega_eq"][k], st["unstable"][k]
                head, why = text[n], text[n + 1]
                rpm = float(head.split("(")[1].split(" rpm")[0])
                assert rpm == pytest.approx(omega * 60 / (2 * math.pi), rel=1e-3)
                # the leading eigenvalues kept (4 of them): as many with Re > 0 as it counts
                right = sum(re > 0 for re, _ in st["eigenvalues"][k])
                if count == 0:
                    assert head.endswith(": stable") and right == 0
                else:
                    seen_unstable = True
                    word = "eigenvalue" if count == 1 else "eigenvalues"
                    assert head.endswith(f": unstable ({count} {word} with Re > 0)")
                    assert right == min(count, len(st["eigenvalues"][k]))
                shown = float(why.split("spectral abscissa ")[1].split(" ")[0])
                assert shown == pytest.approx(st["spectral_abscissa"][k], rel=1e-3)
                margin = float(why.split("Hopf margin ")[1].split(" ")[0])
                assert margin == pytest.approx(st["hopf_margin"][k], rel=1e-3)
                assert (margin > 0) == (count == 0)  # a negative margin: past a crossing
    assert seen_unstable  # the slow steady state of a stick-slip point


def test_info_names_the_string_its_inertias_and_what_is_held(field, tmp_path):
    held = tmp_path / "held.h5"
    run_sweep(parse_spec(HELD, tally_text=TALLY), held, serial=True)
    for path, extra in ((field, ""), (held, ", torque 9 kN·m, bit_damping 60 N·m·s/rad")):
        with h5py.File(path, "r") as f:  # the string the sweep computed with
            inertias = len(json.loads(f.attrs["params"])["base"]["inertias"])
        assert inertias == 6
        line = f"model string paper-eq53 (tally), 6 inertias{extra}; 30 s from each start"
        assert line in " ".join(_run("atlas", "info", str(path)).split())  # wrapped at 79
        model = json.loads(_run("atlas", "info", str(path), "--json"))["model"]
        assert model["string"] == "paper-eq53" and model["from"] == "tally"
        assert model["inertias"] == 6 and model["t_end"] == 30.0
    assert model["held"] == {"torque": 9000.0, "bit_damping": 60.0}


def test_info_of_a_preset_atlas_and_of_a_size_axis(tmp_path):
    small = tmp_path / "small.h5"
    run_sweep(parse_spec(SMALL), small, serial=True)
    line = "  model   preset reduced-scale, 4 inertias; 200 s from each start"
    assert line in _run("atlas", "info", str(small)).splitlines()
    sizes = SMALL.replace("dof = 4\n", "").replace("torque = [6.0, 8.3]", "dof = [3, 5]")
    sizes = sizes.replace("[model]\n", "[model]\ntorque = 8.3\n")
    out = tmp_path / "sizes.h5"
    run_sweep(parse_spec(sizes), out, serial=True)
    model = json.loads(_run("atlas", "info", str(out), "--json"))["model"]
    assert model["inertias"] is None  # an axis sets them
    line = "  model   preset reduced-scale, torque 8.3 N·m; 200 s from each start"
    assert line in _run("atlas", "info", str(out)).splitlines()


def test_holding_every_axis_but_one_draws_the_profile_along_it(field, tmp_path):
    """'--set torque=9kN·m' on a (wob, torque) atlas was refused ("no axis left to draw"):
    what it asks for is the profile along W_ob at that torque, as --profile draws it."""
    import numpy as np

    from pydrill.atlas import Atlas

    with Atlas(field) as atlas:
        fig = atlas.plot(at={"torque": 9e3})
        ax = fig.axes[0]  # the velocities; the regime strip below carries the x label
        assert "weight on bit $W_{ob}$ (kN)" in [a.get_xlabel() for a in fig.axes]
        titles = [ax.get_title(), *(t.get_text() for t in fig.texts)]
        assert any("torque = 9 kN·m" in t for t in titles), titles
        mean = atlas.sel(torque=9e3, initial="rest").bit_mean.values
        drawn = [line for line in ax.get_lines() if line.get_label().startswith("from rest")]
        assert np.allclose(drawn[0].get_ydata(), mean)
        # a map still needs two axes: with --y given, holding its only partner is refused
        with pytest.raises(ValueError, match="no axis left"):
            atlas.plot(y="wob", at={"torque": 9e3})
    out = tmp_path / "profile.png"
    text = _run("atlas", "plot", str(field), "--out", str(out), "--set", "torque=9kN·m")
    assert text.strip() == f"figure: {out}" and out.stat().st_size > 10_000


def test_info_shows_per_element_values_with_their_unit(tmp_path):
    """A list given in [model] was shown as 'inertias (3 values)' beside '3 inertias'."""
    spec = SMALL.replace("dof = 4\n", "dof = 3\ninertias = [0.5, 0.4, 0.3]\n")
    out = tmp_path / "given.h5"
    run_sweep(parse_spec(spec.replace("t_end = 200.0", "t_end = 20.0")), out, serial=True)
    text = " ".join(_run("atlas", "info", str(out)).split())
    assert "model preset reduced-scale, 3 inertias, inertias [0.5, 0.4, 0.3] kg·m²;" in text
    model = json.loads(_run("atlas", "info", str(out), "--json"))["model"]
    assert model["held"] == {"inertias": [0.5, 0.4, 0.3]} and model["inertias"] == 3


def test_an_axis_of_one_value_need_not_be_given(tmp_path):
    """'give a value for every axis; missing: depth' for an atlas whose depth axis held one
    value (the guide's way to sweep a tally string at one depth)."""
    spec = FIELD.replace('wob = ["40 kN"', 'depth = ["3000 m"]\nwob = ["40 kN"')
    out = tmp_path / "one-depth.h5"
    run_sweep(
        parse_spec(spec.replace("t_end = 30.0", "t_end = 10.0"), tally_text=TALLY), out, serial=True
    )
    args = ["atlas", "query", str(out), "--wob", "40kN", "--torque", "6kN·m"]
    text = _run(*args)
    assert text.splitlines()[0] == "depth = 3000 m, wob = 40 kN, torque = 6 kN·m: done"
    doc = json.loads(_run(*args, "--json"))
    assert doc["coords"] == {"depth": 3000.0, "wob": 40e3, "torque": 6e3}
    full = json.loads(_run(*args, "--depth", "3000m", "--json"))
    assert full["regime"] == doc["regime"] and full["bit_mean"] == doc["bit_mean"]
    with pytest.raises(KeyError, match="missing: torque"):  # more values: still asked for
        from pydrill.atlas import Atlas

        with Atlas(out) as atlas:
            atlas.value(wob=40e3)


@pytest.mark.parametrize("command", ["query", "safe", "plot"])
def test_an_axis_set_twice_is_refused(field, tmp_path, command):
    """'--set torque=8 --set torque=9' kept the last, silently."""
    args = ["atlas", command, str(field), "--set", "torque=6kN·m", "--set", "torque=9kN·m"]
    args += {"query": ["--wob", "40kN"], "plot": ["--out", str(tmp_path / "x.png")]}.get(
        command, []
    )
    proc = subprocess.run([*CMD, *args], capture_output=True, text=True)
    assert proc.returncode == 2 and not proc.stdout
    assert "--set 'torque=9kN·m': torque is given twice; give each axis once" in proc.stderr
    assert not (tmp_path / "x.png").exists()


def test_kilo_units_start_where_the_figures_do():
    """An axis of 8000 ... 9000 N·m read 'N·m' in text (kN·m from 10^4) and kN·m on its
    figure (from 5000): one threshold now, KILO."""
    from pydrill.atlas_grid import grid_unit, with_unit
    from pydrill.cli_options import KILO
    from pydrill.plot import unit_scale

    for values in ([8e3, 9e3], [4e3, 4.9e3], [6.0, 8.3], [2e4, 2e5]):
        text, factor = grid_unit("torque", values)
        assert (factor, text) == unit_scale(values, "N·m"), values
        assert (factor == 1e3) == (max(values) > KILO)
    assert with_unit("torque", 8e3) == "8 kN·m" and with_unit("wob", 4e3) == "4000 N"


def test_dry_run_times_slow_points_in_seconds(tmp_path, monkeypatch):
    """A long string's sample was printed '1.63e+04 ms each'."""
    from pydrill import cli, sweep_plan

    spec = tmp_path / "s.toml"
    spec.write_text(SMALL)
    real = sweep_plan.plan_sweep

    def slow(*args, **kwargs):
        import dataclasses

        plan = real(*args, **kwargs)
        return dataclasses.replace(
            plan, sampled=3, point_seconds=16.3, point_seconds_low=0.4, point_seconds_high=32.8
        )

    monkeypatch.setattr(sweep_plan, "plan_sweep", slow)
    import contextlib  # the CLI in this process, to see the patched plan
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert cli.main(["sweep", str(spec), "--dry-run", "--serial"]) == 0
    line = next(x for x in out.getvalue().splitlines() if x.startswith("  timed"))
    assert (
        line
        == "  timed   3 of the 6 points to compute: 16.3 s each on one core (95 %: 0.4 ... 32.8 s)"
    )


def test_info_beside_a_journal_says_whether_a_sweep_writes_it_and_names_the_atlas(tmp_path):
    """'a sweep into this atlas is running or was stopped; pydrill sweep SPEC.toml --out
    ATLAS.h5 --resume' named neither the atlas nor which it was: a sweep holding the atlas's
    lock is named (its process), else the resume command names the atlas as given."""
    import os
    from pathlib import Path

    from pydrill.atlas_lock import writer_lock

    out = tmp_path / "my atlas.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    Path(str(out) + ".journal").write_text("")  # what a sweep stopped (kill -9) leaves

    def last_line():
        proc = subprocess.run([*CMD, "atlas", "info", str(out)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        return proc.stdout.splitlines()[-1].strip()

    stopped = last_line()
    assert f"pydrill sweep SPEC.toml --out '{out}' --resume" in stopped
    assert stopped.startswith("a sweep into this atlas was stopped")
    with writer_lock(out):  # as a running sweep holds it
        running = last_line()
    assert running.startswith("a sweep is writing this atlas now (process ")
    assert f"process {os.getpid()} " in running and "--resume" not in running


# Three axes: a map holds one of them, a profile two.
CUBE = SMALL.replace("[axes]\n", "[axes]\nmu_static = [0.85, 0.8, 0.9]\n").replace(
    "t_end = 200.0", "t_end = 50.0"
)


def test_atlas_plot_says_which_axes_it_holds_at_their_first_value_unasked(tmp_path):
    """A map of a three-axis atlas drew one slice of it, at the first value of the third axis,
    without a word: a newcomer's first map of a depth atlas was its least telling (4 kN·m,
    stuck almost everywhere). Each axis held unasked is named with the value the file holds
    first; none held by --set, or drawn."""
    out = tmp_path / "cube.h5"
    run_sweep(parse_spec(CUBE), out, serial=True)
    with h5py.File(out, "r") as f:
        first = {n: float(f[n][0]) for n in ("mu_static", "wob", "torque")}

    def notes(*args):
        proc = [*CMD, "atlas", "plot", str(out), "--out", str(tmp_path / "f.png"), *args]
        run = subprocess.run(proc, capture_output=True, text=True, check=True)
        return [line for line in run.stderr.splitlines() if " at its first value, " in line]

    (note,) = notes()  # a map on the first two axes (mu_static, wob): torque held
    assert note.startswith("pydrill atlas plot: note: holds torque at its first value, ")
    assert f"value, {first['torque']:g} N·m, of 2 (" in note and "--set torque=VALUE" in note
    assert notes("--set", "torque=8.3") == []
    assert notes("--x", "wob", "--y", "torque") != []  # mu_static now held
    profile = notes("--profile", "--x", "wob")
    held = {line.split(": note: holds ")[1].split(" ")[0] for line in profile}
    assert held == {"mu_static", "torque"}
