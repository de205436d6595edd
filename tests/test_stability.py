"""Stability of steady drilling against brute-force eigenvalues and the paper's closed form."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pydrill
from pydrill import stability as st

PAPER_TALLY = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_general_method_equals_the_papers_closed_form():
    """n' = 3 (dof 2): Eq. (50)–(51) with Δ_2 = a_2 a_1 − a_0 (DESIGN.md's typo fix)."""
    for name in ("reduced-scale", "real-string"):
        p = pydrill.preset(name, dof=2)
        closed = st.hopf_deltas_dof2(p)
        general = [c.delta for c in st.critical_deltas(p) if c.type == "hopf"]
        assert closed, name
        for d in closed:
            assert min(abs(g - d) for g in general) <= 1e-9 * d


def test_characteristic_polynomial_and_hurwitz_agree_with_eigenvalues():
    for dof in (2, 3, 4, 5):
        p = pydrill.preset("reduced-scale", dof=dof)
        for delta in (0.0, 0.005, 0.05, 0.5):
            coeffs = st.characteristic_polynomial(p, delta)
            roots = np.roots(coeffs[::-1])
            ev = st.eigenvalues(p, delta)
            assert np.allclose(np.sort_complex(roots), np.sort_complex(ev), atol=1e-7)
    # Hurwitz: Δ_2 = a_2 a_1 − a_0 for a monic cubic; vanishes at the Hopf point.
    p = pydrill.preset("reduced-scale", dof=2)
    (d_hopf,) = st.hopf_deltas_dof2(p)
    a0, a1, a2, _ = st.characteristic_polynomial(p, d_hopf)
    (h1, h2) = st.hurwitz_determinants([a0, a1, a2, 1.0])
    assert h1 == pytest.approx(a2)
    assert abs(h2) < 1e-12 * (abs(a2 * a1) + abs(a0))


@pytest.mark.parametrize("dof", [*range(2, 13), 20, 35, 50])
def test_crossings_are_where_brute_force_eigenvalues_touch_the_axis(dof):
    p = pydrill.preset("reduced-scale", dof=dof)
    crossings = st.critical_deltas(p)
    assert crossings
    for c in crossings:
        ev = st.eigenvalues(p, c.delta)
        target = 1j * (c.frequency or 0.0)
        nearest = ev[np.argmin(np.abs(ev - target))]
        assert abs(nearest.real) < 1e-8
        assert abs(nearest - target) < 1e-8 * max(1.0, abs(target))
    # The count of unstable eigenvalues changes exactly across each crossing, by its size.
    for c in crossings:
        below = np.sum(st.eigenvalues(p, c.delta * (1 - 1e-7)).real > 0)
        above = np.sum(st.eigenvalues(p, c.delta * (1 + 1e-7)).real > 0)
        assert above - below == c.direction * c.multiplicity
    # And the count predicted from the crossings alone is right everywhere in between.
    deltas = np.array([c.delta for c in crossings])
    probes = np.concatenate([[deltas[0] / 2], np.sqrt(deltas[1:] * deltas[:-1]), [2 * deltas[-1]]])
    predicted = st.unstable_count(crossings, probes)
    brute = [np.sum(st.eigenvalues(p, d).real > 0) for d in probes]
    np.testing.assert_array_equal(predicted, brute)


def test_fold_sits_at_cr_plus_cb():
    for name in ("reduced-scale", "real-string"):
        p = pydrill.preset(name, dof=2)
        (fold,) = [c for c in st.critical_deltas(p) if c.type == "fold"]
        assert fold.delta == pytest.approx(p.top_damping + p.bit_damping)


@pytest.mark.parametrize("name", ["reduced-scale", "real-string"])
def test_fig10_stable_below_the_first_hopf_curve(name):
    """Paper Fig. 10: in (Ω, W_ob) the steady state is stable below the Hopf curve."""
    p = pydrill.preset(name, dof=2)
    first = st.critical_deltas(p)[0]
    assert first.type == "hopf" and first.direction == 1
    rng = np.random.default_rng(1)
    for omega in rng.uniform(0.2, 8.0, 12):
        w_star = float(first.wob(p, omega))
        below = st.stability(p, 0.9 * w_star, omega=omega)[0]
        above = st.stability(p, 1.1 * w_star, omega=omega)[0]
        assert below.stable and below.spectral_abscissa < 0
        assert not above.stable and above.spectral_abscissa > 0


def test_map_matches_brute_force_on_random_points():
    p = pydrill.preset("reduced-scale", dof=6)
    rng = np.random.default_rng(7)
    omega = rng.uniform(0.1, 10.0, 25)
    wob = rng.uniform(1.0, 300.0, 25)
    counts = st.stability_map(p, omega, wob)
    for i in range(0, 25, 3):
        for j in range(0, 25, 4):
            delta = st.stribeck_slope(p, wob[i], omega[j])
            assert counts[i, j] == np.sum(st.eigenvalues(p, delta).real > 0)


def test_simulation_agrees_with_the_verdict():
    """Just inside the first Hopf boundary a perturbed steady state decays; just outside it
    grows. For this string the Hopf point is subcritical: outside, the motion jumps to
    stick-slip rather than to a small oscillation."""
    p = pydrill.preset("reduced-scale", dof=2)
    first = st.critical_deltas(p)[0]
    omega = 2.0
    w_star = float(first.wob(p, omega))
    inside = pydrill.simulate(
        p,
        wob=0.97 * w_star,
        torque=pydrill.equilibrium_torque(p, 0.97 * w_star, omega),
        initial="equilibrium",
        t_end=1500.0,
    )
    outside = pydrill.simulate(
        p,
        wob=1.03 * w_star,
        torque=pydrill.equilibrium_torque(p, 1.03 * w_star, omega),
        initial="equilibrium",
        t_end=1500.0,
    )
    assert inside.regime == "steady"
    assert abs(inside.bit_velocity[-1] - omega) < 1e-4 * omega
    assert outside.regime == "stick-slip"


def test_every_steady_state_of_the_paper_grid_is_judged_as_its_eigenvalues_say():
    """Over the main job's (W_ob, u) grid (dof 4, 300 s from the perturbed steady state), the
    simulated regime and the linear verdict agree point by point: a stable steady state is
    ``steady``, an unstable one is not, and an oscillation is one still growing away from it
    (the first Hopf crossing is subcritical: no small stable cycle exists). Slowly decaying
    transients near the boundary used to be called ``oscillation``, e.g. at (100 N,
    6.189 N·m), whose spectral abscissa is -0.0034 1/s."""
    p = pydrill.preset("reduced-scale", dof=4)
    crossings = st.critical_deltas(p)
    seen, wrong = set(), []
    for wob in [*np.linspace(20.0, 200.0, 37).tolist(), 100.0, 135.0]:
        for torque in [*np.linspace(2.0, 16.0, 29).tolist(), 6.189, 8.0]:
            points = st.stability(p, wob, torque=torque, crossings=crossings)
            if not points:
                continue
            fastest = max(points, key=lambda q: q.omega)  # where "equilibrium" starts
            r = pydrill.simulate(
                p, wob=wob, torque=torque, t_end=300.0, initial="equilibrium", n_out=2
            )
            growing = "still growing" in r.summary.note
            seen.add((fastest.stable, r.regime, growing))
            if fastest.stable != (r.regime == "steady") or (r.regime == "oscillation") != growing:
                wrong.append((wob, torque, fastest.spectral_abscissa, r.regime, r.summary.note))
    assert not wrong, wrong
    # both verdicts and every way of leaving an unstable steady state occur on this grid
    assert {(True, "steady", False), (False, "oscillation", True), (False, "stuck", False)} <= seen


def test_stability_at_torque_covers_every_steady_state():
    p = pydrill.preset("reduced-scale", dof=4)
    wob = 200.0
    ts = p.static_torque(wob)
    points = st.stability(p, wob, torque=ts - 0.5)  # two steady states below T_s
    assert len(points) == 2
    assert points[0].omega < points[1].omega
    for pt in points:
        assert pydrill.equilibrium_torque(p, wob, pt.omega) == pytest.approx(ts - 0.5)
    # The slow branch has the larger slope δ, hence at least as many unstable eigenvalues.
    assert points[0].unstable >= points[1].unstable
    with pytest.raises(ValueError, match="exactly one"):
        st.stability(p, wob)


def test_crossings_handed_in_give_the_points_computed_without_them():
    """A sweep computes a string's crossings once and hands them in at every (W_ob, u)."""
    rng = np.random.default_rng(3)
    differs = 0
    for dof in (2, 4, 12):
        p = pydrill.preset("reduced-scale", dof=dof)
        crossings = st.critical_deltas(p)
        other = st.critical_deltas(pydrill.preset("reduced-scale", dof=dof + 1))
        for _ in range(20):
            wob = float(rng.uniform(10, 250))
            torque = float(p.static_torque(wob) * rng.uniform(0.6, 1.4))
            alone = st.stability(p, wob, torque=torque)
            assert st.stability(p, wob, torque=torque, crossings=crossings) == alone
            # Another string's crossings change the verdicts: they are what is used.
            wrong = st.stability(p, wob, torque=torque, crossings=other)
            differs += [q.delta_margin for q in wrong] != [q.delta_margin for q in alone]
    assert differs > 10


@pytest.mark.parametrize("dof", [2, 4, 23, 80])
def test_the_cores_dense_eigenvalues_are_lapacks(dof):
    """The core's dense solver (Eigen's, which short strings get in every sweep, and long ones
    where the structured solver declines) against LAPACK's (numpy's, behind
    ``stability.eigenvalues``), in the same order."""
    from pydrill import _core

    p = pydrill.preset("reduced-scale", dof=dof)
    for delta in (1e-4, st.critical_deltas(p)[0].delta, 0.05, 2.0):
        core = np.array(_core.eigenvalues(p.to_core(), delta))
        lapack = st.eigenvalues(p, delta)
        assert np.abs(core - lapack).max() < 1e-12 * np.abs(lapack).max(), (dof, delta)


def test_long_strings_get_the_dense_solvers_eigenvalues_faster():
    """From 24 inertias on, a steady state's eigenvalues are the roots of Z_b = δ (O(n'²))
    rather than the dense Jacobian's (O(n'³)); they must be the same numbers."""
    from pydrill import _core

    p = pydrill.preset("reduced-scale", pipes=60)
    crossings = st.critical_deltas(p)
    checked = 0
    for wob in (30.0, 120.0, 250.0):
        for point in st.stability(p, wob, torque=float(p.static_torque(wob)) * 0.98):
            assert _core.roots_of_impedance(p.to_core(), point.delta) is not None  # fast path
            dense = st.eigenvalues(p, point.delta)
            fast = np.array(point.eigenvalues)
            scale = np.abs(dense).max()
            assert np.abs(dense[:, None] - fast[None, :]).min(axis=1).max() < 1e-12 * scale
            assert abs(point.spectral_abscissa - dense[0].real) < 1e-12 * scale
            assert point.unstable == st.unstable_count(crossings, point.delta)
            checked += 1
    assert checked >= 3


@pytest.mark.parametrize(
    ("tally", "depth", "beta"),
    [
        ("paper-eq53", 1000.0, None),
        ("paper-eq53", 3000.0, None),
        ("5.5in-dp-8in-collars", 4000.0, 1.0),
    ],
)
def test_a_real_strings_eigenvalues_come_from_the_structured_solver(tally, depth, beta):
    """A tally's string (c = beta k: its pipes' modes overdamped, their roots bunched by the
    hundred near -1/beta) gets its steady states' eigenvalues from the O(n'^2) solver too,
    equal to LAPACK's: at 3000 m (334 inertias) 20 ms against 0.4 s a steady state. With
    beta = 1 s at 4000 m, 425 real roots lie within 0.11 of -1, some 1e-10 apart."""
    from dataclasses import replace

    from pydrill import _core

    p = pydrill.load_tally(PAPER_TALLY.with_name(f"{tally}.toml")).at_depth(depth).to_params()
    if beta is not None:
        p = replace(p, dampings=tuple(beta * k for k in p.stiffnesses))
    assert p.dof > 100
    checked = 0
    for wob in (20e3, 150e3):
        for point in st.stability(p, wob, torque=float(p.static_torque(wob)) * 0.98):
            assert _core.roots_of_impedance(p.to_core(), point.delta) is not None  # fast path
            dense = st.eigenvalues(p, point.delta)
            assert np.count_nonzero(dense.imag == 0) > p.dof  # overdamped indeed
            fast = np.array(point.eigenvalues)
            scale = np.abs(dense).max()
            assert np.abs(dense[:, None] - fast[None, :]).min(axis=1).max() < 1e-12 * scale
            assert abs(point.spectral_abscissa - dense[0].real) < 1e-12 * scale
            checked += 1
    assert checked >= 2
    for delta in (0.0, 10.0, 1e3):  # and at slopes away from these steady states
        fast = _core.roots_of_impedance(p.to_core(), delta)
        assert fast is not None, delta
        dense = st.eigenvalues(p, delta)
        err = np.abs(dense[:, None] - np.array(fast)[None, :]).min(axis=1).max()
        assert err < 1e-12 * np.abs(dense).max(), delta


def test_hopf_and_stability_commands(tmp_path):
    png = tmp_path / "hopf.png"
    run = [sys.executable, "-m", "pydrill"]
    out = subprocess.run(
        [*run, "hopf", "--dof", "4", "--json", "--plot", str(png)],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    deltas = [c["delta"] for c in data["crossings"]]
    assert deltas == sorted(deltas)
    assert {c["type"] for c in data["crossings"]} == {"hopf", "fold"}
    p4 = pydrill.preset("reduced-scale", dof=4)
    for c, crossing in zip(data["crossings"], st.critical_deltas(p4), strict=True):
        assert (c["frequency"] is None) == (c["type"] == "fold")
        # Criticality: l1 of the Hopf crossings (the test of bifurcation checks it against a
        # simulation's amplitude growth), its sign named; none for the fold.
        assert c["lyapunov"] == crossing.lyapunov(p4)
        assert (c["lyapunov"] is None) == (c["type"] == "fold")
        if c["lyapunov"] is not None:
            assert c["criticality"] == ("subcritical" if c["lyapunov"] > 0 else "supercritical")
    assert png.stat().st_size > 20_000
    out = subprocess.run(
        [*run, "stability", "--dof", "4", "--wob", "40", "--torque", "8.3", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    (eq,) = json.loads(out.stdout)["equilibria"]
    assert eq["stable"] and eq["omega"] == pytest.approx(33.15789473684141)
    bad = subprocess.run(
        [*run, "stability", "--dof", "4", "--wob", "40"], capture_output=True, text=True
    )
    assert bad.returncode == 2 and "Traceback" not in bad.stderr


@pytest.mark.parametrize(("pipes", "crossings", "supercritical"), [(10, 17, 2), (500, 339, 69)])
def test_the_hopf_counts_the_guide_quotes(pipes, crossings, supercritical):
    """docs/guide/stability.md and the README quote these counts (2 of 17 at 10 pipes, 69 of
    339 at 500): they must stay what pydrill computes. (That the crossings are where
    eigenvalues touch the axis is checked against brute force above.)"""
    p = pydrill.preset(pipes=pipes)
    hopf = [c for c in st.critical_deltas(p) if c.type == "hopf"]
    assert len(hopf) == crossings
    assert sum(st.criticality(c.lyapunov(p)) == "supercritical" for c in hopf) == supercritical
    assert all(c.multiplicity == 2 and c.direction in (-1, 1) for c in hopf)


@pytest.mark.parametrize(("wob", "torque"), [(100.0, 8.3), (120.0, 8.3), (40.0, 8.3)])
def test_turning_backwards_mirrors_the_steady_states(wob, torque):
    """u < 0 is the mirror image of |u| (the model is odd in the state and u): the same steady
    states with Ω and u reversed, and the same eigenvalues. A backward run settles on one
    (it once found none)."""
    p = pydrill.preset(dof=4)
    fwd, back = st.stability(p, wob, torque=torque), st.stability(p, wob, torque=-torque)
    assert len(back) == len(fwd) > 0
    for b, f in zip(back, reversed(fwd), strict=True):
        assert (b.omega, b.torque) == (-f.omega, -f.torque)
        assert (b.delta, b.unstable, b.eigenvalues) == (f.delta, f.unstable, f.eigenvalues)
    if wob == 40.0:  # stable: a backward run from rest settles on it
        for initial in ("rest", "equilibrium"):
            run = pydrill.simulate(p, wob=wob, torque=-torque, t_end=300.0, initial=initial)
            assert run.summary.regime == "steady"
            assert run.summary.bit_mean == pytest.approx(back[0].omega, rel=1e-3)


def test_a_stability_map_larger_than_the_memory_is_refused_before_it_is_allocated(monkeypatch):
    """Two axes of 1e5 values (320 GB) are refused at once, naming the grid and the memory; a
    grid that fits is computed. The guard's bytes per point are at least what numpy's peak
    takes (measured with tracemalloc, which sees numpy's arrays), so it cannot let through a
    grid that would not fit."""
    import time
    import tracemalloc

    import psutil

    from pydrill import stability_checks
    from pydrill.stability import stability_map

    p = pydrill.preset(dof=4)
    start = time.perf_counter()
    with pytest.raises(ValueError, match=r"a grid of 100000 wob x 100000 omega values .* 320 GB"):
        stability_map(p, np.linspace(0.0, 10.0, 100_000), np.linspace(1.0, 200.0, 100_000))
    assert time.perf_counter() - start < 1.0  # refused, not attempted
    crossings = st.critical_deltas(p)
    tracemalloc.start()
    counts = stability_map(p, np.linspace(0.0, 10.0, 1000), np.linspace(1.0, 200.0, 500), crossings)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert counts.shape == (500, 1000)
    assert peak <= stability_checks.GRID_BYTES_PER_POINT * counts.size

    # where less memory is available, the same grid is refused
    class Low:
        available = stability_checks.GRID_BYTES_PER_POINT * counts.size - 1

    monkeypatch.setattr(psutil, "virtual_memory", lambda: Low)
    with pytest.raises(ValueError, match=r"500 wob x 1000 omega .* 0.016 GB is available"):
        stability_map(p, np.linspace(0.0, 10.0, 1000), np.linspace(1.0, 200.0, 500), crossings)


def test_a_hand_made_crossing_that_is_no_hopf_point_has_no_lyapunov_coefficient():
    """Crossing("hopf", 0.01, 1.0, ...) on the 4-DOF string had l1 = 0.036, "subcritical",
    though i·1 rad/s is no eigenvalue at δ = 0.01 (numpy's nearest lies 0.27 rad/s away)."""
    p4 = pydrill.preset("reduced-scale", dof=4)
    nearest = np.min(np.abs(st.eigenvalues(p4, 0.01) - 1j))
    assert nearest > 0.2  # (independent of the core's check: LAPACK's eigenvalues)
    made = st.Crossing("hopf", 0.01, 1.0, 1, 2)
    with pytest.raises(ValueError, match=r"delta = 0\.01 and frequency = 1 are not a Hopf point"):
        made.lyapunov(p4)
    hopf = next(c for c in st.critical_deltas(p4) if c.type == "hopf")
    assert math.isfinite(hopf.lyapunov(p4))
