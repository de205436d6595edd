"""Guards from a mutation audit of what the figures show (plot_atlas, plot_atlas_bounds,
plot_atlas_line, plot_map, plot_window): the data on the axes of the returned Figure objects
(mesh arrays, line data, legend texts, axis labels) compared with values got another way —
the atlas's datasets read with plain h5py, pydrill.stability at points of a drawn curve, and
the paper's static and steady torques by hand (T_s = μ_sb W_ob R_b; DESIGN.md)."""

import h5py
import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.model import preset
from pydrill.plot import plt
from pydrill.plot_atlas import MAP_COLORS
from pydrill.spec import parse_spec
from pydrill.stability import stability
from pydrill.sweep import run_sweep

# Three axes (0.2 s to sweep): stuck, stick-slip and steady cells from both starts, and a model
# parameter with a unit to hold or draw. The preset: μ_sb = 0.8, R_b = 0.1 m.
SPEC = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [40.0, 100.0, 160.0]
torque = [3.0, 6.0, 9.0, 12.0]
bit_damping = [0.01, 0.04]
[simulation]
t_end = 60.0
initial = ["rest", "equilibrium"]
"""
MU_R = 0.8 * 0.1  # μ_sb R_b of the preset, by hand


@pytest.fixture(scope="module")
def path(tmp_path_factory):
    out = tmp_path_factory.mktemp("plots") / "map.h5"
    run_sweep(parse_spec(SPEC), out, serial=True)
    return out


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _raw(path, name):
    with h5py.File(path, "r") as f:
        return f[name][...]


def _mesh(ax):
    from matplotlib.collections import QuadMesh

    return next(c for c in ax.collections if isinstance(c, QuadMesh))


def _centres(mesh):
    """The cells' centres along x and y, from the corners the mesh draws."""
    c = mesh.get_coordinates()
    ex, ey = c[0, :, 0], c[:, 0, 1]
    return 0.5 * (ex[1:] + ex[:-1]), 0.5 * (ey[1:] + ey[:-1])


def _legend(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


@pytest.mark.parametrize("initial, j", [("rest", 0), ("equilibrium", 1)])
@pytest.mark.parametrize("swap", [False, True])
def test_each_cell_has_its_regime_s_colour_where_its_grid_values_are(path, initial, j, swap):
    """Every cell's colour is MAP_COLORS[regime name] of the regime h5py reads there, centred on
    its (W_ob, u); the legend's swatches name exactly the regimes present, each in its colour."""
    from matplotlib.colors import to_rgba

    raw = _raw(path, "regime")[:, :, 0, j]  # (wob, torque) at bit_damping's first value
    with Atlas(path) as atlas:
        fig = (
            atlas.plot(initial=initial, x="torque", y="wob")
            if swap
            else atlas.plot(initial=initial)
        )
    ax = fig.axes[0]
    mesh = _mesh(ax)
    xs, ys = _centres(mesh)
    wob, torque = [40.0, 100.0, 160.0], [3.0, 6.0, 9.0, 12.0]
    np.testing.assert_allclose(xs, torque if swap else wob)
    np.testing.assert_allclose(ys, wob if swap else torque)
    faces = mesh.to_rgba(mesh.get_array()).reshape(len(ys), len(xs), 4)  # rows: y
    grid = raw if swap else raw.T  # (y, x)
    for (r, c), code in np.ndenumerate(grid):
        want = to_rgba(MAP_COLORS[fmt.REGIME_NAMES[int(code)]])
        np.testing.assert_allclose(faces[r, c], want, err_msg=f"cell {r, c}")
    names = {fmt.REGIME_NAMES[int(c)] for c in np.unique(raw)}
    legend = ax.get_legend()
    swatches = {
        t.get_text(): h.get_facecolor()
        for t, h in zip(legend.get_texts(), legend.legend_handles, strict=True)
        if t.get_text() in MAP_COLORS
    }
    assert set(swatches) == names
    for name, face in swatches.items():
        np.testing.assert_allclose(face, to_rgba(MAP_COLORS[name]))
    # safe cells (steady from every start, fastest steady state stable): both starts named
    assert "safe: steady from both starts, stable" in _legend(ax)
    labels = ["weight on bit $W_{ob}$ (N)", "surface torque $u$ (N·m)"]
    assert [ax.get_xlabel(), ax.get_ylabel()] == (labels[::-1] if swap else labels)


def _stable_fastest(params, wob, torque):
    pts = stability(params, float(wob), torque=float(torque))
    return bool(pts) and max(pts, key=lambda p: p.omega).stable


@pytest.mark.parametrize("damping, k", [(0.01, 0), (0.04, 1)])
@pytest.mark.parametrize("swap", [False, True])
def test_analytic_boundaries_are_the_static_torque_and_a_change_of_stability(
    path, damping, k, swap
):
    """On (W_ob, u): the stuck line is u = μ_sb W_ob R_b by hand across the whole W_ob range;
    on the Hopf curve the fastest steady state of the string at the held bit damping changes
    stability, and the legend names the side it is stable on, as stability() finds it."""
    params = preset("reduced-scale").replace(bit_damping=damping)
    with Atlas(path) as atlas:
        at = {"bit_damping": damping}
        fig = atlas.plot(x="torque", y="wob", at=at) if swap else atlas.plot(at=at)
    ax = fig.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    stuck = next(ln for lab, ln in lines.items() if lab.startswith("stuck boundary"))
    x, y = stuck.get_data()
    u, w = (x, y) if swap else (y, x)
    assert (w.min(), w.max()) == (40.0, 160.0)
    np.testing.assert_allclose(u, MU_R * w)
    hopf = [ln for lab, ln in lines.items() if lab.startswith("first Hopf curve")]
    assert len(hopf) == 1
    x, y = hopf[0].get_data()
    u, w = (x, y) if swap else (y, x)
    seen = np.flatnonzero((w > 45) & (w < 155) & (u > 3) & (u < 12))
    assert len(seen) > 5, "the Hopf curve crosses the map"
    above = []
    for i in seen[:: max(1, len(seen) // 5)]:
        hi = _stable_fastest(params, w[i], u[i] * 1.02)
        lo = _stable_fastest(params, w[i], u[i] * 0.98)
        assert hi != lo, f"no change of stability across ({w[i]:.4g} N, {u[i]:.4g} N·m)"
        above.append(hi)
    side = (
        ("to the right" if swap else "above") if above[0] else ("to the left" if swap else "below")
    )
    assert hopf[0].get_label() == f"first Hopf curve (steady state stable {side})"
    title = ax.get_title()
    assert f"bit_damping = {damping:g} N·m·s/rad" in title, title
    assert k == [0.01, 0.04].index(damping)


def test_stuck_boundary_off_the_wob_torque_plane_is_where_u_equals_t_s(path):
    """On (u, bit damping) at W_ob = 100 N the stuck contour is the vertical u = μ_sb W_ob R_b
    = 8 N·m (the preset's μ_sb, not μ_cb); the y axis is named with its unit."""
    with Atlas(path) as atlas:
        fig = atlas.plot(x="torque", y="bit_damping", at={"wob": 100.0})
    ax = fig.axes[0]
    black = [  # the stuck contour (the stability one is dark red)
        c for c in ax.collections if hasattr(c, "levels") and not c.get_edgecolor()[0][:3].any()
    ]
    assert len(black) == 1
    pts = np.concatenate([p.vertices for p in black[0].get_paths() if len(p.vertices)])
    np.testing.assert_allclose(pts[:, 0], MU_R * 100.0, rtol=1e-9)
    assert ax.get_ylabel() == "bit_damping (N·m·s/rad)"
    assert ax.get_xlabel() == "surface torque $u$ (N·m)"
    assert "wob = 100 N" in ax.get_title()


@pytest.mark.parametrize("initial", ["rest", "equilibrium"])
def test_metric_maps_show_the_start_s_values_and_hatch_its_stuck_cells(path, initial):
    """severity from ``initial`` and omega_eq of the fastest steady state, cell by cell as h5py
    reads them; the stuck hatching sits on exactly the cells h5py calls stuck."""
    j = ["rest", "equilibrium"].index(initial)
    with Atlas(path) as atlas:
        sev = atlas.plot(initial=initial, metric="severity")
        om = atlas.plot(initial=initial, metric="omega_eq")
        ev = atlas.plot(initial=initial, metric="stick_events")
    for fig, name, col in ((sev, "severity", j), (om, "omega_eq", 0), (ev, "stick_events", j)):
        arr = np.ma.masked_invalid(_mesh(fig.axes[0]).get_array()).reshape(4, 3)  # (torque, wob)
        want = _raw(path, name)[:, :, 0, col].astype(float).T
        if name == "stick_events":
            want[want < 0] = np.nan  # -1: not measured
        np.testing.assert_array_equal(arr.mask, ~np.isfinite(want))
        np.testing.assert_allclose(arr.filled(np.nan), want)
    stuck = _raw(path, "regime")[:, :, 0, j] == fmt.REGIMES["stuck"]
    ax = sev.axes[0]
    cells = [
        p.get_extents() for c in ax.collections if c.get_hatch() == "////" for p in c.get_paths()
    ]
    centres = {(round(b.x0 + b.width / 2, 6), round(b.y0 + b.height / 2, 6)) for b in cells}
    want = {(w, u) for (a, b), w, u in _cells(stuck)}
    assert centres == want


def _cells(mask):
    wob, torque = [40.0, 100.0, 160.0], [3.0, 6.0, 9.0, 12.0]
    return [((a, b), wob[a], torque[b]) for a, b in zip(*np.nonzero(mask), strict=True)]


def test_hopf_margin_is_red_where_unstable(path):
    """A negative hopf margin (unstable) is coloured red, a positive one blue (RdBu)."""
    with Atlas(path) as atlas:
        fig = atlas.plot(metric="hopf_margin")
    mesh = _mesh(fig.axes[0])
    values = np.ma.masked_invalid(mesh.get_array())
    faces = mesh.to_rgba(values)
    for v, (r, _, b, _) in zip(values.compressed(), faces[~values.mask], strict=True):
        if abs(v) > 1e-3:
            assert (r > b) == (v < 0), (v, r, b)


@pytest.mark.parametrize("initial", ["rest", "equilibrium"])
def test_profile_draws_each_start_s_velocities_and_regimes_at_the_held_torque(path, initial):
    """A profile along W_ob at u = 9 N·m (grid index 2): each start's mean line and its
    regime strip are that start's values there (h5py); the steady line is omega_eq solid where
    the spectral abscissa is negative; the title says the held torque."""
    from matplotlib.colors import to_rgba

    with Atlas(path) as atlas:
        fig = atlas.plot(initial=initial, profile=True, x="wob", at={"torque": 9.0})
        ev = atlas.plot("stick_events", initial=initial, profile=True, at={"torque": 9.0})
    ax, strip = fig.axes[0], fig.axes[1]
    mean, regime = _raw(path, "bit_mean")[:, 2, 0], _raw(path, "regime")[:, 2, 0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    for j, s in enumerate(["rest", "equilibrium"]):
        ln = lines[f"from {s}: mean (band: least to largest)"]
        np.testing.assert_allclose(ln.get_xdata(), [40.0, 100.0, 160.0])
        np.testing.assert_allclose(ln.get_ydata(), mean[:, j])
    omega = _raw(path, "omega_eq")[:, 2, 0, 0].astype(float)
    stable = _raw(path, "spectral_abscissa")[:, 2, 0, 0] < 0
    np.testing.assert_allclose(
        lines["fastest steady state, stable"].get_ydata(), np.where(stable, omega, np.nan)
    )
    assert ax.get_ylabel() == "bit velocity (rad/s)"
    assert strip.get_xlabel() == "weight on bit $W_{ob}$ (N)"
    assert "torque = 9 N·m" in ax.get_title()
    starts = [initial] + [s for s in ["rest", "equilibrium"] if s != initial]
    assert [t.get_text() for t in strip.get_yticklabels()] == [f"from {s}" for s in starts]
    mesh = _mesh(strip)
    faces = mesh.to_rgba(mesh.get_array()).reshape(2, 3, 4)
    for row, s in enumerate(starts):
        col = ["rest", "equilibrium"].index(s)
        for i in range(3):
            want = to_rgba(MAP_COLORS[fmt.REGIME_NAMES[int(regime[i, col])]])
            np.testing.assert_allclose(faces[row, i], want, err_msg=f"{s} at {i}")
    # the metric profile: each start's counts (-1: not measured), crosses on its stuck points
    events = _raw(path, "stick_events")[:, 2, 0].astype(float)
    events[events < 0] = np.nan
    ax = ev.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    for j, s in enumerate(["rest", "equilibrium"]):
        np.testing.assert_allclose(lines[f"from {s}"].get_ydata(), events[:, j])
        crosses = [c for c in ax.collections if c.get_label() == f"from {s}: bit stuck"]
        stuck = regime[:, j] == fmt.REGIMES["stuck"]
        got = crosses[0].get_offsets()[:, 0] if crosses else []
        np.testing.assert_allclose(got, np.array([40.0, 100.0, 160.0])[stuck])
