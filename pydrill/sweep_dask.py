"""Running a sweep's points on Dask: a LocalCluster of processes, or an existing scheduler.

The client only hands out batches and absorbs what comes back (``sweep.run_sweep`` does the
writing). The cluster is started in the calling thread, before any point is computed: Dask's
nanny forks the workers from this process, and a fork while another thread of it is busy
(computing, writing) can copy a held lock into the child and hang it — tried, and seen.
The workers inherit the client's signal handlers (``interrupt``): Ctrl-C stops the sweep
through the client alone.
"""

from __future__ import annotations

import contextlib
import logging
import threading
import warnings
from collections.abc import Callable
from typing import Any

import dask
import dask.system
import numpy as np

from .dask_connect import (
    ConfiguredAddress,
    connect,
    connect_timeout,
    kept_environ,
    scheduler_file,
    scheduler_file_address,
    served_dashboard,
    worker_count,
)
from .spec import SweepSpec

# One process per core: the Python around each simulation holds the GIL. Workers are forked
# rather than spawned: two start, pydrill imported, in a fifth of the time (measured 0.18 s
# against 0.86 s). On a machine with as many workers as cores, every cycle Dask's
# housekeeping takes is a cycle a simulation waits for: the workers' statistical profiler (a
# stack sample every 10 ms) is off, and the event-loop tick and memory monitor run 10x less
# often (measured: batches ran ~15 % slower in Dask workers than in a plain process pool with
# the defaults).
QUIET = {
    "distributed.worker.daemon": False,
    "distributed.worker.multiprocessing-method": "fork",
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "200ms",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
}


def run_dask(
    spec: SweepSpec,
    todo: np.ndarray,
    workers: int | None,
    scheduler: Any,
    absorb: Callable[[Any], None],
    dashboard: str | None = None,
    on_cluster: Callable[[Any], None] | None = None,
    starting: Callable[[], contextlib.AbstractContextManager[None]] = contextlib.nullcontext,
) -> None:
    """Compute ``todo`` as :func:`_run_dask` says; the workers a local cluster forks from this
    process get standard streams of their own (``fork_stdio``: a worker forked while another
    thread wrote to stderr hung at its first log line)."""
    from .fork_stdio import forking_workers

    local = not hasattr(scheduler, "submit") and not scheduler  # a cluster of this sweep's
    with forking_workers() if local else contextlib.nullcontext(), kept_environ(), quiet_client():
        _run_dask(spec, todo, workers, scheduler, absorb, dashboard, on_cluster, starting)


@contextlib.contextmanager
def quiet_client() -> Any:
    """Dask's client logs, while the sweep runs, only what is fatal: a scheduler lost midway
    printed a page of tracebacks from the client's attempts to reconnect before the sweep
    could say in one line what happened (``_run_dask``). Whatever fails reaches the sweep
    through its futures."""
    log = logging.getLogger("distributed.client")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)


def _run_dask(
    spec: SweepSpec,
    todo: np.ndarray,
    workers: int | None,
    scheduler: Any,
    absorb: Callable[[Any], None],
    dashboard: str | None = None,
    on_cluster: Callable[[Any], None] | None = None,
    starting: Callable[[], contextlib.AbstractContextManager[None]] = contextlib.nullcontext,
) -> None:
    """Compute the flat indices ``todo`` of ``spec``, handing each finished batch to ``absorb``.
    ``scheduler``: None (a LocalCluster of ``workers`` processes, for this sweep alone), an
    address, a scheduler file (``*.json``), or a ``distributed.Client`` of the caller's, which
    stays open. ``dashboard``: where the LocalCluster serves Dask's dashboard (None: nowhere).
    ``on_cluster`` gets a ``ClusterInfo`` once the batches are submitted. The local cluster
    starts inside ``starting()``: a Ctrl-C then waits for it to be up (a second), and the
    cluster is closed whole, not half started (Dask then printed tracebacks at exit)."""
    from distributed import KilledWorker, LocalCluster, as_completed
    from distributed.client import FutureCancelledError

    from . import __version__, batching
    from .sweep import ClusterInfo, SchedulerError, evaluate_batch
    from .sweep_guard import guarded_batch, refused

    with dask.config.set(QUIET):
        cluster = None
        own = not hasattr(scheduler, "submit")
        if not own:
            client = scheduler
        elif scheduler:
            # A scheduler file (dask scheduler --scheduler-file, dask-mpi, batch systems)
            # names the address and how to connect: HPC clusters share it, not an address.
            file = scheduler_file(scheduler)
            address = scheduler_file_address(file, connect_timeout()) if file else scheduler
            try:  # waits distributed.comm.timeouts.connect (30 s unless configured)
                client = connect(address)
            except (OSError, ValueError) as exc:
                if isinstance(scheduler, ConfiguredAddress):
                    raise SchedulerError(
                        f"{scheduler.source} is {scheduler}, but no Dask scheduler answered "
                        f"there ({exc}). Start it, unset it, or give --workers N (workers=N) to "
                        "run on a local cluster"
                    ) from None
                where = f"{scheduler} (address {address})" if file else scheduler
                if isinstance(exc, ValueError) and not file:  # e.g. "missing port number"
                    raise SchedulerError(
                        f"--scheduler {scheduler}: neither a scheduler's address "
                        "(tcp://HOST:PORT) nor a scheduler file that exists (FILE.json, from "
                        f"'dask scheduler --scheduler-file FILE.json'): {exc}"
                    ) from None
                raise SchedulerError(
                    f"--scheduler {where}: no Dask scheduler answered there ({exc}). "
                    "Start one ('dask scheduler', then 'dask worker ADDRESS' on each machine), "
                    "or leave --scheduler out to run on a local cluster"
                ) from None
        else:
            try:
                with starting(), warnings.catch_warnings():
                    # "Port 8787 is already in use ...": the link names the port taken instead.
                    warnings.filterwarnings("ignore", "Port .* is already in use", UserWarning)
                    cluster = LocalCluster(
                        # Cores this process may use: affinity and cgroup limits (a container's
                        # --cpus, a batch job's allocation) count, not the host's cores.
                        n_workers=workers or dask.system.CPU_COUNT,
                        threads_per_worker=1,
                        processes=True,
                        # The scheduler serves HTTP (health, metrics) even without a dashboard; on
                        # port 8787 by default, which warns when another cluster holds it. Unless
                        # asked for a dashboard: any free port, and none (bokeh's pages cost the
                        # scheduler, which shares the cores, CPU whenever a browser watches).
                        # A dashboard port that is taken: Dask takes a free one, in the link.
                        dashboard_address=dashboard or ":0",
                        scheduler_kwargs={"dashboard": dashboard is not None},
                        # A worker's heartbeat racing the shutdown logs an error; failures that
                        # matter reach the client through the futures.
                        silence_logs=logging.CRITICAL,
                    )
            except KeyboardInterrupt:  # held until the cluster was up: close it whole
                if cluster is not None:
                    cluster.close()
                raise
            except RuntimeError as exc:  # "Nanny failed to start", its reason in the chain
                root: BaseException = exc
                while root.__cause__ is not None:
                    root = root.__cause__
                raise SchedulerError(
                    f"the local Dask workers did not start ({type(root).__name__}: {root}); "
                    "run with --serial, or start a cluster and give --scheduler"
                ) from exc
            try:  # a Ctrl-C while it connects: the cluster's workers were left running
                client = connect(cluster)
            except BaseException:
                cluster.close()
                raise
        pending: set[Any] = set()  # submitted, not absorbed yet
        watch = running = fut = None
        try:
            n = worker_count(client)
            if cluster is None and n:  # workers this process did not fork: can they run it?
                check_workers(client)
            deal = batching.Batcher(todo)
            batch_of: dict[Any, list[int]] = {}  # each future's points
            # Workers of others' clusters are checked again by each batch: one may join after
            # check_workers (a batch job's workers queued, an adaptive cluster scaling).
            task = evaluate_batch if cluster is not None else guarded_batch(__version__)

            def submit(workers: int, parts: list[list[int]] | None = None) -> list[Any]:
                # One message to the scheduler for many batches, not one each (measured: a
                # quarter less of the client's CPU, which the workers would have had).
                alone = parts is not None  # points of a batch that killed its workers
                parts = deal.rest(max(workers, 1)) if parts is None else parts
                futures = client.map(
                    task,
                    [spec.text] * len(parts),
                    parts,
                    [spec.tally_text] * len(parts),
                    [batching.BATCH_SECONDS] * len(parts),
                    pure=False,
                    # A point alone is not retried: each retry would kill a worker again.
                    retries=0 if alone else 3,
                )
                pending.update(futures)
                batch_of.update((f, part) for f, part in zip(futures, parts, strict=True))
                return futures

            running = as_completed(submit(n), loop=client.loop)  # not a default client's
            if on_cluster is not None:
                # Without a dashboard, the local scheduler's HTTP server still makes a link;
                # so does another's, started with --no-dashboard (served_dashboard).
                link = dashboard and client.dashboard_link
                if cluster is None:
                    link = served_dashboard(client.dashboard_link)
                info = ClusterInfo(client.scheduler.address, n, link or None)
                on_cluster(info)
                if cluster is None:  # a cluster of others: its workers come and go
                    watch = WorkerWatch(client, info, on_cluster)
            # Points of batches whose workers kept dying, to run alone, one at a time: a task
            # waiting on a worker that dies counts as suspect too, so two suspects at once
            # could condemn an innocent point beside the guilty one.
            suspects: list[int] = []
            suspect: list[Any] = []  # the one in flight

            def next_suspect() -> None:
                assert running is not None  # set before the loop that calls this
                if suspects and not suspect:
                    suspect.extend(submit(0, [[suspects.pop(0)]]))
                    running.update(suspect)

            for fut in running:
                points = batch_of.pop(fut)
                if fut in suspect:
                    suspect.clear()
                try:
                    done = fut.result()
                    if isinstance(done, dict):  # a worker that may not run it (guarded_batch)
                        raise refused(done, client.scheduler.address)
                except KilledWorker as exc:
                    # Workers died running it, again and again (the scheduler gives up after
                    # distributed.scheduler.allowed-failures): a point that crashes the
                    # process or takes all its memory, or workers killed from outside. Each
                    # point goes again alone; one that still kills its worker is stored as
                    # failed, and the sweep goes on.
                    pending.discard(fut)
                    if len(points) > 1:
                        suspects.extend(points)
                    else:
                        absorb(killed_point(spec, points[0], exc))
                    next_suspect()
                    continue
                # Let go of it, or its result would stay in the workers' memory to the end
                # of the sweep: a gigabyte for a million points.
                pending.discard(fut)
                deal.timed(len(done.indices), done.seconds)
                if done.left:  # out of time: deal the rest again, sized by what points take
                    deal.give_back(done.left)
                    running.update(submit(worker_count(client)))
                absorb(done)
                next_suspect()
        except FutureCancelledError as exc:
            # The scheduler went away (killed, its machine down, the network cut) or another
            # client cancelled the tasks: what was absorbed is saved (run_sweep says how much).
            where = scheduler if cluster is None and not hasattr(scheduler, "submit") else None
            where = where or getattr(client.scheduler, "address", None) or "?"
            if exc.reason == "scheduler-connection-lost" or client.status != "running":
                lost = SchedulerError(f"lost the connection to the Dask scheduler at {where}")
            else:
                lost = SchedulerError(
                    f"the Dask cluster at {where} cancelled the sweep's tasks ({exc.reason})"
                )
            lost.then = (
                "Start the scheduler and its workers again (or sweep without scheduler=... to "
                "run here)"
            )
            raise lost from None
        finally:
            if watch is not None:
                watch.stop()
            if own:
                client.close()
            else:  # the caller's client: take back only what this sweep asked of it
                client.cancel(list(pending))
                # An exception's traceback keeps this frame alive, and with it any future
                # it names, and their results on the workers.
                pending.clear()
                fut = running = None
            if cluster is not None:
                cluster.close()


def killed_point(spec: SweepSpec, index: int, exc: BaseException) -> Any:
    """The batch of one point stored as failed: it killed every worker that ran it."""
    from .sweep_points import Batch, encode_batch

    rec = {
        "i": int(index),
        "status": "failed",
        "runs": {},
        "message": (
            "it killed every Dask worker that ran it (a crash, or out of memory); the "
            f"scheduler gave up: {exc}"
        ),
    }
    return Batch(*encode_batch(spec, [rec]), 0.0, [])


#: how often (s) a sweep on an existing cluster looks at how many workers it has
WATCH_SECONDS = 5.0


class WorkerWatch(threading.Thread):
    """Tells ``on_cluster`` whenever the number of workers of an existing cluster changes: an
    adaptive cluster scaling, a batch job's workers reaching their time limit. At 0 the sweep
    waits for workers to join, and without a word it would look hung. Not for the sweep's
    own local cluster, whose nanny replaces a lost worker (and forks it from this process:
    no thread should be busy then)."""

    def __init__(self, client: Any, info: Any, on_cluster: Callable[[Any], None]) -> None:
        super().__init__(name="pydrill-worker-watch", daemon=True)
        self.client, self.info, self.on_cluster = client, info, on_cluster
        self.done = threading.Event()
        self.start()

    def run(self) -> None:
        import dataclasses

        last = self.info.workers
        while not self.done.wait(WATCH_SECONDS):
            try:
                n = worker_count(self.client)
            except Exception:  # the client is closing: the sweep is over
                return
            if n != last and not self.done.is_set():
                last = n
                self.on_cluster(dataclasses.replace(self.info, workers=n))

    def stop(self) -> None:
        self.done.set()
        self.join(timeout=10)


def check_workers(client: Any) -> None:
    """Refuse, before any point is handed out, an existing cluster whose workers cannot run
    this sweep: without pydrill, a worker dies unpickling its first task, and the sweep would
    wait for ever for workers that are gone; with another version, one atlas would mix the
    results of two. Raises ``SchedulerError`` naming the workers and the fix."""
    from . import __version__
    from .sweep import SchedulerError

    def probe() -> str:  # nested, so pickled by value: it unpickles where pydrill is missing
        import pydrill

        return pydrill.__version__

    found = client.run(probe, on_error="return")
    where = client.scheduler.address
    # A worker that left between the count and the probe (a batch job's time limit) answers
    # with the scheduler's failure to reach it, an OSError (CommClosedError, a connect
    # timeout): it runs nothing of the sweep, and was reported as unable to import pydrill.
    # One that comes back is checked by each batch it runs (guarded_batch).
    found = {w: v for w, v in found.items() if not isinstance(v, OSError)}
    broken = {w: v for w, v in found.items() if isinstance(v, BaseException)}
    if broken:
        worker, exc = sorted(broken.items())[0]
        raise SchedulerError(
            f"{len(broken)} of {len(found)} Dask workers at {where} cannot import pydrill "
            f"(e.g. {worker}: {type(exc).__name__}: {exc}). Install pydrill {__version__} "
            "where they run, in the environment their 'dask worker' starts from"
        )
    other = sorted({str(v) for v in found.values()} - {__version__})
    if other:
        raise SchedulerError(
            f"the Dask workers at {where} run pydrill {', '.join(other)}, this client "
            f"{__version__}: one atlas must come from one version. Install pydrill "
            f"{__version__} where they run"
        )
