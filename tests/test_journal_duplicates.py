"""A point journaled twice replays as its last record alone.

pydrill journals each point once, but a journal joined by hand (two runs' journals
concatenated) can hold a point twice; the atlas must then hold what the last record says and
nothing of the earlier one: a failed record after a done one kept the done run's steady states,
eigenvalues and coexistence. Checked against the atlas of a journal that holds only the last
record, read with plain h5py, within one replay chunk and across two."""

import numpy as np
import pytest
from test_mutation_guards_journal import SPEC, _arrays, _journal, swept  # noqa: F401

import pydrill.atlas_table
from pydrill.journal import prepare
from pydrill.journal_lines import line
from pydrill.sweep_dask import killed_point


def _replayed(tmp_path, name, lines):
    out = tmp_path / name
    _journal(out, lines)
    _, done = prepare(SPEC, out, resume=True, params_json="{}", version="t")
    assert done == SPEC.size
    return _arrays(out)


@pytest.mark.parametrize("chunk", [4096, 3], ids=["one-chunk", "across-chunks"])
def test_the_last_record_of_a_point_is_all_the_atlas_holds(swept, tmp_path, monkeypatch, chunk):  # noqa: F811
    monkeypatch.setattr(pydrill.atlas_table, "REPLAY_CHUNK", chunk)
    whole_path, recs = swept
    whole = _arrays(whole_path)
    failed = killed_point(SPEC, 3, RuntimeError("boom")).lines
    others = [line(recs[i]) for i in (0, 1, 2, 4, 5)]
    # done then failed: point 3 as if only the failed record were there
    want = _replayed(tmp_path, "only.h5", [failed, *others])
    got = _replayed(tmp_path, "both.h5", [line(recs[3]), *others, failed])
    assert np.isfinite(whole["omega_eq"].reshape(SPEC.size, -1)[3]).any()  # it had some
    for k in want:
        np.testing.assert_array_equal(got[k], want[k], err_msg=k)
    # failed then done: the done record wins whole (the uninterrupted sweep's atlas)
    got = _replayed(tmp_path, "again.h5", [failed, *others, line(recs[3])])
    for k in whole:
        np.testing.assert_array_equal(got[k], whole[k], err_msg=k)
