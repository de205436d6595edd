"""Safe operating windows (``Atlas.safe_windows``, ``pydrill atlas safe``) against a brute-force
reading of the raw datasets: every window is a maximal run of safe grid points, and together
they are exactly the safe points; points not computed are counted and never inside one."""

import json
import subprocess
import tomllib

import h5py
import numpy as np
import pytest
from sweeping import CMD

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# The 4-DOF laboratory string on a (W_ob, u) grid (W_ob out of order: the spec sorts each axis)
GRID = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [200.0, 20.0, 40.0, 60.0, 80.0, 100.0, 120.0, 140.0, 160.0, 180.0]
torque = [6.0, 8.3, 10.0, 14.0]
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
"""


@pytest.fixture(scope="module")
def grid(tmp_path_factory):
    out = tmp_path_factory.mktemp("safe") / "grid.h5"
    run_sweep(parse_spec(GRID), out, serial=True)
    return out


def _brute_safe(path):
    """Safe points straight from the file: every start steady, fastest steady state with no
    eigenvalue in the right half-plane."""
    with h5py.File(path, "r") as f:
        steady = np.all(f["regime"][...] == fmt.REGIMES["steady"], axis=-1)
        stable = f["unstable"][..., 0] == 0
        done = f["status"][...] == fmt.STATUS["done"]
        axes = {n: f[n][...] for n in json.loads(f.attrs["axes"])}
    return steady & stable, done, axes


def _check_rows(rows, safe, done, wob, torque):
    """Each row against the brute-force truth along W_ob at its torque."""
    assert [row.at["torque"] for row in rows] == torque.tolist()
    order = np.argsort(wob)
    for j, row in enumerate(rows):
        ok = safe[order, j]
        values = wob[order]
        covered = np.zeros(len(values), bool)
        for lo, hi in row.windows:
            inside = (values >= lo) & (values <= hi)
            assert ok[inside].all()  # a window holds safe points only
            covered |= inside
            k_lo, k_hi = np.flatnonzero(inside)[[0, -1]]
            # maximal: the grid points either side are not safe
            assert k_lo == 0 or not ok[k_lo - 1]
            assert k_hi == len(values) - 1 or not ok[k_hi + 1]
        assert np.array_equal(covered, ok)  # and every safe point is in one
        assert row.safe == ok.sum() and row.points == len(wob)
        assert row.not_done == (~done[:, j]).sum()
        starts = [lo for lo, _ in row.windows]
        assert starts == sorted(starts)


def test_windows_are_the_maximal_runs_of_safe_points(grid):
    safe, done, axes = _brute_safe(grid)
    assert 0 < safe.sum() < safe.size  # something to find, and something to leave out
    with Atlas(grid) as atlas:
        rows = atlas.safe_windows()
        _check_rows(rows, safe, done, axes["wob"], axes["torque"])
        # the paper's picture (Fig. 6b): at a fixed torque the bit drills steadily at light
        # weights, and sticks and slips or stays stuck above; a window starts at the least W_ob
        for row in rows:
            if row.windows:
                assert row.windows[0][0] == 20.0 and len(row.windows) == 1
        # more torque never narrows the window (the stuck boundary u = mu_sb W R_b moves right)
        tops = [row.windows[0][1] if row.windows else 0.0 for row in rows]
        assert tops == sorted(tops) and tops[-1] > tops[0]
        # held at one torque, with a unit; along the other axis
        (one,) = atlas.safe_windows(torque="8.3 N·m")
        assert one == rows[1]
        across = atlas.safe_windows(along="torque", wob=40.0)
        assert len(across) == 1 and across[0].at == {"wob": 40.0}
        k = int(np.flatnonzero(axes["wob"] == 40.0)[0])
        assert across[0].safe == safe[k].sum()
        for bad, error in [
            (dict(along="depth"), KeyError),
            (dict(along="wob", wob=40.0), ValueError),
            (dict(depth=3.0), KeyError),
        ]:
            with pytest.raises(error):
                atlas.safe_windows(**bad)


def test_points_not_computed_end_a_window_and_are_counted(tmp_path):
    """A point whose solver gave up is not safe for want of a result; the row says so."""
    out = tmp_path / "failing.h5"
    spec = GRID.replace("t_end = 100.0", "t_end = 100.0\nmax_steps = 500")
    report = run_sweep(parse_spec(spec), out, serial=True)
    assert 0 < report.failed < report.points
    safe, done, axes = _brute_safe(out)
    assert not (safe & ~done).any()
    with Atlas(out) as atlas:
        rows = atlas.safe_windows()
    _check_rows(rows, safe, done, axes["wob"], axes["torque"])
    assert sum(row.not_done for row in rows) == report.failed


def test_a_point_not_computed_inside_a_window_splits_it(grid, tmp_path):
    """Solvers fail where the stick-slip is hardest, rarely amid steady points: so one safe
    point in the middle of a window is marked failed by hand, as a failed point is stored."""
    import shutil

    out = tmp_path / "holed.h5"
    shutil.copy(grid, out)
    with Atlas(grid) as atlas:
        (row,) = atlas.safe_windows(torque=14.0)
    lo, hi = row.windows[0]
    _, _, axes = _brute_safe(grid)
    inner = sorted(w for w in axes["wob"] if lo < w < hi)
    assert inner, "the window at u = 14 N·m needs a point inside it"
    hole = inner[len(inner) // 2]
    i = int(np.flatnonzero(axes["wob"] == hole)[0])
    j = int(np.flatnonzero(axes["torque"] == 14.0)[0])
    with h5py.File(out, "r+") as f:
        f["status"][i, j] = fmt.STATUS["failed"]
        f["regime"][i, j] = fmt.REGIMES["failed"]
        f["message"][i, j] = "SolverError: marked failed by the test"
    safe, done, axes = _brute_safe(out)
    with Atlas(out) as atlas:
        (split,) = atlas.safe_windows(torque=14.0)
        _check_rows(atlas.safe_windows(), safe, done, axes["wob"], axes["torque"])
    below = max(w for w in axes["wob"] if w < hole)
    above = min(w for w in axes["wob"] if w > hole)
    assert split.windows == [(lo, below), (above, hi)]
    assert split.not_done == 1 and split.safe == row.safe - 1


def test_the_command_prints_and_scripts_read_the_same_windows(grid):
    text = subprocess.run(
        [*CMD, "atlas", "safe", str(grid), "--set", "torque=8.3"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.splitlines()
    with Atlas(grid) as atlas:
        (row,) = atlas.safe_windows(torque=8.3)
    # The held torque is said once, in the first line; the one row needs no label.
    assert text[0] == f"{grid}: safe windows along wob, at torque = 8.3 N·m"
    assert (
        text[1]
        == "  safe: steady from rest and from equilibrium, and the fastest steady state stable"
    )
    lo, hi = row.windows[0]
    assert text[2] == f"  wob {lo:g} N ... {hi:g} N ({row.safe} of 10 points)"
    doc = json.loads(
        subprocess.run(
            [*CMD, "atlas", "safe", str(grid), "--json"], capture_output=True, text=True, check=True
        ).stdout
    )
    safe, _, axes = _brute_safe(grid)
    assert doc["along"] == "wob" and doc["fixed"] == {}
    assert doc["units"] == {"along": "N", "at": {"torque": "N·m"}, "fixed": {}}
    for j, r in enumerate(doc["rows"]):
        assert r["safe_points"] == safe[:, j].sum() and r["points"] == 10
        assert r["at"] == {"torque": axes["torque"][j]}
        for lo, hi in r["windows"]:
            inside = (axes["wob"] >= lo) & (axes["wob"] <= hi)
            assert safe[inside, j].all()


# Torque fixed for the whole sweep ([model]) and an axis of one value: every row shares both.
HELD = """
[model]
preset = "reduced-scale"
dof = 4
torque = 10.0
[axes]
mu_static = [0.8]
wob = [20.0, 40.0, 60.0, 80.0, 100.0]
bit_damping = [0.03, 0.05, 0.07]
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
"""


def test_what_every_row_shares_is_said_once_in_the_first_line(tmp_path):
    """The spec's fixed torque and a one-value axis (and an axis held by --set) are said once,
    in the first line, with the value the atlas file holds; the rows are labelled by what
    varies from one to the next only, and each row's windows are the raw datasets' runs."""
    out = tmp_path / "held.h5"
    run_sweep(parse_spec(HELD), out, serial=True)
    safe, _, axes = _brute_safe(out)
    with h5py.File(out, "r") as f:  # the fixed torque as the file stores it: its spec's text
        torque = tomllib.loads(f.attrs["spec"])["model"]["torque"]
    (mu,) = axes["mu_static"]

    def run(*args):
        proc = [*CMD, "atlas", "safe", str(out), *args]
        return subprocess.run(proc, capture_output=True, text=True, check=True).stdout

    text = run().splitlines()
    assert (
        text[0] == f"{out}: safe windows along wob, at torque = {torque:g} N·m, mu_static = {mu:g}"
    )
    rows = text[2 : 2 + len(axes["bit_damping"])]
    for k, line in enumerate(rows):
        label, _, shown = line.strip().partition(":  ")
        assert label == f"bit_damping = {axes['bit_damping'][k]:g} N·m·s/rad"
        assert "mu_static" not in line and "torque" not in line
        assert shown.endswith(f"({safe[0, :, k].sum()} of {len(axes['wob'])} points)")
    one = run("--set", "bit_damping=0.05").splitlines()[0]
    assert one.endswith(", at torque = 10 N·m, mu_static = 0.8, bit_damping = 0.05 N·m·s/rad")
    doc = json.loads(run("--json"))
    assert doc["fixed"] == {"torque": torque} and doc["units"]["fixed"] == {"torque": "N·m"}
    for k, r in enumerate(doc["rows"]):  # scripts still read every row's place whole
        assert r["at"] == {"mu_static": mu, "bit_damping": axes["bit_damping"][k]}


def test_the_command_refuses_what_it_cannot_answer(grid, tmp_path):
    def refused(*args):
        proc = subprocess.run([*CMD, "atlas", "safe", *args], capture_output=True, text=True)
        assert proc.returncode == 2 and not proc.stdout
        return proc.stderr

    assert "--set wob=40: wob is the axis the windows run along" in refused(
        str(grid), "--set", "wob=40"
    )
    assert "--set torque=30: torque = 30 N·m is outside the atlas (6 N·m ... 14 N·m)" in refused(
        str(grid), "--set", "torque=30"
    )
    assert "--along depth: depth is not an axis of this atlas; axes: wob, torque" in refused(
        str(grid), "--along", "depth"
    )
    blind = tmp_path / "blind.h5"
    run_sweep(parse_spec(GRID + "[record]\nstability = false\n"), blind, serial=True)
    assert "did not record stability" in refused(str(blind))


def _outline(fig):
    """The safe outline's segments, as sets of cell-edge pieces, and the legend's labels."""
    from matplotlib.collections import LineCollection

    ax = fig.axes[0]
    (lines,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    pieces = {tuple(map(tuple, np.round(s, 9))) for s in lines.get_segments()}
    return pieces, [t.get_text() for t in ax.get_legend().get_texts()]


@pytest.mark.parametrize("swap", [False, True])
def test_regime_maps_outline_exactly_the_safe_cells(grid, swap):
    """Every edge of the outline lies between a safe cell and one that is not, and every such
    edge is drawn, none along the grid's border (the frame's: on a map whose axes end at the
    outer cells' edges it traced the whole frame): checked against the raw datasets, cell by
    cell, with the map's axes either way round."""
    from pydrill.plot_atlas import _edges

    safe, _, axes = _brute_safe(grid)
    x, y = ("torque", "wob") if swap else ("wob", "torque")
    mask = safe.T if swap else safe  # (x, y)
    order_x, order_y = np.argsort(axes[x]), np.argsort(axes[y])
    mask = mask[order_x][:, order_y]  # the map's cells run over increasing values
    ex, ey = _edges(np.sort(axes[x])), _edges(np.sort(axes[y]))
    pad = np.pad(mask, 1, mode="edge")  # no edge along the grid's own border
    want = set()
    for i in range(len(ex)):
        for j in range(len(ey) - 1):
            if pad[i, j + 1] != pad[i + 1, j + 1]:
                want.add(((ex[i], ey[j]), (ex[i], ey[j + 1])))
    for i in range(len(ex) - 1):
        for j in range(len(ey)):
            if pad[i + 1, j] != pad[i + 1, j + 1]:
                want.add(((ex[i], ey[j]), (ex[i + 1], ey[j])))
    want = {tuple(tuple(np.round(p, 9)) for p in seg) for seg in want}
    with Atlas(grid) as atlas:
        for initial in ("rest", "equilibrium"):
            pieces, labels = _outline(atlas.plot(x=x, y=y, initial=initial))
            assert pieces == want
            assert "safe: steady from both starts, stable" in labels


def test_no_outline_without_stability(tmp_path):
    from matplotlib.collections import LineCollection

    blind = tmp_path / "blind.h5"
    run_sweep(parse_spec(GRID + "[record]\nstability = false\n"), blind, serial=True)
    with Atlas(blind) as atlas:
        ax = atlas.plot().axes[0]
    assert not [c for c in ax.collections if isinstance(c, LineCollection)]
    assert not any(t.get_text().startswith("safe") for t in ax.get_legend().get_texts())


def test_a_window_at_the_grid_s_end_is_not_said_to_end_within_a_grid_step(grid):
    """'wob 20 kN ... 80 kN' on a grid from 20 kN, and '(the true edges lie within a grid step
    beyond each window's ends)': but past the grid's own end the atlas says nothing. The note
    names the ends that windows reach, and --json gives each window's outside neighbours on the
    grid (null past its end), checked against the raw datasets."""
    safe, _, axes = _brute_safe(grid)
    wob = np.sort(axes["wob"])
    order = np.argsort(axes["wob"])
    text = subprocess.run(
        [*CMD, "atlas", "safe", str(grid)], capture_output=True, text=True, check=True
    ).stdout
    at_first = safe[order[0], :].any()  # some row's window starts at the grid's first W_ob
    at_last = safe[order[-1], :].any()
    assert at_first or at_last  # the case this test is for
    note = " ".join(text.split("(the true edges lie")[1].split())
    if at_first and at_last:
        assert f"one from {wob[0]:g} N or to {wob[-1]:g} N, the grid's ends" in note
    elif at_first:
        assert f"one from {wob[0]:g} N, the grid's first value, may begin below it)" in note
    else:
        assert f"one to {wob[-1]:g} N, the grid's last value, may go on above it)" in note
    doc = json.loads(
        subprocess.run(
            [*CMD, "atlas", "safe", str(grid), "--json"], capture_output=True, text=True, check=True
        ).stdout
    )
    for j, row in enumerate(doc["rows"]):
        ok = safe[order, j]
        for (lo, hi), (below, above) in zip(row["windows"], row["beyond"], strict=True):
            k, m = int(np.searchsorted(wob, lo)), int(np.searchsorted(wob, hi))
            assert below == (None if k == 0 else wob[k - 1])
            assert above == (None if m == len(wob) - 1 else wob[m + 1])
            for outside in (below, above):  # the neighbours are not safe: the edge is between
                assert outside is None or not ok[int(np.searchsorted(wob, outside))]


def test_query_says_each_point_s_verdict_and_why_not(grid, capsys):
    """'atlas query' ends on the verdict 'atlas safe' counts (it was in --json alone): at every
    grid point 'safe: yes' exactly where the raw datasets make the point safe, and a 'no' names
    each start that is not steady, read from the file."""
    from pydrill import cli

    safe, done, axes = _brute_safe(grid)
    with h5py.File(grid, "r") as f:
        regime = f["regime"][...]
    names = {code: name for name, code in fmt.REGIMES.items()}
    for i, w in enumerate(axes["wob"]):
        for j, u in enumerate(axes["torque"]):
            assert (
                cli.main(
                    [
                        "atlas",
                        "query",
                        str(grid),
                        "--wob",
                        repr(float(w)),
                        "--torque",
                        repr(float(u)),
                    ]
                )
                == 0
            )
            last = capsys.readouterr().out.splitlines()[-1]
            if safe[i, j]:
                assert (
                    last == "  safe: yes (steady from rest and from equilibrium, the fastest "
                    "steady state stable)"
                )
                continue
            assert last.startswith("  safe: no")
            for k, start in enumerate(("rest", "equilibrium")):
                name = names[int(regime[i, j, k])]
                assert (f"{name} from {start}" in last) == (name != "steady"), last
            if np.all(regime[i, j] == fmt.REGIMES["steady"]):
                assert last == "  safe: no (the fastest steady state is unstable)"
    assert done.all() and 0 < safe.sum() < safe.size  # both verdicts were asked
