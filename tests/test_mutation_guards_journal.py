"""Guards from a mutation audit of the sweep's write and resume path (journal.py,
journal_records.py, journal_lines.py, atlas_table.py, atlas_merge.py): behaviour no other test
would have noticed breaking, each checked against something independent: an uninterrupted
serial sweep's atlas read with plain h5py, journals written by hand line by line, merged
values placed by brute force with numpy, the rules the docstrings state."""

import json

import h5py
import numpy as np
import pytest
from sweeping import SMALL

from pydrill import AtlasError, merge_atlases, parse_spec, run_sweep
from pydrill.atlas_schema import REGIMES, STATUS
from pydrill.journal import journal_path, journaled, prepare, read_journal
from pydrill.journal_lines import RUN_KEYS, STABILITY_KEYS, Layout, header, line
from pydrill.sweep_dask import killed_point
from pydrill.sweep_points import evaluate_point

# Two starts (coexistence true and false both occur) and a start with no steady state at
# u = 2 N m (its run is {"regime": "no-steady-state"}): every kind of record a sweep writes.
SPEC = parse_spec(
    SMALL.replace("torque = [6.0, 8.3]", "torque = [2.0, 8.3]").replace(
        "t_end = 200.0", "t_end = 60.0"
    )
)


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """An uninterrupted serial sweep's atlas, and every point's record."""
    d = tmp_path_factory.mktemp("whole")
    run_sweep(SPEC, d / "whole.h5", serial=True)
    return d / "whole.h5", [evaluate_point(SPEC, i) for i in range(SPEC.size)]


def _arrays(path):
    """Every dataset of an atlas with plain h5py, run times aside (they are the runs' own)."""
    with h5py.File(path, "r") as f:
        return {k: f[k][...] for k in f if isinstance(f[k], h5py.Dataset) and k != "wall_time"}


def _attrs(path):
    """Every attribute of an atlas, its datasets' too, timing aside (as text)."""
    out = {}
    with h5py.File(path, "r") as f:
        for name, obj in [("/", f), *((k, f[k]) for k in f)]:
            out |= {f"{name}@{k}": str(v) for k, v in obj.attrs.items() if "time" not in k}
    return out


def _journal(out, lines, head=None):
    """A journal written by hand, line by line, as a kill left it (no atlas beside it)."""
    text = head if head is not None else header(SPEC.digest)
    journal_path(out).write_text(text + "".join(lines))
    return journal_path(out)


def read_journal_line(text):
    """The record of one journal line of this layout (its header's orders)."""
    return Layout(json.loads(header(SPEC.digest))).record(json.loads(text))


def test_a_resumed_sweep_is_the_uninterrupted_one(swept, tmp_path):
    """Killed with points 4, 0, 2 journaled (out of order, coexistence true and false among
    them) and no atlas: --resume computes only the 3 others, and the atlas equals the
    uninterrupted run's dataset by dataset; the journal and a half-rewritten one are gone."""
    whole, recs = swept
    assert {r["coexistence"] for r in recs} == {True, False}  # both kinds replayed
    out = tmp_path / "r.h5"
    jp = _journal(out, [line(recs[i]) for i in (4, 0, 2)])
    jp.with_name(jp.name + ".new").write_text("[0, ")  # a rewrite cut by a kill
    report = run_sweep(SPEC, out, serial=True, resume=True)
    assert (report.resumed, report.computed) == (3, SPEC.size - 3)
    want, got = _arrays(whole), _arrays(out)
    assert want.keys() == got.keys()
    for k in want:
        np.testing.assert_array_equal(got[k], want[k], err_msg=k)  # (NaN == NaN here)
    assert _attrs(out) == _attrs(whole)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.h5"]


def test_a_failed_record_without_runs_replays_as_failed_and_the_rest_in_place(swept, tmp_path):
    """A point that killed its workers (no runs, no coexistence, no stability), journaled
    before the others: it is failed from every start, with its message, its coexistence -1
    (not judged) and its steady states not recorded; every other point, steady states
    included, is the uninterrupted run's (a block with a record without stability first)."""
    whole, recs = swept
    out = tmp_path / "k.h5"
    text = killed_point(SPEC, 3, RuntimeError("boom")).lines  # as the sweep journals it
    assert "coexistence" not in read_journal_line(text)
    _journal(out, [text, *(line(recs[i]) for i in (0, 1, 2, 4, 5))])
    _, done = prepare(SPEC, out, resume=True, params_json="{}", version="t")
    assert done == SPEC.size
    want, got = _arrays(whole), _arrays(out)
    rows = {k: v.reshape(SPEC.size, -1) for k, v in got.items() if v.shape[:2] == SPEC.shape}
    assert {"status", "regime", "omega_eq", "unstable", "coexistence"} <= rows.keys()
    for k, v in rows.items():
        ok = np.delete(v, 3, axis=0)
        np.testing.assert_array_equal(ok, np.delete(want[k].reshape(v.shape), 3, axis=0), k)
    assert rows["status"][3].tolist() == [STATUS["failed"]]
    assert rows["coexistence"][3].tolist() == [-1]
    assert rows["regime"][3].tolist() == [REGIMES["failed"]] * 2
    assert np.isnan(rows["omega_eq"][3]).all() and rows["unstable"][3].tolist() == [-1, -1]
    assert rows["message"][3][0].decode().endswith("boom")


def test_a_damaged_middle_line_is_named_and_a_torn_last_one_dropped(swept, tmp_path):
    """The documented rule: only the last line may be cut (a kill mid-write); it is dropped
    and cut off the file. A line damaged anywhere else is named with its number (1-based),
    and the journal is left as it was."""
    _, recs = swept
    good = [line(recs[i]) for i in (0, 1)]
    out = tmp_path / "a.h5"
    for bad, n in (('{"i": 3, "sta\n', 3), ("[5, 7]\n", 3), ("[99, 1]\n", 4)):
        body = [good[0], bad, good[1]] if n == 3 else [*good, bad, line(recs[2])]
        jp = _journal(out, body)
        before = jp.read_bytes()
        with pytest.raises(AtlasError, match=rf"a\.h5\.journal, line {n}, is damaged"):
            read_journal(out, SPEC)
        assert jp.read_bytes() == before  # nothing cut: every point after it is kept
    # A last line whole but for its end of line was cut too: dropped, and the next append
    # starts a line of its own.
    jp = _journal(out, [good[0], good[1].rstrip("\n")])
    assert [r["i"] for r in read_journal(out, SPEC)] == [0]
    assert jp.read_text() == header(SPEC.digest) + good[0]
    with jp.open("a") as fh:
        fh.write(line(recs[5]))
    assert [r["i"] for r in read_journal(out, SPEC)] == [0, 5]
    # A header torn by a kill: no point lost, and the journal starts again with a header.
    jp.write_text(header(SPEC.digest)[:20])
    assert read_journal(out, SPEC) == [] and jp.read_text() == header(SPEC.digest)


def test_a_journal_of_another_sweep_is_refused_and_not_touched(swept, tmp_path):
    """Its first line's digest is not this spec's: refused by name, the file kept as it is."""
    _, recs = swept
    other = json.loads(header(SPEC.digest)) | {"spec_digest": "0" * 16}
    out = tmp_path / "o.h5"
    jp = _journal(out, [line(recs[0]), '{"i": 1, "sta'], head=json.dumps(other) + "\n")
    before = jp.read_bytes()
    with pytest.raises(AtlasError, match="belongs to another sweep"):
        read_journal(out, SPEC)
    assert jp.read_bytes() == before


def test_an_atlas_or_journal_of_another_spec_is_never_overwritten(swept, tmp_path):
    """An atlas of another sweep at out (with or without resume), or its journal alone: refused
    as another sweep's, byte for byte as it was, and nothing created beside it."""
    whole, _ = swept
    other = parse_spec(SMALL.replace("t_end = 200.0", "t_end = 61.0"))
    for resume in (False, True):
        before = whole.read_bytes()
        with pytest.raises(AtlasError, match="holds a different sweep"):
            prepare(other, whole, resume=resume, params_json="{}", version="t")
        assert whole.read_bytes() == before and not journal_path(whole).exists()
    out = tmp_path / "j.h5"
    jp = _journal(out, [])
    for resume in (False, True):
        with pytest.raises(AtlasError, match=r"j\.h5\.journal belongs to another sweep"):
            prepare(other, out, resume=resume, params_json="{}", version="t")
        assert jp.read_text() == header(SPEC.digest) and not out.exists()


def test_journaled_counts_the_points_either_layout_writes(tmp_path):
    """``atlas info``'s count: the index of each line of either layout (two-digit ones too);
    an index the replay would refuse (negative, not an integer) is no point."""
    out = tmp_path / "c.h5"
    lines = [
        '{"i": 12, "status": "done"}\n',  # the earlier layout, as json.dumps wrote it
        '{"i": 3, "status": "done"}\n',
        '[10,"done","",{},null,null]\n',
        '[-1,"done","",{},null,null]\n',
        '[true,"done","",{},null,null]\n',
        '{"status": "done", "i": 7}\n',  # not as run_sweep writes it: parsed whole
    ]
    journal_path(out).write_text(header(SPEC.digest) + "".join(lines))
    assert journaled(out).tolist() == [12, 3, 10, 7]


def _bad(rec, **changes):
    """``rec`` with some of its values changed (``run`` for the rest start's run)."""
    rec = json.loads(json.dumps(rec))
    run = changes.pop("run", {})
    rec["runs"]["rest"].update(run)
    stab = changes.pop("stability", {})
    rec["stability"].update(stab)
    return line(rec | changes)


@pytest.mark.parametrize(
    ("change", "said"),
    [
        ({"i": SPEC.size}, f"point i = {SPEC.size} is not allowed: an integer 0 ... "),
        ({"i": True}, "point i = True is not allowed"),
        ({"status": "ok"}, "status = 'ok' is not one of missing, done, failed"),
        ({"message": 5}, "message = 5 is not text"),
        ({"run": {"regime": "wobbly"}}, "runs.rest.regime = 'wobbly' is not a regime"),
        ({"run": {"stick_events": 2**31}}, "runs.rest.stick_events = 2147483648 is not an "
         "integer of 32 bits"),
        ({"stability": {"unstable": [0, 2**15]}}, "stability.unstable = 32768 is not an "
         "integer of 16 bits"),
        (None, "[0, 'done', '', {}, None, None, 5] is not a point's record"),
    ],
)  # fmt: skip
def test_a_record_that_cannot_be_replayed_is_named_with_its_line(swept, tmp_path, change, said):
    """Line 3 of the journal holds the bad value (each at the edge of what is allowed: one
    past the grid, 2^31 in an i4, 2^15 in an i2, the last steady state's, a 7-value line):
    --resume names the line and the value, and creates no atlas."""
    _, recs = swept
    rec = recs[1] | {"stability": {**recs[1]["stability"], "unstable": [0, 1]}}
    bad = '[0,"done","",{},null,null,5]\n' if change is None else _bad(rec, **change)
    out = tmp_path / "b.h5"
    _journal(out, [line(recs[0]), bad])
    with pytest.raises(AtlasError, match=r"line 3, is damaged \(") as err:
        prepare(SPEC, out, resume=True, params_json="{}", version="t")
    assert said in str(err.value)
    assert not out.exists()


def test_a_journal_in_another_order_of_values_is_written_again_in_this_one(swept, tmp_path):
    """A header naming this layout's run values but its steady states' in another order: the
    journal is written again in this order before the sweep appends (else its new lines
    would be read back in the old order)."""
    _, recs = swept
    a, b = [r for r in recs if r["stability"]["omega_eq"]][:2]  # steady states to swap
    order = STABILITY_KEYS[::-1]
    head = json.loads(header(SPEC.digest)) | {"stability": list(order)}
    assert tuple(head["runs"]) == RUN_KEYS
    packed = json.loads(line(a))
    packed[5] = [a["stability"][k] for k in order]  # by hand, in the header's order
    out = tmp_path / "s.h5"
    jp = _journal(out, [json.dumps(packed) + "\n"], head=json.dumps(head) + "\n")
    prepare(SPEC, out, resume=True, params_json="{}", version="t")
    assert jp.read_text().splitlines()[0] == header(SPEC.digest).strip()
    with jp.open("a") as fh:  # as the sweep appends
        fh.write(line(b))
    assert read_journal(out, SPEC) == [json.loads(json.dumps(r)) for r in (a, b)]


MERGE = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [40.0, 100.0]
torque = TORQUES
[simulation]
t_end = 20.0
initial = ["rest"]
"""


def test_parts_merged_along_the_second_axis_are_placed_by_their_values(tmp_path):
    """Three parts along torque (the second axis), given out of order: every dataset of the
    merged atlas, at each torque, is the part's of that torque (found by value, with
    numpy); the axis increases, and the report's span is its first and last value."""
    parts = {"a.h5": [9.0, 10.0], "b.h5": [5.0], "c.h5": [6.0, 7.0]}
    for name, torques in parts.items():
        run_sweep(parse_spec(MERGE.replace("TORQUES", str(torques))), tmp_path / name, serial=True)
    report = merge_atlases([tmp_path / n for n in parts], tmp_path / "m.h5")
    merged = _arrays(tmp_path / "m.h5")
    with h5py.File(tmp_path / "m.h5", "r") as f:
        axis = f["torque"][...]
    np.testing.assert_array_equal(axis, [5.0, 6.0, 7.0, 9.0, 10.0])
    assert report.span == (5.0, 10.0)
    for name, torques in parts.items():
        part = _arrays(tmp_path / name)
        for t, value in enumerate(torques):
            (k,) = np.flatnonzero(axis == value)
            for ds, data in part.items():
                if data.shape[:2] == (2, len(torques)):  # a per-point dataset
                    np.testing.assert_array_equal(merged[ds][:, k], data[:, t], err_msg=ds)


def test_a_value_two_parts_share_or_an_out_with_a_journal_is_refused(tmp_path):
    """6 N m in the first and the third part (not next to each other when concatenated):
    refused, naming those two parts, with nothing written."""
    for name, torques in {"a.h5": [5.0, 6.0], "b.h5": [7.0], "c.h5": [6.0]}.items():
        run_sweep(parse_spec(MERGE.replace("TORQUES", str(torques))), tmp_path / name, serial=True)
    with pytest.raises(ValueError, match=r"is in both \S*a\.h5 and \S*c\.h5"):
        merge_atlases([tmp_path / n for n in ("a.h5", "b.h5", "c.h5")], tmp_path / "m.h5")
    assert not (tmp_path / "m.h5").exists()
    # Nor into a path whose journal is there (a sweep into it, running or stopped): the
    # merged atlas would take that sweep's place. Refused before any part is read.
    jp = journal_path(tmp_path / "n.h5")
    jp.write_text(header(SPEC.digest))
    read = []
    with pytest.raises(ValueError, match=r"n\.h5 exists"):
        merge_atlases(
            [tmp_path / "a.h5", tmp_path / "b.h5"],
            tmp_path / "n.h5",
            progress=lambda n, _: read.append(n),
        )
    assert read == []
    # A part whose spec_digest was changed after pydrill wrote it: its points are not its
    # spec's, and merged they would pass for them.
    with h5py.File(tmp_path / "b.h5", "r+") as f:
        f.attrs["spec_digest"] = "0" * 16
    with pytest.raises(AtlasError, match=r"b\.h5: its spec makes digest .* written as 0{16}"):
        merge_atlases([tmp_path / "a.h5", tmp_path / "b.h5"], tmp_path / "m.h5")
    assert not (tmp_path / "m.h5").exists()
    assert not (tmp_path / "n.h5").exists() and jp.read_text() == header(SPEC.digest)
