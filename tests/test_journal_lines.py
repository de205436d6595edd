"""The journal's lines: a point's values by position, in the orders its first line names.

Half the bytes of the record as a JSON object; every record the sweep writes comes back as it
was; a journal of the earlier layout (whole objects) still resumes, and is written again in
this one before the sweep appends to it; a damaged header or line is named."""

import json

import pytest
from sweeping import SMALL, same_atlas

from pydrill.journal import AtlasError, journal_path, journaled, read_journal, rewrite_path
from pydrill.journal_lines import LAYOUT, Layout, header, line
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep
from pydrill.sweep_dask import killed_point
from pydrill.sweep_points import evaluate_point

# A grid with a start that has no steady state (u below the fold's torque at W_ob = 160 N):
# its run is {"regime": "no-steady-state"}, not a full run.
SPEC = parse_spec(SMALL.replace("torque = [6.0, 8.3]", "torque = [2.0, 8.3]"))


def _records() -> list[dict]:
    recs = [evaluate_point(SPEC, i) for i in range(SPEC.size)]
    failed = {"i": 1, "status": "failed", "runs": {}, "message": "SolverError: too many steps"}
    return [*recs, failed]


def test_every_record_comes_back_as_it_was_in_half_the_bytes():
    recs = _records()
    kinds = {run["regime"] for r in recs for run in r["runs"].values()}
    assert "no-steady-state" in kinds and len(kinds) >= 3
    layout = Layout(json.loads(header(SPEC.digest)))
    for rec in recs:
        text = line(rec)
        assert text.endswith("\n") and "\n" not in text[:-1]
        data = json.loads(text)
        assert isinstance(data, list) and data[0] == rec["i"]  # the index first: journaled()
        assert layout.record(data) == rec
    done = [r for r in recs if r["status"] == "done" and len(r["runs"]) == 2]
    whole = sum(len(json.dumps(r)) + 1 for r in done)
    assert sum(len(line(r)) for r in done) < 0.6 * whole


def test_a_killed_points_record_and_one_with_names_of_its_own_come_back_too():
    layout = Layout(json.loads(header(SPEC.digest)))
    batch = killed_point(SPEC, 3, RuntimeError("worker died"))
    (rec,) = [layout.record(json.loads(text)) for text in batch.lines.splitlines()]
    assert rec["i"] == 3 and rec["status"] == "failed" and "worker died" in rec["message"]
    odd = {"i": 2, "status": "done", "message": "", "runs": {}, "extra": 1}
    assert json.loads(line(odd)) == odd  # a whole object: read as it is
    assert layout.record(json.loads(line(odd))) == odd


def test_a_journal_of_the_earlier_layout_resumes_and_is_rewritten_in_this_one(tmp_path):
    """A sweep stopped by a pydrill that wrote whole objects under a header without a layout:
    resumed here, the atlas equals an uninterrupted run's, and the journal (before the sweep
    appends to it) holds the same records in this layout."""
    whole = tmp_path / "whole.h5"
    run_sweep(SPEC, whole, serial=True)
    out = tmp_path / "old.h5"
    recs = [evaluate_point(SPEC, i) for i in (0, 3, 4)]
    old = [json.dumps({"spec_digest": SPEC.digest})] + [json.dumps(r) for r in recs]
    journal_path(out).write_text("\n".join(old) + "\n")
    assert sorted(journaled(out).tolist()) == [0, 3, 4]
    rewrite_path(journal_path(out)).write_text("[0, ")  # an earlier rewrite, cut by a kill

    seen = []

    def look(n, _):  # the first batch: the journal was rewritten before it was appended
        if not seen:
            lines = journal_path(out).read_text().splitlines()
            head = json.loads(lines[0])
            seen.append((head["layout"], [json.loads(t) for t in lines[1:4]]))

    report = run_sweep(SPEC, out, serial=True, resume=True, progress=look)
    assert report.resumed == 3 and report.computed == SPEC.size - 3
    (layout, first), = seen  # fmt: skip
    assert layout == LAYOUT and [d[0] for d in first] == [0, 3, 4]
    assert all(isinstance(d, list) for d in first)
    same_atlas(out, whole)  # (wall times aside: the runs' own)
    assert not journal_path(out).exists() and not rewrite_path(journal_path(out)).exists()


@pytest.mark.parametrize(
    ("head", "lines", "said"),
    [
        ({"layout": 3, "runs": ["regime"], "stability": ["delta"]}, [], "line 1, is damaged "
         "(layout 3 with runs ['regime'] and stability ['delta'] is not one this pydrill reads)"),
        ({"layout": 2, "runs": "regime", "stability": []}, [], "line 1, is damaged"),
        ({}, ["[0, \"done\", \"\", {\"rest\": [1, 2]}, null, null]"], "line 2, is damaged"),
        ({}, ["[0, \"done\"]"], "line 2, is damaged ([0, 'done'] is not a point's record)"),
        ({}, ["[99, \"done\", \"\", {}, null, null]"], "line 2, is damaged (point i = 99 is not "
         "allowed"),
    ],
)  # fmt: skip
def test_a_damaged_header_or_line_is_named(tmp_path, head, lines, said):
    out = tmp_path / "a.h5"
    first = json.loads(header(SPEC.digest)) | head
    journal_path(out).write_text("\n".join([json.dumps(first), *lines, ""]))
    with pytest.raises(AtlasError) as err:
        read_journal(out, SPEC)
    assert said in str(err.value)
