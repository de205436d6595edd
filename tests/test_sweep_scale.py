"""What a large study meets and a small test grid does not: costs that grow with the atlas."""

import json
import tracemalloc

import numpy as np
from sweeping import SMALL

from pydrill import atlas_format as fmt
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


def test_resume_replays_a_journal_one_record_at_a_time(tmp_path):
    # The replay read the whole journal into a list first: ~5 kB of Python objects a point,
    # 400 MB at 74000 points (measured), 5 GB at a million, beyond what the sweep's memory
    # check had counted. Read a record at a time, the replay holds the table and a line.
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
