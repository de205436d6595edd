"""Connecting to an existing Dask cluster: a scheduler that is not there (yet), a scheduler
file that is missing."""

import json
import os
import re
import subprocess
import time
from pathlib import Path

import dask
import distributed  # noqa: F401 - its config defaults, before any dask.config.set
import pytest
from sweeping import (
    CMD,
    LONGER,
    ROOT,
    SMALL,
    dask_process,
    dask_scheduler,
    free_port,
    same_atlas,
    stop_processes,
    unserved_port,
    wait_for_journal,
)

from pydrill.atlas import Atlas
from pydrill.dask_connect import unanswered
from pydrill.spec import load_spec, parse_spec
from pydrill.sweep import run_sweep


def test_no_scheduler_at_the_address_is_one_clear_error_and_leaves_no_files(tmp_path):
    out = tmp_path / "never.h5"
    with unserved_port() as port:
        nobody = f"tcp://127.0.0.1:{port}"
        proc = subprocess.run(
            [
                *CMD,
                "sweep",
                str(ROOT / "sweeps" / "minimal.toml"),
                "--out",
                str(out),
                "--scheduler",
                nobody,
            ],
            capture_output=True,
            text=True,
            timeout=120,
            env={**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "2s"},
        )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    # While Dask waits for the scheduler to start, the user is told so; then one error.
    waiting, error = proc.stderr.splitlines()
    assert waiting == (
        f"sweep: no Dask scheduler answers at {nobody} yet; waiting up to 2 s for one to start "
        "(distributed.comm.timeouts.connect)"
    )
    error = error.replace(nobody, "ADDRESS")
    assert error.startswith("pydrill sweep: error: --scheduler ADDRESS: no Dask scheduler")
    assert "'dask scheduler', then 'dask worker ADDRESS'" in error
    assert not out.exists() and not Path(str(out) + ".journal").exists()
    # So the same command, once the address is right, needs no --resume nor any cleaning up.
    report = run_sweep(load_spec(ROOT / "sweeps" / "minimal.toml"), out, serial=True)
    assert report.computed == report.points


def test_a_missing_scheduler_file_is_named_and_nothing_is_written(tmp_path):
    from pydrill.sweep import SchedulerError

    out = tmp_path / "never.h5"
    with (
        dask.config.set({"distributed.comm.timeouts.connect": "1s"}),
        pytest.raises(
            SchedulerError, match=r"no such scheduler file after waiting 1 s.*--scheduler-file"
        ),
    ):
        run_sweep(parse_spec(SMALL), out, scheduler=str(tmp_path / "gone.json"))
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def test_a_sweep_leaves_the_callers_dask_as_it_was(tmp_path):
    """The sweep's own Client was made the process's default before it connected, and one
    that failed to connect stayed so, half made ("connecting"), with dask's scheduler set to
    it: the caller's next sweep took it for theirs ("only a local cluster's dashboard ...")
    and their next dask.compute went to a scheduler that was never there."""
    from distributed import LocalCluster, default_client

    from pydrill.sweep import SchedulerError

    def no_default_client() -> bool:
        try:
            default_client()
        except ValueError:  # "No clients found"
            return True
        return False

    assert no_default_client()
    before = dask.config.get("scheduler", None)
    spec = parse_spec(SMALL)
    with unserved_port() as port, dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        for nowhere in [f"tcp://127.0.0.1:{port}", str(tmp_path / "no-such-file")]:
            with pytest.raises(SchedulerError):
                run_sweep(spec, tmp_path / "never.h5", scheduler=nowhere)
            assert no_default_client(), nowhere
            assert dask.config.get("scheduler", None) == before, nowhere
    seen = []  # while the sweep runs, the caller's threads keep their dask too
    with LocalCluster(n_workers=1, processes=False, dashboard_address=":0") as cluster:
        run_sweep(
            spec,
            tmp_path / "done.h5",
            scheduler=cluster.scheduler_address,
            on_cluster=lambda _: seen.append(
                (no_default_client(), dask.config.get("scheduler", None))
            ),
        )
    assert seen == [(True, before)]
    assert no_default_client() and dask.config.get("scheduler", None) == before


@pytest.mark.parametrize("text", ["{}", "garbage", '{"address": 5}', "[1, 2]"])
def test_a_file_that_is_no_scheduler_file_is_named_not_a_traceback(tmp_path, text):
    """Dask's client failed on these with an AssertionError deep inside it."""
    from pydrill.sweep import SchedulerError

    bad = tmp_path / "bad.json"
    bad.write_text(text)
    out = tmp_path / "never.h5"
    with pytest.raises(SchedulerError, match=r"bad.json: not a Dask scheduler file \(no sch"):
        run_sweep(parse_spec(SMALL), out, scheduler=str(bad))
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def waiting_sweep(tmp_path, scheduler: str) -> subprocess.Popen:
    """``pydrill sweep SMALL --scheduler SCHEDULER --json`` started before its scheduler, with
    90 s to wait for it (what it says it waits for is on its stderr's first line)."""
    small = tmp_path / "small.toml"
    small.write_text(SMALL)
    out = tmp_path / "late.h5"
    return subprocess.Popen(
        [*CMD, "sweep", str(small), "--out", str(out), "--scheduler", scheduler, "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "90s"},
    )


def test_a_scheduler_file_written_while_the_sweep_waits_runs_it(tmp_path):
    """A batch job starts the scheduler and the sweep together: the file is not there yet.
    It was refused at once; now it is waited for (as the guide says), and the user told."""
    file = tmp_path / "sched.json"
    sweep = waiting_sweep(tmp_path, str(file))
    procs = []
    try:
        line = sweep.stderr.readline()
        assert line == (
            f"sweep: no scheduler file {file} yet; waiting up to 90 s for a scheduler to write "
            "it (distributed.comm.timeouts.connect)\n"
        )
        where = ("--scheduler-file", str(file))
        procs.append(dask_process("scheduler", "--host", "127.0.0.1", "--port", "0", *where,
                                  "--dashboard-address", ":0"))  # fmt: skip
        procs.append(dask_process("worker", *where, "--nthreads", "1", "--no-nanny"))
        stdout, stderr = sweep.communicate(timeout=120)
        assert sweep.returncode == 0, line + stderr
        assert json.loads(stdout)["computed"] == parse_spec(SMALL).size
    finally:
        if sweep.poll() is None:
            sweep.kill()
            sweep.wait()
        stop_processes(procs)


def test_a_scheduler_that_starts_while_the_sweep_waits_runs_it(tmp_path):
    """A job script may start the scheduler and the sweep together: Dask's client waits for the
    scheduler, and the user is told that it does instead of seeing nothing."""
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    assert unanswered(address) == 30.0  # nothing there: Dask's default wait, in s
    sweep = waiting_sweep(tmp_path, address)
    procs = []
    try:
        line = sweep.stderr.readline()
        assert line.startswith(
            f"sweep: no Dask scheduler answers at {address} yet; waiting up to 90 s"
        )
        procs.append(dask_process("scheduler", "--host", "127.0.0.1", "--port", str(port),
                                  "--dashboard-address", ":0"))  # fmt: skip
        procs.append(dask_process("worker", address, "--nthreads", "1", "--no-nanny"))
        stdout, stderr = sweep.communicate(timeout=120)
        assert sweep.returncode == 0, line + stderr
        assert json.loads(stdout)["computed"] == parse_spec(SMALL).size
        # connected as soon as the scheduler answered, with its worker or before it joined
        assert re.search(rf"^sweep: [01] Dask workers?, scheduler {address}", stderr, re.M)
        deadline = time.time() + 30  # the scheduler answers now: no notice
        while unanswered(address) is not None and time.time() < deadline:
            time.sleep(0.1)
        assert unanswered(address) is None
    finally:
        if sweep.poll() is None:
            sweep.kill()
            sweep.wait()
        stop_processes(procs)
    # Addresses it cannot probe are left to Dask: a scheduler file, another protocol.
    assert unanswered(str(tmp_path / "scheduler.json")) is None
    assert unanswered("inproc://10.0.0.1/1/2") is None


@pytest.mark.slow
def test_a_scheduler_lost_midway_is_one_clear_error_and_resume_completes_the_atlas(
    tmp_path, longer_reference
):
    """The scheduler killed mid-sweep (its machine down, the job ended): a page of Dask's
    reconnection tracebacks, then FutureCancelledError's, and exit 1. Now one line saying
    how many points are saved and what to do; the atlas holds them (flushed, as after
    Ctrl-C), and --resume on local workers completes it as an uninterrupted sweep would."""
    scheduler, address = dask_scheduler(tmp_path / "scheduler.json", "--dashboard-address", ":0")
    procs = [scheduler]
    spec_file, out = tmp_path / "s.toml", tmp_path / "a.h5"
    spec_file.write_text(LONGER)
    journal = Path(str(out) + ".journal")
    try:
        procs.append(dask_process("worker", address, "--nthreads", "1", "--no-nanny"))
        sweep = subprocess.Popen(
            [*CMD, "sweep", str(spec_file), "--out", str(out), "--scheduler", address],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env={**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "30s"},
        )
        wait_for_journal(journal, 20, sweep)
        stop_processes([scheduler])
        _, stderr = sweep.communicate(timeout=120)
    finally:
        if sweep.poll() is None:
            sweep.kill()
            sweep.wait()
        stop_processes(procs)
    assert sweep.returncode == 2 and "Traceback" not in stderr, stderr
    size = parse_spec(LONGER).size
    saved = journal.read_text().count("\n") - 1  # the header, then a line a point
    assert 20 <= saved < size
    assert stderr.splitlines()[-1] == (
        f"pydrill sweep: error: lost the connection to the Dask scheduler at {address}: the "
        f"sweep stopped with {saved} of {size} points saved in {out}. Start the scheduler and "
        "its workers again (or sweep without --scheduler to run here), then run the sweep "
        "again with --resume"
    )
    with Atlas(out) as atlas:
        assert atlas.summary()["status"] == {"missing": size - saved, "done": saved, "failed": 0}
    resumed = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--resume", "--workers", "2"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert resumed.returncode == 0, resumed.stderr
    same_atlas(out, longer_reference)  # LONGER swept serially, uninterrupted (conftest.py)
