"""Mutation guards of run_sweep's own bookkeeping (sweep.py): progress counts, the signal and
the counts of an interrupted sweep, what a lost scheduler leaves, flushes, the batches of a
serial run, and the local cluster a sweep asks Dask for (a fake LocalCluster: nothing starts).
Every count is checked against the atlas read with plain h5py, or worked out by hand."""

import contextlib
import os
import signal
from typing import ClassVar

import dask.system
import distributed
import h5py
import numpy as np
import pytest
from test_mutation_guards_orchestration import SPEC40, FakeAsCompleted, FakeClient

import pydrill.sweep as sweep_module
import pydrill.sweep_dask as sweep_dask
from pydrill import batching, fork_stdio
from pydrill.spec import parse_spec
from pydrill.sweep import SchedulerError, SweepInterrupted, run_sweep


def saved_in(out):
    with h5py.File(out, "r") as f:
        return int(np.count_nonzero(f["status"][...]))


def interrupted_after_first_batch(out):
    """A serial sweep of SPEC40 stopped by SIGUSR1 once its first batch (20 points: half of
    40, Batcher's rule for one worker) is absorbed."""

    def stop(n, total):
        os.kill(os.getpid(), signal.SIGUSR1)

    with pytest.raises(SweepInterrupted) as info:
        run_sweep(parse_spec(SPEC40), out, serial=True, progress=stop, stop_on=(signal.SIGUSR1,))
    return info.value


def test_an_interrupted_sweep_names_its_signal_and_what_is_saved_and_resumes_counting_right(
    tmp_path,
):
    out = tmp_path / "i.h5"
    exc = interrupted_after_first_batch(out)
    assert exc.signum == signal.SIGUSR1  # the CLI exits 128 + signum
    assert exc.done == exc.computed == saved_in(out) == 20  # flushed on the way out
    # Resumed, then stopped again after its first batch: computed counts this run only.
    seen = []

    def stop_again(n, total):
        seen.append((n, total))
        raise KeyboardInterrupt

    with pytest.raises(SweepInterrupted) as info:
        run_sweep(parse_spec(SPEC40), out, serial=True, resume=True, progress=stop_again)
    first = seen[0][0]
    assert info.value.computed == first and info.value.done == saved_in(out) == 20 + first
    # progress: the points of each batch, out of the points this run has to compute.
    assert seen == [(first, 20)]
    seen.clear()
    report = run_sweep(
        parse_spec(SPEC40), out, resume=True, serial=True, progress=lambda n, t: seen.append((n, t))
    )
    left = 20 - first
    assert {t for _, t in seen} == {left} and sum(n for n, _ in seen) == left
    assert report.computed == left and report.resumed == 20 + first


def test_a_signal_before_any_point_names_that_signal_and_leaves_nothing(tmp_path, monkeypatch):
    real = sweep_module.evaluate_batch

    def evaluate(*args):
        os.kill(os.getpid(), signal.SIGUSR1)  # lands while the first batch computes
        return real(*args)

    monkeypatch.setattr(sweep_module, "evaluate_batch", evaluate)
    out = tmp_path / "n.h5"
    with pytest.raises(SweepInterrupted) as info:
        run_sweep(parse_spec(SPEC40), out, serial=True, stop_on=(signal.SIGUSR1,))
    assert info.value.signum == signal.SIGUSR1 and info.value.done == 0
    assert not out.exists() and not os.path.exists(str(out) + ".journal")


def lose_scheduler_after(monkeypatch, batches, error=None):
    """run_dask that absorbs ``batches`` batches computed here, then fails with ``error``."""

    def run_dask(spec, todo, workers, scheduler, absorb, *rest):
        deal = batching.Batcher(todo)
        for _ in range(batches):
            absorb(sweep_module.evaluate_batch(spec.text, deal.take(1), spec.tally_text))
        raise error or SchedulerError("lost it")

    monkeypatch.setattr(sweep_dask, "run_dask", run_dask)


def test_a_scheduler_lost_midway_says_what_is_saved_and_the_atlas_shows_it(tmp_path, monkeypatch):
    lose_scheduler_after(monkeypatch, 1)
    out = tmp_path / "l.h5"
    with pytest.raises(SchedulerError) as info:
        run_sweep(parse_spec(SPEC40), out, scheduler="tcp://127.0.0.1:1")
    assert f"stopped with {saved_in(out)} of 40 points saved" in str(info.value)
    assert saved_in(out) == 20
    # Resumed and lost again: saved counts the points from before too.
    with pytest.raises(SchedulerError) as info:
        run_sweep(parse_spec(SPEC40), out, scheduler="tcp://127.0.0.1:1", resume=True)
    assert f"stopped with {saved_in(out)} of 40 points saved" in str(info.value)
    assert saved_in(out) > 20


@pytest.mark.parametrize("error", [SchedulerError("lost it"), RuntimeError("boom")])
def test_a_failure_before_any_new_point_keeps_a_resumed_atlas(tmp_path, monkeypatch, error):
    out = tmp_path / "r.h5"
    interrupted_after_first_batch(out)
    lose_scheduler_after(monkeypatch, 0, error)
    with pytest.raises(type(error)):
        run_sweep(parse_spec(SPEC40), out, scheduler="tcp://127.0.0.1:1", resume=True)
    assert saved_in(out) == 20  # what was there stays


@pytest.mark.parametrize(
    ("kwargs", "said"),
    [
        ({"workers": 256, "serial": True}, "give at most one"),  # 256 is allowed
        ({"workers": 257}, "workers = 257 is not allowed"),
        ({"scheduler": "tcp://127.0.0.1:1", "serial": True}, "give at most one"),
        ({"stop_on": (signal.SIGSTOP,)}, "not a signal that can be caught"),
    ],
)
def test_arguments_are_checked_before_anything_runs(tmp_path, kwargs, said):
    with pytest.raises(ValueError, match=said):
        run_sweep(parse_spec(SPEC40), tmp_path / "x.h5", **kwargs)
    assert not (tmp_path / "x.h5").exists()


def test_the_atlas_is_flushed_once_mid_run_when_flushes_are_spaced_far_apart(tmp_path, monkeypatch):
    # Due at once (FLUSH_SECONDS 0), then spaced by 1e9 times what a flush took: one flush
    # after the first batch, one at the end.
    monkeypatch.setattr(sweep_module, "FLUSH_SECONDS", 0.0)
    monkeypatch.setattr(sweep_module, "FLUSH_SPACING", 1e9)
    calls = []
    real = sweep_module.write_atlas
    monkeypatch.setattr(sweep_module, "write_atlas", lambda *a: calls.append(1) or real(*a))
    sizes = []
    real_eval = sweep_module.evaluate_batch
    monkeypatch.setattr(
        sweep_module, "evaluate_batch", lambda t, i, *r: sizes.append(len(i)) or real_eval(t, i, *r)
    )
    seen = []
    run_sweep(
        parse_spec(SPEC40), tmp_path / "f.h5", serial=True, progress=lambda *a: seen.append(a)
    )
    assert len(sizes) >= 2 and len(calls) == 2
    assert seen == [(n, 40) for n in sizes]  # each batch's points, out of 40


def test_a_serial_run_sizes_its_batches_by_the_time_points_take(tmp_path, monkeypatch):
    # No time for more than one point: once the first batch is timed, batches of one point.
    monkeypatch.setattr(batching, "BATCH_SECONDS", 1e-9)
    sizes = []
    real = sweep_module.evaluate_batch
    monkeypatch.setattr(
        sweep_module, "evaluate_batch", lambda t, i, *r: sizes.append(len(i)) or real(t, i, *r)
    )
    report = run_sweep(parse_spec(SPEC40), tmp_path / "t.h5", serial=True)
    assert report.computed == 40 and sizes[0] == 20 and set(sizes[1:]) == {1}
    assert len(sizes) == 40  # one point computed per batch, none twice


class Cluster:
    """LocalCluster as the sweep asks for it: its arguments recorded, nothing started."""

    made: ClassVar[list] = []
    closed = 0

    def __init__(self, **kwargs):
        self.kwargs = kwargs
        self.forked_under_guard = fork_stdio._active > 0
        Cluster.made.append(self)

    def close(self):
        Cluster.closed += 1


@pytest.mark.parametrize("workers", [3, None])
def test_the_local_cluster_is_of_single_threaded_processes_quiet_and_closed(
    tmp_path, monkeypatch, workers
):
    Cluster.made, Cluster.closed = [], 0
    monkeypatch.setattr(distributed, "LocalCluster", Cluster)
    client = FakeClient(workers=workers or 5)
    client.dashboard_link = "http://127.0.0.1:1/status"  # served by no dashboard asked for
    monkeypatch.setattr(sweep_dask, "connect", lambda cluster: client)
    monkeypatch.setattr(distributed, "as_completed", FakeAsCompleted)
    seen = []
    report = run_sweep(
        parse_spec(SPEC40), tmp_path / "w.h5", workers=workers, on_cluster=seen.append
    )
    [c] = Cluster.made
    assert c.kwargs["n_workers"] == (workers or dask.system.CPU_COUNT)
    assert c.kwargs["threads_per_worker"] == 1 and c.kwargs["processes"] is True
    # no dashboard asked for: none served, and its HTTP server on any free port, not 8787
    assert c.kwargs["dashboard_address"] == ":0"
    assert c.kwargs["scheduler_kwargs"] == {"dashboard": False}
    assert [(i.workers, i.dashboard) for i in seen] == [(workers or 5, None)]
    assert c.forked_under_guard and fork_stdio._active == 0
    # the sweep's own client and cluster are closed with it
    assert report.computed == 40 and client.closed and Cluster.closed == 1


def test_ctrl_c_while_the_local_cluster_starts_closes_it(monkeypatch):
    Cluster.made, Cluster.closed = [], 0
    monkeypatch.setattr(distributed, "LocalCluster", Cluster)

    @contextlib.contextmanager
    def starting():
        yield
        raise KeyboardInterrupt  # held until the cluster was up

    spec = parse_spec(SPEC40)
    with pytest.raises(KeyboardInterrupt):
        sweep_dask._run_dask(spec, np.arange(40), 2, None, None, starting=starting)
    assert len(Cluster.made) == 1 and Cluster.closed == 1


def test_local_workers_that_fail_to_start_are_named_by_the_root_cause(monkeypatch):
    def failing(**kwargs):
        try:
            raise OSError("Too many open files")
        except OSError as root:
            raise RuntimeError("Nanny failed to start") from root

    monkeypatch.setattr(distributed, "LocalCluster", failing)
    with pytest.raises(SchedulerError, match="OSError: Too many open files"):
        sweep_dask._run_dask(parse_spec(SPEC40), np.arange(40), 2, None, None)


def test_the_first_failure_reported_is_the_first_in_grid_order(tmp_path, monkeypatch):
    import pydrill.sweep_points as sweep_points

    real = sweep_points.evaluate_point

    def evaluate(spec, i):
        if i in (3, 30):
            return {"i": int(i), "status": "failed", "runs": {}, "message": f"boom {i}"}
        return real(spec, i)

    monkeypatch.setattr(sweep_points, "evaluate_point", evaluate)
    report = run_sweep(parse_spec(SPEC40), tmp_path / "p.h5", serial=True)
    assert (report.failed, report.failed_in_atlas, report.first_failure) == (2, 2, "boom 3")
