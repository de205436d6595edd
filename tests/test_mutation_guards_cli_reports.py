"""What the analysis commands and the sweep's report print, against the Python API and by hand.

Found by a mutation audit of the command line's output layer: stability, hopf, bifurcation, map
and string print in JSON what the API computes (compared here key by key), and in text the same
numbers converted to rpm and kN by factors worked out here (30/pi, 1e3); the sweep's messages
give durations, exit statuses and counts a script or a batch job relies on.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest
from cli_running import ok_json, ok_text
from sweeping import ROOT

from pydrill import cli_sweep_report as report
from pydrill import preset
from pydrill.bifurcation import branch
from pydrill.cli_analysis import counted, slow_note
from pydrill.cli_bifurcation import omega_max_note
from pydrill.cli_window_report import _numbers, check_agreement
from pydrill.stability import critical_deltas, stability
from pydrill.tally import load_tally

TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"
RPM = 30 / math.pi  # rad/s to rev/min


def test_stability_json_and_text_are_the_apis_steady_state(capsys):
    params = preset("reduced-scale", dof=3)
    (pt,) = stability(params, 100.0, torque=8.3)
    d = ok_json(capsys, "stability", "--dof", 3, "--wob", 100, "--torque", 8.3)
    (eq,) = d["equilibria"]
    assert (d["torque"], d["omega"], d["wob"]) == (8.3, None, 100.0)  # the one given, echoed
    assert eq["omega"] == pytest.approx(pt.omega, rel=1e-12)
    assert eq["delta"] == pytest.approx(pt.delta, rel=1e-12)
    assert eq["eigenvalue_count"] == len(pt.eigenvalues) == 5
    d = ok_json(capsys, "stability", "--dof", 3, "--wob", 100, "--omega", 5)
    assert (d["omega"], d["torque"]) == (5.0, None)
    out = ok_text(capsys, "stability", "--dof", 3, "--wob", 100, "--torque", 8.3)
    assert f"Omega = {pt.omega:.6g} rad/s ({pt.omega * RPM:.4g} rpm)" in out
    assert pt.spectral_abscissa < 0 and "the slowest-decaying mode" in out
    assert out.count("i, ") == 4 and out.rstrip().endswith(", ...")  # 4 of 5 eigenvalues


def test_hopf_json_is_the_apis_crossings_and_the_text_counts_them(capsys):
    params = preset("reduced-scale", dof=6)
    crossings = critical_deltas(params)
    d = ok_json(capsys, "hopf", "--dof", 6)
    assert [c["delta"] for c in d["crossings"]] == pytest.approx([c.delta for c in crossings])
    assert [c["frequency"] for c in d["crossings"]] == [c.frequency for c in crossings]
    hopf = sum(c.type == "hopf" for c in crossings)
    folds = len(crossings) - hopf
    assert hopf > 4 and folds == 1  # more rows than 4, and the singular
    out = ok_text(capsys, "hopf", "--dof", 6)
    assert out.splitlines()[0] == f"reduced-scale, dof 6: {hopf} Hopf crossings, 1 fold"
    rows = [line for line in out.splitlines() if line.startswith(("hopf ", "fold "))]
    assert len(rows) == len(crossings)
    assert [counted(n, "fold") for n in (0, 1, 2)] == ["0 folds", "1 fold", "2 folds"]


def test_slow_and_fast_notes_are_where_their_numbers_put_them(capsys):
    slow_note("stability", 10_000)  # 6e-7 s x 10000^2 = 60 s: a minute, said
    assert "stability of 10000 inertias takes roughly 1 min 00 s" in capsys.readouterr().err
    slow_note("stability", 9_000)  # 48.6 s: nothing said
    omega_max_note(2000.0)  # past 1e3 rad/s (9549 rpm): noted, with its rpm
    err = capsys.readouterr().err
    assert err.count("note") == 1 and f"= {2000 * RPM:.3g} rpm" in err


def test_bifurcation_of_a_real_string_in_kn_and_rpm(capsys):
    params = preset("real-string")
    b = branch(params, vary="wob", torque=9000.0)
    d = ok_json(capsys, "bifurcation", "--preset", "real-string", "--vary", "wob", "--torque", 9000)
    assert d["fixed"] == 9000.0 and d["units"]["fixed"] == "N·m" and d["units"]["wob"] == "N"
    out = ok_text(
        capsys, "bifurcation", "--preset", "real-string", "--vary", "wob", "--torque", 9000
    )
    rows = out.splitlines()[2:]
    assert len(rows) == len(b.points) > 0
    for row, pt in zip(rows, b.points, strict=True):
        cells = row.split()
        assert cells[0] == pt.label
        assert float(cells[1]) == pytest.approx(pt.wob / 1e3, rel=1e-7)  # kN
        assert float(cells[2]) == pytest.approx(pt.torque / 1e3, rel=1e-7)  # kN m
        assert float(cells[4]) == pytest.approx(pt.omega * RPM, abs=0.051)  # rpm, to .1f


def test_map_json_grid_checks_and_text_table(capsys):
    d = ok_json(capsys, "map", "--dof", 2, "--check", 2)
    assert d["wob"] == pytest.approx(np.linspace(250 / 200, 250, 200).tolist(), rel=1e-12)
    assert (d["wob_max"], d["torque_max"], d["t_end"]) == (250.0, 25.0, 300.0)  # the defaults
    assert [(c["wob"], c["torque"]) for c in d["checks"]] == [
        (125.0, 12.5),
        (125.0, 25.0),
        (250.0, 12.5),
        (250.0, 25.0),
    ]
    assert d["failed_checks"] == sum(c["message"] is not None for c in d["checks"]) == 0
    out = ok_text(capsys, "map", "--dof", 2)
    for name, frac in d["fractions"].items():
        assert f"  {100 * frac:5.1f} %  {name}" in out
    # the safe-u table of a real string, in kN: T_s = mu_s W_ob R_b by hand at 40 ... 200 kN,
    # and safe u from T_s where steady drilling is stable below it
    real = preset("real-string")
    out = ok_text(capsys, "map", "--preset", "real-string")
    rows = out.splitlines()[-5:]
    for row, w in zip(rows, np.linspace(40e3, 200e3, 5), strict=True):
        ts = real.mu_static * w * real.bit_radius
        cells = row.split()
        assert float(cells[0]) == pytest.approx(w / 1e3) and float(cells[1]) == pytest.approx(
            ts / 1e3, rel=1e-3
        )
        assert float(cells[2]) < ts / 1e3 and cells[3:] == [">", f"{ts / 1e3:.4g}"]


def test_string_json_and_text_are_the_tallys(capsys):
    tally = load_tally(TALLY)
    d = ok_json(capsys, "string", TALLY, "--dof", 13)
    assert d["length"] == pytest.approx(tally.length) and d["bha_length"] == pytest.approx(
        tally.bha_length
    )
    assert d["bha_length"] < d["length"]
    # the tally's [top_drive] and [bit] dampings, each in its own key
    assert (d["top_damping"], d["bit_damping"]) == (425.0, 50.0)
    # friction coefficients are plain numbers, as every other document writes them
    assert d["units"]["friction"]["mu_static"] == d["units"]["friction"]["mu_coulomb"] == "1"
    assert d["units"]["friction"]["stribeck_velocity"] == "rad/s"
    out = ok_text(capsys, "string", TALLY, "--dof", 13)
    series = 1 / np.sum(1 / np.array(d["stiffnesses"]))
    assert f"12 elements; total inertia {sum(d['inertias'][1:]):.6g} kg m^2" in out
    assert f"series stiffness {series:.6g} N m/rad" in out
    assert f"(2122 + {d['inertias'][0] - 2122:.4g} of the string)" in out
    out = ok_text(capsys, "string", TALLY, "--dof", 12)
    assert sum(line.startswith("  element") for line in out.splitlines()) == 11


def test_window_json_numbers_and_check_agreement():
    assert _numbers([1.5, math.inf, -math.inf, math.nan]) == [1.5, None, None, None]
    # (wob, rpm, outcome, stable, cannot stay stuck, bit rpm, message)
    checks = [
        (1, 1, "steady", True, True, 60.0, None),
        (1, 2, "stick-slip", True, True, 0.0, None),
        (2, 1, "stick-slip", False, True, 0.0, None),
        (2, 2, "steady", True, False, 60.0, None),
        (3, 3, "stuck", True, False, 0.0, None),
    ]
    # from equilibrium: steady exactly where stable at 3 of 5 (rows 1, 3 and 4)
    assert check_agreement(checks, "equilibrium") == "steady exactly where stable at 3/5 points"
    assert check_agreement(checks, "rest") == (
        "safe points steady from rest 1/2; where the bit may stay stuck: steady 1, stuck 1"
    )


def test_sweep_durations_exit_statuses_and_counts(capsys):
    assert [report.duration(s) for s in (5, 59.6, 61, 3725)] == [
        "5 s",
        "1 min 00 s",
        "1 min 01 s",
        "1 h 02 min",
    ]
    first = "x" * 301
    run_ = SimpleNamespace(failed_in_atlas=4, points=4, all_failed=True, atlas="a.h5")
    assert report.failures(SimpleNamespace(**vars(run_), first_failure="boom")) == 3
    run_.all_failed, run_.points = False, 8
    assert report.failures(SimpleNamespace(**vars(run_), first_failure=first)) == 0
    assert "x" * 297 + "...\n" in capsys.readouterr().err
    args = SimpleNamespace(
        spec="s.toml", out="a.h5", scheduler=None, workers=None, serial=True, json=False
    )
    exc = SimpleNamespace(done=3, points=8, atlas="a.h5", signum=15)
    assert report.interrupted(args, exc, None) == 128 + 15
    assert "compute the other 5: pydrill sweep s.toml --out a.h5 --serial --resume" in (
        capsys.readouterr().err
    )
    done = SimpleNamespace(
        points=8, computed=3, failed=1, resumed=5, wall_time=1.0, write_time=0.1,
        failed_in_atlas=1, first_failure="boom",
    )  # fmt: skip
    results = report.results_of(done, None, False)
    assert (results["computed"], results["already_done"]) == (3, 5)


def test_next_steps_hold_the_middle_value_in_its_unit_and_merge_two_parts(capsys):
    spec = SimpleNamespace(
        record={"stability": True},
        axes={"wob": [1e4, 2e4], "torque": [6e3, 9e3, 12e3], "depth": [1000.0, 2000.0]},
    )
    args = SimpleNamespace(json=False, plot="x.png", part="1/2")
    report.next_steps(args, SimpleNamespace(all_failed=False, atlas="a.h5"), spec)
    err = capsys.readouterr().err
    # one row per torque; depth held at its middle grid value (2000 m); the other part
    assert "pydrill atlas safe a.h5 --set depth=2000m" in err
    assert "once the other part is swept" in err
    spec.axes = {"wob": [1e4, 2e4], "torque": [6e3, 9e3], "pipes": [1.0, 3.0, 5.0]}
    report.next_steps(args, SimpleNamespace(all_failed=False, atlas="a.h5"), spec)
    assert "--set pipes=3 " in capsys.readouterr().err


def test_log_progress_counts_its_rate_from_the_first_batch_back(monkeypatch, capsys):
    now = [100.0]
    monkeypatch.setattr(report.time, "monotonic", lambda: now[0])
    bar = report.LogProgress(1000, every=30.0, resumed=True)
    now[0] = 200.0
    bar.update(400)  # the journal's replay: the rate counts from here
    now[0] = 240.0
    bar.update(200)  # 200 points in 40 s: 5 points/s, 400 left: 80 s
    assert capsys.readouterr().err == (
        "sweep: 600/1000 points (60 %), 5 points/s, about 1 min 20 s left\n"
    )
