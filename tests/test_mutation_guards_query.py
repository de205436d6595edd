"""The atlas queries against the file itself, read with h5py and counted with numpy.

Found by a mutation audit of the query side (atlas_value, atlas_summary, atlas_safe,
atlas_xarray, export_csv): an atlas whose every code occurs (failed and missing points, each
regime, counts not measured, a second steady state or none, coexistence unknown) is checked
point by point, so that a lookup, a count or an exported cell taken from the wrong place
fails here. The atlas is a small sweep whose datasets are then overwritten with random codes:
what the queries read is whatever the file holds, not what a simulation would make.
"""

import csv
import math
import shutil

import h5py
import numpy as np
import pytest

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

SPEC = """
[model]
preset = "reduced-scale"
dof = 2
[axes]
wob = [40.0, 70.0, 100.0, 130.0, 160.0, 190.0]
torque = [6.0, 7.0, 8.3]
[simulation]
t_end = 20.0
initial = ["rest", "equilibrium"]
"""


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    path = tmp_path_factory.mktemp("query") / "swept.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    return path


@pytest.fixture(scope="module")
def scrambled(swept, tmp_path_factory):
    """The swept atlas with random codes and values: every status, regime, caveat and
    coexistence code, counts of -1 (not measured), a second steady state at some points."""
    path = tmp_path_factory.mktemp("query") / "scrambled.h5"
    shutil.copy(swept, path)
    rng = np.random.default_rng(34)
    with h5py.File(path, "r+") as f:
        shape = f["status"].shape
        f["status"][...] = rng.choice([0, 1, 1, 1, 2], size=shape)
        f["message"][...] = np.array(
            [f"boom {k}" for k in range(math.prod(shape))], dtype=object
        ).reshape(shape)
        regimes = list(fmt.REGIMES.values())
        f["regime"][...] = rng.choice(regimes + [0] * 6, size=f["regime"].shape)
        f["caveat"][...] = rng.choice(list(fmt.CAVEATS.values()), size=f["caveat"].shape)
        f["coexistence"][...] = rng.choice([-1, 0, 1], size=shape)
        f["unstable"][...] = rng.choice([-1, 0, 0, 1, 2], size=f["unstable"].shape)
        f["stick_events"][...] = rng.choice([-1, 0, 3], size=f["stick_events"].shape)
        omega = rng.uniform(-2.0, 9.0, size=f["omega_eq"].shape)
        omega[rng.random(omega.shape) < 0.3] = np.nan
        f["omega_eq"][...] = omega
        mean = rng.uniform(0.0, 9.0, size=f["bit_mean"].shape)
        mean[rng.random(mean.shape) < 0.2] = np.inf
        f["bit_mean"][...] = mean
    return path


def _raw(path):
    with h5py.File(path, "r") as f:
        return {name: f[name][...] for name in f if isinstance(f[name], h5py.Dataset)}


def _safe_by_hand(raw):
    """Every start steady and the fastest steady state's unstable count exactly 0."""
    shape = raw["status"].shape
    safe = np.zeros(shape, dtype=bool)
    for idx in np.ndindex(*shape):
        steady = all(r == fmt.REGIMES["steady"] for r in raw["regime"][idx])
        safe[idx] = steady and raw["unstable"][idx][0] == 0
    return safe


def test_value_is_what_the_file_holds_at_every_point(scrambled):
    raw = _raw(scrambled)
    names = {c: n for n, c in fmt.REGIMES.items()}
    status = {c: n for n, c in fmt.STATUS.items()}
    caveats = {c: n for n, c in fmt.CAVEATS.items()}
    with Atlas(scrambled) as atlas:
        starts = atlas.initials
        wobs, torques = raw["wob"], raw["torque"]
        for i, j in np.ndindex(len(wobs), len(torques)):
            point = atlas.value(wob=float(wobs[i]), torque=float(torques[j]))
            assert point["coords"] == {"wob": float(wobs[i]), "torque": float(torques[j])}
            assert point["status"] == status[raw["status"][i, j]]
            if point["status"] == "failed":
                assert point["message"] == raw["message"][i, j].decode()
            else:
                assert "message" not in point
            assert point["regime"] == {
                s: names[raw["regime"][i, j, k]] for k, s in enumerate(starts)
            }
            events = raw["stick_events"][i, j]
            assert point["metrics"]["stick_events"] == {
                s: None if events[k] == -1 else int(events[k]) for k, s in enumerate(starts)
            }
            mean = raw["bit_mean"][i, j]
            assert point["metrics"]["bit_mean"] == {
                s: float(mean[k]) if np.isfinite(mean[k]) else None for k, s in enumerate(starts)
            }
            # the steady states: as many as omega_eq has finite values, fastest first
            found = int(np.sum(np.isfinite(raw["omega_eq"][i, j])))
            stability = point["stability"]
            assert len(stability["omega_eq"]) == found
            assert stability["unstable"] == [
                None if u == -1 else int(u) for u in raw["unstable"][i, j][:found]
            ]
            co = raw["coexistence"][i, j]
            assert point["coexistence"] == {-1: None, 0: False, 1: True}[int(co)]
            assert point["caveat"] == {
                s: caveats[raw["caveat"][i, j, k]] or None for k, s in enumerate(starts)
            }


def test_nearest_answers_for_the_grid_point_within_half_a_step(scrambled):
    """A value a third of a step off a grid point: refused exactly, that point's with nearest."""
    raw = _raw(scrambled)
    with Atlas(scrambled) as atlas:
        for i, j in [(0, 0), (2, 1), (5, 2), (3, 0)]:
            w, t = float(raw["wob"][i]), float(raw["torque"][j])
            off = w + (10.0 if i < 5 else -10.0)  # the wob step is 30
            with pytest.raises(KeyError):
                atlas.value(wob=off, torque=t)
            near = atlas.value("nearest", wob=off, torque=t + 0.3)
            assert near == atlas.value(wob=w, torque=t)


def test_summary_counts_are_numpys(scrambled, swept):
    raw = _raw(scrambled)
    with Atlas(scrambled) as atlas:
        s = atlas.summary()
        starts = atlas.initials
    assert s["points"] == raw["status"].size
    assert s["status"] == {n: int(np.sum(raw["status"] == c)) for n, c in fmt.STATUS.items()}
    for k, start in enumerate(starts):
        codes = raw["regime"][..., k]
        want = {n: int(np.sum(codes == c)) for n, c in fmt.REGIMES.items()}
        assert s["regimes"][start] == {n: c for n, c in want.items() if c}
        notes = raw["caveat"][..., k]
        want = {n: int(np.sum(notes == c)) for n, c in fmt.CAVEATS.items() if n}
        assert s["caveats"][start] == {n: c for n, c in want.items() if c}
    assert s["safe_points"] == int(_safe_by_hand(raw).sum())
    assert s["coexistence_points"] == int(np.sum(raw["coexistence"] == 1))
    for name in ("wob", "torque"):
        v = raw[name]
        assert s["axes"][name] == {"size": len(v), "min": v.min(), "max": v.max()}
    # a status no point has is counted as 0, not left out
    with Atlas(swept) as atlas:
        assert atlas.summary()["status"] == {"missing": 0, "done": 18, "failed": 0}


def _runs(mask, values):
    """(first, last) grid values of each run of True in ``mask`` over increasing values."""
    runs, k = [], 0
    while k < len(mask):
        if mask[k]:
            end = k
            while end + 1 < len(mask) and mask[end + 1]:
                end += 1
            runs.append((float(values[k]), float(values[end])))
            k = end + 1
        else:
            k += 1
    return runs


def test_safe_windows_are_the_runs_of_the_safe_points(scrambled):
    raw = _raw(scrambled)
    safe = _safe_by_hand(raw)
    with Atlas(scrambled) as atlas:
        assert atlas.safe_region().tolist() == safe.tolist()
        rows = atlas.safe_windows()  # along wob, one row a torque
        assert [r.at for r in rows] == [{"torque": float(t)} for t in raw["torque"]]
        for j, row in enumerate(rows):
            assert row.windows == _runs(safe[:, j], raw["wob"])
            assert row.safe == int(safe[:, j].sum()) and row.points == len(raw["wob"])
            assert row.not_done == int(np.sum(raw["status"][:, j] != fmt.STATUS["done"]))
        # along torque, at the wob nearest 95 N: 100 N's column
        (row,) = atlas.safe_windows("torque", wob=95.0)
        assert row.at == {"wob": 100.0}
        assert row.windows == _runs(safe[2, :], raw["torque"])
        # every wob, each its own row
        assert [r.at for r in atlas.safe_windows("torque")] == [
            {"wob": float(w)} for w in raw["wob"]
        ]


def test_to_xarray_holds_the_files_values_on_its_axes(scrambled):
    raw = _raw(scrambled)
    with Atlas(scrambled) as atlas, atlas.to_xarray() as ds:
        assert ds["wob"].values.tolist() == raw["wob"].tolist()
        assert ds["torque"].values.tolist() == raw["torque"].tolist()
        assert ds["regime"].dims == ("wob", "torque", "initial")
        assert ds["regime"].values.tolist() == raw["regime"].tolist()
        assert ds["safe"].values.tolist() == _safe_by_hand(raw).astype(int).tolist()
        events = ds["stick_events"].values
        want = np.where(raw["stick_events"] == -1, np.nan, raw["stick_events"])
        np.testing.assert_array_equal(events, want)
        unstable = np.where(raw["unstable"] == -1, np.nan, raw["unstable"])
        np.testing.assert_array_equal(ds["unstable"].values, unstable)


def test_the_csv_export_read_back_is_the_file(scrambled, tmp_path, monkeypatch, capsys):
    """Written five wob rows a block (blocks of 5 and 1: the last block holds the last row
    alone), read back with the csv module, cell by cell against h5py's reading of the atlas;
    the row count --json reports against the file's lines."""
    import json

    from pydrill import cli_atlas_export
    from pydrill.cli import main

    raw = _raw(scrambled)
    monkeypatch.setattr(cli_atlas_export, "BLOCK_POINTS", 5 * len(raw["torque"]))
    out = tmp_path / "scrambled.csv"
    assert main(["atlas", "export", str(scrambled), "--out", str(out), "--json"]) == 0
    with out.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert json.loads(capsys.readouterr().out)["rows"] == len(rows)
    starts = [s.decode() if isinstance(s, bytes) else s for s in raw["initial"]]
    assert len(rows) == raw["status"].size * len(starts)
    header = list(rows[0])
    assert header[:3] == ["wob", "torque", "initial"]
    assert header.index("regime_name") == header.index("regime") + 1
    regimes = {c: n for n, c in fmt.REGIMES.items()}
    status = {c: n for n, c in fmt.STATUS.items()}
    coexistence = {c: n for n, c in fmt.COEXISTENCE.items()}
    k = 0
    for i, j, s in np.ndindex(len(raw["wob"]), len(raw["torque"]), len(starts)):
        row = rows[k]
        k += 1
        assert (float(row["wob"]), float(row["torque"]), row["initial"]) == (
            raw["wob"][i],
            raw["torque"][j],
            starts[s],
        )
        assert int(row["regime"]) == raw["regime"][i, j, s]
        assert row["regime_name"] == regimes[raw["regime"][i, j, s]]
        assert row["status_name"] == status[raw["status"][i, j]]
        assert row["coexistence_name"] == coexistence[int(raw["coexistence"][i, j])]
        caveat = fmt.CAVEAT_NAMES[raw["caveat"][i, j, s]]
        assert row["caveat_name"] == (caveat or "none")
        events = raw["stick_events"][i, j, s]
        assert row["stick_events"] == ("" if events == -1 else str(events))
        assert row["message"] == raw["message"][i, j].decode()
