"""Where a sweep runs: a real Dask cluster (a worker killed mid-sweep), local workers,
schedulers that are not there, the caller's own client."""

import itertools
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from sweeping import (
    CMD,
    LONGER,
    MEDIUM,
    ROOT,
    SMALL,
    TINY,
    dask_process,
    dask_scheduler,
    same_atlas,
    stop_processes,
    wait_for_workers,
)

from pydrill.atlas import Atlas
from pydrill.dask_connect import kept_environ
from pydrill.spec import parse_spec
from pydrill.sweep import SweepInterrupted, run_sweep


@pytest.mark.slow
def test_real_dask_cluster_and_a_worker_killed_mid_sweep(tmp_path):
    scheduler, address = dask_scheduler(tmp_path / "scheduler.json", "--dashboard-address", ":0")
    procs = [scheduler]
    try:
        for _ in range(2):
            procs.append(
                dask_process(
                    "worker", address, "--nthreads", "1", "--no-nanny", "--host", "127.0.0.1"
                )
            )
        wait_for_workers(address, 2)
        spec_file = tmp_path / "m.toml"
        spec_file.write_text(MEDIUM)
        out = tmp_path / "cluster.h5"
        journal = Path(str(out) + ".journal")
        sweep = subprocess.Popen(
            [*CMD, "sweep", str(spec_file), "--out", str(out), "--scheduler", address, "--json"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        deadline = time.time() + 120
        while time.time() < deadline:
            if journal.exists() and journal.read_text().count("\n") > 20:
                break
            time.sleep(0.05)
        os.killpg(procs[1].pid, signal.SIGKILL)  # a worker dies mid-sweep
        stdout, stderr = sweep.communicate(timeout=300)
        assert sweep.returncode == 0, stderr
        report = json.loads(stdout)
        assert report["computed"] == 16 * 12 and report["failed"] == 0
        reference = tmp_path / "ref.h5"
        run_sweep(parse_spec(MEDIUM), reference, serial=True)
        same_atlas(out, reference)
        # The same cluster found through its scheduler file, as on a batch system.
        small = tmp_path / "small.toml"
        small.write_text(SMALL)
        args = ["sweep", str(small), "--out", str(tmp_path / "file.h5"), "--json"]
        via_file = subprocess.run(
            [*CMD, *args, "--scheduler", str(tmp_path / "scheduler.json")],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert via_file.returncode == 0, via_file.stderr
        assert json.loads(via_file.stdout)["computed"] == parse_spec(SMALL).size
        # The cluster's own dashboard, its link printed for the user, answers.
        link = re.search(rf"scheduler {address}, dashboard (\S+)", via_file.stderr)
        assert link, via_file.stderr
        with urllib.request.urlopen(link[1], timeout=30) as page:
            assert page.status == 200 and b"Dask" in page.read()
        # Named in the environment, as a Dask user names their cluster for every client.
        via_env = subprocess.run(
            [*CMD, "sweep", str(small), "--out", str(tmp_path / "env.h5"), "--json"],
            capture_output=True,
            text=True,
            timeout=120,
            env={**os.environ, "DASK_SCHEDULER_ADDRESS": address},
        )
        assert via_env.returncode == 0, via_env.stderr
        assert json.loads(via_env.stdout)["computed"] == parse_spec(SMALL).size
        assert f"scheduler {address} (from DASK_SCHEDULER_ADDRESS" in via_env.stderr
    finally:
        stop_processes(procs)


def test_a_sweep_beside_another_cluster_on_port_8787_stays_quiet(tmp_path):
    """Dask's HTTP port 8787 is often held by a user's own cluster (or its dashboard). The
    sweep's throwaway cluster then used to warn "Port 8787 is already in use"; with pytest's
    warnings-as-errors this test failed before the sweep asked for any free port."""
    holder = socket.socket()
    try:
        holder.bind(("", 8787))
        holder.listen()
    except OSError:
        pass  # somebody else holds it already: the same situation
    try:
        spec = parse_spec(SMALL.replace("[40.0, 100.0, 160.0]", "[40.0, 160.0]"))
        report = run_sweep(spec, tmp_path / "beside.h5", workers=2)
        assert report.computed == 4 and report.failed == 0
    finally:
        holder.close()


def test_local_workers_that_cannot_start_are_one_clear_error(tmp_path):
    import dask

    from pydrill.sweep import SchedulerError

    out = tmp_path / "never.h5"
    # A worker preloads this module before it registers; there is none, so none starts.
    broken = {"distributed.worker.preload": ["pydrill_test_no_such_module"]}
    with (
        dask.config.set(broken),
        pytest.raises(SchedulerError, match=r"workers did not start \(.*pydrill_test_no_such"),
    ):
        run_sweep(parse_spec(SMALL), out, workers=1)
    assert not out.exists() and not Path(str(out) + ".journal").exists()


@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="needs two cores to pin to one")
def test_default_workers_are_the_cores_this_process_may_use(tmp_path):
    # Pinned to one core (as a container's --cpus or a batch job's allocation would), the local
    # cluster gets one worker, not one per core of the host.
    script = f"""
import distributed
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep
asked = []
class Recording(distributed.LocalCluster):
    def __init__(self, *args, **kwargs):
        asked.append(kwargs["n_workers"])
        super().__init__(*args, **kwargs)
distributed.LocalCluster = Recording
run_sweep(parse_spec({SMALL!r}), {str(tmp_path / "pinned.h5")!r})
print(asked)
"""
    proc = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=lambda: os.sched_setaffinity(0, {min(os.sched_getaffinity(0))}),
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[1]"


def test_conflicting_places_to_run_are_refused_before_anything_is_written(tmp_path):
    out = tmp_path / "never.h5"
    with pytest.raises(ValueError, match="at most one of workers"):
        run_sweep(parse_spec(SMALL), out, serial=True, workers=2)
    assert not out.exists() and not Path(str(out) + ".journal").exists()
    proc = subprocess.run(
        [
            *CMD,
            "sweep",
            str(ROOT / "sweeps" / "minimal.toml"),
            "--out",
            str(out),
            "--serial",
            "--scheduler",
            "tcp://127.0.0.1:8786",
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and "not allowed with argument --serial" in proc.stderr
    assert not out.exists()


def test_a_dask_client_of_the_callers_runs_the_sweep_and_stays_open(tmp_path):
    """In a notebook the Dask cluster already exists: pass its Client, as Dask users do."""
    from distributed import Client, LocalCluster

    reference = tmp_path / "ref.h5"
    run_sweep(parse_spec(SMALL), reference, serial=True)
    with (
        LocalCluster(n_workers=1, processes=False, dashboard_address=":0") as cluster,
        Client(cluster) as client,
    ):
        report = run_sweep(parse_spec(SMALL), tmp_path / "client.h5", scheduler=client)
        assert report.computed == 6
        assert not client.futures  # nothing of the sweep's left behind on it
        # Nor during the sweep: a batch's result is let go of once absorbed. Kept, the results
        # of a million-point sweep would fill the workers' memory (a gigabyte) to the end.
        # Counted on the client, whose last reference to a future releases it at once (the
        # workers forget it a message later, so their count lags by a batch or two).
        held = []
        run_sweep(
            parse_spec(MEDIUM),
            tmp_path / "held.h5",
            scheduler=client,
            progress=lambda n, total: held.append(len(client.futures)),
        )
        # Kept, it would stay at the number of batches; let go of, it falls by one a batch
        # to the one being absorbed.
        assert len(held) >= 5 and held[-1] == 1, held
        assert all(b < a for a, b in itertools.pairwise(held)), held
        assert client.submit(sum, [1, 2], pure=False).result() == 3  # still the caller's

        def stop_after_the_first_batch(n, total):
            raise KeyboardInterrupt

        with pytest.raises(SweepInterrupted) as stopped:
            run_sweep(
                parse_spec(MEDIUM),
                tmp_path / "stopped.h5",
                scheduler=client,
                progress=stop_after_the_first_batch,
            )
        assert 0 < stopped.value.done < 16 * 12
        assert not client.futures  # the batches not yet done were cancelled, not left running
        assert client.submit(sum, [3, 4], pure=False).result() == 7
    same_atlas(tmp_path / "client.h5", reference)


def _break_pydrill():
    sys.modules["pydrill"] = None  # as on a worker where pydrill is not installed


def _older_pydrill():
    import pydrill

    pydrill.__version__ = "0.0.1"


@pytest.mark.parametrize(
    ("harm", "said"),
    [
        (_break_pydrill, r"1 of 2 Dask workers at tcp://127\.0\.0\.1:\d+ cannot import pydrill"),
        (_older_pydrill, r"run pydrill 0\.0\.1, this client .*: one atlas must come from one"),
    ],
)
def test_workers_that_cannot_run_the_sweep_are_refused_before_any_point(tmp_path, harm, said):
    """Without pydrill a worker dies unpickling its first batch, and the sweep used to wait
    for ever for workers that were gone; with another pydrill, one atlas would mix two."""
    from distributed import Client, LocalCluster

    from pydrill.sweep import SchedulerError

    out = tmp_path / "never.h5"
    with (
        kept_environ(),  # the test's own nanny sets OMP_NUM_THREADS and more in this process
        LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=":0") as cluster,
        Client(cluster) as client,
    ):
        first = sorted(client.scheduler_info()["workers"])[0]
        client.run(harm, workers=[first])
        t0 = time.perf_counter()
        with pytest.raises(SchedulerError, match=said):
            run_sweep(parse_spec(SMALL), out, scheduler=cluster.scheduler_address)
        assert time.perf_counter() - t0 < 30
        assert len(client.scheduler_info()["workers"]) == 2  # no worker was lost to it
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def test_a_cluster_without_workers_yet_is_waited_for_and_said_so(tmp_path):
    """An adaptive or batch-system cluster may have no workers when the sweep starts: the
    sweep says so, waits, and runs on the workers that join."""
    from distributed import LocalCluster

    spec_file = tmp_path / "small.toml"
    spec_file.write_text(SMALL)
    with (
        kept_environ(),  # the nanny scale(1) starts sets OMP_NUM_THREADS and more here
        LocalCluster(n_workers=0, threads_per_worker=1, dashboard_address=":0") as cluster,
    ):
        out = tmp_path / "later.h5"
        where = ["--scheduler", cluster.scheduler_address]
        sweep = subprocess.Popen(
            [*CMD, "sweep", str(spec_file), "--out", str(out), *where, "--json"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        line = sweep.stderr.readline()
        assert line.startswith("sweep: 0 Dask workers, scheduler tcp://127.0.0.1:"), line
        assert "(none yet: the points wait for workers to join)" in line
        cluster.scale(1)
        stdout, stderr = sweep.communicate(timeout=120)
    assert sweep.returncode == 0, stderr
    report = json.loads(stdout)
    assert report["computed"] == parse_spec(SMALL).size and report["cluster"]["workers"] == 0


def test_workers_leaving_and_joining_an_existing_cluster_are_told(tmp_path, monkeypatch):
    """A batch job's workers reach their time limit, an adaptive cluster scales: the sweep
    tells on_cluster (the command prints a line), waits at 0 workers, and completes on the
    workers that join."""
    import threading

    from distributed import LocalCluster

    from pydrill import sweep_dask

    monkeypatch.setattr(sweep_dask, "WATCH_SECONDS", 0.2)
    seen, done = [], []
    # Long enough (256 points of 3000 s from rest) to be stopped mid-way.
    spec = parse_spec(LONGER.replace("num = 32", "num = 16").replace(', "equilibrium"', ""))
    with LocalCluster(
        n_workers=1, processes=False, threads_per_worker=1, dashboard_address=":0"
    ) as cluster:
        box = {}

        def sweep():
            box["report"] = run_sweep(
                spec,
                tmp_path / "scaled.h5",
                scheduler=cluster.scheduler_address,
                on_cluster=seen.append,
                progress=lambda n, total: done.append(n),
            )

        runner = threading.Thread(target=sweep)
        runner.start()
        deadline = time.time() + 60
        while not done and time.time() < deadline:  # the first batch is in
            time.sleep(0.01)
        cluster.scale(0)
        while [i.workers for i in seen][-1:] != [0] and time.time() < deadline:
            time.sleep(0.05)
        stalled = sum(done)
        time.sleep(1.0)
        assert sum(done) == stalled < spec.size  # nothing computes without workers
        cluster.scale(1)
        runner.join(timeout=120)
    assert not runner.is_alive()
    assert [i.workers for i in seen] == [1, 0, 1]
    assert box["report"].computed == spec.size and box["report"].failed == 0


def test_workers_are_counted_beyond_the_five_some_dask_versions_list(tmp_path):
    """distributed 2025.4 ... 2026.6 lists at most 5 workers in scheduler_info()["workers"]
    (dask/distributed#9065) but gives their number in "n_workers"; older versions list all."""
    from distributed import Client, LocalCluster

    from pydrill.dask_connect import worker_count

    class Capped:  # what those versions' client answers for 7 workers
        def scheduler_info(self):
            return {"n_workers": 7, "workers": {f"tcp://w{i}": {} for i in range(5)}}

    class Old:  # before the cap: no count, the whole list
        def scheduler_info(self):
            return {"workers": {f"tcp://w{i}": {} for i in range(7)}}

    assert worker_count(Capped()) == worker_count(Old()) == 7
    seen = []
    with (
        LocalCluster(
            n_workers=7, threads_per_worker=1, processes=False, dashboard_address=":0"
        ) as c,
        Client(c) as client,
    ):
        run_sweep(
            parse_spec(SMALL), tmp_path / "seven.h5", scheduler=client, on_cluster=seen.append
        )
    assert seen[0].workers == 7


def test_a_point_that_kills_its_workers_is_stored_failed_and_the_sweep_goes_on(
    tmp_path, monkeypatch
):
    """A point that takes its worker process down (a crash in native code, the memory
    killer) every time: the scheduler gives up on its batch (KilledWorker), which once ended
    the sweep with a traceback. Now the batch's points go again one by one; the one that
    still kills is stored as failed with the reason, every other point is computed. The
    workers are forked from this process, so they run the patched point."""
    from pydrill import sweep_points

    spec = parse_spec(TINY)
    reference = tmp_path / "ref.h5"
    run_sweep(spec, reference, serial=True)
    real = sweep_points.evaluate_point

    def crashing(spec, index):
        if index == 4:
            os._exit(9)  # as a segfault or SIGKILL would: no exception, no cleanup
        return real(spec, index)

    monkeypatch.setattr(sweep_points, "evaluate_point", crashing)
    out = tmp_path / "crash.h5"
    report = run_sweep(spec, out, workers=2)
    assert (report.computed, report.failed) == (6, 1)
    with Atlas(out) as atlas, Atlas(reference) as ref:
        for i in range(6):
            coords = spec.coords(i)
            got, want = atlas.value(**coords), ref.value(**coords)
            if i == 4:
                assert got["status"] == "failed"
                assert "killed every Dask worker that ran it" in got["message"]
            else:  # all but the time each run took
                got["metrics"].pop("wall_time"), want["metrics"].pop("wall_time")
                assert got == want
