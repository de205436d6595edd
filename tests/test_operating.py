"""The (W_ob, u) map against eigenvalue verdicts and simulations."""

import json
import subprocess
import sys

import numpy as np

import pydrill
from pydrill import stability as st
from pydrill.operating import CATEGORIES, hopf_curve_wu, operating_map


def test_categories_agree_with_the_stability_of_every_steady_state():
    p = pydrill.preset("reduced-scale", dof=3)
    wob = np.linspace(10.0, 250.0, 13)
    torque = np.linspace(0.5, 25.0, 11)
    omap = operating_map(p, wob, torque)
    for i, u in enumerate(torque):
        for j, w in enumerate(wob):
            points = st.stability(p, w, torque=u)
            has_stable = any(pt.stable for pt in points)
            stuck = u <= 0.8 * w * 0.1
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


def test_map_command(tmp_path):
    png = tmp_path / "map.png"
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pydrill",
            "map",
            "--dof",
            "2",
            "--check",
            "3",
            "--json",
            "--plot",
            str(png),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    assert len(data["category"]) == len(data["torque"])
    assert len(data["category"][0]) == len(data["wob"])
    assert len(data["checks"]) == 9
    assert {c["regime"] for c in data["checks"]} <= set(pydrill.REGIMES)
    assert abs(sum(data["fractions"].values()) - 1) < 1e-9
    assert png.stat().st_size > 20_000
