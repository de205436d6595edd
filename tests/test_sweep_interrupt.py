"""Interrupted sweeps lose nothing: kill -9, Ctrl-C, SIGTERM, cut journals, then --resume."""

import contextlib
import json
import os
import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from sweeping import (
    CMD,
    LONGER,
    MEDIUM,
    SMALL,
    interrupt_mid_sweep,
    same_atlas,
    wait_for_journal,
)

import pydrill.atlas_lock
from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import AtlasError, run_sweep


@pytest.mark.slow
def test_kill_minus_9_then_resume_gives_the_same_atlas(tmp_path):
    spec_file = tmp_path / "m.toml"
    spec_file.write_text(MEDIUM)
    reference = tmp_path / "ref.h5"
    run_sweep(parse_spec(MEDIUM), reference, serial=True)
    out = tmp_path / "killed.h5"
    journal = Path(str(out) + ".journal")
    proc = subprocess.Popen(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--workers", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    wait_for_journal(journal, 40, proc)  # some, not all, points are journaled
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    assert journal.exists()
    done_before = journal.read_text().count("\n") - 1
    assert 0 < done_before < 16 * 12
    report = run_sweep(parse_spec(MEDIUM), out, resume=True, serial=True)
    assert report.resumed >= done_before
    assert report.resumed + report.computed == 16 * 12
    same_atlas(out, reference)


def test_ctrl_c_stops_a_dask_sweep_quietly_and_keeps_every_finished_point(
    tmp_path, longer_reference
):
    rc, _, err, out = interrupt_mid_sweep(tmp_path, signal.SIGINT, "--workers", "2")
    assert rc == 130, err
    assert "Traceback" not in err  # neither the client's nor the workers'
    assert "interrupted" in err and f"--out {out} --workers 2 --resume" in err
    journal = Path(str(out) + ".journal")
    journaled = {json.loads(line)[0] for line in journal.read_text().splitlines()[1:]}
    total = 32 * 16
    assert 0 < len(journaled) < total
    with h5py.File(out, "r") as f:  # flushed on the way out: the atlas shows them already
        done = np.flatnonzero(f["status"][...].ravel() != 0)
    assert set(done.tolist()) == journaled
    assert f"{len(journaled)} of {total} points are saved" in err
    report = run_sweep(parse_spec(LONGER), out, resume=True, serial=True)
    assert report.resumed == len(journaled) and report.computed == total - len(journaled)
    assert not journal.exists()
    # Both starts, so the coexistence flags and every run's fields come back from the journal.
    same_atlas(out, longer_reference)  # LONGER swept serially, uninterrupted (conftest.py)


def test_sigterm_stops_a_serial_sweep_like_ctrl_c(tmp_path):
    rc, stdout, err, out = interrupt_mid_sweep(tmp_path, signal.SIGTERM, "--serial", "--json")
    assert rc == 128 + signal.SIGTERM, err
    assert "Traceback" not in err and "--resume" in err
    from pydrill.plot_atlas import atlas_figure

    with Atlas(out) as atlas:
        s = atlas.summary()
        title = atlas_figure(atlas).axes[0].get_title()
    assert 0 < s["status"]["done"] < 32 * 16
    assert s["journal"] == str(out) + ".journal"
    assert f"({s['status']['done']} of 512 points done)" in title  # blank cells explained
    data = json.loads(stdout)  # --json: scripts learn of the stop too
    assert data["interrupted"] is True and data["done"] == s["status"]["done"]
    # the command to resume runs where this one ran (here, in one process)
    assert data["resume"].endswith(f"--out {out} --serial --resume")


def test_a_journal_line_cut_mid_write_is_recomputed_and_cut_off(tmp_path):
    """A kill while a batch was being appended leaves a last line without its end. Resuming
    drops it, and must cut it off the file: the next batch appended after it would otherwise
    share its line, and the journal could never be read again."""
    spec = parse_spec(SMALL)
    out = tmp_path / "cut.h5"
    reference = tmp_path / "ref.h5"
    run_sweep(spec, reference, serial=True)
    journal = Path(str(out) + ".journal")
    from pydrill.sweep import evaluate_point

    header = json.dumps({"spec_digest": spec.digest}) + "\n"
    whole = json.dumps(evaluate_point(spec, 0)) + "\n"
    cut = json.dumps(evaluate_point(spec, 1))[:37]
    journal.write_text(header + whole + cut)
    report = run_sweep(spec, out, resume=True, serial=True)
    assert report.resumed == 1 and report.computed == spec.size - 1
    same_atlas(out, reference)
    # The same, interrupted again right after the resume appended: readable, nothing lost.
    journal.write_text(header + whole + cut)
    out.unlink()
    from pydrill.journal import read_journal

    assert [r["i"] for r in read_journal(out, spec)] == [0]
    with journal.open("a") as fh:
        fh.write(json.dumps(evaluate_point(spec, 2)) + "\n")
    assert [r["i"] for r in read_journal(out, spec)] == [0, 2]


def test_a_damaged_journal_line_is_named(tmp_path):
    spec = parse_spec(SMALL)
    out = tmp_path / "bad.h5"
    from pydrill.sweep import evaluate_point

    Path(str(out) + ".journal").write_text(
        json.dumps({"spec_digest": spec.digest})
        + "\n{not json\n"
        + json.dumps(evaluate_point(spec, 0))
        + "\n"
    )
    with pytest.raises(AtlasError, match=r"journal, line 2, is damaged"):
        run_sweep(spec, out, resume=True, serial=True)


def test_a_second_sweep_into_an_atlas_being_written_is_refused(tmp_path, monkeypatch):
    """Before the lock, ``--resume`` from a second terminal ran beside the first sweep: two
    writers appending to one journal and overwriting each other's atlas flushes. The first
    sweep must still be running when the second gives up on the lock: with LONGER's points it
    had 1-2 s left after its first batch, and the second kept trying for BUSY_PATIENCE (1 s,
    for a reader's momentary hold) — once long enough for the first to finish, and the second
    resumed a finished atlas. Here it tries once, against a sweep of twice the points."""
    monkeypatch.setattr(pydrill.atlas_lock, "BUSY_PATIENCE", 0.0)
    spec_text = LONGER.replace("num = 32", "num = 64")
    spec_file = tmp_path / "longer.toml"
    spec_file.write_text(spec_text)
    out = tmp_path / "busy.h5"
    journal = Path(str(out) + ".journal")
    first = subprocess.Popen(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--workers", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        wait_for_journal(journal, 1, first)
        before = journal.read_bytes()
        with pytest.raises(
            AtlasError,
            match=rf"being written by another sweep \(process {first.pid} on host "
            rf"{re.escape(socket.gethostname())} \(this machine\), since ",
        ):
            run_sweep(parse_spec(spec_text), out, resume=True, serial=True)
        assert journal.read_bytes()[: len(before)] == before  # untouched by the refused one
        # kill -9 of the sweep alone: its lock file stays, but the kernel drops the lock
        # with the process, though its workers may still be finishing their batches.
        os.kill(first.pid, signal.SIGKILL)
        first.wait()
        report = run_sweep(parse_spec(spec_text), out, resume=True, serial=True)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(first.pid, signal.SIGKILL)
    assert report.resumed + report.computed == 64 * 16
    assert not Path(str(out) + ".lock").exists()


def test_ctrl_c_while_the_local_cluster_starts_leaves_nothing_and_no_traceback(tmp_path):
    """A Ctrl-C during the cluster's start (the first second) once left Dask's tracebacks at
    exit ("close_clusters ... Status.init") and an atlas and journal of 0 points that
    demanded --resume. The signal is sent from inside LocalCluster's start here, so it
    always lands there: the start completes, the cluster closes whole, nothing is left."""
    out = tmp_path / "never.h5"
    script = f"""
import os, signal, sys
import distributed
from pydrill.spec import parse_spec
from pydrill.sweep import SweepInterrupted, run_sweep

real = distributed.LocalCluster.__init__
def starting(self, *args, **kwargs):
    os.kill(os.getpid(), signal.SIGINT)
    real(self, *args, **kwargs)
distributed.LocalCluster.__init__ = starting
try:
    run_sweep(parse_spec({SMALL!r}), {str(out)!r}, workers=2)
except SweepInterrupted as exc:
    print("interrupted", exc.done, exc.signum)
"""
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["interrupted", "0", str(int(signal.SIGINT))]
    assert "Traceback" not in proc.stderr and "Exception ignored" not in proc.stderr
    assert not out.exists() and not Path(str(out) + ".journal").exists()
    # The command says so, and names no --resume to run.
    spec_file = tmp_path / "s.toml"
    spec_file.write_text(SMALL)
    cli = script.split("try:")[0] + (
        "from pydrill.cli import main\n"
        f"sys.exit(main(['sweep', {str(spec_file)!r}, '--out', {str(out)!r}, '--workers', '2']))"
    )
    proc = subprocess.run([sys.executable, "-c", cli], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 130, proc.stderr
    assert proc.stderr.splitlines()[-1] == (
        "pydrill sweep: interrupted before any point was computed; nothing was written"
    )
    assert "--resume" not in proc.stderr and "Traceback" not in proc.stderr
    assert not out.exists() and not Path(str(out) + ".journal").exists()
