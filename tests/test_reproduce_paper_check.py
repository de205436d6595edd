"""The report of ``pydrill reproduce`` against the paper's text (helper paper, session 38).

Each test holds a statement of the report, or a curve it draws, against something found
another way: numpy's eigenvalues of the Jacobian (Theorem 5's Eq. 48 holds where every other
eigenvalue is stable), the paper's own n' = 3 coefficients of Eq. (50) written out here, the
closed-form branch u(Ω) = (c_r + c_b)Ω + W_ob R_b μ_b(Ω), or a verdict worked out here from
the numbers the report quotes (fed numbers that say otherwise, the report must say so too).
"""

from __future__ import annotations

import numpy as np

from pydrill import preset
from pydrill import reproduce_analysis as ra
from pydrill import reproduce_report as rr
from pydrill import reproduce_report_analysis as rra
from pydrill import reproduce_report_beyond as rrb
from pydrill.bifurcation import branch
from pydrill.reproduce_atlases import atlas_plan
from pydrill.stability import critical_deltas, eigenvalues

# --- Theorem 5 (Eq. 48) at the multiple Hopf crossings ---


def test_theorem5_holds_whole_only_where_numpy_finds_every_other_eigenvalue_stable():
    """Eq. (48) asks Δ_1 … Δ_{n'−2} > 0 and a_0 > 0 besides Δ_{n'−1} = 0: a pair on the axis
    and every other eigenvalue stable. numpy's eigenvalues at each Hopf δ_k of the n' = 7
    string say where that is: at the first crossing only (the report once said the whole
    criterion held at all five)."""
    p = preset("reduced-scale", dof=4)
    cs = critical_deltas(p)
    hopf = [c for c in cs if c.type == "hopf"]
    by_numpy = []
    for c in hopf:
        ev = eigenvalues(p, c.delta)
        others = ev[np.abs(np.abs(ev) - c.frequency) > 1e-6 * c.frequency]  # off the pair
        assert len(others) == len(ev) - 2
        if np.all(others.real < 0):
            by_numpy.append(c.delta)
    assert len(hopf) == 5 and by_numpy == [hopf[0].delta]  # so the count below can be wrong
    h = ra.hurwitz_check(p, cs)
    assert h["sign_changes"] == 5
    np.testing.assert_allclose(h["theorem5_deltas"], by_numpy, rtol=1e-12)
    text = rrb._theorem5_rest(h)
    assert "Δ_1 … Δ_5 > 0 and a_0 > 0" in text  # n' − 2 = 5
    assert f"holds at 1 of them (δ = {rr.g(hopf[0].delta, 4)})" in text
    # The whole paragraph: the sign change of Δ_6 is only the Hurwitz part of the criterion.
    n = {"strings": ra.paper_strings()}
    beyond = "\n".join(rrb._beyond(n))
    assert "the Hurwitz part of the paper's own criterion of Theorem 5 holds at each" in beyond
    assert "holds at 1 of them" in beyond
    # n' = 3: H₁ (δ = 0.2305 > c_r + c_b) has a₀ < 0, so Eq. (48) fails there (Fig. 10 text).
    p2 = preset("reduced-scale", dof=2)
    h2 = ra.hurwitz_check(p2, critical_deltas(p2))
    assert h2["hopf"] == 2 and len(h2["theorem5_deltas"]) == 1
    assert h2["theorem5_deltas"][0] < 0.19 < max(c.delta for c in critical_deltas(p2))


# --- the head table and Section 3 verdicts ---


def _head_numbers(entries: int, stable: bool) -> dict:
    """The least ``head`` reads, with the Fig. 7 entries and the Fig. 9 stability given."""
    run = {"regime": "steady", "period": None, "bit_max": 1.0}
    hb = {"type": "HB", "wob": 137.0, "lyapunov": 0.1}
    return {
        "fig04": {"exact": {"regime": "stick-slip", "period": 17.5, "bit_max": 67.0}},
        "fig05": {"interval": {"lower": 55.0, "upper": 113.0}},
        "fig06b_band": {"points": 1, "wob_lo": 70.0, "wob_hi": 100.0},
        "fig07": {"loaded": {"regime": "stuck"}, "entries": entries},
        "fig08": {"static_torque": 8.0, "visits": [{"torque_out": 8.0}]},
        "fig09": {"run": run, "omega": 33.16, "stable": stable},
        "fig10a": {"h2_delta": 0.0107584},
        "fig10b": {"h2_delta": 327.086},
        **{f"fig11{k}": {"points": [hb]} for k in "abd"},
        "fig11c": {"points": [hb], "first_hopf": hb, "fold": {"wob": 145.0}},
        "strings": {"dof4": {"fig12": {"curves": [{}] * 5}}},
    }


def _head_row(lines: list[str], figure: str) -> str:
    (row,) = [x for x in lines if x.startswith(f"| {figure} |")]
    return row


def test_head_table_quotes_fig7s_entries_and_fig9s_stability_as_computed():
    """Rows 7 and 9 once said "one entry into Σ̃" and "stable" whatever the simulation and
    the analysis found."""
    summary = {"pydrill_version": "x", "quick": True, "wall_time": 0.0}
    lines = rra.head(_head_numbers(1, True), summary)
    assert _head_row(lines, "7").endswith("stuck, one entry into Σ̃ |")
    assert _head_row(lines, "9").endswith("rad/s, stable |")
    lines = rra.head(_head_numbers(3, False), summary)
    assert _head_row(lines, "7").endswith("stuck, 3 entries into Σ̃ |")
    assert _head_row(lines, "9").endswith("rad/s, UNSTABLE |")


def _fig4_numbers(stable: bool, near: str) -> dict:
    sim = {
        "regime": "stick-slip",
        "period": 17.54,
        "bit_min": 0.0,
        "bit_max": 67.1,
        "bit_mean": 13.4,
        "top_mean": 12.5,
        "bit_top_ratio": 5.4,
        "stuck_fraction": 0.7,
        "static_torque": 8.0,
        "window": [150.0, 300.0],
    }
    eq = {"omega": 17.37, "delta": 4.4e-7 if stable else 0.02, "delta_1": 0.0108}
    eq.update(stable=stable, spectral_abscissa=-0.016 if stable else 0.01)
    return {
        "fig04": {
            "exact": sim,
            "karnopp": {**sim, "period": 17.55},
            "first_switches": [{"t": 15.2}, {"t": 20.2}],
            "steady_state": eq,
            "from_equilibrium": {"regime": near},
        }
    }


def test_fig4_calls_the_steady_state_stable_only_when_the_analysis_does():
    """δ = 4.4e-7 < δ₁ (stable, a start near it drills on): stick-slip is a second attractor.
    δ = 0.02 > δ₁ (unstable, as numpy's count of the n' = 7 string says there): not that."""
    p = preset("reduced-scale", dof=4)
    assert np.max(eigenvalues(p, 0.02).real) > 0 > np.max(eigenvalues(p, 4.4e-7).real)
    text = "\n".join(rr._fig4(_fig4_numbers(True, "steady")))
    assert "is linearly stable (δ = 4.4e-07 < δ₁" in text and "second attractor" in text
    text = "\n".join(rr._fig4(_fig4_numbers(False, "stick-slip")))
    assert "is linearly UNSTABLE (δ = 0.02 ≥ δ₁" in text and "second attractor" not in text
    text = "\n".join(rr._fig4(_fig4_numbers(True, "stick-slip")))
    assert "yet started near it the bit ends stick-slip" in text
    assert "second attractor" not in text


def test_fig5_judges_the_papers_claim_on_the_stuck_time_not_the_period():
    """The paper gives no stick-slip period; it says (Section 3.2) the smaller W_ob, the less
    time stuck. The report once credited the paper with "the period grows with W_ob". Here
    the period grows while the stuck time a cycle (period × stuck fraction) falls: 3.0 s at
    90 N, 2.4 s at 100 N."""
    orbits = {
        "90": {"regime": "stick-slip", "period": 5.0, "stuck_fraction": 0.6},
        "100": {"regime": "stick-slip", "period": 6.0, "stuck_fraction": 0.4},
        "120": {"regime": "stuck", "period": None, "stuck_fraction": 1.0},
    }
    text = rr._period_verdict({"orbits": orbits})
    assert text.startswith("The stick-slip period grows with W_ob (5 s at 90 N, 6 s at 100 N)")
    assert "as the paper says" not in text
    assert text.endswith("the time stuck a cycle is 3 s at 90 N, 2.4 s at 100 N — NOT as it says")
    orbits["100"]["stuck_fraction"] = 0.6  # 3.6 s a cycle: longer at the larger W_ob
    assert rr._period_verdict({"orbits": orbits}).endswith("3.6 s at 100 N — as it says")


def test_fig7_and_fig9_differences_follow_the_simulations():
    """Fig. 7: "the single entry it describes" only with one entry that stays stuck; Fig. 9:
    "never sticks again" only with no stick event, "None" only when steady and stable."""
    f7 = {
        "rest": {"regime": "stuck"},
        "loaded": {"regime": "stuck"},
        "static_torque": 12.8,
        "start_omega": 17.37,
        "t_in": 0.18,
        "entries": 1,
        "final_reaction_torque": 8.37,
        "quasi_equilibrium_twist": 113.7,
        "quasi_equilibrium_real": True,
    }
    assert "shows the single entry it describes" in "\n".join(rr._fig7({"fig07": f7}))
    text = "\n".join(rr._fig7({"fig07": {**f7, "entries": 2}}))
    assert "enters Σ̃ **2 times**" in text and "does NOT show the single entry" in text
    run = {"regime": "steady", "period": None, "bit_min": 33.0, "bit_max": 33.3}
    run.update(bit_mean=33.16, stuck_fraction=0.0, window=[150.0, 300.0])
    f9 = {"run": run, "first_slip": 5.93, "stick_events_total": 0, "settled_1pct": 143.0}
    f9.update(omega=33.16, delta=1.2e-13, delta_1=0.0108, stable=True, spectral_abscissa=-0.016)
    text = "\n".join(rr._fig9({"fig09": f9}))
    assert "never sticks again (0 stick events)" in text and "**Differences.** None." in text
    bad = {**f9, "run": {**run, "regime": "stick-slip"}, "stick_events_total": 4}
    text = "\n".join(rr._fig9({"fig09": bad}))
    assert "never sticks again" not in text and "sticks again 4 times" in text
    assert "**Differences.** The paper's steady drilling is NOT reproduced" in text


# --- the figures ---


def test_fig10_title_says_the_printed_delta2_has_no_positive_root():
    """Eq. (50)'s printed Δ₂ = a₁ − a₂ − a₀ with the paper's coefficients (d_b = −δ) written
    out here is linear in δ with a negative root for Eq. (14): no positive root (the title
    said "no root")."""
    jr, jb, kt, ct, cr, cb = 0.518, 0.0318, 0.073, 1e-4, 0.18, 0.01

    def printed(delta):
        d = -delta
        a2 = (jr * (cb + ct + d) + jb * (cr + ct)) / (jb * jr)
        a1 = (cb * (cr + ct) + ct * (cr + d) + d * cr + kt * (jb + jr)) / (jb * jr)
        a0 = kt / (jb * jr) * (cb + cr + d)
        return a1 - a2 - a0

    from pydrill.reproduce_plots import fig10_title

    root = -printed(0.0) / (printed(1.0) - printed(0.0))  # linear in δ
    assert root < 0
    roots = ra.fig10("reduced-scale")["typo_roots"]
    assert roots == []
    assert fig10_title(roots).endswith("a₁ − a₂ − a₀ has no positive root)")
    assert fig10_title([0.5]).endswith("has its root at δ = 0.5)")


def test_fig11s_u_branches_reach_the_atlas_range_with_the_same_special_points():
    """Fig. 11 (b, d): the stable branch drawn over the atlas of u = 2 … 12 N·m stopped at
    u(40 rad/s) = 0.19·40 + W_ob·0.05 = 11.6 N·m (W_ob = 80 N), as if no steady drilling lay
    beyond. It must end at the atlas's largest u, stable there, and its HB and LP points must be
    those of the default branch."""
    top = max(atlas_plan(quick=True)["fig11b"]["axes"]["torque"])  # the atlas's largest u
    assert top == max(atlas_plan()["fig11d"]["axes"]["torque"]) == 12.0
    for dof, wob in ((2, 80.0), (4, 60.0)):
        p = preset("reduced-scale", dof=dof)
        cs = critical_deltas(p)
        b = ra.fig11_branch(p, "torque", wob, cs)
        u = np.array(b["branch"]["x"])
        omega = np.array(b["branch"]["omega"])
        by_hand = 0.19 * omega + wob * 0.1 * (0.5 + 0.3 * np.exp(-0.9 * omega))
        np.testing.assert_allclose(u, by_hand, rtol=1e-12)
        # To the atlas's largest u and no further (past it, the branch stretched the Ω axis
        # of the figure, and its inset came to hide orbits), stable there.
        assert abs(u.max() - top) < 1e-6 and b["branch"]["unstable"][int(np.argmax(u))] == 0
        default = branch(p, vary="torque", wob=wob, crossings=cs, samples=1500)
        assert default.torque.max() < top  # what the figure drew before
        for got, want in zip(b["points"], default.points, strict=True):
            assert got["type"] == want.type
            np.testing.assert_allclose(got["omega"], want.omega, rtol=1e-9)
