"""What a large study meets and a small test grid does not: costs that grow with the atlas."""

import json
import os
import subprocess
import sys
import tracemalloc

import numpy as np
from sweeping import SMALL, TINY

from pydrill import atlas_format as fmt
from pydrill import atlas_table
from pydrill.journal import journal_path, prepare
from pydrill.spec import parse_spec
from pydrill.sweep import evaluate_point

# 4000 points from rest and equilibrium, with stability: a journal line of ~1 kB a point.
WIDE = SMALL.replace("wob = [40.0, 100.0, 160.0]", "wob = { start = 20.0, stop = 200.0, num = 80 }")
WIDE = WIDE.replace("torque = [6.0, 8.3]", "torque = { start = 2.0, stop = 16.0, num = 50 }")


def journal_of_every_point(spec, out):
    """A journal holding every point of ``spec`` (records of a few points computed, copied to
    every index: replaying does not care where they came from), and no atlas: what a kill -9
    before the first flush leaves."""
    lines = [json.dumps({"spec_digest": spec.digest}) + "\n"]
    computed = [evaluate_point(spec, i) for i in (0, 1234, 2500)]
    for i in range(spec.size):
        lines.append(json.dumps({**computed[i % 3], "i": i}) + "\n")
    journal_path(out).write_text("".join(lines))
    return computed


def test_resume_replays_a_journal_a_few_records_at_a_time(tmp_path, monkeypatch):
    # The replay read the whole journal into a list first: ~5 kB of Python objects a point,
    # 400 MB at 74000 points (measured), 5 GB at a million, beyond what the sweep's memory
    # check had counted. Read a chunk at a time, the replay holds the table and the chunk
    # (4096 records; 256 here, a sixteenth of this journal).
    monkeypatch.setattr(atlas_table, "REPLAY_CHUNK", 256)
    spec = parse_spec(WIDE)
    out = tmp_path / "big.h5"
    computed = journal_of_every_point(spec, out)
    table_bytes = sum(a.nbytes for a in fmt.AtlasTable(spec).columns().values())
    tracemalloc.start()
    try:
        table, done = prepare(spec, out, resume=True, params_json="{}", version="test")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert done == spec.size
    # the table itself, and what HDF5's writing copies of a column (was ~10x the table)
    assert peak < 3 * table_bytes + 2_000_000, (peak, table_bytes)
    flat = table.regime.reshape(spec.size, -1)
    for i in (0, 1, 2, 3999):
        want = [fmt.REGIMES[computed[i % 3]["runs"][s]["regime"]] for s in spec.initials]
        assert flat[i].tolist() == want
    assert np.all(table.status == fmt.STATUS["done"])


def test_a_resumed_sweep_counts_the_points_left_from_the_start_and_says_so(tmp_path):
    # The bar counted the whole grid (0/100000) until the first batch came back, then jumped
    # to the points left (256/48288): minutes of a wrong total for strings of hundreds of
    # pipes, whose batches take seconds each, and no word that this was a resume.
    spec = parse_spec(TINY)
    out = tmp_path / "r.h5"
    lines = [json.dumps({"spec_digest": spec.digest}) + "\n"]
    lines += [json.dumps(evaluate_point(spec, i)) + "\n" for i in (0, 3)]
    journal_path(out).write_text("".join(lines))
    spec_file = tmp_path / "tiny.toml"
    spec_file.write_text(TINY)
    # With no terminal, the progress is a line every 30 s, of the points left (LogProgress).
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    script = (
        "import sys, pydrill.cli_sweep_report as c\n"
        "class Log(c.LogProgress):\n"
        "    def __init__(self, total, every=30.0, **kw):\n"
        "        print('total', total, file=sys.stderr)\n"
        "        super().__init__(total, every, **kw)\n"
        "c.LogProgress = Log\n"
        "from pydrill.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            script,
            "sweep",
            str(spec_file),
            f"--out={out}",
            "--resume",
            "--serial",
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.startswith("total 4\n"), proc.stderr
    assert f"sweep: resuming {out}: 2 of 6 points are done, 4 to compute" in proc.stderr


def test_a_resumed_sweeps_log_progress_counts_its_rate_from_the_first_batch(monkeypatch, capsys):
    # A resumed million-point sweep replays its journal for ~40 s before its first batch; the
    # rate counted from the bar's creation said "7 points/s, about 4 min 05 s left" of a sweep
    # that had seconds to go.
    import pydrill.cli_sweep_report as cli_sweep

    clock = [0.0]
    monkeypatch.setattr(cli_sweep.time, "monotonic", lambda: clock[0])
    log = cli_sweep.LogProgress(10000, every=30.0, resumed=True)
    clock[0] = 100.0  # the replay, the cluster's start and the first batch
    log.update(100)
    clock[0] = 131.0
    log.update(3000)  # 3000 points in 31 s: ~97 a second, 6900 left: 71 s
    said = capsys.readouterr().err
    assert said == "sweep: 3100/10000 points (31 %), 97 points/s, about 1 min 11 s left\n"


def test_a_journal_replayed_in_blocks_or_a_workers_block_equals_records_applied_one_by_one():
    # The replay stores a few thousand records a field at a time (a million-point journal
    # took over a minute record by record); every kind of record must land as it did.
    # stick-slip needs more steps than this: those points fail
    spec = parse_spec(SMALL.replace("t_end = 200.0", "t_end = 200.0\nmax_steps = 900"))
    records = [evaluate_point(spec, i) for i in range(spec.size)]
    kinds = {rec["status"] for rec in records}
    regimes = {run["regime"] for rec in records for run in rec["runs"].values()}
    assert kinds == {"done", "failed"} and "no-steady-state" in regimes, (kinds, regimes)
    records[0].pop("stability", None)  # as a spec with [record] stability = false writes
    records[1].pop("coexistence", None)
    records[2]["runs"].pop("equilibrium", None)  # one start only
    by_block, by_record = fmt.AtlasTable(spec), fmt.AtlasTable(spec)
    assert by_block.apply_all(iter(records), chunk=4) == spec.size
    for rec in records:
        by_record.apply(rec)
    # and as a worker encodes its batch: rows 0, 1, ... of a block, put at the points' indices
    order = [3, 0, 5, 1, 4, 2, *range(6, spec.size)]
    worker = fmt.AtlasTable(spec, points=spec.size)
    worker.fill([records[i] for i in order])
    by_worker = fmt.AtlasTable(spec)
    by_worker.put(np.array(order), worker.columns())
    for name, a in by_block.columns().items():
        for b in (by_record.columns()[name], by_worker.columns()[name]):
            if a.dtype.kind in "fc":
                np.testing.assert_array_equal(a, b, err_msg=name)  # NaN where NaN
            else:
                assert a.tolist() == b.tolist(), name


def _chunk_layouts(path):
    """(name, shape, chunks, bytes of a chunk) of every chunked dataset of an atlas."""
    import h5py

    found = []
    with h5py.File(path, "r") as f:
        for name, ds in f.items():
            if isinstance(ds, h5py.Dataset) and ds.chunks:
                found.append((name, ds.shape, ds.chunks, ds.dtype.itemsize * np.prod(ds.chunks)))
    return found


def test_a_point_query_inflates_small_chunks_however_large_the_atlas(tmp_path):
    """A point query reads one chunk of each of some 25 datasets. Chunks of 64 x 64 grid
    points (64 kB to 512 kB) took 9 ms a query (13 ms at the 95th percentile) on a 10^6-point
    atlas of smooth data: now each chunk holds about fmt.CHUNK_BYTES of points, whatever the
    grid, with the starts, steady states and eigenvalues of a point whole in it, and the
    chunks along an axis of nearly equal length (no last chunk of a few values)."""
    for text in (
        SMALL.replace(
            "wob = [40.0, 100.0, 160.0]", "wob = { start = 1, stop = 300, num = 1000 }"
        ).replace("torque = [6.0, 8.3]", "torque = { start = 0.1, stop = 30, num = 1000 }"),
        WIDE,
        WIDE.replace("[axes]", "[axes]\nmu_coulomb = [0.4, 0.5, 0.6]"),
    ):
        spec = parse_spec(text)
        out = tmp_path / f"{spec.digest}.h5"
        fmt.create(out, spec, "{}", "test")
        layouts = _chunk_layouts(out)
        assert len(layouts) >= 20
        grid = len(spec.shape)
        for name, shape, chunks, size in layouts:
            assert shape[:grid] == spec.shape, name
            assert chunks[grid:] == shape[grid:], name  # a point's values whole
            assert size <= fmt.CHUNK_BYTES, (name, chunks)
            whole = chunks[:grid] == shape[:grid]
            assert whole or size >= fmt.CHUNK_BYTES / 8, (name, chunks)
            for n, c in zip(shape[:grid], chunks[:grid], strict=True):
                pieces = -(-n // c)
                assert pieces * c - n < pieces, (name, shape, chunks)  # equal lengths


def test_an_atlas_is_made_and_read_back_without_a_second_table(tmp_path):
    """Making an atlas built a whole table only for its fill values (0.4 GB at 10^6 points), and
    reading one back made four temporaries of the eigenvalues' size (real + 1j * imag): a
    resume held 1.8 times the table at its peak, more than the memory check counts
    (sweep_plan.MEMORY_FACTOR). Now making holds a few MB, reading the table and a column."""
    text = SMALL.replace(
        "wob = [40.0, 100.0, 160.0]", "wob = { start = 1, stop = 300, num = 500 }"
    ).replace("torque = [6.0, 8.3]", "torque = { start = 0.1, stop = 30, num = 400 }")
    spec = parse_spec(text)
    out = tmp_path / "a.h5"
    table_bytes = sum(a.nbytes for a in fmt.AtlasTable(spec).columns().values())
    tracemalloc.start()
    try:
        fmt.create(out, spec, "{}", "test")
        made = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        start = tracemalloc.get_traced_memory()[0]
        table = fmt.read_table(out, spec)
        read = tracemalloc.get_traced_memory()[1] - start
    finally:
        tracemalloc.stop()
    assert made < 0.05 * table_bytes, (made, table_bytes)
    from pydrill.sweep_plan import MEMORY_FACTOR

    assert read < MEMORY_FACTOR * table_bytes, (read, table_bytes)
    assert np.isnan(table.eig).all() and np.all(table.status == fmt.STATUS["missing"])
