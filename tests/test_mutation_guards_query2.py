"""The atlas queries' edges, against the grid rules as documented, numpy, h5py, io.BytesIO.

What a mutation audit of the query side left alive after test_mutation_guards_query.py: the
bounds of "on the grid" and "within reach", open slices of a negative axis, one-value axes,
ties under "nearest", default start and axis, held axes, the journal's count, eigenvalues,
xarray options, global heaps, SinkFile; and an atlas swept without stability, whose
``to_xarray`` recursed without end on closing.
"""

import csv
import io
import json
import os
import re
import shutil
import struct
from types import SimpleNamespace

import h5py
import numpy as np
import pytest
import xarray as xr
from test_fuzz_heap import hanging_copy
from test_mutation_guards_query import _runs

import pydrill.atlas as atlas_module
from pydrill import atlas_format as fmt
from pydrill import cli_atlas_export, export_csv
from pydrill.atlas import Atlas
from pydrill.atlas_check import layout_problem
from pydrill.atlas_grid import CoordinateError, grid_index, selection
from pydrill.atlas_heap import MIN_SIZE, SIGNATURE, heap_problem
from pydrill.cli import main
from pydrill.export_file import SinkFile
from pydrill.journal import JOURNAL_SUFFIX, AtlasError
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep
from pydrill.xarray_backend import AtlasBackend

# wob is not the first axis, and has one value; dof resizes the string (no one inertia list)
SPEC = """
[model]
preset = "reduced-scale"
[axes]
torque = [6.0, 7.0]
wob = [100.0]
dof = [2, 3]
[simulation]
t_end = 5.0
initial = ["rest", "equilibrium"]
"""

UNRECORDED = SPEC.replace('initial = ["rest", "equilibrium"]', "[record]\nstability = false")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """A 2 x 1 x 2 atlas, then random codes and values (as test_mutation_guards_query has
    them): the two starts' regimes differ, some points are safe, eigenvalues complex."""
    path = tmp_path_factory.mktemp("query2") / "tiny.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    rng = np.random.default_rng(35)
    with h5py.File(path, "r+") as f:
        shape = f["regime"].shape
        f["regime"][...] = rng.choice(list(fmt.REGIMES.values()), size=shape)
        f["regime"][0, 0, 0] = [fmt.REGIMES["steady"], fmt.REGIMES["stick-slip"]]
        f["regime"][1, 0, 1] = [fmt.REGIMES["steady"], fmt.REGIMES["steady"]]
        f["unstable"][...] = 0
        im = rng.uniform(-5.0, 5.0, size=f["eigenvalues_imag"].shape)
        f["eigenvalues_imag"][...] = im
        f["eigenvalues_real"][...] = rng.uniform(-3.0, -1.0, size=im.shape)
    return path


def _raw(path):
    with h5py.File(path, "r") as f:
        return {name: f[name][...] for name in f if isinstance(f[name], h5py.Dataset)}


def _copy(path, tmp_path):
    out = tmp_path / path.name
    shutil.copy(path, out)
    return out


def test_exact_is_within_a_millionth_and_a_quarter_step_nearest_within_half_a_step():
    """on_grid: equal within 1e-6 of the grid value (relative), but never nearer a
    neighbour than a quarter step, bounds included, two-value axes too; near_enough."""
    wide = np.array([40.0, 1000.0])
    assert grid_index("wob", wide, 1000.0 * (1 + 5e-7)) == 1
    with pytest.raises(CoordinateError, match="not on the grid"):
        grid_index("wob", wide, 1000.0 * (1 + 5e-6))  # within 1e-5, not 1e-6
    # two values 2 N apart at 1e6 N: 1e-6 of 1e6 is 1 N, more than the quarter step 0.5 N
    close = np.array([1e6, 1e6 + 2.0])
    assert grid_index("wob", close, 1e6 + 0.5) == 0  # a quarter step exactly: on it
    for off in (0.75, 1.0 - 1e-9):
        with pytest.raises(CoordinateError, match="not on the grid"):
            grid_index("wob", close, 1e6 + off)
    # nearest: within half of each end's own step past it (30 and 60 here), no further
    values = np.array([40.0, 70.0, 130.0])
    assert grid_index("wob", values, 25.0, "nearest") == 0
    assert grid_index("wob", values, 160.0, "nearest") == 2
    for v in (25.0 - 1e-9, 160.0 + 1e-9):
        with pytest.raises(CoordinateError, match="outside the atlas"):
            grid_index("wob", values, v, "nearest")


def test_a_slice_open_at_its_start_keeps_a_negative_axis_from_its_first_value():
    """Torque may be negative (only its size is bounded): slice(None, b) is every grid
    value up to b, numpy's mask of them, not those from 0."""
    axis = np.array([-3.0, -2.0, -1.0, 0.5])
    for stop in (-2.5, -1.0, 0.5):
        got = selection({"torque": axis}, ["rest"], None, {"torque": slice(None, stop)})
        assert got["torque"] == axis[axis <= stop].tolist()


def test_a_one_value_axis_is_taken_when_left_out_and_refused_when_wrong(tiny):
    with Atlas(tiny) as atlas:
        assert atlas.value(torque=6.0, dof=2)["coords"] == {
            "torque": 6.0,
            "wob": 100.0,
            "dof": 2,
        }
        for method in ("exact", "nearest"):
            with pytest.raises(CoordinateError, match="outside the atlas"):
                atlas.value(method, torque=6.0, wob=101.0, dof=2)


def test_nearest_at_a_tie_is_the_same_grid_point_for_value_index_and_sel(tiny):
    """6.5 is as near 6 as 7: value and index take the first (np.argmin's brute-force
    choice); sel took pandas' (the larger), another point for the same question."""
    first = float(np.array([6.0, 7.0])[np.argmin(np.abs(np.array([6.0, 7.0]) - 6.5))])
    with Atlas(tiny) as atlas:
        assert atlas.value("nearest", torque=6.5, dof=2)["coords"]["torque"] == first
        assert atlas.index("nearest", torque=6.5, wob=100.0, dof=2)[0] == 0
        ds = atlas.sel("nearest", torque=6.5, dof=2)
        assert ds["torque"].item() == first


def test_regimes_default_to_the_first_start_and_sel_takes_a_start_exactly(tiny):
    raw = _raw(tiny)
    names = {c: n for n, c in fmt.REGIMES.items()}
    with Atlas(tiny) as atlas:
        first = np.vectorize(names.get)(raw["regime"][..., 0])
        assert atlas.regimes().tolist() == first.tolist()
        assert not np.array_equal(raw["regime"][..., 0], raw["regime"][..., 1])
        ds = atlas.sel(initial="equilibrium")
        want = np.vectorize(names.get)(raw["regime"][..., 1])
        assert ds["regime_name"].values.tolist() == want.tolist()


def test_eigenvalues_are_the_files_real_and_imaginary_parts(tiny):
    raw = _raw(tiny)
    with Atlas(tiny) as atlas:
        for i, k in np.ndindex(2, 2):
            got = atlas.value(torque=float(raw["torque"][i]), dof=int(raw["dof"][k]))
            found = int(np.sum(np.isfinite(raw["omega_eq"][i, 0, k])))
            re, im = raw["eigenvalues_real"][i, 0, k], raw["eigenvalues_imag"][i, 0, k]
            want = [
                [[float(a), float(b)] for a, b in zip(r, m, strict=True) if np.isfinite(a)]
                for r, m in zip(re, im, strict=True)
            ][:found]
            assert got["stability"]["eigenvalues"] == want


def test_safe_windows_run_along_wob_though_it_is_not_the_first_axis(tiny):
    raw = _raw(tiny)
    steady = np.all(raw["regime"] == fmt.REGIMES["steady"], axis=-1)
    safe = steady & (raw["unstable"][..., 0] == 0)
    assert safe.any()
    with Atlas(tiny) as atlas:
        rows = atlas.safe_windows()
        assert [r.at for r in rows] == [{"torque": t, "dof": d} for t in (6.0, 7.0) for d in (2, 3)]
        for row, (i, k) in zip(rows, np.ndindex(2, 2), strict=True):
            assert row.windows == _runs(safe[i, :, k], raw["wob"])
        # dof held (the last axis): its nearest grid value, not the first axis's index
        held = atlas.safe_windows(dof=2.9)
        assert [r.at for r in held] == [
            {"torque": 6.0, "dof": 3},
            {"torque": 7.0, "dof": 3},
        ]
        assert [r.windows for r in held] == [_runs(safe[i, :, 1], raw["wob"]) for i in (0, 1)]


def test_the_journal_counts_each_missing_point_once_and_no_other(tiny, tmp_path):
    """journal_points: the distinct journaled points whose status is still missing; an
    index past the grid, a point done or failed, a repeated line are not more of them."""
    path = _copy(tiny, tmp_path)
    with h5py.File(path, "r+") as f:
        status = np.full(f["status"].shape, fmt.STATUS["done"], dtype=np.uint8)
        status.flat[0] = status.flat[1] = fmt.STATUS["missing"]
        status.flat[2] = fmt.STATUS["failed"]
        f["status"][...] = status
    lines = [{"i": i} for i in (0, 0, 1, 2, 3, status.size, status.size + 1)]
    text = '{"header": true}\n' + "".join(json.dumps(line) + "\n" for line in lines)
    path.with_name(path.name + JOURNAL_SUFFIX).write_text(text)
    with Atlas(path) as atlas:
        assert atlas.summary()["journal_points"] == 2  # 0 and 1


def test_summary_model_and_parts_where_there_is_no_one_answer(tiny, tmp_path):
    """A dof axis: no one list of inertias (None), while each point has its own; a
    merged_from that is JSON but no list of parts: None, as unreadable text is."""
    path = _copy(tiny, tmp_path)
    with h5py.File(path, "r+") as f:
        f.attrs["merged_from"] = json.dumps({"file": "a.h5"})
    with Atlas(path) as atlas:
        s = atlas.summary()
        sizes = {atlas.spec.params_at(atlas.spec.coords(k)).dof for k in range(4)}
    assert sizes == {2, 3}
    assert s["model"]["inertias"] is None
    assert s["merged_from"] is None


def test_an_atlas_swept_without_stability_opens_closes_and_has_no_safe(tmp_path):
    """There ``safe`` cannot be said (None in summary); to_xarray returned the dataset it
    opened with its own close as its closer, and closing it recursed without end."""
    path = tmp_path / "unrecorded.h5"
    run_sweep(parse_spec(UNRECORDED), path, serial=True)
    raw = _raw(path)
    with Atlas(path) as atlas:
        assert atlas.summary()["safe_points"] is None
        with atlas.to_xarray() as ds:
            assert "safe" not in ds
            assert ds["regime"].values.tolist() == raw["regime"].tolist()
        assert atlas.sel(torque=6.0)["status"].values.tolist() == raw["status"][0].tolist()
    with xr.open_dataset(path, engine=AtlasBackend) as ds:
        assert "safe" not in ds and "regime" in ds


def test_chunks_minus_one_is_whole_and_a_name_not_a_dimension_is_refused(tiny):
    raw = _raw(tiny)
    with Atlas(tiny) as atlas:
        with atlas.to_xarray(chunks=-1) as ds:
            assert ds["status"].chunks == tuple((n,) for n in raw["status"].shape)
            assert ds["status"].values.tolist() == raw["status"].tolist()
        with pytest.raises(ValueError, match="'torq' is not a dimension"):
            atlas.to_xarray(chunks={"torq": 1})


def test_messages_are_read_in_the_blocks_of_status(tiny):
    raw = _raw(tiny)
    with Atlas(tiny) as atlas, atlas.to_xarray(chunks={"torque": 1}) as ds:
        assert ds["message"].chunks == ds["status"].chunks == ((1, 1), (1,), (2,))
        want = [[[m.decode() for m in row] for row in plane] for plane in raw["message"]]
        assert ds["message"].values.tolist() == want


def test_an_older_atlass_axis_units_and_count_fills_are_read_as_now(tiny, tmp_path):
    """Atlases written before axis_units said "SI": read as each axis's unit. Before counts
    had a _FillValue: their -1 (not measured) read as NaN all the same, written back -1."""
    path = _copy(tiny, tmp_path)
    with h5py.File(path, "r+") as f:
        for name in ("torque", "wob"):
            f[name].attrs["units"] = "SI"
        for name in ("stick_events", "unstable"):
            del f[name].attrs["_FillValue"]
        f["stick_events"][0, 0, 0] = [-1, 4]
    raw = _raw(path)
    with Atlas(path) as atlas, atlas.to_xarray() as ds:
        assert ds["torque"].attrs["units"] == "N m" == fmt.axis_units("torque")
        assert ds["wob"].attrs["units"] == "N" == fmt.axis_units("wob")
        for name in ("stick_events", "unstable"):
            want = np.where(raw[name] == -1, np.nan, raw[name])
            np.testing.assert_array_equal(ds[name].values, want)
            assert ds[name].encoding["_FillValue"] == -1


@pytest.mark.parametrize("drop", ["caveat", ("caveat", "period")])
def test_the_engine_drops_what_it_is_told_to(tiny, drop):
    dropped = {drop} if isinstance(drop, str) else set(drop)
    with xr.open_dataset(tiny, engine=AtlasBackend) as whole:
        assert dropped <= set(whole.data_vars)
        every = set(whole.data_vars)
    with xr.open_dataset(tiny, engine=AtlasBackend, drop_variables=drop) as ds:
        assert set(ds.data_vars) == every - dropped


def test_csv_in_pieces_is_the_file_and_the_bar_moves_by_its_points(tiny, tmp_path, monkeypatch):
    """Lines made 3 at a time (8 rows: 3, 3, 2), read back cell by cell against h5py. A point
    done has no message: its cell empty, not '""' (the csv module quotes an empty field only
    when it is a row's one field; pandas writes it bare). The bar moved by the points."""
    moved: list[int] = []  # the bar's updates
    bar = SimpleNamespace(total=4, update=moved.append, close=lambda: None)  # 2 x 1 x 2
    monkeypatch.setattr(export_csv, "LINES", 3)
    monkeypatch.setattr(cli_atlas_export, "check_progress", lambda *a, **k: bar)
    out = tmp_path / "tiny.csv"
    assert main(["atlas", "export", str(tiny), "--out", str(out)]) == 0
    text = out.read_text()
    assert '""' not in text
    rows = list(csv.DictReader(text.splitlines()))
    raw = _raw(tiny)
    assert len(rows) == raw["status"].size * 2
    for row, (i, k, s) in zip(rows, np.ndindex(2, 2, 2), strict=True):
        got = (float(row["torque"]), float(row["wob"]), int(row["dof"]), row["initial"])
        assert got == (raw["torque"][i], raw["wob"][0], raw["dof"][k], ["rest", "equilibrium"][s])
        assert int(row["regime"]) == raw["regime"][i, 0, k, s]
        assert row["message"] == raw["message"][i, 0, k].decode() == ""
    assert sum(moved) == raw["status"].size


def _collection(size, objects, claim=None, free=True):
    """A global heap collection: signature, size (or ``claim``), the (index, data) objects,
    the free space (index 0, its size with its header) if ``free`` and room, zeros."""
    out = SIGNATURE + struct.pack("<Q", size if claim is None else claim)
    for index, data in objects:
        out += struct.pack("<HHIQ", index, 1, 0, len(data)) + data.ljust(-(-len(data) // 8) * 8)
    if free and size - len(out) >= 16:
        out += struct.pack("<HHIQ", 0, 0, 0, size - len(out))
    return out.ljust(size, b"\0")


def test_heap_collections_that_hdf5_walks_for_ever_or_never_made_are_named():
    lead, whole = b"\x89HDF\r\n\x1a\n".ljust(64, b"\0"), _collection(MIN_SIZE, [(1, b"x" * 9)])
    assert heap_problem(lead + whole) is None
    # an object header in the last 16 bytes exactly: HDF5 reads it (free space of size 0)
    last = _collection(MIN_SIZE, [(1, b"y" * (MIN_SIZE - 48))], free=False)
    assert "has size 0" in heap_problem(lead + last)
    # a collection claiming more than the file holds, its free space reaching its claim
    cut = _collection(2 * MIN_SIZE, [(1, b"z" * 8)])[:MIN_SIZE]
    assert f"claims {2 * MIN_SIZE} bytes" in heap_problem(lead + cut)
    # smaller than any HDF5 makes, though its objects tile it
    small = _collection(64, [(1, b"w" * 16)])
    assert f"claims 64 bytes, fewer than any HDF5 writes ({MIN_SIZE})" in heap_problem(
        lead + small + whole
    )
    # a signature inside an object's data (a message may hold any text) starts no collection
    inner = _collection(MIN_SIZE, [(1, SIGNATURE + struct.pack("<Q", 5))])
    assert heap_problem(lead + inner + whole) is None


def test_to_xarray_checks_the_whole_files_heaps_before_xarray_reads_it(tiny, tmp_path, monkeypatch):
    """Opening checks only the first OPENING_BYTES (0 here); xarray reads every heap (a
    message's too), where a damaged one hangs HDF5: to_xarray refuses it before."""
    path = _copy(tiny, tmp_path)
    with h5py.File(path, "r+") as f:
        f["message"][...] = np.full(f["message"].shape, "boom: a message", dtype=object)
    hanging_copy(path, tmp_path / "damaged.h5", holding=b"boom")

    monkeypatch.setattr(atlas_module, "OPENING_BYTES", 0)
    monkeypatch.setattr(atlas_module, "_to_xarray", None)  # reached (it would hang): TypeError
    with Atlas(tmp_path / "damaged.h5") as atlas:
        with pytest.raises(AtlasError, match="has size 0"):
            atlas.to_xarray()


def test_a_sink_file_seeks_truncates_and_reads_as_a_bytesio_does(tmp_path):
    """SinkFile (what HDF5 writes an export into) against io.BytesIO, step by step: a seek
    from the current position, a truncation, reads after each."""
    fd = os.open(tmp_path / "sink", os.O_RDWR | os.O_CREAT)
    try:
        sink, ref = SinkFile(fd), io.BytesIO()
        s, c, e = os.SEEK_SET, os.SEEK_CUR, os.SEEK_END
        steps = [("write", b"0123456789abcdef"), ("seek", 4, s), ("seek", 3, c)]
        steps += [("read", 5), ("seek", -6, c), ("write", b"XY"), ("truncate", 9)]
        steps += [("seek", 0, e), ("seek", 0, s), ("read", 100), ("truncate", None)]
        steps += [("seek", -2, e), ("read", 100)]
        for name, *args in steps:
            assert getattr(sink, name)(*args) == getattr(ref, name)(*args), (name, args)
            assert sink.tell() == ref.tell()
        sink.close()
    finally:
        os.close(fd)


def _damage(f, problem):
    if problem.startswith("caveat"):  # a start too many (its last dimension)
        shape = f["caveat"].shape
        del f["caveat"]
        f.create_dataset("caveat", data=np.zeros((*shape[:-1], 3), dtype="i1"))
    elif problem.startswith("no dataset"):
        del f["coexistence"]
    elif problem.startswith(("status", "coexistence")):
        f[problem.split()[0]][0, 0, 0] = 7  # one code that is none among good ones
    elif problem.startswith("axis"):
        f["wob"][0] = 100.0 * (1 + 1e-6)  # beyond float64's rounding, within allclose's
    else:
        f.attrs["axes"] = json.dumps(["wob", "torque", "dof"])  # the spec's, out of order


@pytest.mark.parametrize(
    "problem",
    [
        "caveat has shape (2, 1, 2, 3), not (2, 1, 2, 2)",
        "no dataset coexistence",
        "status holds codes other than those of missing, done, failed",
        "coexistence holds codes other than those of unknown, no, yes",
        "axis wob is not the spec's 1 values",
        'attribute axes = \'["wob", "torque", "dof"]\' is not ["torque", "wob", "dof"]',
    ],
)
def test_a_file_unlike_the_layout_of_its_spec_is_refused(tiny, tmp_path, problem):
    """layout_problem: whole shapes, every dataset, every code, axis values exactly, axes
    in the spec's order; what opening or check() says, naming the damage."""
    path = _copy(tiny, tmp_path)
    with h5py.File(path, "r+") as f:
        _damage(f, problem)
        assert problem in layout_problem(f, parse_spec(SPEC))  # as resume asks it too
    with pytest.raises(AtlasError, match=re.escape(problem)):
        with Atlas(path) as atlas:
            atlas.check()
