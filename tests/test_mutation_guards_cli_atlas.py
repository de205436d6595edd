"""What ``atlas query``, ``atlas info`` and ``atlas safe`` print, against the file read with h5py.

Found by a mutation audit of the command line's output layer: scripts read ``--json``, so a key
holding another start's value, a unit not written as the other documents write it, a window's
neighbours off by one, or a count taken from the wrong place is a bug. A small atlas has its
codes overwritten with chosen ones (safe runs of one and of two points, failed and missing
points, unstable steady states, caveats); each document is compared with the file's datasets
and with counts and units worked out here by hand.
"""

import math

import h5py
import numpy as np
import pytest
from cli_running import ok_json, ok_text
from test_mutation_guards_query import _runs as runs_of

from pydrill import atlas_format as fmt
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# wob crosses 5 kN (KILO): the whole axis reads in kN, its 100 N as 0.1 kN
SPEC = """
[model]
preset = "reduced-scale"
dof = 2
[axes]
wob = [40.0, 100.0, 2500.0, 6000.0]
torque = [6.0, 7.0, 8.3]
[simulation]
t_end = 5.0
initial = ["rest", "equilibrium"]
"""

# torque held by the spec, a count axis, and one start; stability not recorded
HELD = """
[model]
preset = "reduced-scale"
torque = 8.3
[axes]
pipes = [1, 2]
wob = [100.0]
[simulation]
t_end = 5.0
initial = ["rest"]
[record]
stability = false
"""

S, X = fmt.REGIMES["steady"], fmt.REGIMES["stick-slip"]


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    """Safe (every start steady, fastest state stable): torque 6 at wob 40, 100; torque 7 at
    100 alone; torque 8.3 at 100 and at 2500, 6000. (0, 1) failed, (3, 1) missing; (2, 0)
    steady but its fastest steady state unstable (2 eigenvalues), (1, 2) steady with the
    second one unstable; at (0, 2) and (3, 0) one start is steady, the other not."""
    path = tmp_path_factory.mktemp("cliatlas") / "a.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    rng = np.random.default_rng(36)
    with h5py.File(path, "r+") as f:
        regime = np.full(f["regime"].shape, X, dtype=np.int8)
        for i, j in [(0, 0), (1, 0), (1, 1), (2, 2), (3, 2), (2, 0), (1, 2)]:
            regime[i, j] = S
        regime[0, 2, 0] = regime[3, 0, 1] = S  # the starts disagree: not safe
        regime[0, 1] = fmt.REGIMES["failed"]
        regime[3, 1] = fmt.REGIMES["missing"]
        f["regime"][...] = regime
        status = np.full(f["status"].shape, fmt.STATUS["done"], dtype=np.uint8)
        status[0, 1], status[3, 1] = fmt.STATUS["failed"], fmt.STATUS["missing"]
        f["status"][...] = status
        unstable = np.zeros(f["unstable"].shape, dtype=np.int16)
        unstable[2, 0, 0] = 2
        unstable[1, 2, 1] = 1
        f["unstable"][...] = unstable
        omega = rng.uniform(1.0, 9.0, size=f["omega_eq"].shape)
        omega[..., 1] = np.nan  # a second steady state only where one is unstable
        omega[1, 2, 1] = 0.5
        f["omega_eq"][...] = omega
        f["caveat"][...] = rng.choice(list(fmt.CAVEATS.values()), size=f["caveat"].shape)
        f["stuck_fraction"][...] = rng.uniform(0.0, 1.0, size=f["stuck_fraction"].shape)
        f["bit_mean"][...] = rng.uniform(0.0, 9.0, size=f["bit_mean"].shape)
        f["period"][...] = rng.uniform(1.0, 5.0, size=f["period"].shape)
    return path


@pytest.fixture(scope="module")
def held(tmp_path_factory):
    path = tmp_path_factory.mktemp("cliatlas") / "held.h5"
    run_sweep(parse_spec(HELD), path, serial=True)
    return path


def _raw(path):
    with h5py.File(path, "r") as f:
        return {name: f[name][...] for name in f if isinstance(f[name], h5py.Dataset)}


def _safe(raw):
    """By hand: every start steady and the fastest steady state's count of unstable 0."""
    return np.all(raw["regime"] == S, axis=-1) & (raw["unstable"][..., 0] == 0)


def _number(x):
    return None if not np.isfinite(x) else float(x)


def test_query_json_holds_the_first_starts_values_and_every_unit(atlas, capsys):
    raw = _raw(atlas)
    safe = _safe(raw)
    assert safe.sum() == 6  # the windows the fixture means
    regimes = {c: n for n, c in fmt.REGIMES.items()}
    for (i, j), _ in np.ndenumerate(raw["status"]):
        w, u = float(raw["wob"][i]), float(raw["torque"][j])
        d = ok_json(capsys, "atlas", "query", atlas, "--wob", w, "--torque", u)
        assert d["asked"] == {"wob": w, "torque": u} == d["coords"]
        # the flat keys are the first start's (rest), by_initial each start's
        assert d["regime"] == regimes[raw["regime"][i, j, 0]]
        assert d["by_initial"]["regime"] == {
            "rest": regimes[raw["regime"][i, j, 0]],
            "equilibrium": regimes[raw["regime"][i, j, 1]],
        }
        for name in ("bit_mean", "stuck_fraction", "period"):
            assert d[name] == _number(raw[name][i, j, 0]), name
            assert d["by_initial"]["metrics"][name]["equilibrium"] == _number(raw[name][i, j, 1])
        assert d["caveat"] == (fmt.CAVEAT_NAMES[raw["caveat"][i, j, 0]] or None)
        assert d["safe"] is bool(safe[i, j])
    # units as every other document writes them: N·m·s/rad with a middle dot, 1/s, the axes'
    assert d["units"]["eigenvalues"] == "1/s"
    assert d["units"]["hopf_margin"] == d["units"]["delta"] == "N·m·s/rad"
    assert d["units"]["coords"] == {"wob": "N", "torque": "N·m"}


def test_query_json_of_a_held_torque_a_count_axis_and_no_stability(held, capsys):
    d = ok_json(capsys, "atlas", "query", held, "--pipes", "2", "--wob", "100", "--torque", "8.3")
    # asked: all that was given (the held torque too), the count as an int; coords the grid's
    assert d["asked"] == {"pipes": 2, "wob": 100.0, "torque": 8.3}
    assert type(d["asked"]["pipes"]) is int
    assert d["units"]["coords"] == {"pipes": "1", "wob": "N"}
    assert d["safe"] is None  # stability not recorded: nothing called safe, or not
    out = ok_text(capsys, "atlas", "query", held, "--pipes", "2", "--wob", "100")
    assert "safe:" not in out


def _line(out, start):
    (line,) = [x for x in out.splitlines() if x.strip().startswith(start)]
    return line


def test_query_text_says_the_files_numbers_in_their_units(atlas, capsys):
    raw = _raw(atlas)
    for i, j, safe in [(1, 0, "yes"), (2, 0, "no (the fastest steady state is unstable)")]:
        w, u = raw["wob"][i], raw["torque"][j]
        out = ok_text(capsys, "atlas", "query", atlas, "--wob", w, "--torque", u, "--nearest")
        # the whole axis reads in kN (it reaches 6 kN): 100 N is 0.1 kN; no 'nearest' line
        assert out.splitlines()[0] == f"wob = {w / 1e3:g} kN, torque = {u:g} N·m: done"
        assert "nearest" not in out
        rest = _line(out, "from rest")
        stuck, mean, period = (raw[n][i, j, 0] for n in ("stuck_fraction", "bit_mean", "period"))
        assert f"stuck {100 * stuck:.1f} %" in rest and f"bit mean {mean:.4g} rad/s" in rest
        assert rest.endswith(f", period {period:.4g} s")
        omega = raw["omega_eq"][i, j, 0]
        state = _line(out, "steady state")
        assert f"Omega = {omega:.5g} rad/s ({omega * 30 / math.pi:.4g} rpm)" in state
        n = raw["unstable"][i, j, 0]
        assert state.endswith("stable" if n == 0 else f"unstable ({n} eigenvalues with Re > 0)")
        assert _line(out, "safe:") == "  safe: " + (
            safe
            if safe != "yes"
            else "yes (steady from rest and from equilibrium, the fastest steady state stable)"
        )
    # steady from both, the fastest stable, a slower one unstable in its singular: safe
    out = ok_text(capsys, "atlas", "query", atlas, "--wob", 100, "--torque", 8.3)
    assert "unstable (1 eigenvalue with Re > 0)" in out and "safe: yes" in out
    out = ok_text(capsys, "atlas", "query", atlas, "--wob", 6000, "--torque", 7)
    assert "safe: no (the point is missing" in out
    out = ok_text(capsys, "atlas", "query", atlas, "--wob", 95, "--torque", 7, "--nearest")
    assert "(the grid point nearest wob = 0.095 kN)" in out


def test_info_counts_and_units_are_the_files(atlas, held, capsys):
    raw = _raw(atlas)
    d = ok_json(capsys, "atlas", "info", atlas)
    assert d["units"]["axes"] == {"wob": "N", "torque": "N·m"}
    assert d["points"] == raw["status"].size
    assert d["safe_points"] == int(_safe(raw).sum())
    for name, code in fmt.STATUS.items():
        assert d["status"][name] == int(np.sum(raw["status"] == code))
    out = ok_text(capsys, "atlas", "info", atlas)
    assert "  axis wob               4 values, 0.04 kN ... 6 kN" in out
    assert "  axis torque            3 values, 6 N·m ... 8.3 N·m" in out
    assert "safe points 6, rest/equilibrium disagree at " in out
    for k, init in enumerate(("rest", "equilibrium")):
        counts = {
            name: int(np.sum(raw["caveat"][..., k] == c))
            for name, c in fmt.CAVEATS.items()
            if name and name not in fmt.FINAL_CAVEATS and np.any(raw["caveat"][..., k] == c)
        }
        notes = ", ".join(f"{n} {v}" for n, v in counts.items())
        assert f"  caveats from {init}: {notes} (points to simulate" in out
    # the held torque in the model's units (N·m), one start: no disagreement counted
    d = ok_json(capsys, "atlas", "info", held)
    assert d["units"]["model"]["held"]["torque"] == "N·m"
    out = ok_text(capsys, "atlas", "info", held)
    assert "  model   preset reduced-scale, torque 8.3 N·m; 5 s from each start" in out
    assert (
        "  axis pipes             2 values, 1 ... 2\n  axis wob               1 value,  100 N"
        in out
    )
    assert "safe points unknown (stability not recorded)\n" in out


def test_safe_json_windows_neighbours_and_counts_are_the_files(atlas, capsys):
    raw = _raw(atlas)
    safe, wob = _safe(raw), [float(w) for w in raw["wob"]]
    d = ok_json(capsys, "atlas", "safe", atlas)
    assert [r["at"] for r in d["rows"]] == [{"torque": float(t)} for t in raw["torque"]]
    for j, row in enumerate(d["rows"]):
        windows = [list(r) for r in runs_of(safe[:, j], wob)]  # JSON's lists
        assert row["windows"] == windows
        # the grid values just outside each window (None past the grid's ends)
        assert row["beyond"] == [
            [
                wob[wob.index(a) - 1] if a != wob[0] else None,
                wob[wob.index(b) + 1] if b != wob[-1] else None,
            ]
            for a, b in windows
        ]
        assert row["safe_points"] == int(safe[:, j].sum()) and row["points"] == len(wob)
        assert row["not_done"] == int(np.sum(raw["status"][:, j] != fmt.STATUS["done"]))
    assert d["units"] == {"along": "N", "at": {"torque": "N·m"}, "fixed": {}}
    out = ok_text(capsys, "atlas", "safe", atlas)
    lines = out.splitlines()
    assert lines[2] == "  torque = 6 N·m:    wob 0.04 kN ... 0.1 kN (2 of 4 points)"
    # (0, 1) failed, (3, 1) missing: counted apart (a failed point was computed)
    assert lines[3] == "  torque = 7 N·m:    wob 0.1 kN (1 of 4 points; 1 failed; 1 not computed)"
    assert lines[5] == "  3 of 3 have a safe window"
    # windows from the grid's first value and to its last: both ends named
    assert "one from 0.04 kN or to 6 kN, the grid's ends" in out
    out = ok_text(capsys, "atlas", "safe", atlas, "--along", "torque", "--set", "wob=2.5kN")
    assert out.splitlines()[0].endswith("safe windows along torque, at wob = 2.5 kN")
    assert "one to 8.3 N·m, the grid's last value, may go on above it)" in out


def test_safe_json_of_a_held_torque_names_its_unit(held, tmp_path, capsys):
    spec = HELD.replace("[record]\nstability = false", "")
    path = tmp_path / "held.h5"
    run_sweep(parse_spec(spec), path, serial=True)
    d = ok_json(capsys, "atlas", "safe", path)
    assert d["fixed"] == {"torque": 8.3}
    assert d["units"] == {"along": "N", "at": {"pipes": "1"}, "fixed": {"torque": "N·m"}}
