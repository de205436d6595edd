"""Operating windows in (W_ob, surface rpm) for strings built from a tally."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import pydrill
from pydrill import stability as st
from pydrill.tally import load_tally
from pydrill.window import RPM, operating_window

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_window_agrees_with_eigenvalues_and_the_sliding_condition():
    p = load_tally(PAPER).at_depth(1000.0).to_params(dof=10)
    wob = np.linspace(2e4, 3e5, 9)
    rpm = np.linspace(10.0, 200.0, 8)
    w = operating_window(p, wob, rpm)
    for i, r in enumerate(rpm):
        for j, wb in enumerate(wob):
            omega = r * RPM
            delta = float(st.stribeck_slope(p, wb, omega))
            brute_stable = np.all(st.eigenvalues(p, delta).real < 0)
            assert w.stable[i, j] == brute_stable
            u = pydrill.equilibrium_torque(p, wb, omega)
            assert abs(w.torque[i, j] - u) < 1e-9 * u
            assert w.unstick[i, j] == (u > p.static_torque(wb))


def test_safe_points_drill_steadily_in_simulation():
    p = load_tally(PAPER).at_depth(1000.0).to_params(dof=8)
    wob = np.array([3e4, 6e4])
    rpm = np.array([120.0, 180.0])
    w = operating_window(p, wob, rpm)
    assert w.safe.any()
    for i, r in enumerate(rpm):
        for j, wb in enumerate(wob):
            if not w.safe[i, j]:
                continue
            u = pydrill.equilibrium_torque(p, wb, r * RPM)
            res = pydrill.simulate(p, wob=wb, torque=u, initial="equilibrium", t_end=120.0)
            assert res.regime == "steady"
            assert abs(res.summary.bit_mean - r * RPM) < 1e-3 * r * RPM


def test_window_command_over_depths():
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pydrill",
            "window",
            str(PAPER),
            "--depth",
            "500m,3000m,5000m",
            "--json",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    assert [w["depth"] for w in data["windows"]] == [500.0, 3000.0, 5000.0]
    dofs = [w["dof"] for w in data["windows"]]
    assert dofs == sorted(dofs) and dofs[0] < dofs[-1]
    for w in data["windows"]:
        assert 0 < w["safe_fraction"] < 1
        assert len(w["min_rpm"]) == len(data["wob"])


# --- Closed-form edges, depth, checks -------------------------------------------------------

import pytest  # noqa: E402
from scipy.linalg import eigh_tridiagonal  # noqa: E402

from pydrill.window import Limits, parse_depths, window_against_depth  # noqa: E402

OTHER = PAPER.parent / "5.5in-dp-8in-collars.toml"
TALLIES = [PAPER, OTHER]
IDS = ["paper-eq53", "5.5in-dp-8in-collars"]


@pytest.mark.parametrize("path", TALLIES, ids=IDS)
@pytest.mark.parametrize("depth", [1000.0, 3000.0, 5000.0])
def test_edges_against_brute_force(path, depth):
    """Just inside each closed-form edge the point passes, just outside it fails, judged by
    eigenvalues of the Jacobian and by comparing the steady torque with T_s directly."""
    p = load_tally(path).at_depth(depth).to_params(lump=10)  # ~ 50 ... 80 inertias: fast eig
    lim = Limits.of(p)
    for rpm in (15.0, 25.0, 40.0):
        w = float(lim.wob_max_stable(rpm))
        for factor, stable in ((0.995, True), (1.005, False)):
            delta = float(st.stribeck_slope(p, factor * w, rpm * RPM))
            assert np.all(st.eigenvalues(p, delta).real < 0) == stable
    for rpm in (10.0, 60.0, 150.0):
        w = float(lim.wob_max_unstuck(rpm))
        for factor, unstuck in ((0.999, True), (1.001, False)):
            u = pydrill.equilibrium_torque(p, factor * w, rpm * RPM)
            assert (u > p.static_torque(factor * w)) == unstuck
    # The rpm edges are the inverses of the W_ob edges (the stall one through Lambert's W).
    wob = np.array([2e4, 5e4, 1e5, 2.5e5])
    np.testing.assert_allclose(lim.wob_max_unstuck(lim.rpm_min_unstuck(wob)), wob, rtol=1e-9)
    np.testing.assert_allclose(lim.wob_max_stable(lim.rpm_min_stable(wob)), wob, rtol=1e-9)
    # And the grid classification, point by point, agrees away from the edges.
    grid = operating_window(p, np.linspace(5e3, 3e5, 40), np.linspace(5.0, 200.0, 40))
    margin = np.abs(grid.wob[None, :] / lim.wob_max(grid.rpm)[:, None] - 1) > 0.02
    closed = grid.wob[None, :] < lim.wob_max(grid.rpm)[:, None]
    assert np.array_equal(grid.safe[margin], closed[margin])


def _fundamental_mode(p):
    j = np.array(p.inertias)
    k = np.array(p.stiffnesses)
    diag = np.zeros(j.size)
    diag[:-1] += k
    diag[1:] += k
    s = 1 / np.sqrt(j)
    w2, v = eigh_tridiagonal(diag * s * s, -k * s[:-1] * s[1:], select="i", select_range=(1, 1))
    phi = v[:, 0] * s
    return float(np.sqrt(w2[0])), phi / phi[-1]


@pytest.mark.parametrize("path", TALLIES, ids=IDS)
def test_window_shrinks_with_depth_for_the_reason_physics_gives(path):
    """The first Hopf is the fundamental torsional mode losing its damping to the bit's negative
    slope: δ_1 ≈ c_b + c_r φ_top² + Σ c_i Δφ_i² (mode shape φ, φ_bit = 1; an undamped-mode
    estimate). A longer string has a slower fundamental (ω_1 ~ 1/L), and stiffness-proportional
    damping c = βk damps a slow mode less, so δ_1 falls with depth and with it the heaviest
    stable W_ob ∝ δ_1; the stall edge does not depend on the string at all."""
    tally = load_tally(path)
    depths = [1000.0, 2000.0, 3000.0, 4000.0, 5000.0]
    freqs = []
    for d in depths:
        p = tally.at_depth(d).to_params()
        w1, phi = _fundamental_mode(p)
        modal = p.bit_damping + p.top_damping * phi[0] ** 2
        modal += float(np.sum(np.array(p.dampings) * np.diff(phi) ** 2))
        hopf = next(c for c in st.critical_deltas(p) if c.type == "hopf" and c.direction > 0)
        assert hopf.delta == pytest.approx(modal, rel=0.02)
        assert hopf.frequency == pytest.approx(w1, rel=0.03)
        freqs.append(w1)
    assert np.all(np.diff(freqs) < 0)
    rpm = np.array([10.0, 20.0, 30.0, 60.0, 120.0])
    wob = np.array([1e4, 2e4, 5e4, 1e5])
    dw = window_against_depth(tally, depths, rpm, wob)
    assert np.all(np.diff(dw.delta_limit) < 0)  # 1000 m on: the Hopf, not the fold, binds
    assert np.all(np.diff(dw.wob_max, axis=0) <= 1e-9 * dw.wob_max[1:])  # lighter, deeper
    assert np.all(np.diff(dw.rpm_min, axis=0) >= -1e-9)  # faster, deeper
    assert np.any(np.diff(dw.wob_max, axis=0) < 0)  # and it does move within the chart
    # The same at every depth: the stall edge.
    np.testing.assert_allclose(dw.wob_max_unstuck, Limits.of(p).wob_max_unstuck(rpm))
    # Grid areas (an independent count of safe cells) shrink too.
    areas = [
        operating_window(
            tally.at_depth(d).to_params(), np.linspace(1e3, 1e5, 60), np.linspace(1.0, 60.0, 60)
        ).safe.mean()
        for d in depths
    ]
    assert np.all(np.diff(areas) <= 0) and areas[-1] < areas[0]


def test_window_check_simulations_agree_with_the_verdict():
    """pydrill window --check: from near the steady state, steady (at the set speed) exactly
    where the analysis says stable."""
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pydrill",
            "window",
            str(PAPER),
            "--depth",
            "3000m",
            "--check",
            "4",
            "--rpm-max",
            "80",
            "--wob-max",
            "80kN",
            "--json",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    checks = data["windows"][0]["checks"]
    assert len(checks) == 16 and data["check_from"] == "equilibrium"
    assert {c["stable"] for c in checks} == {True, False}  # both sides are sampled
    for c in checks:
        assert (c["outcome"] == "steady") == c["stable"], c
        if c["outcome"] == "steady":
            assert c["bit_rpm"] == pytest.approx(c["rpm"], rel=1e-2)


def test_safe_point_starts_from_rest():
    """Well inside the window (far from both edges) the driller's start-up from rest ends in
    steady drilling at the set speed; under the stick-slip edge it does not."""
    p = load_tally(PAPER).at_depth(3000.0).to_params(dof=12)
    lim = Limits.of(p)
    for wob, rpm, safe in ((3e4, 150.0, True), (1e5, 180.0, True), (2e4, 10.0, False)):
        assert (wob < lim.wob_max(rpm)) == safe
        u = pydrill.equilibrium_torque(p, wob, rpm * RPM)
        res = pydrill.simulate(p, wob=wob, torque=u, initial="rest", t_end=200.0, n_out=2)
        assert (res.regime == "steady") == safe
        if safe:
            assert res.summary.bit_mean == pytest.approx(rpm * RPM, rel=1e-3)


def test_depth_ranges_and_errors():
    assert parse_depths("500m:5000m:10") == pytest.approx(np.linspace(500, 5000, 10))
    assert parse_depths("3000m") == [3000.0]
    assert parse_depths("5000ft,1km") == pytest.approx([1524.0, 1000.0])
    for bad, msg in (
        ("500m:5000m", "start:stop:count"),
        ("500m:5000m:x", "not an integer"),
        ("0m", "> 0"),
        ("3 furlong", "furlong"),
    ):
        with pytest.raises(ValueError, match=msg):
            parse_depths(bad)
    out = subprocess.run(
        [sys.executable, "-m", "pydrill", "window", str(PAPER), "--depth", "30m"],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 2 and "shallower than the BHA" in out.stderr


def test_window_plots(tmp_path):
    for depth, name in (("3000m", "one.png"), ("500m:5000m:4", "depth.png")):
        out = subprocess.run(
            [
                sys.executable,
                "-m",
                "pydrill",
                "window",
                str(OTHER),
                "--depth",
                depth,
                "--plot",
                str(tmp_path / name),
            ],
            capture_output=True,
            text=True,
            check=True,
        )
        assert f"figure: {tmp_path / name}" in out.stdout
        assert (tmp_path / name).stat().st_size > 50_000


def test_start_up_checks_count_the_outcomes_where_the_bit_may_stay_stuck(capsys):
    """--check-from rest: the text gives how many safe points drilled steadily, and counts the
    start-ups' outcomes where a stopped bit may stay stuck (both stuck and, when the wind-up
    overshoots the static twist, stick-slip occur there: it scored them "stuck 1/3"), each
    count as the --json checks give it."""
    from collections import Counter

    from pydrill.cli import main

    argv = ["window", str(PAPER), "--depth", "3000m", "--check", "2", "--check-from", "rest"]
    assert main([*argv, "--json"]) == 0
    checks = json.loads(capsys.readouterr().out)["windows"][0]["checks"]
    assert main(argv) == 0
    line = next(s for s in capsys.readouterr().out.splitlines() if s.startswith("checks at"))
    safe = [c["outcome"] for c in checks if c["stable"] and c["cannot_stay_stuck"]]
    stall = Counter(c["outcome"] for c in checks if c["stable"] and not c["cannot_stay_stuck"])
    assert len(stall) >= 2  # this sample has both outcomes, or the test would not tell
    said = ", ".join(f"{g} {n}" for g, n in sorted(stall.items()))
    assert f"safe points steady from rest {safe.count('steady')}/{len(safe)}" in line
    assert line.endswith(f"; where the bit may stay stuck: {said}")
