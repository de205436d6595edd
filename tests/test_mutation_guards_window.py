"""Guards from a mutation audit of pydrill/window.py (the operating window), drilling.py (a real
string drilled ahead) and reproduce_analysis.py (the stability edges the paper report
compares): behaviour no other test would have noticed breaking, each checked against something
independent of the code under test (the point-by-point grid, numpy's eigenvalues, the
definitions in DESIGN.md, a hand computation)."""

import itertools
from pathlib import Path

import numpy as np
import pytest

import pydrill
from pydrill import stability as st
from pydrill.stability import stability
from pydrill.tally import load_tally
from pydrill.window import RPM, Limits, operating_window, parse_depths, window_against_depth

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


@pytest.fixture(scope="module")
def string():
    return load_tally(PAPER).at_depth(1000.0).to_params(lump=10)


def test_min_rpm_is_the_least_safe_rpm_of_each_column(string):
    """Window.min_rpm: the least rpm of the grid whose cell is safe, per W_ob, NaN where none
    is; counted here from ``safe`` directly, on grids in any order (a decreasing grid's
    first safe rpm, its largest, was answered)."""
    wob = np.array([2e4, 6e4, 1.2e5, 2.5e5, 1e7])
    increasing = np.linspace(2.0, 200.0, 60)
    shuffled = np.random.default_rng(3).permutation(increasing)
    for rpm in (increasing, increasing[::-1], shuffled):
        w = operating_window(string, wob, rpm)
        got = w.min_rpm()
        for j in range(wob.size):
            safe = rpm[w.safe[:, j]]
            if safe.size:
                assert got[j] == safe.min()
            else:
                assert np.isnan(got[j])
        # The grid has columns safe over a band of rpm (its least is what the driller needs)
        # and a weight no rpm of the grid frees.
        assert np.isnan(got[-1])
        assert np.sum(w.safe[:, 1]) > 1 and got[1] < rpm[w.safe[:, 1]].max()
    ref = operating_window(string, wob, increasing).min_rpm()
    np.testing.assert_array_equal(operating_window(string, wob, shuffled).min_rpm(), ref)


def test_the_stall_edge_at_zero_rpm_is_its_limit(string):
    """At 0 rpm (allowed: "0 is the limit of the edge there") the stall edge is the limit of
    cΩ / (R_b Δμ (1 − e^{−gΩ})) as Ω → 0, c / (R_b Δμ g), computed here by hand, and the
    edge is continuous there."""
    p = string
    lim = Limits.of(p)
    g = p.stribeck_decay / p.stribeck_velocity
    by_hand = (p.top_damping + p.bit_damping) / (p.bit_radius * (p.mu_static - p.mu_coulomb) * g)
    assert float(lim.wob_max_unstuck(0.0)) == pytest.approx(by_hand, rel=1e-12)
    assert float(lim.wob_max_unstuck(1e-6)) == pytest.approx(by_hand, rel=1e-6)
    # And it is what the definition gives just above 0 rpm: u > T_s below it, not above.
    rpm = 1e-3
    edge = float(lim.wob_max_unstuck(rpm))
    for factor, unstuck in ((0.999, True), (1.001, False)):
        u = pydrill.equilibrium_torque(p, factor * edge, rpm * RPM)
        assert (u > p.static_torque(factor * edge)) == unstuck


def test_steady_torque_is_the_definition(string):
    """Limits.torque: u = (c_r + c_b) Ω + W_ob R_b μ_b(Ω), as equilibrium_torque gives it."""
    lim = Limits.of(string)
    for wob, rpm in ((3e4, 60.0), (1.5e5, 20.0), (5e4, 180.0)):
        u = pydrill.equilibrium_torque(string, wob, rpm * RPM)
        assert float(lim.torque(wob, rpm)) == pytest.approx(u, rel=1e-12)


def _safe(p, wob, rpm):
    """Safe by the point-by-point grid (eigenvalue count and u > T_s, no closed form)."""
    return bool(operating_window(p, [wob], [rpm]).safe[0, 0])


def _stable(p, wob, rpm):
    delta = float(st.stribeck_slope(p, wob, rpm * RPM))
    return bool(np.all(st.eigenvalues(p, delta).real < 0))


def test_every_edge_window_against_depth_reports_is_the_one_it_names():
    """window_against_depth: each field at each depth is the edge of its name, checked
    against the grid's verdict just inside and just outside it, for the lumped string the
    call asked for (``lump``)."""
    tally = load_tally(PAPER)
    depths = [1500.0, 4000.0]
    rpm = np.array([20.0, 45.0])
    wob = np.array([3e4, 1.2e5])
    lump = 10
    dw = window_against_depth(tally, depths, rpm, wob, lump=lump)
    eps = 2e-3
    for k, d in enumerate(depths):
        p = tally.at_depth(d).to_params(lump=lump)
        assert dw.dof[k] == p.dof  # the lumped string, not the joint-by-joint one
        assert dw.dof[k] < tally.at_depth(d).to_params().dof
        for i, r in enumerate(rpm):
            w = dw.wob_max[k, i]
            assert _safe(p, w * (1 - eps), r) and not _safe(p, w * (1 + eps), r)
            ws = dw.wob_max_stable[k, i]
            assert _stable(p, ws * (1 - eps), r) and not _stable(p, ws * (1 + eps), r)
            wu = dw.wob_max_unstuck[i]
            for f, unstuck in ((1 - eps, True), (1 + eps, False)):
                u = pydrill.equilibrium_torque(p, f * wu, r * RPM)
                assert (u > p.static_torque(f * wu)) == unstuck
        for j, wb in enumerate(wob):
            r = dw.rpm_min[k, j]
            assert _safe(p, wb, r * (1 + eps)) and not _safe(p, wb, r * (1 - eps))
            rs = dw.rpm_min_stable[k, j]
            assert _stable(p, wb, rs * (1 + eps)) and not _stable(p, wb, rs * (1 - eps))
            ru = dw.rpm_min_unstuck[j]
            for f, unstuck in ((1 + eps, True), (1 - eps, False)):
                u = pydrill.equilibrium_torque(p, wb, f * ru * RPM)
                assert (u > p.static_torque(wb)) == unstuck
    # The chosen points have both edges binding somewhere, so that a mix-up shows: the
    # stall edge is the tighter at the heavier weight and slow rpm, the stick-slip one at 4 km.
    assert np.any(dw.wob_max < dw.wob_max_stable[:, :] * (1 - 1e-6))
    assert np.any(dw.rpm_min > dw.rpm_min_stable * (1 + 1e-6))
    assert np.any(dw.rpm_min_unstuck[None, :] < dw.rpm_min * (1 - 1e-6))


def test_a_depth_range_needs_two_depths_at_least():
    """ "start:stop:count" includes both ends, so a count of 1 would drop ``stop``."""
    assert parse_depths("500m:900m:2") == pytest.approx([500.0, 900.0])
    with pytest.raises(ValueError, match=r"count must be 2 \.\.\. 500"):
        parse_depths("500m:900m:1")
    with pytest.raises(ValueError, match=r"count must be 2 \.\.\. 500"):
        parse_depths("500m:900m:501")
    assert len(parse_depths("500m:900m:500")) == 500


# --- drilling ahead ---------------------------------------------------------------------------


def test_drilling_ahead_keeps_its_books():
    """drill_ahead's record against the definitions: the bit goes down at the rate of
    penetration (depth = depth_0 + rop t), a stand of ``lump`` joints at a time (each stand's
    span, the last one cut at depth_end), a connection at each stand's end that adds one
    element with that stand's compliance and inertia (lump joints in series)."""
    from pydrill.drilling import drill_ahead
    from pydrill.tally import load_tally

    tally = load_tally(PAPER)
    pipe = next(s for s in tally.sections if s.kind == "drill-pipe")
    lump, rop = 5, 0.25
    stand = lump * pipe.length
    d0 = tally.at_depth(1000.0).length
    end = d0 + 2.4 * stand
    run = drill_ahead(
        tally,
        depth_start=1000.0,
        depth_end=end,
        rop=rop,
        wob=6e4,
        torque=8e3,
        lump=lump,
        initial="equilibrium",
        n_out_per_stand=50,
    )
    np.testing.assert_allclose(run.depth, d0 + rop * run.t, rtol=1e-12)
    assert run.depth[-1] == pytest.approx(end, rel=1e-12) and run.depth.max() <= end + 1e-9
    spans = [(a, b) for a, b, _ in run.regimes]
    assert len(spans) == 3 and spans[0][0] == pytest.approx(d0)
    np.testing.assert_allclose([b - a for a, b in spans], [stand, stand, 0.4 * stand])
    assert all(b == c for (_, b), (c, _) in itertools.pairwise(spans))
    assert spans[-1][1] == pytest.approx(end)
    assert len(run.connections) == len(run.strings) - 1 == 2
    for (t, depth, dof), (_, b), old, new in zip(
        run.connections, spans[:-1], run.strings[:-1], run.strings[1:], strict=True
    ):
        assert depth == pytest.approx(b) and t == pytest.approx((b - d0) / rop)
        assert dof == new.dof == old.dof + 1
        compliance = sum(1 / k for k in new.stiffnesses) - sum(1 / k for k in old.stiffnesses)
        assert compliance == pytest.approx(lump / pipe.joint_stiffness(), rel=1e-9)
        assert sum(new.inertias) - sum(old.inertias) == pytest.approx(
            lump * pipe.joint_inertia(), rel=1e-9
        )


# --- the stability edges of the paper's report -------------------------------------------------


@pytest.mark.parametrize("name", ["reduced-scale", "real-string"])
def test_fig10s_hurwitz_roots_are_where_eigenvalues_cross_the_axis(name):
    """fig10's roots of Δ₂ = a₂a₁ − a₀ (n' = 3): the two Hopf crossings H₂ and H₁ the
    crossings give, each a δ where the Jacobian has a pair of eigenvalues on the imaginary
    axis (checked with numpy's eigenvalues of the dense Jacobian)."""
    from pydrill import reproduce_analysis as ra
    from pydrill.stability import eigenvalues

    n = ra.fig10(name)
    p = pydrill.preset(name, dof=2)
    roots = n["hurwitz_roots"]
    assert roots == pytest.approx([n["h2_delta"], n["h1_delta"]], rel=1e-9)
    for delta in roots:
        ev = eigenvalues(p, delta)
        pair = ev[np.argsort(np.abs(ev.real))[:2]]
        assert np.all(np.abs(pair.real) < 1e-8 * np.abs(pair.imag))


def test_string_summary_counts_what_eigenvalues_count():
    """string_summary of the paper's n' = 7 string: its destabilising Hopf crossings are those
    across which numpy's count of eigenvalues with Re > 0 goes up, and max_unstable is the
    largest such count over δ (counted just past every crossing)."""
    from pydrill import reproduce_analysis as ra
    from pydrill.stability import critical_deltas, eigenvalues

    p = pydrill.preset("reduced-scale", dof=4)
    crossings = critical_deltas(p)
    s = ra.string_summary(p, crossings)

    def count(delta):
        return int(np.sum(eigenvalues(p, delta).real > 0))

    up = [count(c.delta * (1 + 1e-6)) - count(c.delta * (1 - 1e-6)) for c in crossings]
    hopf = [u for c, u in zip(crossings, up, strict=True) if c.type == "hopf"]
    assert s["hopf"] == len(hopf) and s["destabilising"] == sum(u > 0 for u in hopf)
    assert 0 < s["destabilising"] < s["hopf"]  # both kinds, so a mix-up shows
    counts = [count(c.delta * (1 + 1e-6)) for c in crossings]
    assert s["max_unstable"] == max(counts) > counts[-1]


def test_fig12s_first_hopf_weights_are_on_the_first_hopf_curve():
    """hopf_curves' W_ob at each torque: a steady state there has the Stribeck slope of the
    first destabilising crossing, δ_1 (stability's, computed afresh at that (W_ob, u))."""
    from pydrill import reproduce_analysis as ra
    from pydrill.stability import critical_deltas

    p = pydrill.preset("reduced-scale", dof=4)
    crossings = critical_deltas(p)
    first = next(c for c in crossings if c.type == "hopf" and c.direction > 0)
    found = ra.hopf_curves(p, crossings)["first_hopf_wob_at_torque"]
    assert len(found) == 5 and all(len(ws) == 1 for ws in found.values())
    for torque, ws in found.items():
        pts = stability(p, ws[0], torque=float(torque))
        assert min(abs(q.delta / first.delta - 1) for q in pts) < 1e-5


def test_fig10s_eq7_row_is_expected_as_the_corrected_eq7_gives_it():
    """Eq. (7) corrected (the top drive damped by its own motion): the row the report prints
    as expected, by hand, and the Jacobian's row agree."""
    from pydrill import reproduce_analysis as ra

    n = ra.fig10("reduced-scale")
    p = pydrill.preset("reduced-scale", dof=2)
    jr, kt, ct, cr = p.inertias[0], p.stiffnesses[0], p.dampings[0], p.top_damping
    hand = [-(ct + cr) / jr, -kt / jr, ct / jr]
    assert n["eq7_expected"] == pytest.approx(hand, rel=1e-12)
    assert n["eq7_row"] == pytest.approx(n["eq7_expected"], rel=1e-12)
