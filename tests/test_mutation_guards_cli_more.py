"""The rest of the command line's output layer that no test pinned, against h5py, by hand and by
the documented rules.

Found by a mutation audit (after tests/test_mutation_guards_cli_atlas.py and _cli_reports.py):
what an atlas's spec holds (a torque to 6 digits, its dof), a list of four per-element values
shown, a depth in m, the kilo-units of a negative force, the rows with a safe window counted,
the fastest steady state's verdict, a branch's stability in part, the sweep's failure message
and its next step holding a torque axis in kN·m.
"""

import json
import math
import shlex
from types import SimpleNamespace

import h5py
import numpy as np
import pytest
from cli_running import ok_text, run
from sweeping import ROOT

from pydrill import atlas_format as fmt
from pydrill import cli_sweep_report as report
from pydrill import preset
from pydrill.bifurcation import branch
from pydrill.cli_atlas_query import axis_values
from pydrill.cli_bifurcation import _no_points
from pydrill.cli_options import kilo, shown
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# a spec holding a torque, a dof and four inertias (one per element); two rows of mu_static
SPEC = """
[model]
preset = "reduced-scale"
dof = 4
inertias = [0.5, 0.4, 0.3, 0.2]
torque = 8.3
[axes]
mu_static = [0.8, 0.9]
wob = [40.0, 100.0, 200.0]
[simulation]
t_end = 5.0
initial = ["rest", "equilibrium"]
"""

# a tally's string held at a depth
DEPTH = """
[model]
tally = "ROOT/examples/tallies/paper-eq53.toml"
dof = 2
depth = "3000 m"
torque = "9 kN·m"
[axes]
wob = ["40 kN"]
[simulation]
t_end = 5.0
initial = ["rest"]
"""

S, X = fmt.REGIMES["steady"], fmt.REGIMES["stick-slip"]


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    """Codes overwritten: mu_static 0.8 safe at wob 40 and 100 (a window), 0.9 safe nowhere;
    at (0.9, 200 N) steady from both starts, its fastest steady state unstable (1 eigenvalue)
    and a slower one stable."""
    path = tmp_path_factory.mktemp("climore") / "a.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    with h5py.File(path, "r+") as f:
        regime = np.full(f["regime"].shape, X, dtype=np.int8)
        regime[0, :2] = regime[1, 2] = S
        f["regime"][...] = regime
        f["status"][...] = fmt.STATUS["done"]
        f["unstable"][...] = 0
        f["unstable"][1, 2] = [1, 0]
        f["omega_eq"][...] = np.where(np.isnan(f["omega_eq"][...]), 3.0, f["omega_eq"][...])
        f["omega_eq"][1, 2] = [5.0, 2.0]
    return path


def test_a_value_the_spec_holds_is_left_out_to_six_digits_and_its_dof_too(atlas, capsys):
    base = ["atlas", "query", atlas, "--set", "mu_static=0.8", "--wob", 100]
    plain = ok_text(capsys, *base)
    # the held torque and dof asked as the spec holds them: the same point, said the same
    assert ok_text(capsys, *base, "--torque", 8.3 * (1 + 1e-8), "--dof", 4) == plain
    # 0.6 % off the held 8.3 N·m (8.35 prints as another number): refused, named
    code, _, err = run(capsys, *base, "--torque", 8.35)
    assert code == 2 and "its spec holds torque = 8.3 N·m at every point, not 8.35 N·m" in err
    code, _, err = run(capsys, *base, "--dof", 5)
    assert code == 2 and "its spec holds dof = 4 at every point, not 5" in err


def test_safe_counts_the_rows_with_a_window_and_query_says_why_not(atlas, capsys):
    with h5py.File(atlas, "r") as f:  # by hand: every start steady, the fastest stable
        safe = np.all(f["regime"][...] == S, axis=-1) & (f["unstable"][..., 0] == 0)
    rows = int(np.sum(safe.any(axis=1)))
    assert rows == 1
    out = ok_text(capsys, "atlas", "safe", atlas)
    assert f"  {rows} of 2 have a safe window" in out.splitlines()
    # steady from both starts, not safe: the fastest steady state (not the slowest) is why
    out = ok_text(capsys, "atlas", "query", atlas, "--set", "mu_static=0.9", "--wob", 200)
    assert "  safe: no (the fastest steady state is unstable)" in out.splitlines()


def test_info_shows_four_per_element_values_and_a_depth_in_metres(atlas, tmp_path, capsys):
    out = ok_text(capsys, "atlas", "info", atlas)
    assert "inertias [0.5, 0.4, 0.3, 0.2] kg·m²" in out  # four: each shown, not "as given"
    path = tmp_path / "depth.h5"
    run_sweep(parse_spec(DEPTH.replace("ROOT", str(ROOT))), path, serial=True)
    d = json.loads(ok_text(capsys, "atlas", "info", path, "--json"))
    assert d["units"]["model"]["held"] == {"torque": "N·m", "depth": "m"}
    text = ok_text(capsys, "atlas", "info", path)
    assert "depth 3000 m;" in text
    assert f"{path}: 1 point, pydrill" in text  # one grid point ("1 points" once)
    assert f"{atlas}: 6 points, pydrill" in out


def test_kilo_units_go_by_the_size_of_a_force_not_its_sign(capsys):
    # -6 kN (a pull) is a real string's force as 6 kN is; 4 kN either way is not
    assert kilo(-6000.0) and kilo(6000.0) and not kilo(-4000.0, 4000.0, math.nan)
    assert shown(-6000.0, "N", True) == "-6 kN" and shown(6000.0, "N m", True) == "6 kN m"
    assert shown(4000.0, "N", False) == "4000 N"
    # simulate driven backwards at -6 kN m (W_ob 4 kN alone would stay in N): all in kN m,
    # T_s = mu_s W_ob R_b by hand
    p = preset("reduced-scale")
    t_s = p.mu_static * 4000.0 * p.bit_radius
    out = ok_text(capsys, "simulate", "--wob", 4000, "--torque", -6000, "--t-end", 1)
    assert f"static torque   T_s = {t_s / 1e3:.4g} kN m (surface torque -6 kN m)" in out


def test_a_branch_without_points_says_how_much_of_it_is_stable():
    """Counted by hand: no unstable sample, all, or some (a branch whose ends fall either side
    of a boundary the detection did not place)."""
    omega = np.array([1.0, 2.0, 4.0])
    said = [
        _no_points(SimpleNamespace(omega=omega, unstable=np.array(u)))
        for u in ([0, 0, 0], [2, 2, 1], [0, 0, 2])
    ]
    assert [s.split("steady state is ")[1] for s in said] == [
        "stable along all of it",
        "unstable along all of it",
        "stable in part",
    ]
    assert said[0].startswith("no Hopf or fold point on this branch (Omega 1 ... 4 rad/s)")


def test_sweep_shows_a_failure_message_whole_up_to_300_characters(capsys):
    run_ = dict(failed_in_atlas=1, points=4, all_failed=False, atlas="a.h5")
    for n in (100, 300):
        message = "m" * (n - 1) + "."
        assert report.failures(SimpleNamespace(**run_, first_failure=message)) == 0
        # whole, to its last character (a cut one ends in "..." before the newline)
        assert f"The first: {message}\n" in capsys.readouterr().err


def test_next_step_holds_a_torque_axis_at_its_middle_value_in_kn_m(capsys):
    """The held value, read back as ``--set`` reads it, is the grid's middle torque (9000 N·m
    written as 9 kN·m, not 9000 kN·m)."""
    spec = SimpleNamespace(
        record={"stability": True},
        axes={"wob": [1e4, 2e4], "depth": [1000.0, 2000.0], "torque": [6e3, 9e3, 12e3]},
    )
    args = SimpleNamespace(json=False, plot="x.png", part=None)
    report.next_steps(args, SimpleNamespace(all_failed=False, atlas="a.h5"), spec)
    err = capsys.readouterr().err
    line = next(s for s in err.splitlines() if "atlas safe" in s)
    words = shlex.split(line.split("#")[0].removeprefix("next:"))
    held = [words[k + 1] for k, w in enumerate(words) if w == "--set"]
    assert held == ["torque=9kN·m"]
    assert axis_values(held) == {"torque": pytest.approx(9000.0, rel=1e-12)}


def test_bifurcation_in_kn_when_the_points_weights_are_big_though_the_torque_is_not(capsys):
    """u = 4 kN·m held (under the 5 kN threshold by itself), the branch's Hopf and fold points
    at W_ob near 36 kN: a real string's numbers, so all in kN and kN m (as the API's / 1e3)."""
    b = branch(preset("real-string"), vary="wob", torque=4000.0)
    assert b.points and all(pt.wob > 5e3 for pt in b.points)
    out = ok_text(
        capsys, "bifurcation", "--preset", "real-string", "--vary", "wob", "--torque", 4000
    )
    lines = out.splitlines()
    assert lines[0].endswith("steady states as wob varies at u = 4 kN m")
    assert "wob (kN) torque (kN m)" in lines[1]
    for row, pt in zip(lines[2:], b.points, strict=True):
        _, wob, torque, *_ = row.split()
        assert float(wob) == pytest.approx(pt.wob / 1e3, rel=1e-7)
        assert float(torque) == pytest.approx(4.0, rel=1e-12)
