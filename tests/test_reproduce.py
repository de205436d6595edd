"""The reproduction's numbers stay where the report says, and agree with what the paper states.

Each check recomputes a number through the function ``pydrill reproduce`` uses for its report and
compares it with something independent: the paper's stated regimes and reference values
(Eqs. 38–39), its closed forms written out here from the paper's Eq. (50), or analytic facts
(the fold at δ = c_r + c_b, the quasi-equilibrium u/k). The end-to-end test runs a reduced
``pydrill reproduce`` and checks that report.md quotes those numbers.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar
from test_cli_json import check_layout

from pydrill import preset
from pydrill import reproduce_analysis as ra
from pydrill import reproduce_sims as rs
from pydrill.reproduce import Cache
from pydrill.reproduce_report import g


def _eq50(name: str, delta: float, printed: bool = False) -> float:
    """The paper's Eq. (50) for n' = 3 with d_b = −δ: Δ₂ = a₂a₁ − a₀ (DESIGN.md), or the
    printed Δ₂ = a₁ − a₂ − a₀."""
    p = preset(name, dof=2)
    jr, jb = p.inertias
    (kt,), (ct,) = p.stiffnesses, p.dampings
    cr, cb, db = p.top_damping, p.bit_damping, -delta
    a2 = (jr * (cb + ct + db) + jb * (cr + ct)) / (jb * jr)
    a1 = (cb * (cr + ct) + ct * (cr + db) + db * cr + kt * (jb + jr)) / (jb * jr)
    a0 = kt / (jb * jr) * (cb + cr + db)
    return a1 - a2 - a0 if printed else a2 * a1 - a0


@pytest.mark.parametrize("name", ["reduced-scale", "real-string"])
def test_fig10_hopf_locus_is_the_root_of_the_papers_hurwitz_determinant(name):
    n = ra.fig10(name)
    p = preset(name, dof=2)
    fold = p.top_damping + p.bit_damping  # a0 = 0
    h2 = brentq(lambda d: _eq50(name, d), 1e-9 * fold, fold)  # inside H+ (a0 > 0)
    h1 = brentq(lambda d: _eq50(name, d), fold, 100 * fold)
    assert n["h2_delta"] == pytest.approx(h2, rel=1e-9)
    assert n["eq51_deltas"][0] == pytest.approx(h2, rel=1e-9)
    assert n["h1_delta"] == pytest.approx(h1, rel=1e-9)
    assert n["fold_delta"] == pytest.approx(fold, rel=1e-12)
    # The printed Δ₂ = a₁ − a₂ − a₀ never vanishes for δ > 0: no Hopf curve at all.
    deltas = np.geomspace(1e-8, 1e4, 2000) * fold
    assert n["typo_roots"] == []
    assert np.all(np.sign([_eq50(name, d, printed=True) for d in deltas]) == 1)
    # Eq. (7) corrected: the top drive is damped by its own motion.
    jr, kt, ct = p.inertias[0], p.stiffnesses[0], p.dampings[0]
    assert n["eq7_row"] == pytest.approx([-(ct + p.top_damping) / jr, -kt / jr, ct / jr])
    assert n["lyapunov_h2"] > 0  # subcritical


def test_section3_regimes_are_the_papers():
    """Fig. 4 stick-slip, Fig. 7 stuck, Fig. 9 steady (n = 8, u = 8.3 N·m), from rest."""
    f4, _ = rs.fig4()
    f7, _ = rs.fig7()
    f9, _ = rs.fig9()
    assert f4["exact"]["regime"] == "stick-slip"
    assert f4["karnopp"]["regime"] == "stick-slip"  # the paper's own Eq. (9)
    assert f4["karnopp"]["period"] == pytest.approx(f4["exact"]["period"], rel=1e-4)
    assert 15 < f4["exact"]["period"] < 20  # the report's 17.54 s
    assert f4["exact"]["bit_max"] > 4 * f4["exact"]["top_mean"]  # bit spins far above the top
    assert f7["rest"]["regime"] == "stuck" and f7["loaded"]["regime"] == "stuck"
    assert f7["entries"] == 1  # "hits the sliding manifold only once and remains there"
    # The stuck string relaxes to the quasi-equilibrium of Eq. (30): collar twist u / k_tb.
    assert f7["quasi_equilibrium_twist"] == pytest.approx(8.3 / 0.073)
    assert f7["final_collar_twist"] == pytest.approx(8.3 / 0.073, rel=0.02)
    assert f9["run"]["regime"] == "steady"
    # Ω from u = (c_r + c_b)Ω + W_ob R_b μ_b(Ω), solved here.
    omega = brentq(lambda w: 0.19 * w + 4.0 * (0.5 + 0.3 * math.exp(-0.9 * w)) - 8.3, 1, 100)
    assert f9["omega"] == pytest.approx(omega, rel=1e-10)
    assert f9["run"]["bit_mean"] == pytest.approx(omega, rel=1e-3)
    assert f9["stable"] and f9["delta"] < f9["delta_1"]


def test_fig8_breakaway_on_the_sliding_boundary_and_stuck_time_grows_with_wob():
    f8, _ = rs.fig8()
    ts = 0.8 * 100.0 * 0.1  # T_s = μ_sb W_ob R_b
    assert [v["torque_out"] for v in f8["visits"]] == pytest.approx([ts] * 3, abs=1e-9)
    assert f8["visits"][1]["phi_b"] > f8["visits"][0]["phi_b"]  # Σ̃_i moves with φ̄_b
    fractions = list(f8["stuck_fraction_by_wob"].values())
    assert fractions == sorted(fractions)


def test_fig5_stick_slip_then_stuck_as_wob_grows():
    f5, _ = rs.fig5()
    regimes = [s["regime"] for s in f5["schedule"]]
    assert regimes[0] == "stick-slip" and regimes[-1] == "stuck"
    assert regimes == sorted(regimes, key=lambda r: r == "stuck")  # stuck once, stuck for good
    iv = f5["interval"]
    assert iv["wob_star"] == pytest.approx(8.1 / (0.8 * 0.1))  # Eq. (38)
    # Stuck for good only where the rock can hold u (Eq. 39): past W*_ob.
    assert iv["wob_star"] < iv["upper"] < 150 and iv["lower"] < 90
    assert (iv["below"], iv["above"]) == ("steady", "stuck")


@pytest.mark.parametrize("panel", ["a", "b", "c", "d"])
def test_fig11_fold_and_hopf_points(panel):
    n = ra.fig11(panel)
    _, dof, vary, fixed = next(f for f in ra.FIG11 if f[0] == panel)
    c = 0.19  # c_r + c_b
    if vary == "wob":
        # W_ob(Ω) = (u − cΩ) / (R_b μ_b(Ω)) peaks at the fold: found here by minimisation.
        res = minimize_scalar(
            lambda w: -(fixed - c * w) / (0.1 * (0.5 + 0.3 * math.exp(-0.9 * w))),
            bounds=(0.1, 20),
            method="bounded",
            options={"xatol": 1e-10},
        )
        assert n["fold"]["wob"] == pytest.approx(-res.fun, rel=1e-8)
    else:
        res = minimize_scalar(
            lambda w: c * w + fixed * 0.1 * (0.5 + 0.3 * math.exp(-0.9 * w)),
            bounds=(0.1, 20),
            method="bounded",
            options={"xatol": 1e-10},
        )
        assert n["fold"]["torque"] == pytest.approx(res.fun, rel=1e-8)
    first = n["first_hopf"]
    delta_1 = ra.critical_deltas(preset("reduced-scale", dof=dof))[0].delta
    w = first["wob"]
    slope = w * 0.1 * 0.9 * 0.3 * math.exp(-0.9 * first["omega"])
    assert slope == pytest.approx(delta_1, rel=1e-9)
    if dof == 2:
        assert delta_1 == pytest.approx(ra.fig10("reduced-scale")["h2_delta"], rel=1e-12)
    assert all(p["criticality"] == "subcritical" for p in n["points"] if p["type"] == "HB")


def test_multiple_hopf_crossings_of_the_papers_n7_string():
    d = ra.paper_strings()["dof4"]
    assert d["summary"]["hopf"] == 5 and d["summary"]["folds"] == 1
    assert d["verify"]["count_mismatches"] == 0
    assert d["verify"]["worst_axis_distance"] < 1e-8
    h = d["hurwitz"]
    assert h["n_prime"] == 7 and h["sign_changes"] == h["hopf"] == 5
    # Eq. (55)'s relations do not locate Hopf points for n' = 7.
    for rel in h["eq55"]:
        assert min(rel["min_abs_real_at_roots"]) > 1e-4
    # ... but for n' = 3 it is Δ₂ = 0 itself.
    (rel3,) = ra.paper_strings()["dof2"]["hurwitz"]["eq55"]
    assert max(rel3["min_abs_real_at_roots"]) < 1e-10


def test_ten_pipes_first_hopf_is_subcritical_and_above_the_n3_estimate():
    d = ra.long_string(10)
    s = d["summary"]
    assert s["dof"] == 13 and s["hopf"] == 17
    assert d["verify"]["count_mismatches"] == 0
    base = ra.fig10("reduced-scale")["h2_delta"]
    assert 1.0 < s["first"]["delta"] / base < 1.2  # the n' = 3 region is conservative
    assert d["fig12"]["curves"][0]["lyapunov"] > 0
    assert d["fig11c"]["fold"]["wob"] == pytest.approx(ra.fig11("a")["fold"]["wob"], rel=1e-12)


def test_cache_is_keyed_on_what_was_computed(tmp_path):
    calls = []
    cache = Cache(tmp_path)
    assert cache.get("x", {"a": 1}, lambda: calls.append(1) or {"v": 1.0}) == {"v": 1.0}
    assert Cache(tmp_path).get("x", {"a": 1}, lambda: calls.append(2) or {"v": 2.0}) == {"v": 1.0}
    assert Cache(tmp_path).get("x", {"a": 2}, lambda: calls.append(3) or {"v": 3.0}) == {"v": 3.0}
    assert calls == [1, 3]


@pytest.mark.slow
def test_reproduce_end_to_end_quick(reproduce_quick, tmp_path):
    """A reduced run writes every figure and a report quoting the computed numbers; a second
    run reuses every atlas and analysis. The first run is the session's (conftest.py), shared
    with test_reproduce_figures.py; the second runs in a copy of its output."""
    out, first = reproduce_quick
    # Laid out as every command's --json (test_cli_json): inputs, results, units.
    check_layout(first, {"out": str(out), "quick": True, "force": False}, None)
    assert first["units"] == {"wall_time": "s"}
    assert len(first["figures"]) == 12
    for f in first["figures"]:
        assert (out / f.split("/")[-1]).stat().st_size > 20_000
    report = (out / "report.md").read_text()
    numbers = json.loads((out / "numbers.json").read_text())
    for value, digits in (
        (numbers["fig04"]["exact"]["period"], 4),
        (numbers["fig10a"]["h2_delta"], 6),
        (numbers["fig10b"]["h2_delta"], 6),
        (numbers["fig11c"]["first_hopf"]["wob"], 6),
        (numbers["fig05"]["interval"]["upper"], 4),
        (numbers["fig07"]["quasi_equilibrium_twist"], 4),
    ):
        assert g(value, digits) in report
    for fig in (
        "Fig. 4",
        "Fig. 5",
        "Fig. 6(b)",
        "Fig. 7",
        "Fig. 8",
        "Fig. 9",
        "Fig. 10",
        "Fig. 11",
        "Fig. 12",
        "Multiple Hopf",
        "criticality",
        "10 pipes",
    ):
        assert fig in report
    h = first["highlights"]
    assert (h["fig4_regime"], h["fig7_regime"], h["fig9_regime"]) == (
        "stick-slip",
        "stuck",
        "steady",
    )
    again = tmp_path / "again"
    shutil.copytree(out, again)
    cmd = [sys.executable, "-m", "pydrill", "reproduce", "--out", str(again), "--quick"]
    second = json.loads(
        subprocess.run([*cmd, "--json"], capture_output=True, text=True, check=True).stdout
    )
    assert set(second["atlases"].values()) == {"reused"}
    assert second["cache"]["computed"] == []


def test_reproduce_workers_sizes_the_cluster_and_small_atlases_stay_serial(tmp_path):
    """``reproduce --workers N`` once failed on every serial atlas ("give at most one of
    workers, scheduler, serial"): it sizes the cluster of the parallel ones only. An atlas run
    here and one run on a cluster of one worker hold the same points."""
    from pydrill.atlas import Atlas
    from pydrill.reproduce_atlases import run_atlas

    base = {"model": {"dof": 2, "torque": 8.1}, "axes": {"wob": [60.0, 100.0, 160.0]}}
    regimes = []
    for parallel in (False, True):
        settings = {**base, "t_end": 60.0, "parallel": parallel}
        path, how = run_atlas(
            tmp_path / str(parallel), "fig", settings, force=False, workers=1, scheduler=None
        )
        assert how == "computed"
        with Atlas(path) as atlas:
            assert atlas.summary()["status"]["missing"] == 0
            regimes.append(atlas.to_xarray()["regime"].values.tolist())
    assert regimes[0] == regimes[1]
    assert len({r for row in regimes[0] for r in row}) > 2  # not one regime repeated
