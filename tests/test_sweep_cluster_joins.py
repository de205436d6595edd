"""A sweep on a cluster others run, as a batch system's: workers that join after the sweep
checked them, a scheduler lost before the first batch came back, a scheduler file of any
name."""

import json
import os
import re
import signal
import subprocess
from pathlib import Path

import pytest
from sweeping import (
    CMD,
    LONGER,
    TINY,
    dask_process,
    dask_scheduler,
    same_atlas,
    stop_processes,
    wait_for_workers,
)

from pydrill import __version__
from pydrill.spec import parse_spec
from pydrill.sweep import SchedulerError, SweepInterrupted, run_sweep

# Preloaded by a `dask worker` (--preload): a worker where pydrill is missing or another.
HARMS = {
    "missing": 'import sys\nsys.modules["pydrill"] = None\n',
    "older": 'import pydrill\npydrill.__version__ = "0.0.1"\n',
}


@pytest.mark.slow
@pytest.mark.parametrize(
    ("harm", "said"),
    [
        ("missing", "cannot import pydrill (ModuleNotFoundError: "),
        ("older", f"runs pydrill 0.0.1, this client {__version__}: one atlas must come from one"),
    ],
    ids=["missing", "older"],
)
def test_a_worker_that_joins_later_without_this_pydrill_is_refused(tmp_path, harm, said):
    """A batch job's workers queued when the sweep starts: check_workers finds none to ask,
    and the worker that joined ran the sweep unasked. With another pydrill, the atlas took
    its points (the sweep ended 0, the versions mixed); without pydrill, the worker died on its
    first batch and the sweep waited for ever (so the test waits 60 s at most)."""
    from distributed import LocalCluster

    spec_file, out = tmp_path / "tiny.toml", tmp_path / "mixed.h5"
    spec_file.write_text(TINY)
    preload = tmp_path / f"{harm}.py"
    preload.write_text(HARMS[harm])
    procs = []
    with LocalCluster(n_workers=0, dashboard_address=":0") as cluster:
        address = cluster.scheduler_address
        sweep = subprocess.Popen(
            [*CMD, "sweep", str(spec_file), "--out", str(out), "--scheduler", address],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        try:
            line = sweep.stderr.readline()  # the points are out, waiting for workers
            assert line.startswith("sweep: 0 Dask workers"), line
            procs.append(dask_process("worker", address, "--nthreads", "1", "--preload",
                                      str(preload)))  # fmt: skip
            _, stderr = sweep.communicate(timeout=60)
        finally:
            if sweep.poll() is None:
                sweep.kill()
                sweep.wait()
            stop_processes(procs)
    assert sweep.returncode == 2, stderr
    worker = rf"the Dask worker tcp://127\.0\.0\.1:\d+ at {address}, which joined after"
    assert said in stderr and re.search(worker, stderr), stderr
    assert stderr.rstrip().endswith(
        "the sweep stopped before any point was saved (nothing is written). Install pydrill "
        f"{__version__} where it runs (in the environment its 'dask worker' starts from), or "
        "stop it, then run the sweep again"
    ), stderr
    assert not out.exists() and not Path(str(out) + ".journal").exists()


@pytest.mark.slow
def test_a_scheduler_lost_before_the_first_batch_says_what_to_do(tmp_path):
    """Killed before any batch came back (a batch job's time up at the start): the sweep
    said only "lost the connection to the Dask scheduler at ...", neither what was saved
    nor what to do. The first batch takes seconds (LONGER's points, 10x longer, past the
    batches' 5 s budget), the scheduler is killed as soon as the points are out."""
    scheduler, address = dask_scheduler(tmp_path / "scheduler.json", "--dashboard-address", ":0")
    procs = [scheduler, dask_process("worker", address, "--nthreads", "1", "--no-nanny")]
    out = tmp_path / "lost.h5"
    slow = parse_spec(LONGER.replace("t_end = 3000.0", "t_end = 30000.0"))
    seen = []

    def kill_the_scheduler(info):
        seen.append(info.workers)
        os.killpg(scheduler.pid, signal.SIGKILL)

    try:
        wait_for_workers(address, 1)  # before the sweep looks (CI once saw 0 workers there)
        with pytest.raises(SchedulerError) as raised:
            run_sweep(slow, out, scheduler=address, on_cluster=kill_the_scheduler)
    finally:
        stop_processes(procs)
    assert seen == [1]
    assert str(raised.value) == (
        f"lost the connection to the Dask scheduler at {address}: the sweep stopped before "
        "any point was saved (nothing is written). Start the scheduler and its workers again "
        "(or sweep without scheduler=... to run here), then run the sweep again"
    )
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def test_a_scheduler_file_of_any_name_is_read_as_one(tmp_path):
    """Batch systems name the file as they like (--scheduler-file $HOME/scheduler): one
    whose name did not end in .json was taken for an address and refused ("missing port
    number"). The atlas equals a serial sweep's; a name that is neither is told so."""
    from distributed import LocalCluster

    spec = parse_spec(TINY)
    with LocalCluster(
        n_workers=1, processes=False, threads_per_worker=1, dashboard_address=":0"
    ) as cluster:
        file = tmp_path / "scheduler"  # as `dask scheduler --scheduler-file` writes it
        file.write_text(json.dumps({"type": "Scheduler", "address": cluster.scheduler_address}))
        report = run_sweep(spec, tmp_path / "file.h5", scheduler=str(file))
    assert report.computed == spec.size
    run_sweep(spec, tmp_path / "serial.h5", serial=True)
    same_atlas(tmp_path / "file.h5", tmp_path / "serial.h5")
    nowhere = tmp_path / "no-such-file"
    with pytest.raises(SchedulerError, match=r"neither a scheduler's address \(tcp://HOST:PORT"):
        run_sweep(spec, tmp_path / "never.h5", scheduler=str(nowhere))
    assert not (tmp_path / "never.h5").exists()


@pytest.mark.parametrize("given", ["", "  "])
def test_an_empty_scheduler_is_refused_not_run_on_this_machine(tmp_path, given):
    """A job script's unset variable, --scheduler "$SCHED_FILE": the sweep ran on a local
    cluster of the login node's cores, as if no --scheduler were given (exit 0)."""
    spec_file, out = tmp_path / "tiny.toml", tmp_path / "here.h5"
    spec_file.write_text(TINY)
    cli = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--scheduler", given],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert cli.returncode == 2, cli.stderr
    assert cli.stderr.startswith(f"pydrill sweep: error: --scheduler {given!r} is not allowed: ")
    with pytest.raises(ValueError, match=rf"scheduler = {given!r} is not allowed: .* or None$"):
        run_sweep(parse_spec(TINY), out, scheduler=given)
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def test_a_sweep_stopped_before_any_point_says_nothing_was_written(tmp_path):
    """Ctrl-C while the points wait for workers (here: as they go out): the new atlas is
    removed, but the exception said "0 of N points are saved in ATLAS", a file not there."""
    from distributed import LocalCluster

    def ctrl_c(info):
        raise KeyboardInterrupt

    out = tmp_path / "never.h5"
    with LocalCluster(n_workers=0, processes=False, dashboard_address=":0") as cluster:
        with pytest.raises(SweepInterrupted) as raised:
            run_sweep(parse_spec(TINY), out, scheduler=cluster.scheduler_address, on_cluster=ctrl_c)
    assert not out.exists() and not raised.value.written and raised.value.done == 0
    assert str(raised.value) == (
        f"sweep interrupted before any point was computed: nothing was written ({out} is not "
        "made); run it again to start"
    )
