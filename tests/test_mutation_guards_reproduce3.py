"""Mutation guards for ``pydrill reproduce``'s figures and atlases left alive by
test_mutation_guards_reproduce_figs.py and test_mutation_guards_reproduce_plots.py: Fig. 12's
shading and sliding line, the long-string Fig. 11's atlas, the stuck-above-T_s count of Fig. 6b's
band, and the reuse of an atlas only when it is complete.

Everything is checked on the laboratory string of Eq. (14) against what the tests compute
themselves: stability() at single points, T_s = μ_sb W_ob R_b = 0.8 · 0.1 · W_ob by hand, counts
made with numpy on small hand-written atlases, and atlases read back with Atlas / h5py.
"""

from __future__ import annotations

from pathlib import Path, PurePath

import h5py
import matplotlib
import numpy as np
import pytest

import pydrill
from pydrill import reproduce_analysis as ra
from pydrill import reproduce_atlases as rat
from pydrill import reproduce_plots as rp
from pydrill import reproduce_plots_long as rpl
from pydrill.atlas import Atlas
from pydrill.plot import plt
from pydrill.stability import stability

matplotlib.use("Agg")


def _ts(wob):  # Eq. (38)-(39) by hand: μ_sb R_b W_ob with μ_sb = 0.8, R_b = 0.1 m
    return 0.8 * 0.1 * np.asarray(wob, dtype=float)


@pytest.fixture(scope="module")
def fig12():
    n = {"strings": ra.paper_strings()}
    saved = rp.save
    rp.save = lambda fig, path: fig
    try:
        fig = rp.fig12(PurePath("unused"), n)
    finally:
        rp.save = saved
    yield fig
    plt.close(fig)


# (W_ob, u) well inside each kind of cell (a grid step of fig12's map is 1.25 N by 0.1 N·m):
# a stable steady state below T_s (the stuck bit possible too: category 1), one above T_s
# (category 0), and only the stuck bit (no stable steady state, u < T_s: category 3).
STABLE_BELOW_TS = [(60.0, 4.5), (100.0, 7.0), (160.0, 11.0)]
STABLE_ABOVE_TS = [(60.0, 6.0), (100.0, 9.5), (160.0, 14.5)]
STUCK_ONLY = [(60.0, 2.5), (100.0, 4.0), (160.0, 7.0)]


def test_fig12_shades_every_point_with_a_stable_steady_state_also_below_t_s(fig12):
    """The shading is "a stable steady state exists", whether or not the bit could also stay
    stuck there (u <= T_s): stability() at the point decides, not the map's own categories."""
    for ax, dof in zip(fig12.axes, (2, 4), strict=True):
        p = pydrill.preset("reduced-scale", dof=dof)
        (filled,) = [c for c in ax.collections if hasattr(c, "levels")]  # the contourf
        paths = filled.get_paths()

        def shaded(w, u, paths=paths):
            return any(path.contains_point((w, u)) for path in paths if len(path.vertices))

        for points, below, stable in (
            (STABLE_BELOW_TS, True, True),
            (STABLE_ABOVE_TS, False, True),
            (STUCK_ONLY, True, False),
        ):
            for w, u in points:
                assert (u < _ts(w)) == below, (w, u)  # the point is where it is meant to be
                has_stable = any(e.stable for e in stability(p, w, torque=u))
                assert has_stable == stable, (dof, w, u)
                assert shaded(w, u) == stable, (dof, w, u)


def test_fig12_sliding_line_is_the_static_torque_mu_sb_r_b_w_ob(fig12):
    """Fig. 12's line u⁺ is the one of Fig. 6b: T_s = μ_sb R_b W_ob, not the Coulomb level
    μ_cb R_b W_ob (0.05 W_ob) of a sliding bit."""
    for ax in fig12.axes:
        (line,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("$u^+")]
        w = np.asarray(line.get_xdata())
        assert w.max() == pytest.approx(200.0)  # the whole W_ob axis
        assert np.allclose(line.get_ydata(), _ts(w))


def _row_atlas(key, x, rest, eq):
    """A 1-D atlas's numbers as reproduce keeps them (atlas_numbers): max φ̇_b = 1, 2, ..."""
    top = np.arange(1.0, 1 + len(x)).tolist()
    zeros = [0.0] * len(x)

    def row(reg):
        return {"regime": reg, "bit_max": top, "bit_min": zeros, "period": zeros}

    return {"axes": {key: x}, "dof": 13, "t_end": 600.0, "rest": row(rest), "equilibrium": row(eq)}


def test_fig11_long_draws_the_orbits_of_the_long_strings_own_atlases(monkeypatch):
    """fig11_long's orbits are those of the atlases atlas_plan() names for that many pipes
    (reproduce keys them "atlas_<name>"), not those of the paper's dof-4 Fig. 11 (c, d), which
    reproduce's numbers hold as well."""
    figs = {}
    monkeypatch.setattr(rpl, "save", lambda fig, path: figs.setdefault(path.stem, fig))
    # The names of the inset's points are placed by rendering (20 s): not looked at here.
    monkeypatch.setattr(rpl, "name_points", lambda fig, panels: None)
    rest = ["steady", "stick-slip", "oscillation", "stuck", "stick-slip"]
    eq = ["stick-slip", "steady", "stuck", "oscillation", "steady"]
    own = {"c": [50.0, 70.0, 90.0, 110.0, 130.0], "d": [3.0, 5.0, 7.0, 9.0, 11.0]}
    decoy = {"c": [41.0, 61.0, 81.0, 101.0, 121.0], "d": [2.5, 4.5, 6.5, 8.5, 10.5]}
    n = {"pipes10": ra.long_string(10)}
    names = [k for k in rat.atlas_plan(quick=True) if k.startswith("pipes10-")]
    assert sorted(names) == ["pipes10-fig11c", "pipes10-fig11d"]
    for name in names:
        letter = name[-1]
        key = n["pipes10"][f"fig11{letter}"]["vary"]
        n[f"atlas_{name}"] = _row_atlas(key, own[letter], rest, eq)
        n[f"atlas_fig11{letter}"] = _row_atlas(key, decoy[letter], eq, rest)
    rpl.fig11_long(PurePath("unused"), n, 10)
    fig = figs["fig11_pipes10"]
    try:
        panels = [a for a in fig.axes if a.get_title().startswith("(")]
        assert len(panels) == 2
        for ax, letter in zip(panels, "cd", strict=True):
            x = own[letter]
            for marker, reg in (("o", rest), ("^", eq)):
                drawn = sorted(
                    (float(a), float(b))
                    for ln in ax.get_lines()
                    if ln.get_marker() == marker
                    for a, b in zip(ln.get_xdata(), ln.get_ydata(), strict=True)
                )
                # max φ̇_b (k + 1) at the periodic points, 0 at the stuck ones, by hand
                want = [(x[k], 0.0 if r == "stuck" else k + 1.0) for k, r in enumerate(reg)]
                want = [pt for pt, r in zip(want, reg, strict=True) if r != "steady"]
                assert drawn == sorted(want), (letter, marker)
    finally:
        plt.close(fig)


def test_stuck_above_ts_counts_only_stuck_points_with_u_above_t_s():
    """Eq. (39): from rest the bit stays stuck only where u <= T_s; the band reports the stuck
    points above it. Counted here with numpy on a hand-made map with stuck points on both
    sides of T_s (and a stick-slip one above it, not counted)."""
    wob = [50.0, 100.0, 150.0]  # T_s = 4, 8, 12 N·m
    torque = [3.0, 6.0, 9.0, 13.0]
    rest = [
        ["stuck", "stuck", "steady", "steady"],  # 6 > 4: one above
        ["stuck", "stuck", "stuck", "stick-slip"],  # 9 > 8: one above
        ["stuck", "stuck", "stuck", "steady"],  # none above 12
    ]
    zeros = np.zeros((3, 4)).tolist()
    row = {"regime": rest, "bit_max": zeros, "bit_min": zeros, "period": zeros}
    a = {
        "axes": {"wob": wob, "torque": torque},
        "dof": 4,
        "t_end": 300.0,
        "rest": row,
        "equilibrium": row,
    }
    ww, uu = np.meshgrid(wob, torque, indexing="ij")
    above = int(np.sum((np.array(rest) == "stuck") & (uu > _ts(ww))))
    below = int(np.sum((np.array(rest) == "stuck") & (uu < _ts(ww))))
    assert (above, below) == (2, 6)
    assert rat.band(a)["stuck_above_ts"] == above


def test_an_atlas_with_points_missing_is_resumed_not_reused(tmp_path):
    """An atlas of this spec and version is reused only when complete: one whose point is
    missing without a journal (a sweep killed before its journal was written, or the journal
    lost) is resumed, and the missing point computed again as the first run computed it."""
    settings = {
        "model": {"dof": 2, "torque": 8.1},
        "axes": {"wob": [60.0, 160.0]},
        "t_end": 5.0,
        "parallel": False,
    }

    def run():
        return rat.run_atlas(tmp_path, "tiny", settings, force=False, workers=None, scheduler=None)

    path, how = run()
    assert how == "computed"
    with Atlas(path) as atlas:
        first = atlas.regimes("rest").tolist()
    assert run()[1] == "reused"  # complete: reused as it is
    with h5py.File(path, "r+") as f:  # the first point back to missing, by plain h5py
        f["status"][0] = 0  # atlas_schema.STATUS["missing"]
        f["regime"][0] = -2  # atlas_schema.REGIMES["missing"]
    assert not Path(str(path) + ".journal").exists()
    with Atlas(path) as atlas:
        assert atlas.summary()["status"]["missing"] == 1
    path, how = run()
    assert how == "resumed"
    with Atlas(path) as atlas:
        assert atlas.summary()["status"]["missing"] == 0
        assert atlas.regimes("rest").tolist() == first
