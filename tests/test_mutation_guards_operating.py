"""Mutation guards for pydrill/operating.py: the stable-torque intervals, the (W_ob, u) map and
the Hopf curve in (W_ob, u), each against something computed another way.

The intervals are checked against a scan in Ω: the steady state at Ω is stable when every
eigenvalue of its Jacobian (numpy's dense solver) has Re < 0, at the Stribeck slope
δ(Ω) = W_ob R_b (γ_b/v_f)(μ_sb − μ_cb) exp(−γ_b Ω/v_f), and holds u(Ω) = (c_r + c_b) Ω +
W_ob R_b μ_b(Ω) (DESIGN.md §2–3). The ends of each stable run of the scan are refined by
bisection on the same verdict, so the intervals are compared to near rounding, not to the
scan's step.
"""

import numpy as np
import pytest

import pydrill
from pydrill import stability as st
from pydrill.operating import hopf_curve_wu, operating_map, stable_torques
from pydrill.stability import Crossing


def _gamma(p):
    return p.stribeck_decay / p.stribeck_velocity


def _scale(p):
    """R_b (γ_b/v_f)(μ_sb − μ_cb): δ per unit W_ob at Ω = 0."""
    return p.bit_radius * _gamma(p) * (p.mu_static - p.mu_coulomb)


def _slope(p, w, omega):
    """δ(Ω, W_ob) from the model's formula, not pydrill.stability.stribeck_slope."""
    return w * _scale(p) * np.exp(-_gamma(p) * omega)


def _torque(p, w, omega):
    """u(Ω) = (c_r + c_b) Ω + W_ob R_b μ_b(Ω): the steady state's surface torque."""
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-_gamma(p) * omega)
    return (p.top_damping + p.bit_damping) * omega + w * p.bit_radius * mu


def _eigen_verdict(p, w):
    """Stable at Ω: the largest real part of numpy's eigenvalues of the Jacobian is < 0."""
    return lambda omega: bool(
        np.max(np.linalg.eigvals(st.jacobian(p, _slope(p, w, omega))).real) < 0
    )


def _count_verdict(p, w, crossings):
    """Stable at Ω by the crossings given (the public counting rule, any list of them)."""
    return lambda omega: int(st.unstable_count(crossings, _slope(p, w, omega))) == 0


def _edge(stable, inside, outside):
    """The Ω where the verdict changes between ``inside`` (stable) and ``outside``, by
    bisection to rounding; returned on the stable side."""
    for _ in range(80):
        mid = 0.5 * (inside + outside)
        if mid in (inside, outside):
            break
        inside, outside = (mid, outside) if stable(mid) else (inside, mid)
    return inside


def _scanned_intervals(p, w, stable, omega_max, n=600):
    """The u-range of every run of stable Ω on a grid from 0+ to ``omega_max`` (beyond the
    last change of verdict: a run reaching it is unbounded in u), ends refined by bisection
    (a run from the grid's first point starts at Ω -> 0+, where u is T_s)."""
    omega = np.concatenate([np.geomspace(1e-12, 1e-3, 30), np.linspace(2e-3, omega_max, n)])
    flags = np.array([stable(om) for om in omega])
    intervals = []
    i = 0
    while i < omega.size:
        if not flags[i]:
            i += 1
            continue
        j = i
        while j + 1 < omega.size and flags[j + 1]:
            j += 1
        start = _edge(stable, omega[i], omega[i - 1]) if i > 0 else 0.0
        end = _edge(stable, omega[j], omega[j + 1]) if j + 1 < omega.size else omega[j]
        # u is convex in Ω: its least value on the run by ternary search, its greatest at an end.
        a, b = start, end
        for _ in range(100):
            m1, m2 = a + (b - a) / 3, b - (b - a) / 3
            a, b = (a, m2) if _torque(p, w, m1) < _torque(p, w, m2) else (m1, b)
        u = _torque(p, w, np.array([start, end, a]))
        intervals.append((float(u.min()), np.inf if j + 1 == omega.size else float(u.max())))
        i = j + 1
    return intervals


def _omega_max(p, w, deltas):
    """An Ω beyond every change of verdict: below the smallest positive crossing δ and the
    fold's c_r + c_b (where u turns), by 5 rad/s."""
    top = _slope(p, w, 0.0)
    small = min([d for d in deltas if d > 0] + [p.top_damping + p.bit_damping])
    return max(np.log(top / small) / _gamma(p), 0.0) + 5.0


def _assert_same(got, want, where):
    assert len(got) == len(want), (where, got, want)
    for (lo, hi), (blo, bhi) in zip(got, want, strict=True):
        assert lo == pytest.approx(blo, rel=1e-7), (where, got, want)
        assert hi == pytest.approx(bhi, rel=1e-7), (where, got, want)


def _exact_wob(p, delta):
    """A W_ob whose δ(0) is exactly ``delta`` in floats (searched among neighbouring floats)."""
    w = delta / _scale(p)
    for candidate in [w, *(np.nextafter(w, s * np.inf) for s in (-1, 1))]:
        for _ in range(8):
            if float(st.stribeck_slope(p, candidate, 0.0)) == delta:
                return float(candidate)
            candidate = np.nextafter(candidate, np.inf if candidate > w else -np.inf)
    raise AssertionError(f"no float W_ob with delta(0) = {delta}")


_STRINGS = {
    # The paper's string: stable only below the first Hopf δ_1, far below the fold.
    "reduced-scale": ({}, [0.2, 3.0, 40.0, 250.0]),
    # v_f != 1: every Ω of the law scales with v_f/γ_b (the preset's v_f = 1 hides it).
    "slow-stribeck": ({"stribeck_velocity": 2.5}, [0.2, 3.0, 40.0]),
    # A well-damped string whose first crossing is the fold δ = c_r + c_b: the stable branch
    # starts where u turns (Ω_c), or at T_s when δ(0) lies between c_r and c_r + c_b.
    "fold-first": ({"top_damping": 0.01, "bit_damping": 0.1, "dampings": [0.3]}, [2.0, 40.0]),
}


@pytest.mark.parametrize("name", list(_STRINGS))
def test_stable_torques_against_an_eigenvalue_scan(name):
    """Each string at a W_ob with δ(0) below every crossing (stable from Ω -> 0+: the interval
    starts at T_s = μ_sb W_ob R_b), and at larger ones where the branch starts at a crossing
    or, on the fold-first string, where u turns."""
    changes, wobs = _STRINGS[name]
    p = pydrill.preset("reduced-scale", dof=2).replace(**changes)
    crossings = st.critical_deltas(p)
    deltas = [c.delta for c in crossings]
    assert np.isclose(_torque(p, 3.0, 0.7), pydrill.equilibrium_torque(p, 3.0, 0.7), rtol=1e-12)
    for w in wobs:
        got = stable_torques(p, w, crossings)
        want = _scanned_intervals(p, w, _eigen_verdict(p, w), _omega_max(p, w, deltas))
        _assert_same(got, want, (name, w))


def test_stable_torques_when_the_first_crossing_sits_at_zero_velocity():
    """δ(0) exactly δ_1 (a W_ob found among floats): the crossing lies at Ω = 0, the stuck
    bit, not a steady state; every Ω > 0 has δ < δ_1 and is stable (numpy's eigenvalues say
    so just above 0), so there is one interval, from T_s up, not an empty one at T_s too."""
    p = pydrill.preset("reduced-scale", dof=2)
    crossings = st.critical_deltas(p)
    w = _exact_wob(p, crossings[0].delta)
    assert _eigen_verdict(p, w)(1e-9)
    assert stable_torques(p, w, crossings) == [(p.static_torque(w), np.inf)]


def test_stable_torques_follow_any_crossings_given(monkeypatch):
    """The interval arithmetic in general, as stable_torques' docstring states it: on a piece
    of Ω with no crossing, u(Ω) is convex with its least value at Ω_c (δ(Ω_c) = c_r + c_b)
    or at an end, its greatest at an end. A string's own crossings never make a piece stable
    at δ > c_r + c_b (its fold), so there every stable piece lies where u rises and the
    least/greatest are simply its ends; these made-up crossings (stable for δ in (0.95, δ(0)),
    (0.6, 0.9), (0.1, 0.3) around c_r + c_b = 0.19, and below 0.001) reach the other cases:
    a piece where u falls, one holding Ω_c, one from Ω = 0 entirely below T_s. (They have no
    fold, so the public functions refuse them as another string's: that check is lifted.)"""
    p = pydrill.preset("reduced-scale", dof=2)
    monkeypatch.setattr(pydrill.operating, "_check_crossings", lambda params, c: list(c))
    made_up = [
        Crossing("hopf", d, 1.0, s, 2)
        for d, s in [(0.001, 1), (0.1, -1), (0.3, 1), (0.6, -1), (0.9, 1), (0.95, -1)]
    ]
    # Several W_ob: each piece's count is read inside it, not at an end, where δ(Ω_k)
    # rounds to either side of δ_k (above at 1 to 3 of these six cuts at each W_ob here).
    scanned = {}
    for w in [40.0, 48.0, 52.0, 56.0, 60.0]:
        stable = _count_verdict(p, w, made_up)
        got = stable_torques(p, w, made_up)
        scanned[w] = _scanned_intervals(p, w, stable, _omega_max(p, w, [0.001]), n=1500)
        assert len(scanned[w]) == 4
        _assert_same(got, scanned[w], w)
    # At W_ob = 40 N (δ(0) = 1.08, T_s = 3.2), the least safe u: a stable steady state with
    # u > T_s. Only the last piece has one (the three others lie below T_s: the first
    # reaches T_s only in the limit Ω -> 0+).
    w, want = 40.0, scanned[40.0]
    ts = p.static_torque(w)
    assert all(hi <= ts for lo, hi in want[:3]) and want[3][0] > ts
    # At u = T_s: the first piece's u rises to T_s only as Ω -> 0+, the stuck bit, and no
    # other stable piece holds T_s: no stable steady state (the map once said there was one).
    torque = [ts, 0.5 * sum(want[0]), 0.5 * sum(want[2]), 3.3, 3.5]
    omap = operating_map(p, [w], torque, crossings=made_up)
    assert list(omap.category[:, 0]) == [3, 1, 1, 2, 0]
    assert omap.safe_torque_min[0] == pytest.approx(want[3][0], rel=1e-7)


def test_map_at_the_static_torque_has_no_steady_state_when_the_branch_starts_there():
    """At a small W_ob (δ(0) below δ_1 and c_r + c_b) every steady state is stable and u(Ω)
    rises from T_s at Ω -> 0+; u = T_s itself is held by none (Ω = 0 is the stuck bit, not a
    steady state): stability() finds no steady state there, and the map must agree (it
    claimed a stable one: the interval's lower end was taken as reached)."""
    p = pydrill.preset("reduced-scale", dof=2)
    w = 0.2
    ts = p.static_torque(w)
    torque = [ts * (1 - 1e-9), ts, ts * (1 + 1e-6)]
    omap = operating_map(p, [w], torque)
    for u, code in zip(torque, omap.category[:, 0], strict=True):
        points = st.stability(p, w, torque=u)
        has_stable = any(pt.stable for pt in points)
        expected = {(True, False): 0, (True, True): 1, (False, False): 2, (False, True): 3}
        assert code == expected[(has_stable, u <= ts)], u
    assert list(omap.category[:, 0]) == [3, 3, 0]
    assert omap.safe_torque_min[0] == ts  # safe just above T_s, the branch's start


def test_operating_map_refuses_zero_wob_by_name():
    with pytest.raises(ValueError, match="wob = 0 is not allowed: every wob must be > 0 N"):
        operating_map(pydrill.preset("reduced-scale", dof=2), [10.0, 0.0], [1.0])


def _boundary_wob(p, delta, omega):
    """W_ob with δ(Ω, W_ob) = delta, from the model's formula."""
    return delta * np.exp(_gamma(p) * omega) / _scale(p)


@pytest.mark.parametrize("v_f", [1.0, 2.5])
def test_hopf_curve_keeps_exactly_the_velocities_with_wob_up_to_1e300(v_f):
    """The curve is cut where its W_ob reaches 1e300 N: Ω* = (v_f/γ_b) ln(1e300 R_b (γ_b/v_f)
    (μ_sb − μ_cb)/δ). Points a quarter of v_f/γ_b either side of Ω* are kept or dropped;
    at Ω = 0 its torque is the limit T_s = μ_sb W_ob R_b (the core refuses Ω = 0)."""
    p = pydrill.preset("reduced-scale", dof=2).replace(stribeck_velocity=v_f)
    delta = st.critical_deltas(p)[0].delta
    star = (300 * np.log(10) + np.log(_scale(p) / delta)) / _gamma(p)
    step = 0.25 / _gamma(p)
    near = [star - 20 * step, star - step, star + step, star + 20 * step]
    omega = np.array([0.0, 0.5, 100.0, *near])
    kept = omega[omega < star]
    w, u = hopf_curve_wu(p, delta, omega)
    assert w.shape == u.shape == kept.shape
    np.testing.assert_allclose(w, _boundary_wob(p, delta, kept), rtol=1e-9)
    assert np.all(w <= 1e300)
    assert u[0] == pytest.approx(p.mu_static * w[0] * p.bit_radius, rel=1e-15)
    assert u[0] == pytest.approx(pydrill.equilibrium_torque(p, w[0], 1e-9), rel=1e-8)
    for wi, ui, om in zip(w[1:3], u[1:3], kept[1:3], strict=True):
        assert ui == pytest.approx(_torque(p, wi, om), rel=1e-12)


def test_another_strings_crossings_are_refused_as_stability_refuses_them():
    """Crossings of a string with other end damping (its fold elsewhere than c_r + c_b) gave
    a map of neither string; stability() refused them, the map and intervals did not."""
    p = pydrill.preset("reduced-scale", dof=2)
    other = st.critical_deltas(p.replace(bit_damping=2 * p.bit_damping))
    for call in (
        lambda: stable_torques(p, 50.0, other),
        lambda: operating_map(p, [50.0], [5.0], crossings=other),
        lambda: st.stability(p, 50.0, torque=5.0, crossings=other),
    ):
        with pytest.raises(ValueError, match="not this string's"):
            call()
    own = st.critical_deltas(p)  # and its own still pass, as a list or any iterable
    assert stable_torques(p, 50.0, iter(own)) == stable_torques(p, 50.0, own)
