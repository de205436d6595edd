"""A drilling engineer's audit of the single-run commands on a real string: a string given in kN
and kN·m is reported in kN and kN·m (not 9000 N·m beside 80 kN), and a tally's run says which
string its file and depth made. Values are checked against the tally's own constants and the
--json output, converted here."""

import json
import re
from pathlib import Path

import pytest

from pydrill import cli, load_tally

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
# paper-eq53.toml: mu_static = 0.8, a 12.25 in bit
MU_S, R_B = 0.8, 12.25 * 0.0254 / 2


def run(capsys, *args):
    code = cli.main([str(a) for a in args])
    out = capsys.readouterr()
    assert code == 0, out.err
    return out.out


def field(text, name):
    """The text after ``name`` on its line."""
    (line,) = [x for x in text.splitlines() if x.startswith(name)]
    return line[len(name) :].strip()


def test_simulate_a_real_string_gives_torques_in_kilonewton_metres(capsys):
    args = ["simulate", "--tally", PAPER, "--depth", "3000m", "--dof", "12"]
    args += ["--wob", "30kN", "--torque", "3.8kN*m", "--t-end", "20"]
    text = run(capsys, *args)
    t_s = MU_S * 30e3 * R_B  # 3734 N·m: under 5000 N·m, yet beside 30 kN it is in kN·m
    want = f"T_s = {t_s / 1e3:.4g} kN m (surface torque {3800 / 1e3:g} kN m)"
    assert field(text, "static torque") == want
    data = json.loads(run(capsys, *args, "--json"))
    assert data["static_torque"] == pytest.approx(t_s)


def test_simulate_a_laboratory_string_keeps_newton_metres(capsys):
    text = run(capsys, "simulate", "--dof", "4", "--wob", "100", "--torque", "8.3", "--t-end", "20")
    # the preset's bit: mu_s = 0.8, R_b = 0.1 m
    want = f"T_s = {0.8 * 100 * 0.1:.4g} N m (surface torque 8.3 N m)"
    assert field(text, "static torque") == want


def test_simulate_a_tally_names_the_string_its_file_and_depth_made(capsys, tmp_path):
    args = ["--wob", "60kN", "--torque", "9kN*m", "--t-end", "20"]
    text = run(capsys, "simulate", "--tally", PAPER, "--depth", "3000m", *args)
    tally = load_tally(PAPER).at_depth(3000.0)
    dof = len(tally.to_params().inertias)
    assert field(text, "string") == f"{tally.name} at {tally.length:.1f} m, {dof} inertias"
    data = json.loads(
        run(capsys, "simulate", "--tally", PAPER, "--depth", "3000m", *args, "--json")
    )
    assert data["string"] == f"{tally.name} at {tally.length:.1f} m"
    assert data["inputs"]["dof"] == dof
    # a joint length typed "9 mm" for "9 m" makes a 50 m string: the first line says so
    typo = tmp_path / "typo.toml"
    typo.write_text(PAPER.read_text().replace('length = "9 m"', 'length = "9 mm"'))
    text = run(capsys, "simulate", "--tally", typo, *args)
    metres = float(re.search(r" at ([\d.]+) m,", field(text, "string")).group(1))
    assert metres == pytest.approx(100 * 0.009 + load_tally(PAPER).bha_length, abs=0.05)


def test_simulation_figure_of_a_real_string_has_one_torque_unit():
    import pydrill
    from pydrill.plot import simulation_figure

    p = load_tally(PAPER).at_depth(3000.0).to_params(dof=12)
    r = pydrill.simulate(p, wob=30e3, torque=3800.0, t_end=20.0)
    fig = simulation_figure(r)
    assert "$u$ = 3.8 kN·m" in fig._suptitle.get_text()  # was "u = 3800 N·m" beside 30 kN
    assert fig.axes[1].get_ylabel() == "torque at the bit (kN·m)"


def test_bifurcation_of_a_real_string_is_in_kilonewtons(capsys):
    args = ["bifurcation", "--tally", PAPER, "--dof", "12", "--vary", "wob", "--torque", "12kN*m"]
    text = run(capsys, *args)
    data = json.loads(run(capsys, *args, "--json"))
    lines = text.splitlines()
    assert lines[0].endswith("steady states as wob varies at u = 12 kN m")
    assert "wob (kN)" in lines[1] and "torque (kN m)" in lines[1]
    rows = [x.split() for x in lines[2:] if x.split()[0].rstrip("0123456789") in ("HB", "LP")]
    assert len(rows) == len(data["points"]) > 0
    for row, pt in zip(rows, data["points"], strict=True):
        assert float(row[1]) == pytest.approx(pt["wob"] / 1e3, rel=1e-7)
        assert float(row[2]) == pytest.approx(pt["torque"] / 1e3, rel=1e-7)


def test_map_and_stability_of_a_real_string_are_in_kilonewtons(capsys):
    data = json.loads(run(capsys, "map", "--tally", PAPER, "--dof", "12", "--json"))
    text = run(capsys, "map", "--tally", PAPER, "--dof", "12")
    want = f"W_ob 0..{data['wob_max'] / 1e3:g} kN, u 0..{data['torque_max'] / 1e3:g} kN m"
    assert text.splitlines()[0].endswith(want)
    # 9 kN·m against T_s = mu_s W_ob R_b = 24.9 kN·m at 200 kN: no steady rotation
    text = run(capsys, "stability", "--tally", PAPER, "--wob", "200kN", "--torque", "9kN*m")
    assert text.startswith("no steady rotation: u = 9 kN m cannot balance the bit friction at "
                           "W_ob = 200 kN")  # fmt: skip


def test_bifurcation_figure_of_a_real_string_has_one_force_and_torque_scale():
    from pydrill.bifurcation import branch
    from pydrill.plot_analysis import bifurcation_figure

    p = load_tally(PAPER).to_params(dof=12)
    b = branch(p, vary="torque", wob=20e3, omega_max=1.2)  # torques of 2.4 ... 2.5 kN·m
    assert max(b.torque) < 5000.0
    ax = bifurcation_figure(p, b).axes[0]
    assert ax.get_xlabel() == "surface torque $u$ (kN·m)"  # was N·m beside W_ob = 20 kN
    assert ax.get_title().endswith("$W_{ob}$ = 20 kN")


@pytest.mark.parametrize("regimes", [("steady", "stuck"), ("steady", "stick-slip")])
def test_map_figure_title_fits_and_says_only_what_the_checks_found(regimes):
    import numpy as np

    from pydrill.operating import operating_map
    from pydrill.plot_map import operating_figure
    from pydrill.stability import critical_deltas

    tally = load_tally(PAPER)
    p = tally.to_params(dof=12).replace(name=f"{tally.name} at {tally.length:.1f} m")
    wob, torque = np.linspace(1e3, 2e5, 40), np.linspace(1e2, 2e4, 40)
    crossings = critical_deltas(p)
    checks = [(1e5, 2e4, regimes[0]), (1e5, 5e3, regimes[1])]
    fig = operating_figure(p, operating_map(p, wob, torque, crossings), crossings, checks)
    fig.draw_without_rendering()
    title = fig._suptitle
    box, page = title.get_window_extent(), fig.bbox
    assert page.x0 <= box.x0 and box.x1 <= page.x1  # it ran off the left edge
    assert ("stick-slip still fills a band" in title.get_text()) == ("stick-slip" in regimes)


def test_hopf_figure_of_a_real_string_stays_within_bit_loads_and_reads_in_rpm():
    import math

    from pydrill.plot_analysis import hopf_figure
    from pydrill.stability import critical_deltas

    p = load_tally(PAPER).at_depth(3000.0).to_params()
    fig = hopf_figure(p, critical_deltas(p))
    fig.draw_without_rendering()
    ax = fig.axes[0]
    lo, hi = ax.get_ylim()
    assert lo < 10e3 and 300e3 < hi <= 2000e3  # was up to 19 400 kN; no bit takes 2000 kN
    (rpm,) = ax.child_axes  # the same Ω in rpm along the top: 2π rad/s is 60 rpm
    assert rpm.get_xlabel() == "steady bit speed (rpm)"
    assert rpm.get_xlim() == pytest.approx([x * 60 / (2 * math.pi) for x in ax.get_xlim()])


@pytest.mark.parametrize("command", [["simulate", "--t-end", "20"], ["stability"]])
def test_a_real_strings_weight_on_the_laboratory_string_is_noted(capsys, command):
    code = cli.main([*command, "--wob", "60kN", "--torque", "9kN*m", "--json"])
    out = capsys.readouterr()
    assert code == 0
    data = json.loads(out.out)  # the note is on stderr: the JSON stays whole
    omega = data.get("omega_equilibrium") or [pt["omega"] for pt in data["equilibria"]]
    assert min(omega) * 60 / (2 * 3.141592653589793) > 1e5  # an absurd 300 000 rpm, silently
    assert "on the reduced-scale laboratory string" in out.err and "--tally" in out.err
    assert cli.main([*command, "--wob", "100", "--torque", "8.3"]) == 0
    assert capsys.readouterr().err == ""  # the laboratory's own weights: no note


def test_bifurcation_gives_each_points_speed_in_rpm_beside_rad_per_s(capsys):
    """Ω in rad/s alone, where every other command gives a driller's rpm beside it: the table
    now has an rpm column, the same speed (2π rad/s is 60 rpm), checked against --json."""
    args = ["bifurcation", "--tally", PAPER, "--depth", 3000, "--vary", "wob", "--torque", "11kN*m"]
    text = run(capsys, *args)
    points = json.loads(run(capsys, *args, "--json"))["points"]
    header, *rows = text.splitlines()[1 : 1 + len(points) + 1]
    assert "omega (rad/s)     rpm  freq (rad/s)" in header
    assert len(rows) == len(points) >= 1
    for row, pt in zip(rows, points, strict=True):
        rpm = float(row.split()[4])
        assert rpm == pytest.approx(pt["omega"] * 60 / (2 * 3.141592653589793), abs=0.05)
