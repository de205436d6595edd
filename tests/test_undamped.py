"""Strings with no damping at their ends, or none at all: their crossings sit at δ = 0.

critical_deltas returned none for an undamped string (stability called it stable at every
slope, while numpy's eigenvalues put all 2 dof - 1 in the right half-plane), and left out the
fold of a string with c_r = c_b = 0. The references: numpy's dense eigenvalues (LAPACK, no
code shared with the core), the free uniform chain's modes in closed form, and the limit of a
vanishing top damping. Then what every command and figure makes of such a string."""

import itertools
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hst

import pydrill
from pydrill import stability as st
from pydrill.operating import hopf_curve_wu, operating_map
from pydrill.plot_analysis import hopf_figure
from pydrill.window import Limits

TALLY = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "5.5in-dp-8in-collars.toml"

#: The fuzzer's reproducer: six equal inertias and springs, no damping anywhere.
UNDAMPED = pydrill.Params(
    inertias=[3e-5] * 6,
    stiffnesses=[7.3e-5] * 5,
    dampings=[0.0] * 5,
    top_damping=0.0,
    bit_damping=0.0,
    bit_radius=1.0,
    mu_coulomb=5e-4,
    mu_static=8e-4,
    stribeck_decay=9e-4,
)


def dense_unstable(params, delta):
    return int(np.sum(st.eigenvalues(params, delta).real > 0))


def test_an_undamped_string_is_unstable_at_every_slope():
    crossings = st.critical_deltas(UNDAMPED)
    assert [c.type for c in crossings] == ["fold"] + ["hopf"] * 5
    assert all(c.delta == 0.0 and c.direction == 1 for c in crossings)
    # The free uniform chain: ω_j = 2 √(k/J) sin(jπ / 2n).
    expected = [2 * math.sqrt(7.3e-5 / 3e-5) * math.sin(j * math.pi / 12) for j in range(1, 6)]
    assert [c.frequency for c in crossings[1:]] == pytest.approx(expected, rel=1e-12)
    for delta in (1e-9, 3.16e-4, 1.0, 1e3):  # 3.16e-4: the fuzzer's, which counted 0
        assert int(st.unstable_count(crossings, delta)) == 11 == dense_unstable(UNDAMPED, delta)
    assert int(st.unstable_count(crossings, 0.0)) == 0  # on the axis at δ = 0 itself
    # Flat friction at δ = 0: every Hopf point there is degenerate.
    assert {c.criticality(UNDAMPED) for c in crossings[1:]} == {"degenerate"}


def test_the_undamped_crossings_are_the_limit_of_a_vanishing_top_damping():
    at_zero = st.critical_deltas(UNDAMPED)
    back = {}
    for d in (1e-8, 1e-10):  # damping ratios near 1e-4 and 1e-6: frequencies shift by ζ²
        damped = st.critical_deltas(UNDAMPED.replace(top_damping=d))
        first = sorted((c for c in damped if c.direction > 0), key=lambda c: c.frequency or 0)
        assert len(first) == len(at_zero)
        assert [c.delta for c in first] == pytest.approx([d] * len(first), rel=1e-3)
        assert [c.frequency or 0 for c in first] == pytest.approx(
            [c.frequency or 0 for c in at_zero], rel=1e-6
        )
        back[d] = [c.delta for c in damped if c.direction < 0]
    # What comes back does so at δ ∝ 1/d: beyond any slope, as d → 0.
    assert len(back[1e-8]) == 5
    assert back[1e-10] == pytest.approx([100 * x for x in back[1e-8]], rel=1e-6)


@pytest.mark.parametrize(
    "dampings",
    [[1e-6] * 5, [0.0, 0.0, 1e-6, 0.0, 0.0], [1e-6, 0.0, 0.0, 0.0, 0.0]],
    ids=["damped elements", "one damper in the middle", "one damper at the top"],
)
def test_free_ends_put_the_fold_at_zero_and_every_count_agrees(dampings):
    """c_r = c_b = 0: the string turns freely as one body, and any δ > 0 sets it accelerating.
    With one damper in the middle of this symmetric string, the modes symmetric about it do not
    twist it: their Hopf points stay at δ = 0 (two of them), and were lost too."""
    p = UNDAMPED.replace(dampings=dampings)
    crossings = st.critical_deltas(p)
    assert (crossings[0].type, crossings[0].delta, crossings[0].direction) == ("fold", 0.0, 1)
    at_zero = [c for c in crossings if c.delta == 0 and c.type == "hopf"]
    assert len(at_zero) == (2 if dampings[2] and not dampings[0] else 0)
    deltas = sorted({c.delta for c in crossings})
    probes = [0.5 * (a + b) for a, b in itertools.pairwise(deltas)] + [2 * deltas[-1]]
    for delta in probes:
        assert int(st.unstable_count(crossings, delta)) == dense_unstable(p, delta), delta


def test_the_boundary_of_a_crossing_at_zero_is_the_omega_axis():
    assert np.all(st.boundary_wob(UNDAMPED, 0.0, [0.0, 5.0]) == 0.0)
    w, u = hopf_curve_wu(UNDAMPED, 0.0, np.linspace(0.0, 5.0, 11))
    assert w.size == u.size == 0  # no curve in a map of W_ob > 0 (it divided by 0)
    with pytest.raises(ValueError, match=r"delta = -1 is not allowed: .* >= 0"):
        st.boundary_wob(UNDAMPED, -1.0, 1.0)


def test_no_safe_window_and_no_stable_cell_without_damping():
    lim = Limits.of(UNDAMPED)
    assert lim.delta_limit == 0.0
    assert np.all(lim.wob_max([10.0, 100.0]) == 0.0)
    # The steady torque c Ω + T_fb(Ω) never reaches T_s with c = 0: no speed frees the bit
    # (nan before: 0/0 in the closed form).
    assert np.all(lim.rpm_min_unstuck([1e-3, 1.0]) == np.inf)
    assert lim.rpm_min_unstuck(0.0) == 0.0
    omap = operating_map(UNDAMPED, [1e-3, 1e-2], [1e-6, 1e-5, 1e-4])
    assert set(np.unique(omap.category)) <= {2, 3}  # no stable steady state anywhere


def test_the_operating_map_draws_no_first_hopf_curve_where_nothing_is_stable():
    """A free-ends string's first Hopf crossing is no boundary of stable drilling: the map drew
    it as "first Hopf curve" over cells stable on neither side. The damped string keeps it."""
    from pydrill.plot_map import operating_figure

    for params, drawn in (
        (UNDAMPED.replace(dampings=[1e-6] * 5), False),
        (pydrill.preset("reduced-scale", dof=4), True),
    ):
        crossings = st.critical_deltas(params)
        wob = np.linspace(1e-3, 3e-3, 5) if not drawn else np.linspace(20.0, 200.0, 10)
        torque = np.linspace(1e-7, 3e-6, 5) if not drawn else np.linspace(1.0, 16.0, 10)
        fig = operating_figure(params, operating_map(params, wob, torque, crossings), crossings)
        labels = [line.get_label() for line in fig.axes[0].get_lines()]
        assert ("first Hopf curve" in labels) == drawn, labels


def test_the_hopf_figure_says_why_nothing_is_stable():
    for params, cause in (
        (UNDAMPED, "at all"),
        (UNDAMPED.replace(dampings=[1e-6] * 5), "at the top"),
    ):
        fig = hopf_figure(params, st.critical_deltas(params))
        title = fig.axes[0].get_title()
        assert "steady drilling is unstable at every" in title and cause in title, title
        assert "eigenvalues cross at $\\delta$ = 0" in title or "eigenvalue crosses" in title
        fig.canvas.draw()  # renders: no curve on the axis W_ob = 0 of the log scale


def write_tally(tmp_path, beta):
    text = TALLY.read_text()
    text = text.replace("damping = 500.0", "damping = 0.0").replace(
        "damping = 40.0", "damping = 0.0"
    )
    text = text.replace("beta = 0.2 ", f"beta = {beta} ")
    path = tmp_path / "tally.toml"
    path.write_text(text)
    return path


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "pydrill", *map(str, args)], capture_output=True, text=True
    )


def test_the_commands_on_a_string_with_no_damping(tmp_path):
    tally = write_tally(tmp_path, 0.0)
    out = run("hopf", "--tally", tally, "--lump", 30, "--json", "--plot", tmp_path / "h.png")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    crossings = data["crossings"]
    assert len(crossings) == data["dof"] and all(c["delta"] == 0 for c in crossings)
    assert (tmp_path / "h.png").stat().st_size > 0
    text = run("hopf", "--tally", tally, "--lump", 30).stdout
    assert text.splitlines()[-1] == (
        f"{2 * data['dof'] - 1} eigenvalues cross at delta = 0: the string has no damping at all, "
        "so steady drilling is unstable at every W_ob"
    )
    text = run("hopf", "--tally", write_tally(tmp_path, 0.2), "--lump", 30).stdout
    assert text.splitlines()[-1].startswith(
        "1 eigenvalue crosses at delta = 0: the string has no damping at the top or the bit"
    )
    out = run("map", "--tally", tally, "--lump", 30, "--plot", tmp_path / "m.png")
    assert out.returncode == 0, out.stderr
    out = run("window", tally, "--lump", 30, "--depth", "3000m", "--json")
    assert out.returncode == 0, out.stderr
    # Why every weight is 0 and every speed inf; no RuntimeWarning of 0/0 (nan before).
    assert "no damping at the top drive or the bit (c_r + c_b = 0)" in out.stderr
    assert "Warning" not in out.stderr, out.stderr
    data = json.loads(out.stdout)
    assert data == json.loads(json.dumps(data))  # plain JSON (no nan)


ATLAS_SPEC = """
[model]
preset = "reduced-scale"
dof = 3
{extra}
[axes]
wob = {{ start = 60.0, stop = 160.0, num = 3 }}
torque = [6.0, 10.0]
[simulation]
t_end = 20.0
initial = ["rest"]
"""


@pytest.mark.parametrize("extra", ["", "top_damping = 0.0\nbit_damping = 0.0"])
def test_an_atlas_map_draws_the_first_hopf_curve_only_as_a_stability_boundary(tmp_path, extra):
    """With the fold at δ = 0 nothing is stable on either side of the first Hopf curve: its
    legend said "steady state stable below" (the side it tried). The same map of the damped
    string keeps it."""
    from pydrill.sweep import run_sweep

    run_sweep(pydrill.parse_spec(ATLAS_SPEC.format(extra=extra)), tmp_path / "a.h5", serial=True)
    with pydrill.Atlas(tmp_path / "a.h5") as atlas:
        labels = [line.get_label() for line in atlas.plot().axes[0].get_lines()]
        stable = atlas.safe_region().any()
    drawn = any("first Hopf curve" in label for label in labels)
    assert drawn == (extra == "")
    assert drawn or not stable  # (the free-ends string has no stable cell to bound)


@hst.composite
def strings(draw):
    """A short string with each damping present or missing (half the time symmetric, where a
    damper in the middle leaves modes undamped): a sample of where crossings sit at δ = 0."""
    n = draw(hst.integers(2, 7))
    decade = hst.floats(-0.5, 0.5)
    inertias = [10 ** draw(decade) for _ in range(n)]
    stiffnesses = [10 ** draw(decade) for _ in range(n - 1)]
    damper = hst.one_of(hst.just(0.0), hst.floats(1e-3, 1e-1))
    dampings = [draw(damper) for _ in range(n - 1)]
    if draw(hst.booleans()):
        inertias = [(a + b) / 2 for a, b in zip(inertias, inertias[::-1], strict=True)]
        stiffnesses = [(a + b) / 2 for a, b in zip(stiffnesses, stiffnesses[::-1], strict=True)]
        dampings = [(a + b) / 2 for a, b in zip(dampings, dampings[::-1], strict=True)]
    return UNDAMPED.replace(
        inertias=inertias,
        stiffnesses=stiffnesses,
        dampings=dampings,
        top_damping=draw(damper),
        bit_damping=draw(damper),
    )


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(params=strings())
def test_the_crossings_count_what_the_dense_eigenvalues_say_with_damping_missing(params):
    """Between and beyond the crossings, unstable_count equals the eigenvalues numpy puts in
    the right half-plane, wherever they are far enough from the axis to tell."""
    crossings = st.critical_deltas(params)
    assert [c.type for c in crossings].count("fold") == 1
    deltas = sorted({c.delta for c in crossings})
    probes = [0.5 * (a + b) for a, b in itertools.pairwise(deltas)]
    probes += [2 * deltas[-1] if deltas[-1] > 0 else 1.0, 1e-3 * deltas[0] if deltas[0] else 1e-6]
    for delta in probes:
        if any(abs(delta - c.delta) <= 1e-6 * delta for c in crossings):
            continue
        ev = st.eigenvalues(params, delta)
        if np.min(np.abs(ev.real)) <= 1e-9 * np.max(np.abs(ev)):
            continue  # too near the axis for a dense solver to say which side
        assert int(st.unstable_count(crossings, delta)) == int(np.sum(ev.real > 0)), delta


RUNAWAY_SPEC = """
[model]
preset = "reduced-scale"
dof = 4
top_damping = 0.0
bit_damping = 0.0
[axes]
wob = [50.0, 60.0]
torque = [2.4, 3.25, 4.4, 10.0]
[simulation]
t_end = 300.0
initial = ["rest"]
"""


def atlas_info(path):
    """What ``pydrill atlas info`` prints of the atlas at ``path``."""
    return subprocess.run(
        [sys.executable, "-m", "pydrill", "atlas", "info", str(path)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout


def test_a_bit_nothing_holds_runs_away_and_the_atlas_says_so(tmp_path):
    """With c_r + c_b = 0 the net torque on the turning string is u - T_fb(omega_b), and the
    slip friction falls to T_c = mu_cb R_b W_ob: above it the bit speeds up without bound, the
    string gaining speed at (u - T_c) / sum(J) once fast (the reference: that rigid-body
    balance, between runs of 200 s and 300 s, whose windows' centres are 75 s apart). It was
    judged "steady" at u = 3.25 N m (mean 287 rad/s, beside a steady state at 0.77)."""
    from pydrill.sweep import run_sweep

    spec = pydrill.parse_spec(RUNAWAY_SPEC)
    params = spec.params_at(spec.coords(0))
    total = sum(params.inertias)
    for u in (3.25, 4.4, 10.0):
        early, late = (
            pydrill.simulate(params, wob=50.0, torque=u, t_end=t).summary for t in (200.0, 300.0)
        )
        assert (late.regime, late.caveat) == ("oscillation", "run-away")
        assert "speeds up without bound" in late.note and late.period is None
        gain = (late.bit_mean - early.bit_mean) / 75.0
        assert gain == pytest.approx((u - 2.5) / total, rel=0.03)
    run_sweep(spec, tmp_path / "a.h5", serial=True)
    with pydrill.Atlas(tmp_path / "a.h5") as atlas:
        for w, u in itertools.product((50.0, 60.0), (2.4, 3.25, 4.4, 10.0)):
            v = atlas.value(wob=w, torque=u)
            coulomb = params.mu_coulomb * params.bit_radius * w
            # below T_c it sticks; at 60 N, T_c = 3 N m and u = 3.25 slips on into stick-slip
            away = u > coulomb and not (w == 60.0 and u == 3.25)
            regime, caveat = v["regime"]["rest"], v["caveat"]["rest"]
            assert (caveat == "run-away") == away, (w, u, regime, caveat)
            assert regime == "oscillation" if away else regime in ("stuck", "stick-slip")
        labels = [h.get_label() for h in atlas.plot().axes[0].get_legend().legend_handles]
    assert "run-away: no steady state holds the bit" in labels
    assert not any("simulate longer" in label for label in labels)
    out = atlas_info(tmp_path / "a.h5")
    assert "run-away from rest: 5 points (c_r + c_b = 0 and |u| > T_c" in out
    assert "simulate longer" not in out


def test_a_steady_judgement_still_on_its_way_says_so_and_the_atlas_keeps_it(tmp_path):
    """c_b = 1e-3 alone holds the bit at (u - T_c)/c_b = 750 rad/s, reached at the rate
    c_b / sum(J) (600 s): after 300 s the bit is at 238 rad/s and rising, judged steady by where
    it goes, with a caveat (none once settled)."""
    from pydrill.sweep import run_sweep

    spec = pydrill.parse_spec(
        RUNAWAY_SPEC.replace("bit_damping = 0.0", "bit_damping = 1e-3")
        .replace("wob = [50.0, 60.0]", "wob = [50.0]")
        .replace("torque = [2.4, 3.25, 4.4, 10.0]", "torque = [3.25]")
    )
    params = spec.params_at(spec.coords(0))
    s = pydrill.simulate(params, wob=50.0, torque=3.25, t_end=300.0).summary
    assert (s.regime, s.caveat) == ("steady", "approaching")
    assert "on its way to the steady state at 750 rad/s" in s.note
    assert pydrill.simulate(params, wob=50.0, torque=3.25, t_end=3e4).summary.caveat == ""
    run_sweep(spec, tmp_path / "a.h5", serial=True)
    with pydrill.Atlas(tmp_path / "a.h5") as atlas:
        v = atlas.value(wob=50.0, torque=3.25)
    assert (v["regime"]["rest"], v["caveat"]["rest"]) == ("steady", "approaching")
    out = atlas_info(tmp_path / "a.h5")
    assert "caveats from rest: approaching 1 (points to simulate longer" in out


def test_an_approach_under_a_big_swing_is_said():
    """A lightly damped laboratory string (c_r = 0.0043, c_b = 2.5e-5) at 87.5 N and 5.63 N m
    swings by 90 % of its mean with a period of 8.5 s while its mean climbs towards its steady
    state at 291 rad/s: 231 rad/s at 300 s. The drift was measured against what a swing of the
    string's slowest period (30 s) could fake, and went unsaid; against the swing's own
    cycles it is said. The reference: the same run 3000 s long, settled at the steady state."""
    params = pydrill.preset("reduced-scale", dof=4).replace(
        top_damping=4.275e-3, bit_damping=2.47e-5
    )
    s = pydrill.simulate(params, wob=87.54, torque=5.6287, t_end=300.0).summary
    assert (s.regime, s.caveat) == ("steady", "approaching") and s.severity > 0.8
    ahead = max(s.omega_equilibrium)
    assert f"on its way to the steady state at {ahead:.3g} rad/s" in s.note
    settled = pydrill.simulate(params, wob=87.54, torque=5.6287, t_end=3000.0).summary
    assert settled.bit_mean == pytest.approx(ahead, rel=1e-3) and settled.caveat == ""
    assert abs(s.bit_mean - ahead) > 0.15 * ahead  # still far from it at 300 s
