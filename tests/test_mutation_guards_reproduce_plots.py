"""Mutation guards for ``pydrill reproduce``'s analysis figures and atlases (the paper's Figs. 6b,
10, 11, 12 and their long-string analogues): reproduce_plots.py, reproduce_plots_branch.py,
reproduce_plots_long.py, reproduce_atlases.py.

The figures are drawn (Agg, ``save`` replaced, nothing written) from the analysis numbers and
small atlases written out here; each test checks the drawn artists against hand computations on
the laboratory string of Eq. (14): μ_b(Ω) = 0.5 + 0.3 e^{−0.9 Ω}, R_b = 0.1 m, so the Stribeck
slope is δ = 0.027 W_ob e^{−0.9 Ω} and T_s = 0.08 W_ob; the fold at δ = c_r + c_b = 0.19.
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest

import pydrill
from pydrill import reproduce_analysis as ra
from pydrill import reproduce_atlases as rat
from pydrill import reproduce_plots as rp
from pydrill import reproduce_plots_long as rpl
from pydrill.plot import plt
from pydrill.reproduce_plots_branch import SUB, SUPER, _branch_panel
from pydrill.stability import critical_deltas, stability

matplotlib.use("Agg")


def _atlas(axes, rest, eq, bit_max=None):
    shape = np.shape(rest)
    bm = np.arange(1.0, 1 + np.size(rest)).reshape(shape) if bit_max is None else bit_max

    def row(reg):
        zeros = np.zeros(shape).tolist()
        return {
            "regime": reg,
            "bit_max": np.asarray(bm).tolist(),
            "bit_min": zeros,
            "period": zeros,
        }

    return {
        "axes": axes,
        "dof": 4,
        "t_end": 300.0,
        "rest": row(rest),
        "equilibrium": row(eq),
    }


REST6 = [["steady", "stick-slip"], ["stick-slip", "stuck"], ["stuck", "failed"]]
EQ6 = [["steady", "steady"], ["no-steady-state", "stuck"], ["stuck", "stuck"]]
# Fig. 11's rows: one regime per point of the varied parameter.
ROW_REST = ["steady", "stick-slip", "oscillation", "stuck", "steady"]
ROW_EQ = ["steady", "steady", "oscillation", "stuck", "stick-slip"]


@pytest.fixture(scope="module")
def drawn():
    from pathlib import PurePath

    n = {k: ra.fig10(name) for k, name in (("fig10a", "reduced-scale"), ("fig10b", "real-string"))}
    n.update({f"fig11{x}": ra.fig11(x) for x in "abcd"})
    n["strings"] = ra.paper_strings()
    n["pipes10"], n["pipes20"] = ra.long_string(10), ra.long_string(20)
    n["atlas_fig06b"] = _atlas({"wob": [40.0, 100.0, 160.0], "torque": [8.3, 12.0]}, REST6, EQ6)
    n["fig06b_band"] = {"wob_lo": 100.0, "wob_hi": 100.0, "wob_star": 103.75}
    for x in "abcd":
        key = n[f"fig11{x}"]["vary"]
        n[f"atlas_fig11{x}"] = _atlas({key: [60.0, 80.0, 100.0, 120.0, 140.0]}, ROW_REST, ROW_EQ)
    n["atlas_pipes10-fig11c"] = _atlas({"wob": [50.0, 70.0, 90.0, 110.0, 130.0]}, ROW_EQ, ROW_EQ)
    n["atlas_pipes10-fig11d"] = _atlas({"torque": [3.0, 5.0, 7.0, 9.0, 11.0]}, ROW_EQ, ROW_EQ)
    figs = {}
    saved = rp.save, rpl.save
    rp.save = rpl.save = lambda fig, path: figs.setdefault(path.stem, fig)
    try:
        out = PurePath("unused")
        rp.fig6b(out, n), rp.fig10(out, n, (10,)), rp.fig12(out, n)
        rpl.fig12_long(out, n, (10, 20)), rpl.multiple_hopf(out, n, (10,))
    finally:
        rp.save, rpl.save = saved
    # Fig. 11's panels as fig11() draws them, on a plain figure: the whole figure places its
    # point names by rendering (20 s), which these tests do not look at.
    fig, axes = plt.subplots(2, 2, figsize=(15, 10.5))
    for ax, x in zip(axes.ravel(), "abcd", strict=True):
        _branch_panel(ax, n[f"fig11{x}"], n[f"atlas_fig11{x}"], x)
    figs["fig11_bifurcation"] = fig
    yield n, figs
    for fig in figs.values():
        plt.close(fig)


def _w_on(delta, omega):  # W_ob where the Stribeck slope is δ at Ω (lab string, by hand)
    return delta / (0.027 * np.exp(-0.9 * np.asarray(omega)))


def test_fig6b_maps_each_start_and_marks_the_papers_section3_cases(drawn):
    fig = drawn[1]["fig06b_regime_map"]
    order = ("steady", "stick-slip", "stuck", "oscillation", "no-steady-state")
    for ax, regimes in zip(fig.axes[:2], (REST6, EQ6), strict=True):
        codes = [[order.index(r) if r in order else 4 for r in row] for row in regimes]
        assert np.array_equal(np.asarray(ax.collections[0].get_array()), np.array(codes).T)
        cases = [ln for ln in ax.get_lines() if ln.get_markerfacecolor() == "white"]
        assert sorted((float(ln.get_xdata()[0]), float(ln.get_ydata()[0])) for ln in cases) == [
            (40.0, 8.3),
            (100.0, 8.3),
            (160.0, 8.3),
        ]  # Figs. 9, 4, 7
        (line,) = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
        assert np.allclose(line.get_ydata(), 0.08 * line.get_xdata())  # u⁺ = μ_sb R_b W_ob


def test_fig10_curves_are_the_hand_boundaries_in_n_and_kn(drawn):
    n, figs = drawn
    ax_a, ax_b = figs["fig10_stability_region"].axes
    lines = {ln.get_label().split(":")[0]: ln for ln in ax_a.get_lines()}
    h2, fold, h1 = (
        lines["$\\mathcal{H}_2$"],
        lines["$a_0 = 0$ (fold)"],
        lines["$\\mathcal{H}_1$"],
    )
    om = h2.get_xdata()
    assert np.allclose(h2.get_ydata(), _w_on(n["fig10a"]["h2_delta"], om))
    assert np.allclose(h1.get_ydata(), _w_on(n["fig10a"]["h1_delta"], om))
    assert np.allclose(fold.get_ydata(), _w_on(0.19, om))
    assert "subcritical" in h2.get_label()  # l1 > 0 at H2 (test_reproduce.py)
    first10 = critical_deltas(pydrill.preset("reduced-scale", pipes=10))[0].delta
    (pipes,) = [ln for ln in ax_a.get_lines() if "10 pipes" in ln.get_label()]
    assert np.allclose(pipes.get_ydata(), _w_on(first10, om))
    # (b) the real string in kN: its own Eq. (53) parameters, W_ob / 1000.
    real = pydrill.preset("real-string", dof=2)
    (h2b,) = [ln for ln in ax_b.get_lines() if ln.get_label().startswith("$\\mathcal{H}_2$")]
    wb = pydrill.stability.boundary_wob(real, n["fig10b"]["h2_delta"], h2b.get_xdata())
    assert np.allclose(h2b.get_ydata(), wb / 1000) and "(kN)" in ax_b.get_ylabel()
    assert "(N)" in ax_a.get_ylabel()


def _on_hopf_curve(w, u, delta):
    """(W_ob, u) on the Hopf curve of δ, by hand: Ω from δ = 0.027 W e^{−0.9Ω}, then
    u = (c_r + c_b) Ω + W R_b μ_b(Ω)."""
    om = np.log(0.027 * w / delta) / 0.9
    return np.allclose(u, 0.19 * om + 0.1 * w * (0.5 + 0.3 * np.exp(-0.9 * om)), rtol=1e-6)


def test_fig12_curves_coloured_by_criticality_with_the_fold_and_the_stick_slip_cells(
    drawn,
):
    n, figs = drawn
    ax_a, ax_b = figs["fig12_hopf_wob_torque"].axes
    for ax, dof in ((ax_a, 2), (ax_b, 4)):
        curves = n["strings"][f"dof{dof}"]["fig12"]["curves"]
        hb = [ln for ln in ax.get_lines() if ln.get_label().startswith("HB")]
        assert hb
        for ln in hb:
            c = next(c for c in curves if f"δ = {c['delta']:.4g}," in ln.get_label())
            assert _on_hopf_curve(ln.get_xdata(), ln.get_ydata(), c["delta"])
            want = SUB if (c["lyapunov"] or 0) > 0 else (SUPER if c["lyapunov"] else "0.5")
            assert ln.get_color() == want
        (fold,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("fold (LP)")]
        assert _on_hopf_curve(fold.get_xdata(), fold.get_ydata(), 0.19)
    (dots,) = [ln for ln in ax_b.get_lines() if ln.get_label().startswith("stick-slip from rest")]
    cells = sorted(
        (w, u)
        for i, w in enumerate((40.0, 100.0, 160.0))
        for j, u in enumerate((8.3, 12.0))
        if REST6[i][j] == "stick-slip"
    )
    assert sorted(zip(dots.get_xdata(), dots.get_ydata(), strict=True)) == cells


def test_fig11_branch_hopf_points_at_the_steady_states_omega_and_the_atlas_orbits(
    drawn,
):
    n, figs = drawn
    axes = [a for a in figs["fig11_bifurcation"].axes if a.get_title().startswith("(")]
    for ax, x in zip(axes, "abcd", strict=True):
        b = n[f"fig11{x}"]
        key = b["vary"]
        p = pydrill.preset("reduced-scale", dof=b["dof"])
        (thick,) = [ln for ln in ax.get_lines() if ln.get_linewidth() == 3]
        stable = np.isfinite(thick.get_ydata())
        assert np.array_equal(stable, np.array(b["branch"]["unstable"]) == 0)
        squares = [ln for ln in ax.get_lines() if ln.get_marker() == "s" and len(ln.get_xdata())]
        hb = [pt for pt in b["points"] if pt["type"] == "HB"]
        assert len(squares) == len(hb)
        for ln in squares:
            xv, om = float(ln.get_xdata()[0]), float(ln.get_ydata()[0])
            pt = next(pt for pt in hb if pt[key] == xv)
            fixed = {"wob": 8.1} if key == "wob" else {"wob": b["fixed"]}
            w, u = (xv, 8.1) if key == "wob" else (b["fixed"], xv)
            # Ω of the steady state at that point, by stability() there.
            assert min(abs(e.omega - om) for e in stability(p, w, torque=u)) < 1e-6 * om, fixed
            assert ln.get_color() == (SUB if pt["lyapunov"] > 0 else SUPER)
        (fold,) = [ln for ln in ax.get_lines() if ln.get_marker() == "D" and len(ln.get_xdata())]
        fw, fu = (b["fold"][key], 8.1) if key == "wob" else (b["fixed"], b["fold"][key])
        assert min(abs(e.omega - fold.get_ydata()[0]) for e in stability(p, fw, torque=fu)) < 1e-3
        # The atlas: max φ̇_b at the periodic cells (stick-slip, oscillation), 0 at the stuck.
        for marker, row in (("o", ROW_REST), ("^", ROW_EQ)):
            drawn_pts = sorted(
                (float(a), float(c))
                for ln in ax.get_lines()
                if ln.get_marker() == marker
                for a, c in zip(ln.get_xdata(), ln.get_ydata(), strict=True)
            )
            xs = (60.0, 80.0, 100.0, 120.0, 140.0)
            want = [
                (xs[i], i + 1.0) for i, r in enumerate(row) if r in ("stick-slip", "oscillation")
            ]
            want += [(xs[i], 0.0) for i, r in enumerate(row) if r == "stuck"]
            assert drawn_pts == sorted(want)
        title = ax.get_title()
        if key == "wob":
            assert "$u$ = 8.1 N·m" in title and f"HB1 at {b['first_hopf']['wob']:.5g} N" in title
        else:
            assert f"$W_{{ob}}$ = {b['fixed']:g} N" in title


def test_long_string_fig12_and_the_multiple_hopf_scatter(drawn):
    n, figs = drawn
    dof2 = pydrill.preset("reduced-scale", dof=2)
    base = critical_deltas(dof2)[0].delta  # n' = 3's first Hopf, by stability.py here
    for ax, pipes in zip(figs["fig12_long_strings"].axes, (10, 20), strict=True):
        (ref,) = [ln for ln in ax.get_lines() if ln.get_label() == "first Hopf curve of n' = 3"]
        assert _on_hopf_curve(ref.get_xdata(), ref.get_ydata(), base)
        first = critical_deltas(pydrill.preset("reduced-scale", pipes=pipes))[0].delta
        (hb1,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("HB1")]
        assert _on_hopf_curve(hb1.get_xdata(), hb1.get_ydata(), first)
    ax, ax2 = figs["hopf_multiple_criticality"].axes
    (fold,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("fold")]
    assert list(fold.get_xdata()) == [0.19, 0.19]  # c_r + c_b of the laboratory string
    strings = [n["strings"]["dof4"], n["pipes10"]]
    filled, hollow = ax.collections[0::2], ax.collections[1::2]
    for d, f, h in zip(strings, filled, hollow, strict=False):
        curves = d["fig12"]["curves"]
        want = sorted((c["delta"], c["frequency"]) for c in curves if c["direction"] > 0)
        assert np.allclose(sorted(map(tuple, f.get_offsets().tolist())), want)
        assert len(h.get_offsets()) == len(curves) - len(want)
    l1 = [c["lyapunov"] for d in strings for c in d["fig12"]["curves"] if c["lyapunov"] is not None]
    sub = sum(v > 0 for v in l1)
    assert (
        f"{sub} of {sum(v != 0 for v in l1)} computed Hopf crossings are subcritical"
        in ax2.get_title()
    )
    # |l₁| on a log axis: the supercritical ones drawn at −l₁ > 0.
    pts = np.concatenate([c.get_offsets()[:, 1] for c in ax2.collections if len(c.get_offsets())])
    assert len(pts) == sum(v != 0 for v in l1) and (pts > 0).all()


# --- reproduce_atlases.py ----------------------------------------------------------------------


def test_atlas_plan_is_the_papers_cases_and_captions():
    plan = rat.atlas_plan()
    axes = plan["fig06b"]["axes"]
    assert {40.0, 100.0, 160.0} <= set(axes["wob"]) and 8.3 in axes["torque"]  # Section 3
    assert axes["wob"][0] == 20.0 and axes["wob"][-1] == 200.0 and len(axes["wob"]) == 37
    assert plan["fig06b"]["t_end"] == 300.0  # the runs of Section 3
    # Fig. 11: (a) n' = 3, u = 8.1; (b) n' = 3, W_ob = 80; (c) n' = 7, u = 8.1; (d) n' = 7, 60 N.
    want = {
        "a": (2, "torque", 8.1),
        "b": (2, "wob", 80.0),
        "c": (4, "torque", 8.1),
        "d": (4, "wob", 60.0),
    }
    for x, (dof, fixed, value) in want.items():
        assert plan[f"fig11{x}"]["model"] == {"dof": dof, fixed: value}
    for pipes in (10, 100, 500):
        p = pydrill.preset("reduced-scale", pipes=pipes)
        tau = p.top_damping * sum(1 / k for k in p.stiffnesses)  # c_r Σ 1/k_i, the docstring's
        assert plan[f"pipes{pipes}-fig11c"]["t_end"] >= 20 * tau
        assert plan[f"pipes{pipes}-fig11c"]["parallel"] == (pipes >= 100)
    assert "pipes10-fig11c" in rat.atlas_plan(quick=True)


def test_band_and_orbits_by_hand():
    a = _atlas({"wob": [40.0, 100.0, 160.0], "torque": [8.3, 12.0]}, REST6, EQ6)
    b = rat.band(a)
    assert b["wob_star"] == pytest.approx(8.3 / 0.08)  # Eq. (38): u / (μ_sb R_b)
    # stick-slip at (100, 8.3): (8.3 − 8)/8; at (40, 12): (12 − 3.2)/3.2
    assert b["slip_rel_min"] == pytest.approx(0.3 / 8)
    assert b["slip_rel_max"] == pytest.approx(8.8 / 3.2)
    assert b["stuck_above_ts"] == 1  # stuck at (100, 12) > 8; not at (160, *) ≤ 12.8
    # (40, 12) stick-slip/steady and (160, 12) failed/stuck; not (100, 8.3): no steady state
    assert b["coexistence"] == 2
    row = _atlas({"wob": [60.0, 80.0, 100.0, 120.0, 140.0]}, ROW_REST, ROW_EQ)
    o = rat.orbits(row, {"vary": "wob"})
    assert o["rest"]["stick_slip"] == [[80.0, 80.0]]
    assert o["rest"]["steady"] == [[60.0, 60.0], [140.0, 140.0]]
    assert o["end"] == 80.0  # W_ob1: the lowest W_ob of periodic motion
    col = _atlas({"torque": [60.0, 80.0, 100.0, 120.0, 140.0]}, ROW_REST, ROW_EQ)
    assert rat.orbits(col, {"vary": "torque"})["end"] == 140.0  # u1: the highest u


def test_hopf_meets_band_by_hand():
    delta = 0.05
    wob = [40.0, 100.0, 160.0]
    u_ax = [2.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0]
    rest = [["steady"] * 7 for _ in wob]
    # The cell nearest the Hopf curve: stick-slip at 100 N, stuck at 160 N.
    for i, w in enumerate(wob):
        om = math.log(0.027 * w / delta) / 0.9
        u = 0.19 * om + 0.1 * w * (0.5 + 0.3 * math.exp(-0.9 * om))
        j = int(np.argmin(np.abs(np.array(u_ax) - u)))
        rest[i][j] = {100.0: "stick-slip", 160.0: "stuck"}.get(w, "steady")
    h = rat.hopf_meets_band(_atlas({"wob": wob, "torque": u_ax}, rest, rest), delta)
    assert h["stick_slip_wob"] == [100.0]
