"""Boundaries on maps over axes other than (W_ob, u): where they are drawn is checked against
the stuck condition and the atlas's own spectral abscissa, not against the drawing code."""

import h5py
import numpy as np
import pytest

from pydrill.atlas import Atlas
from pydrill.model import preset
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

SIZE = """
[model]
preset = "reduced-scale"
torque = 8.3
[axes]
wob = { start = 60.0, stop = 160.0, num = 21 }
pipes = [1, 3, 6]
[simulation]
t_end = 50.0
initial = ["rest"]
"""

FRICTION = """
[model]
preset = "reduced-scale"
dof = 4
wob = 100.0
[axes]
torque = { start = 4.0, stop = 14.0, num = 11 }
mu_static = { start = 0.55, stop = 1.0, num = 10 }
[simulation]
t_end = 50.0
initial = ["rest"]
"""

STUCK = "stuck boundary $u = \\mu_{sb} W_{ob} R_b$\n(static: a start-up can overshoot it)"
UNSTABLE = "stability boundary of the fastest steady state\n(from the atlas's eigenvalues)"


@pytest.fixture(scope="module")
def atlases(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("bounds")
    out = {}
    for name, text in (("size", SIZE), ("friction", FRICTION)):
        out[name] = tmp / f"{name}.h5"
        run_sweep(parse_spec(text), out[name], serial=True)
    return out


def _curves(fig):
    """The contour lines drawn, as (N, 2) vertex arrays, and the legend's labels."""
    ax = fig.axes[0]
    sets = [c for c in ax.collections if hasattr(c, "levels")]
    paths = [[p.vertices for p in cs.get_paths() if len(p.vertices)] for cs in sets]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    return paths, labels


def test_the_stuck_boundary_on_torque_and_friction_is_where_u_equals_t_s(atlases):
    r_b = preset("reduced-scale", dof=4).bit_radius
    with Atlas(atlases["friction"]) as atlas:
        paths, labels = _curves(atlas.plot())
    assert STUCK in labels
    stuck = np.concatenate(paths[0])
    assert len(stuck) >= 2
    u, mu = stuck[:, 0], stuck[:, 1]
    np.testing.assert_allclose(u, mu * 100.0 * r_b, rtol=1e-9)  # u = mu_sb W R_b, exactly
    assert u.min() < 6.0 and u.max() > 9.0  # across the map, not a stub


def test_the_stability_boundary_lies_between_grid_points_of_opposite_sign(atlases):
    with Atlas(atlases["size"]) as atlas:
        paths, labels = _curves(atlas.plot())
        swapped, _ = _curves(atlas.plot(x="pipes", y="wob"))  # the grid read transposed
    for drawn, turned in zip(paths, swapped, strict=True):
        a, b = np.concatenate(drawn), np.concatenate(turned)[:, ::-1]
        np.testing.assert_allclose(a[np.lexsort(a.T)], b[np.lexsort(b.T)], rtol=1e-12)
    with h5py.File(atlases["size"], "r") as f:
        wob, pipes = f["wob"][...], f["pipes"][...]
        abscissa = f["spectral_abscissa"][..., 0]  # (wob, pipes), the fastest steady state
    assert UNSTABLE in labels and len(paths) == 2
    line = np.concatenate(paths[1])
    for p, n in enumerate(pipes):  # on each grid row, the curve crosses where the sign does
        row = abscissa[:, p]
        k = [i for i in range(len(wob) - 1) if row[i] < 0 < row[i + 1]]
        assert len(k) == 1, row
        at = line[np.isclose(line[:, 1], n)][:, 0]
        assert len(at) == 1 and wob[k[0]] <= at[0] <= wob[k[0] + 1]
        # linear between the two grid values, as a contour interpolates
        i = k[0]
        expect = wob[i] - row[i] * (wob[i + 1] - wob[i]) / (row[i + 1] - row[i])
        assert at[0] == pytest.approx(expect, rel=1e-9)
    # The stuck boundary does not depend on the size: one wob, u / (mu_sb R_b)
    p = preset("reduced-scale", dof=4)
    stuck = np.concatenate(paths[0])
    np.testing.assert_allclose(stuck[:, 0], 8.3 / (p.mu_static * p.bit_radius), rtol=1e-9)


def test_no_stability_boundary_without_recorded_stability(atlases, tmp_path):
    out = tmp_path / "nostab.h5"
    run_sweep(parse_spec(SIZE + "[record]\nstability = false\n"), out, serial=True)
    with Atlas(out) as atlas:
        paths, labels = _curves(atlas.plot())
    assert labels[-1] == STUCK and UNSTABLE not in labels and len(paths) == 1


def test_the_stuck_boundary_runs_across_whole_cells(atlases):
    """The stuck boundary's contour was taken over the grid points alone, so it stopped half a
    cell short of each side of a map drawn in whole cells (a (depth, W_ob) map's line ran
    1000 ... 5000 m across cells from 750 to 5250 m). It is the closed form, so it is drawn
    out to the cells' outer edges: half a step beyond the first and last of pipes 1, 3, 6."""
    with Atlas(atlases["size"]) as atlas:
        paths, labels = _curves(atlas.plot())
    assert STUCK in labels
    pipes = np.concatenate(paths[0])[:, 1]
    assert pipes.min() == pytest.approx(1 - (3 - 1) / 2) and pipes.max() == pytest.approx(
        6 + (6 - 3) / 2
    )
