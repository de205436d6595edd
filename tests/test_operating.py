"""The (W_ob, u) map against eigenvalue verdicts and simulations."""

import json
import subprocess
import sys

import numpy as np
import pytest

import pydrill
from pydrill import stability as st
from pydrill.operating import CATEGORIES, hopf_curve_wu, operating_map


def test_categories_agree_with_the_stability_of_every_steady_state():
    """Negative torques too: the steady state there turns backwards, and the map once called
    every u < 0 "no stable steady state" (it compared signed u with |u|'s intervals)."""
    p = pydrill.preset("reduced-scale", dof=3)
    wob = np.linspace(10.0, 250.0, 13)
    torque = np.concatenate([-np.linspace(0.5, 25.0, 6), np.linspace(0.5, 25.0, 11)])
    omap = operating_map(p, wob, torque)
    for i, u in enumerate(torque):
        for j, w in enumerate(wob):
            points = st.stability(p, w, torque=u)
            has_stable = any(pt.stable for pt in points)
            stuck = abs(u) <= 0.8 * w * 0.1
            expected = {(True, False): 0, (True, True): 1, (False, False): 2, (False, True): 3}
            assert omap.category[i, j] == expected[(has_stable, stuck)], (w, u)
    assert abs(sum(omap.fractions().values()) - 1.0) < 1e-12
    assert len(CATEGORIES) == 4


def test_hopf_curve_in_wob_torque_is_on_the_critical_slope():
    p = pydrill.preset("reduced-scale", dof=4)
    first = st.critical_deltas(p)[0]
    omega = np.array([0.5, 2.0, 6.0])
    w, u = hopf_curve_wu(p, first.delta, omega)
    for wi, ui, om in zip(w, u, omega, strict=True):
        assert abs(pydrill.equilibrium_torque(p, wi, om) - ui) < 1e-12 * ui
        assert abs(float(st.stribeck_slope(p, wi, om)) - first.delta) < 1e-12 * first.delta


def test_papers_section3_picture_at_fixed_torque():
    """Paper Section 3 (i)–(iii): at fixed u, small W_ob drills steadily, W_ob near W* =
    u / (μ_sb R_b) sticks and slips, large W_ob stays stuck."""
    p = pydrill.preset("reduced-scale", dof=4)
    u = 8.3
    w_star = u / (0.8 * 0.1)
    regimes = [
        pydrill.simulate(p, wob=w, torque=u, t_end=300.0, n_out=301).regime
        for w in (0.4 * w_star, 0.97 * w_star, 1.6 * w_star)
    ]
    assert regimes == ["steady", "stick-slip", "stuck"]
    omap = operating_map(p, [0.4 * w_star, 1.6 * w_star], [u])
    assert omap.category[0, 0] == 0  # steady drilling is safe there
    assert omap.category[0, 1] == 3  # no steady state can hold: stuck


def _brute_force_safe_torque_min(p, wob, step):
    """The least u = k * step at which drilling is safe at ``wob``, by scanning up from T_s:
    u > T_s = μ_sb W_ob R_b (the rock cannot hold the bit: the quasi-equilibrium of the stuck
    bit is not real) and some steady state of u is stable (every eigenvalue of its Jacobian in
    Re < 0, numpy's dense solver, the Stribeck slope from the model's formula)."""
    ts = p.mu_static * wob * p.bit_radius
    c = p.top_damping + p.bit_damping
    g = p.stribeck_decay / p.stribeck_velocity
    for k in range(int(ts // step), int((ts + 50.0) / step)):
        u = k * step
        if u <= ts:
            continue
        for omega in pydrill.equilibrium_velocities(p, wob=wob, torque=u):
            mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-g * omega)
            assert abs(c * omega + wob * p.bit_radius * mu - u) < 1e-9 * u  # a steady state
            delta = wob * p.bit_radius * g * (p.mu_static - p.mu_coulomb) * np.exp(-g * omega)
            if np.max(st.eigenvalues(p, delta).real) < 0:
                return u
    raise AssertionError(f"no safe torque up to T_s + 50 N m at wob = {wob}")


@pytest.mark.parametrize("dof", [2, 4])
def test_safe_torque_min_against_a_brute_force_scan(dof):
    """``safe_torque_min`` is the least u with a stable steady state and u > T_s: at small
    W_ob the stable branch starts above T_s (the least safe u is its start), at large W_ob below
    it (the least safe u is T_s). The scan's resolution is ``step``; the map's own Ω sampling
    puts it above the true value by < 0.004 N m."""
    p = pydrill.preset("reduced-scale", dof=dof)
    wob = [2.0, 5.0, 20.0, 60.0, 160.0, 250.0]
    step = 0.005
    omap = operating_map(p, wob, [1.0])
    above_ts = 0
    for w, safe, ts in zip(wob, omap.safe_torque_min, omap.static_torque, strict=True):
        assert ts == pytest.approx(0.8 * w * 0.1, rel=1e-12)
        u = _brute_force_safe_torque_min(p, w, step)
        assert u - step <= safe <= u + step, (w, safe, u)
        above_ts += u > ts + 10 * step
    assert 0 < above_ts < len(wob)  # both cases: the stable branch's start, and T_s


@pytest.mark.parametrize("dof", [2, 4, 7])
def test_safe_torque_min_is_the_closed_form_edge_of_the_stable_branch(dof):
    """Exact, not sampled: the steady state is stable where the Stribeck slope δ(Ω) lies
    below δ_1, the first crossing (it falls with Ω), i.e. for Ω > Ω_1 = (v_s/γ) ln(δ(0)/δ_1);
    u(Ω) = (c_t + c_b) Ω + W_ob R_b μ(Ω) is least there, or at Ω_c where u' = 0, whichever is
    larger; safe drilling also needs u > T_s. Written from the model's formulas (DESIGN §1),
    checked to rounding; the first crossing's eigenvalues confirm the side."""
    p = pydrill.preset("reduced-scale", dof=dof)
    first = st.critical_deltas(p)[0]
    assert first.direction == 1  # the string is stable below δ_1
    g = p.stribeck_decay / p.stribeck_velocity
    c = p.top_damping + p.bit_damping
    wob = np.array([1.0, 3.0, 8.0, 15.0, 25.0, 40.0, 120.0])
    omap = operating_map(p, wob, [1.0])
    above = 0
    for w, safe in zip(wob, omap.safe_torque_min, strict=True):
        scale = w * p.bit_radius * (p.mu_static - p.mu_coulomb)
        omega_1 = max(0.0, np.log(scale * g / first.delta) / g)
        omega_c = max(0.0, np.log(scale * g / c) / g)
        om = max(omega_1, omega_c)
        u = c * om + w * p.bit_radius * (
            p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-g * om)
        )
        ts = p.mu_static * w * p.bit_radius
        assert safe == pytest.approx(max(u, ts), rel=1e-12, abs=1e-12), (w, safe, u, ts)
        above += u > ts
        if omega_1 > 0:  # just past Ω_1 stable, just before it not
            for sign in (-1, 1):
                delta = scale * g * np.exp(-g * omega_1 * (1 + sign * 1e-6))
                stable = np.max(st.eigenvalues(p, delta).real) < 0
                assert stable == (sign > 0), (w, sign)
    assert 0 < above < len(wob)  # both cases met: the branch's edge, and T_s


def _check_regimes_against_categories(p, data):
    """Each ``map --check`` point (simulated from rest, t_end 300 s) against its category in
    the same map (the grid's value at that point), by what the category means
    (pydrill.operating.CATEGORIES, docs/guide/stability.md): a stable steady state drills on
    from the equilibrium start; without one neither start ends steady; u > T_s cannot end
    stuck; u <= T_s without a stable steady state sticks (or sticks and slips near the line).
    With a stable steady state and u <= T_s the start decides (coexistence): nothing is
    asserted from rest. Returns the categories met."""
    names = data["categories"]
    assert names == list(CATEGORIES)
    wob, torque = np.array(data["wob"]), np.array(data["torque"])
    category = np.array(data["category"])
    met = set()
    for check in data["checks"]:
        w, u, regime = check["wob"], check["torque"], check["regime"]
        j, i = int(np.argmin(abs(wob - w))), int(np.argmin(abs(torque - u)))
        assert wob[j] == pytest.approx(w, rel=1e-12) and torque[i] == pytest.approx(u, rel=1e-12)
        code = int(category[i, j])
        met.add(code)
        name = names[code]
        stable = not name.startswith("no stable steady state")
        can_stick = "cannot stay stuck" not in name
        assert can_stick == (u <= 0.8 * w * 0.1), (w, u, name)
        where = (w, u, name, regime)
        assert regime in pydrill.REGIMES, where
        if stable:
            assert pydrill.equilibrium_velocities(p, wob=w, torque=u), where
            from_equilibrium = pydrill.simulate(
                p, wob=w, torque=u, initial="equilibrium", t_end=300.0, n_out=301
            ).regime
            assert from_equilibrium == "steady", (*where, from_equilibrium)
        else:
            assert regime != "steady", where
            if pydrill.equilibrium_velocities(p, wob=w, torque=u):
                from_equilibrium = pydrill.simulate(
                    p, wob=w, torque=u, initial="equilibrium", t_end=300.0, n_out=301
                ).regime
                assert from_equilibrium != "steady", (*where, from_equilibrium)
        if not can_stick:
            assert regime != "stuck", where
        elif not stable:
            assert regime in ("stuck", "stick-slip"), where
    return met


def _map_json(*args):
    out = subprocess.run(
        [sys.executable, "-m", "pydrill", "map", "--dof", "2", "--json", *args],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout)


def test_map_command(tmp_path):
    png = tmp_path / "map.png"
    # --check 4 puts every check on the map's 200 x 200 grid.
    data = _map_json("--check", "4", "--plot", str(png))
    assert len(data["category"]) == len(data["torque"])
    assert len(data["category"][0]) == len(data["wob"])
    assert len(data["checks"]) == 16
    assert abs(sum(data["fractions"].values()) - 1) < 1e-9
    assert png.stat().st_size > 20_000
    p = pydrill.preset("reduced-scale", dof=2)
    assert _check_regimes_against_categories(p, data) == {0, 1, 3}


def test_map_check_at_small_weights_meets_the_band_between_stuck_and_stable():
    """Below W_ob ≈ 30 N the stable branch starts above T_s: a band with neither a stable
    steady state nor a stuck bit (category 2) lies between them."""
    data = _map_json("--check", "4", "--wob-max", "20", "--torque-max", "2")
    p = pydrill.preset("reduced-scale", dof=2)
    assert _check_regimes_against_categories(p, data) == {0, 2, 3}


@pytest.mark.parametrize(
    ("wob", "torque", "error", "says"),
    [
        ([100.0], [float("nan"), 5.0], ValueError, "torque = nan is not allowed"),
        ([100.0], "5", TypeError, "torque must be a number"),
        ([], [5.0], ValueError, "wob is empty"),
        ([100.0, -3.0], [5.0], ValueError, "wob = -3 is not allowed: every wob must be > 0 N"),
        ([[100.0]], [5.0], TypeError, "wob must be a number or a 1-d sequence"),
    ],
)
def test_operating_map_refuses_a_bad_grid_by_name(wob, torque, error, says):
    with pytest.raises(error, match=says):
        operating_map(pydrill.preset("reduced-scale", dof=2), wob, torque)
