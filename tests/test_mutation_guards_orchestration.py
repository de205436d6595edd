"""Mutation guards of a sweep's orchestration on Dask (sweep_dask.py) without a cluster: a fake
client runs each batch in this process, so what the sweep deals, hands back, resubmits, runs
alone and cancels is seen directly, and the atlas is compared with a serial run's, read with
plain h5py (sweeping.same_atlas)."""

import threading
import types

import distributed
import h5py
import numpy as np
import pytest
from distributed.client import FutureCancelledError
from sweeping import same_atlas

import pydrill
from pydrill import batching
from pydrill.spec import parse_spec
from pydrill.sweep import SchedulerError, run_sweep

# 40 points of a few ms each: enough for several batches (16 points at least, see Batcher).
SPEC40 = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 40.0, stop = 160.0, num = 8 }
torque = { start = 6.0, stop = 8.3, num = 5 }
[simulation]
t_end = 50.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def serial40(tmp_path_factory):
    out = tmp_path_factory.mktemp("serial") / "serial.h5"
    run_sweep(parse_spec(SPEC40), out, serial=True)
    return out


class FakeFuture:
    def __init__(self, client, fn, args, alone):
        self.client, self.fn, self.args, self.alone = client, fn, args, alone

    def result(self):
        self.client.outstanding_alone -= self.alone
        if self.client.cancelled_reason:
            raise FutureCancelledError("k", self.client.cancelled_reason)
        if self.client.poison in self.args[1]:
            raise distributed.KilledWorker("k", types.SimpleNamespace(address="tcp://w1"), 3)
        done = self.fn(*self.args)
        self.client.computed.extend(done.indices.tolist())
        return done


class FakeClient:
    """A caller's distributed.Client (it has submit): batches run in this process when their
    futures are asked for a result. ``poison``: "first" kills every batch holding the first
    point dealt, as a point that crashes its worker would."""

    def __init__(self, workers=2, poison=None, found=None):
        self.workers, self.poison, self.found = workers, poison, found
        self.maps, self.cancelled, self.computed = [], [], []
        self.closed = False
        self.status = "running"
        self.cancelled_reason = None
        self.outstanding_alone = 0
        self.two_alone_at_once = False
        self.scheduler = types.SimpleNamespace(address="tcp://fake:8786")
        self.dashboard_link = None
        self.loop = object()  # the IO loop its futures report on (FakeAsCompleted checks it)

    def submit(self, *args, **kwargs):
        raise AssertionError("the sweep hands out batches with map")

    def scheduler_info(self):
        return {"n_workers": self.workers, "workers": {}}

    def run(self, probe, on_error):
        return self.found if self.found is not None else {"tcp://w1": probe(), "tcp://w2": probe()}

    def map(self, fn, *iterables, pure, retries):
        assert len(self.maps) < 500, "the sweep keeps resubmitting"
        parts = [list(p) for p in iterables[1]]
        if self.poison == "first":
            self.poison = parts[0][0]
        alone = len(parts) == 1 and len(parts[0]) == 1 and retries == 0
        if alone:
            self.two_alone_at_once |= self.outstanding_alone > 0
            self.outstanding_alone += 1
        self.maps.append((parts, retries))
        return [FakeFuture(self, fn, args, alone) for args in zip(*iterables, strict=True)]

    def cancel(self, futures):
        self.cancelled.append([list(f.args[1]) for f in futures])

    def close(self):
        self.closed = True


class FakeAsCompleted:
    """distributed.as_completed, first submitted first done."""

    def __init__(self, futures, loop=None):
        # The client's own loop: the sweep's client is not the default one, whose loop
        # as_completed takes when given none ("No clients found").
        futures = list(futures)
        assert futures and loop is futures[0].client.loop, "as_completed without the client's loop"
        self.queue = futures

    def update(self, futures):
        self.queue.extend(futures)

    def __iter__(self):
        while self.queue:
            yield self.queue.pop(0)


@pytest.fixture
def fake_dask(monkeypatch):
    monkeypatch.setattr(distributed, "as_completed", FakeAsCompleted)


def test_a_caller_s_client_gets_every_point_once_sized_for_its_workers(
    tmp_path, serial40, fake_dask
):
    client = FakeClient(workers=2)
    report = run_sweep(parse_spec(SPEC40), tmp_path / "a.h5", scheduler=client)
    same_atlas(tmp_path / "a.h5", serial40)
    assert report.computed == 40 and sorted(client.computed) == list(range(40))
    # All at once, one message: guided batches for 2 workers, each 1/4 of what is left but at
    # least 16 points (Batcher's rule, by hand): 16, 16, then the 8 left; retried on failure.
    [(parts, retries)] = client.maps
    assert [len(p) for p in parts] == [16, 16, 8] and retries == 3
    assert sorted(i for p in parts for i in p) == list(range(40))
    # The caller's client stays open, and a finished sweep has nothing left to cancel.
    assert not client.closed and client.cancelled == [[]]
    assert not (tmp_path / "a.h5.journal").exists()  # all in the atlas: the journal goes


def test_batches_out_of_time_are_dealt_again_and_every_point_computed_once(
    tmp_path, serial40, fake_dask, monkeypatch
):
    # Every batch runs out of time after its first point and hands back the rest.
    monkeypatch.setattr(batching, "BATCH_SECONDS", 1e-9)
    client = FakeClient(workers=2)
    report = run_sweep(parse_spec(SPEC40), tmp_path / "b.h5", scheduler=client)
    assert sorted(client.computed) == list(range(40))  # none lost, none twice
    assert report.computed == 40 and len(client.maps) > 3  # the rest was resubmitted
    same_atlas(tmp_path / "b.h5", serial40)


def test_a_point_that_kills_its_workers_is_stored_failed_after_running_alone(
    tmp_path, serial40, fake_dask
):
    client = FakeClient(workers=2, poison="first")
    out = tmp_path / "k.h5"
    report = run_sweep(parse_spec(SPEC40), out, scheduler=client)
    poison = client.poison
    # The killed batch's 16 points each went again alone, never retried, one at a time.
    alone = [parts for parts, retries in client.maps[1:]]
    assert sorted(i for parts in alone for p in parts for i in p) == sorted(client.maps[0][0][0])
    assert all(len(p) == 1 and len(p[0]) == 1 for p in alone)
    assert all(retries == 0 for _, retries in client.maps[1:])
    assert not client.two_alone_at_once
    assert sorted(client.computed) == sorted(set(range(40)) - {poison})
    assert report.computed == 40 and report.failed == 1
    with h5py.File(out, "r") as f, h5py.File(serial40, "r") as ref:
        status, ref_status = f["status"][...].ravel(), ref["status"][...].ravel()
        message = f["message"][...].ravel()[poison]
        bit = f["bit_mean"][...].reshape(40, -1)  # grid points first, in flat order
        ref_bit = ref["bit_mean"][...].reshape(40, -1)
    others = np.arange(40) != poison
    assert status[poison] != ref_status[poison]  # failed, where the serial run has it done
    np.testing.assert_array_equal(status[others], ref_status[others])
    np.testing.assert_array_equal(bit[others], ref_bit[others])
    assert b"killed every Dask worker" in message or "killed every Dask worker" in str(message)


def test_ctrl_c_cancels_what_the_sweep_asked_of_the_callers_client_and_leaves_it_open(
    tmp_path, fake_dask
):
    client = FakeClient(workers=2)

    def stop(n, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt) as info:
        run_sweep(parse_spec(SPEC40), tmp_path / "c.h5", scheduler=client, progress=stop)
    assert info.value.done == 16 and info.value.computed == 16
    [(parts, _)] = client.maps
    [cancelled] = client.cancelled  # the two batches not absorbed, and no other
    assert sorted(cancelled) == sorted(parts[1:])
    assert not client.closed
    with h5py.File(tmp_path / "c.h5", "r") as f:  # flushed on the way out
        assert np.count_nonzero(f["status"][...]) == 16


@pytest.mark.parametrize(
    ("reason", "status", "said"),
    [
        ("scheduler-connection-lost", "running", "lost the connection to the Dask scheduler"),
        ("other", "closed", "lost the connection to the Dask scheduler"),
        ("other", "running", "cancelled the sweep's tasks (other)"),
    ],
)
def test_cancelled_futures_say_whether_the_scheduler_was_lost(
    tmp_path, fake_dask, reason, status, said
):
    client = FakeClient(workers=2)
    client.cancelled_reason, client.status = reason, status
    with pytest.raises(SchedulerError, match="tcp://fake:8786") as info:
        run_sweep(parse_spec(SPEC40), tmp_path / "d.h5", scheduler=client)
    assert said in str(info.value)
    assert not (tmp_path / "d.h5").exists()  # nothing computed, nothing left


@pytest.mark.parametrize(
    ("found", "said"),
    [
        (
            {"tcp://w2": "x", "tcp://w1": ImportError("No module named 'pydrill'")},
            "1 of 2 Dask workers at tcp://fake:8786 cannot import pydrill (e.g. tcp://w1: "
            "ImportError",
        ),
        ({"tcp://w1": "0.0.1", "tcp://w2": pydrill.__version__}, "run pydrill 0.0.1, this"),
    ],
)
def test_workers_without_this_pydrill_are_refused_before_any_point(
    tmp_path, fake_dask, found, said
):
    client = FakeClient(workers=2, found=found)
    with pytest.raises(SchedulerError) as info:
        run_sweep(parse_spec(SPEC40), tmp_path / "e.h5", scheduler=client)
    assert said in str(info.value)
    assert client.maps == [] and not (tmp_path / "e.h5").exists()


def test_on_cluster_names_the_scheduler_workers_and_a_link_that_may_answer(tmp_path, fake_dask):
    from sweeping import unserved_port

    client = FakeClient(workers=3)
    seen = []
    with unserved_port() as port:
        # A link that does not answer is kept (only a scheduler's own 404 takes it away).
        client.dashboard_link = f"http://127.0.0.1:{port}/status"
        run_sweep(parse_spec(SPEC40), tmp_path / "f.h5", scheduler=client, on_cluster=seen.append)
    assert [(i.scheduler, i.workers, i.dashboard) for i in seen] == [
        ("tcp://fake:8786", 3, client.dashboard_link)
    ]
    # Its worker watch ended with the sweep.
    assert not [t for t in threading.enumerate() if t.name == "pydrill-worker-watch"]
