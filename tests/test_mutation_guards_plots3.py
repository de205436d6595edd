"""Guards from a second mutation audit of what the figures show, on cases the first guards'
data never reached: a map whose cells can all hold the bit, a start-up that stays stuck where
the equilibrium start drills, a steady state barely unstable, an axis of one value, an atlas
with points missing, a string without damping at its ends, an operating map without one of
its categories, and a real string's torque contours. Each compares the drawn data with
values got another way: h5py, pydrill.stability, or the paper's torques by hand."""

import shutil
from pathlib import Path

import h5py
import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.model import preset
from pydrill.plot import plt
from pydrill.spec import parse_spec
from pydrill.stability import critical_deltas, stability
from pydrill.sweep import run_sweep

# Eight points (0.1 s to sweep). The preset: μ_sb = 0.8, R_b = 0.1 m, so T_s = 8 N·m at
# W_ob = 100 N and 12.8 N·m at 160 N: above every torque here, even out to the torque cells'
# outer edge 7.45 N·m. At 100 N and u = 6.1 N·m the steady state is barely unstable (spectral
# abscissa 0.03 /s); from rest the bit stays stuck, from equilibrium it does not.
SPEC = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [100.0, 160.0]
torque = [6.1, 7.0]
bit_damping = [0.01, 0.04]
[simulation]
t_end = 60.0
initial = ["rest", "equilibrium"]
"""
MU_R = 0.8 * 0.1  # μ_sb R_b of the preset, by hand
P = preset("reduced-scale")  # dof 4, c_t 0.18, c_b 0.01, μ_cb 0.5, γ 0.9, v_f 1
STARTS = ["rest", "equilibrium"]


@pytest.fixture(scope="module")
def path(tmp_path_factory):
    out = tmp_path_factory.mktemp("plots3") / "stuck.h5"
    run_sweep(parse_spec(SPEC), out, serial=True)
    return out


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _raw(path, name):
    with h5py.File(path, "r") as f:
        return f[name][...]


def _legend(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


def _black_contours(ax):
    return [
        c for c in ax.collections if hasattr(c, "levels") and not c.get_edgecolor()[0][:3].any()
    ]


@pytest.mark.parametrize("wob", [100.0, 160.0])
def test_no_stuck_boundary_is_listed_on_a_map_whose_every_cell_can_hold_the_bit(path, wob):
    """On (u, bit damping) every torque out to the cells' outer edge (7.45 N·m) is below
    T_s = μ_sb W_ob R_b (by hand): the bit can stay stuck everywhere, there is no boundary to
    draw, and the legend must not name one. On (W_ob, bit damping) at u = 6.1 N·m the line
    W_ob = u / (μ_sb R_b) = 76.25 N lies inside the cells (edges 70 to 190 N): drawn, named."""
    top_edge = 7.0 + 0.5 * (7.0 - 6.1)
    assert top_edge < MU_R * wob  # the whole map, by hand, on the stuck side
    with Atlas(path) as atlas:
        ax = atlas.plot(x="torque", y="bit_damping", at={"wob": wob}).axes[0]
        other = atlas.plot(x="wob", y="bit_damping", at={"torque": 6.1}).axes[0]
    assert not any(t.startswith("stuck boundary") for t in _legend(ax)), _legend(ax)
    assert not _black_contours(ax)
    assert any(t.startswith("stuck boundary") for t in _legend(other))
    (black,) = _black_contours(other)
    pts = np.concatenate([p.vertices for p in black.get_paths() if len(p.vertices)])
    np.testing.assert_allclose(pts[:, 0], 6.1 / MU_R, rtol=1e-9)


def _stable_fastest(params, wob, torque):
    pts = stability(params, float(wob), torque=float(torque))
    return bool(pts) and max(pts, key=lambda p: p.omega).stable


def test_profile_steady_line_is_solid_exactly_where_stability_finds_the_state_stable(path):
    """Along u at W_ob = 100 N, c_b = 0.01: the steady line is solid where stability() finds
    the fastest steady state stable and dashed where not, a barely unstable one (abscissa
    0.03 /s, h5py) included; the omega it draws is the atlas's."""
    with Atlas(path) as atlas:
        fig = atlas.plot(profile=True, x="torque", at={"wob": 100.0, "bit_damping": 0.01})
    lines = {ln.get_label(): ln for ln in fig.axes[0].get_lines()}
    abscissa = _raw(path, "spectral_abscissa")[0, :, 0, 0]
    assert 0 < abscissa[0] < 0.05 and abscissa[1] < 0  # the case this guards
    omega = _raw(path, "omega_eq")[0, :, 0, 0].astype(float)
    stable = np.array([_stable_fastest(P, 100.0, u) for u in (6.1, 7.0)])
    assert list(stable) == [False, True]
    np.testing.assert_allclose(
        lines["fastest steady state, stable"].get_ydata(), np.where(stable, omega, np.nan)
    )
    np.testing.assert_allclose(
        lines["fastest steady state, unstable"].get_ydata(), np.where(stable, np.nan, omega)
    )


@pytest.mark.parametrize("initial", STARTS)
def test_profile_crosses_out_each_start_s_own_stuck_points_and_strips_it_in_order(path, initial):
    """A severity profile along u at W_ob = 100 N: from rest the bit stays stuck at both
    torques (below T_s = 8 N·m), from equilibrium it does not (h5py): each start's crosses sit
    on its own stuck points. The regime strip lists the starts from the top, ``initial``
    first, as its labels say, each row in its own start's regime colours."""
    from matplotlib.collections import QuadMesh
    from matplotlib.colors import to_rgba

    from pydrill.plot_atlas import MAP_COLORS

    regime = _raw(path, "regime")[0, :, 0]  # (torque, start)
    stuck = regime == fmt.REGIMES["stuck"]
    assert stuck[:, 0].all() and not stuck[:, 1].any()  # the starts disagree: the case guarded
    at = {"wob": 100.0, "bit_damping": 0.01}
    with Atlas(path) as atlas:
        ev = atlas.plot("severity", initial=initial, profile=True, x="torque", at=at)
        fig = atlas.plot(initial=initial, profile=True, x="torque", at=at)
    ax = ev.axes[0]
    for j, s in enumerate(STARTS):
        crosses = [c for c in ax.collections if c.get_label() == f"from {s}: bit stuck"]
        got = crosses[0].get_offsets()[:, 0] if crosses else []
        np.testing.assert_allclose(got, np.array([6.1, 7.0])[stuck[:, j]])
    strip = fig.axes[1]
    starts = [initial] + [s for s in STARTS if s != initial]
    labels = [t.get_text() for t in strip.get_yticklabels()]
    heights = strip.transData.transform([(6.5, t) for t in strip.get_yticks()])[:, 1]
    top_down = [lab for _, lab in sorted(zip(-heights, labels, strict=True))]
    assert top_down == [f"from {s}" for s in starts]
    # and the rows drawn: row r of the mesh (y from r to r + 1) is starts[r]'s regimes
    mesh = next(c for c in strip.collections if isinstance(c, QuadMesh))
    faces = mesh.to_rgba(mesh.get_array()).reshape(2, 2, 4)
    rows_y = strip.transData.transform([(6.5, 0.5), (6.5, 1.5)])[:, 1]
    assert rows_y[0] > rows_y[1]  # the first row on top
    for r, s in enumerate(starts):
        for i in range(2):
            want = MAP_COLORS[fmt.REGIME_NAMES[int(regime[i, STARTS.index(s)])]]
            np.testing.assert_allclose(faces[r, i], to_rgba(want), err_msg=f"{s} at {i}")


def test_an_axis_of_one_value_gets_a_cell_of_5_percent_each_side(tmp_path):
    """A sweep of one W_ob (100 N, torque held): its profile spans 95 to 105 N (±5 %, the
    documented single-value cell), the regime strip's cell too; the title says 1 point."""
    from matplotlib.collections import QuadMesh

    one = tmp_path / "one.h5"
    spec = SPEC.replace(
        "[axes]\nwob = [100.0, 160.0]\ntorque = [6.1, 7.0]\n",
        "torque = 7.0\n[axes]\nwob = [100.0]\n",
    )
    spec = spec.replace("bit_damping = [0.01, 0.04]\n", "")
    run_sweep(parse_spec(spec), one, serial=True)
    with Atlas(one) as atlas:
        assert list(atlas.axes) == ["wob"]
        fig = atlas.plot()
    ax, strip = fig.axes[:2]
    np.testing.assert_allclose(ax.get_xlim(), (95.0, 105.0))
    corners = next(c for c in strip.collections if isinstance(c, QuadMesh)).get_coordinates()
    np.testing.assert_allclose(corners[0, :, 0], [95.0, 105.0])
    assert "(1 point)" in ax.get_title()


def test_a_map_of_an_atlas_with_missing_points_says_how_many_are_done(path, tmp_path):
    """Points an interrupted sweep left missing (status 0, as the schema has it): the title
    counts the done ones as h5py does, or the blank cells read as a regime of their own."""
    part = tmp_path / "part.h5"
    shutil.copy(path, part)
    with h5py.File(part, "r+") as f:
        # both damping values at (160 N, 7 N·m), as a sweep stopped before them leaves them
        for name, fill in (("status", 0), ("regime", fmt.REGIMES["missing"])):
            data = f[name][...]
            data[1, 1] = fill
            f[name][...] = data
        done = int(np.count_nonzero(f["status"][...] != 0))
    assert done == 6
    with Atlas(part) as atlas:
        title = atlas.plot().axes[0].get_title()
    assert "(6 of 8 points done)" in title, title


def test_operating_map_of_a_string_without_end_damping_draws_no_stability_boundary():
    """c_t = c_b = 0: the fold at δ = 0 leaves a real eigenvalue unstable at every slope, so
    the first destabilising Hopf curve separates nothing: stability() finds the fastest steady
    state unstable on both sides of it. The map must not draw it as a boundary."""
    from pydrill.operating import hopf_curve_wu, operating_map
    from pydrill.plot_map import operating_figure

    bare = P.replace(top_damping=0.0, bit_damping=0.0)
    crossings = critical_deltas(bare)
    first = next(c for c in crossings if c.type == "hopf" and c.direction > 0)
    wob, torque = np.linspace(10.0, 200.0, 12), np.linspace(1.0, 20.0, 10)
    w, u = hopf_curve_wu(bare, first.delta, np.linspace(0.5, 20.0, 9))
    for wi, ui in zip(w, u, strict=True):
        if 10 < wi < 200:
            assert not _stable_fastest(bare, wi, ui * 1.05)
            assert not _stable_fastest(bare, wi, ui * 0.95)
    fig = operating_figure(bare, operating_map(bare, wob, torque, crossings), crossings)
    labels = [ln.get_label() for ln in fig.axes[0].get_lines()]
    assert "first Hopf curve" not in labels, labels
    assert any("sliding boundary" in lab for lab in labels)


def test_operating_map_fold_curve_and_legend_of_the_categories_it_shows():
    """W_ob 100 to 300 N, u 1 to 20 N·m: every cell's category by hand (u ≤ μ_sb W_ob R_b: can
    stay stuck; a stable steady state: stability()) has no "unstable, cannot stay stuck"; the
    legend names exactly the categories present, each in its mesh colour. On the fold curve
    the count of steady states changes (stability(): none below, two above)."""
    from matplotlib.collections import QuadMesh

    from pydrill.operating import CATEGORIES, operating_map
    from pydrill.plot_map import operating_figure

    wob, torque = np.linspace(100.0, 300.0, 6), np.linspace(1.0, 20.0, 6)
    crossings = critical_deltas(P)
    hand = np.empty((6, 6), dtype=int)
    for (i, u), (j, w) in ((a, b) for a in enumerate(torque) for b in enumerate(wob)):
        has_stable = any(p.stable for p in stability(P, w, torque=u, crossings=crossings))
        hand[i, j] = (0 if has_stable else 2) + (u <= MU_R * w)
    present = sorted(set(hand.ravel().tolist()))
    assert present == [0, 1, 3]  # one missing between others: the case guarded
    fig = operating_figure(P, operating_map(P, wob, torque, crossings), crossings)
    ax = fig.axes[0]
    mesh = next(c for c in ax.collections if isinstance(c, QuadMesh))
    np.testing.assert_array_equal(np.asarray(mesh.get_array()).reshape(6, 6), hand)
    faces = mesh.to_rgba(mesh.get_array()).reshape(6, 6, 4)
    legend = ax.get_legend()
    named = {}
    for text, handle in zip(legend.get_texts(), legend.legend_handles, strict=True):
        if text.get_text() in CATEGORIES:
            named[CATEGORIES.index(text.get_text())] = handle.get_facecolor()
    assert sorted(named) == present
    for k, face in named.items():
        np.testing.assert_allclose(face, faces[hand == k][0], err_msg=CATEGORIES[k])
    (fold,) = [ln for ln in ax.get_lines() if ln.get_label() == "fold (LP) curve"]
    w, u = fold.get_data()
    inside = np.flatnonzero((w > 110) & (w < 290))
    assert len(inside) > 5
    for k in inside[:: max(1, len(inside) // 6)]:
        below = stability(P, float(w[k]), torque=float(u[k]) * 0.99, crossings=crossings)
        above = stability(P, float(w[k]), torque=float(u[k]) * 1.01, crossings=crossings)
        assert (len(below), len(above)) == (0, 2), (w[k], u[k])


@pytest.mark.parametrize("string", ["eq53", "lab"])
def test_window_torque_contours_are_the_steady_torque_in_kn_m(string):
    """The paper's Eq. 53 string at 3000 m, W_ob to 250 kN, and the reduced-scale string to
    400 N (its torques are thousandths of a kN·m: no level was drawn, yet the legend named
    the contours): torque contours are drawn and named, and along each the steady torque by
    hand, (c_t + c_b) Ω + W_ob R_b (μ_cb + Δμ e^{-γΩ/v_f}) in kN·m with W_ob in N, is the
    contour's level."""
    from pydrill.plot_window import window_figure
    from pydrill.tally_parse import load_tally
    from pydrill.window import Limits

    if string == "eq53":
        root = Path(__file__).resolve().parents[1]
        tally = load_tally(root / "examples/tallies/paper-eq53.toml")
        p, wob_max = tally.at_depth(3000.0).to_params(lump=10), 250e3
    else:
        p, wob_max = P, 400.0
    fig = window_figure(string, 3000.0, Limits.of(p), wob_max, 200.0)
    ax = fig.axes[0]
    assert "steady surface torque (kN·m)" in [t.get_text() for t in ax.get_legend().texts]
    (contours,) = [c for c in ax.collections if hasattr(c, "levels")]
    g, c = p.stribeck_decay / p.stribeck_velocity, p.top_damping + p.bit_damping
    drawn = 0
    for level, path in zip(contours.levels, contours.get_paths(), strict=False):
        v = path.vertices
        if not len(v):
            continue
        om = v[:, 1] * 2 * np.pi / 60  # rpm to rad/s, by hand
        mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-g * om)
        np.testing.assert_allclose(
            (c * om + v[:, 0] * 1e3 * p.bit_radius * mu) / 1e3, level, rtol=2e-2
        )
        drawn += 1
    assert drawn >= 2
