"""Parameter sweeps into HDF5 atlases, serially or on a Dask cluster.

Only the client writes. Every finished batch is first appended to a journal next to the atlas
(``ATLAS.h5.journal``, one JSON line per point, synced to disk every second), then folded
into the atlas every few seconds and at the end. A sweep killed at any moment (Ctrl-C,
kill -9, a lost worker machine) therefore loses nothing that finished: ``--resume`` replays
the journal — rebuilding the atlas from it if the kill caught the HDF5 file mid-write — and
computes only the rest.
"""

from __future__ import annotations

import contextlib
import json
import numbers
import os
import signal
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from . import atlas_format as fmt
from . import batching
from .batching import Batcher, batches, dealing_order  # noqa: F401 (re-exported)
from .file_kinds import atlas_name_problem
from .interrupt import stop_between_batches
from .journal import AtlasError, _reason, journal_path, prepare, rewrite_path, write_atlas
from .spec import SweepSpec, _require_spec
from .sweep_points import (  # noqa: F401 (re-exported: pydrill.sweep.evaluate_point and kin)
    Batch,
    encode_batch,
    evaluate_batch,
    evaluate_point,
)
from .sweep_results import (  # re-exported too: pydrill.sweep.SweepReport and kin
    ClusterInfo,
    SchedulerError,
    SweepInterrupted,
    SweepReport,
)

#: Most local workers ``run_sweep`` starts (as ``pydrill sweep --workers``).
MAX_WORKERS = 256

# The atlas is rewritten from the table every FLUSH_SECONDS at the soonest, and no sooner than
# FLUSH_SPACING times the last rewrite took: a rewrite costs in proportion to the atlas (0.2 s
# for 20000 points, measured), so a fixed period would make big sweeps spend their time
# flushing. Flushes stay under 1/FLUSH_SPACING of the sweep at any size; the journal, written
# every batch, is what makes an interruption lose nothing.
FLUSH_SECONDS = 5.0
FLUSH_SPACING = 50.0
#: the journal is synced to disk at most this often (s): what a crash of the machine can lose
SYNC_SECONDS = 1.0


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    resume: bool = False,
    progress: Callable[[int, int], None] | None = None,
    serial: bool = False,
    stop_on: tuple[int, ...] = (signal.SIGINT,),
    dashboard: str | None = None,
    on_cluster: Callable[[ClusterInfo], None] | None = None,
) -> SweepReport:
    """Compute every missing point of ``spec`` into the atlas ``out``: on a LocalCluster of
    ``workers`` processes (default: one per core it may use: affinity and cgroup limits
    count), started for this sweep; on an existing Dask cluster, given as ``scheduler`` (its
    address, its scheduler file (``*.json``, or any file that exists), or a
    ``distributed.Client``, left open); or ``serial``-ly in this process. Given none of
    these, it runs where Dask's own work would: on the caller's default
    ``distributed.Client`` (left open), else on the cluster named in the Dask config's
    ``scheduler-address`` (e.g. ``DASK_SCHEDULER_ADDRESS``), else locally.

    Any of the signals ``stop_on`` (``pydrill sweep`` adds SIGTERM) stops the sweep between
    batches with everything finished saved, raising ``SweepInterrupted``. Raises
    ``AtlasError`` for an atlas it may not write (another sweep's, one being written, one
    that exists without ``resume``), and ``SchedulerError`` when there is no cluster to run
    on.

    ``dashboard`` (``"HOST:PORT"``, e.g. ``"127.0.0.1:8787"``; port 0 for any free one) serves
    Dask's dashboard from the local cluster while the sweep runs; it needs bokeh >= 3.1. An
    existing cluster serves its own. ``on_cluster`` is called with a :class:`ClusterInfo`
    (scheduler, workers, dashboard link) once a Dask sweep's points are submitted, and on an
    existing cluster again whenever its number of workers changes (from another thread).

    ``spec`` is a :class:`SweepSpec` (``pydrill.load_spec(path)``), ``workers`` None or an
    integer 1 ... ``MAX_WORKERS`` (256); both are checked before anything is written."""
    from . import __version__

    _require_spec(spec)
    if workers is not None:
        allowed = f"None (one per core) or an integer 1 ... {MAX_WORKERS}"
        if isinstance(workers, bool) or not isinstance(workers, numbers.Integral):
            raise TypeError(f"workers = {workers!r} is not allowed: {allowed}")
        if not 1 <= workers <= MAX_WORKERS:
            raise ValueError(f"workers = {workers!r} is not allowed: {allowed}")
        workers = int(workers)
    for name, call in (("progress", progress), ("on_cluster", on_cluster)):
        if call is not None and not callable(call):
            raise TypeError(f"{name} = {call!r} is not allowed: None or a function")
    stop_on = _signals(stop_on)
    if isinstance(scheduler, str) and not scheduler.strip():  # not None: an unset variable?
        raise ValueError(
            f"scheduler = {scheduler!r} is not allowed: a scheduler's address "
            "(tcp://HOST:PORT), its scheduler file, a distributed.Client, or None"
        )
    if (workers is not None) + bool(scheduler) + bool(serial) > 1:
        raise ValueError("give at most one of workers (a local cluster), scheduler, serial")
    implicit = None  # where the sweep goes when told nowhere, as Dask's own work would
    if scheduler is None and workers is None and not serial:
        from .dask_connect import configured_scheduler, default_dask_client

        client = default_dask_client()
        if client is not None:
            scheduler, implicit = client, "your default Dask client"
        else:
            scheduler = configured_scheduler()
            implicit = scheduler.source if scheduler else None
    if dashboard is not None:
        elsewhere = (
            "serial runs use no Dask"
            if serial
            else f"this one runs on the cluster of {implicit}, which serves its own "
            "(--workers N, or workers=N, runs on a local cluster instead)"
            if implicit
            else "an existing cluster serves its own"
            if scheduler
            else None
        )
        if elsewhere:
            raise ValueError(
                f"dashboard: only a local cluster's dashboard is started by the sweep; {elsewhere}"
            )
        from .dask_connect import check_dashboard

        check_dashboard(dashboard)
    from .sweep_plan import check_memory

    check_memory(spec)
    out = Path(out)
    if not (out.exists() or journal_path(out).exists()):
        problem = atlas_name_problem(out)
        if problem:  # before the folder is made: nothing is written
            raise AtlasError(problem)
    t0 = time.perf_counter()
    params_json = model_json(spec)
    # The atlas's directory is made as for every other output of pydrill, and removed again
    # if the sweep is refused before anything is written into it.
    made = [d for d in (out.parent, *out.parent.parents) if not d.exists()]
    out.parent.mkdir(parents=True, exist_ok=True)
    from .atlas_lock import writer_lock

    try:
        with writer_lock(out):
            return _sweep_locked(
                spec,
                out,
                resume,
                params_json,
                __version__,
                t0,
                workers=workers,
                scheduler=scheduler,
                progress=progress,
                serial=serial,
                stop_on=stop_on,
                dashboard=dashboard,
                on_cluster=on_cluster,
            )
    except BaseException:
        if not (out.exists() or journal_path(out).exists()):
            for d in made:  # deepest first; only empty ones go
                with contextlib.suppress(OSError):
                    d.rmdir()
        raise


def model_json(spec: SweepSpec) -> str:
    """The atlas's ``params`` attribute: the model as the spec gives it, and the string of its
    first point in full."""
    base = spec.params_at(spec.coords(0))
    return json.dumps(
        {
            "preset": spec.preset,
            "dof": spec.dof,
            "overrides": {
                k: (list(v) if isinstance(v, list | tuple) else v)
                for k, v in spec.overrides.items()
            },
            "base": base.to_dict(),
        }
    )


def _signals(stop_on: Any) -> tuple[int, ...]:
    """``stop_on`` checked before anything is written: signals this system has, not SIGKILL or
    SIGSTOP (they cannot be caught)."""
    allowed = "a tuple of signals, e.g. (signal.SIGINT, signal.SIGTERM)"
    try:
        found = tuple(stop_on)
    except TypeError:
        raise TypeError(f"stop_on = {stop_on!r} is not allowed: {allowed}") from None
    valid = set(signal.valid_signals()) - {signal.SIGKILL, signal.SIGSTOP}
    for s in found:
        if isinstance(s, bool) or not isinstance(s, int) or s not in valid:
            raise ValueError(
                f"stop_on = {stop_on!r} is not allowed: {s!r} is not a signal that can be "
                f"caught here; {allowed}"
            )
    return tuple(signal.Signals(s) for s in found)


def _sweep_locked(
    spec: SweepSpec,
    out: Path,
    resume: bool,
    params_json: str,
    version: str,
    t0: float,
    *,
    workers: int | None,
    scheduler: Any,
    progress: Callable[[int, int], None] | None,
    serial: bool,
    stop_on: tuple[int, ...],
    dashboard: str | None,
    on_cluster: Callable[[ClusterInfo], None] | None,
) -> SweepReport:
    """``run_sweep`` once the atlas is this process's alone (``atlas_lock``)."""
    jp = journal_path(out)
    fresh = not (out.exists() or jp.exists())
    table, resumed = prepare(spec, out, resume=resume, params_json=params_json, version=version)
    todo = table.missing()
    write_time = 0.0
    computed = failed = 0
    last_flush = last_sync = time.perf_counter()
    flush_every = FLUSH_SECONDS

    def absorb(batch: Batch) -> None:
        nonlocal computed, failed, write_time, last_flush, flush_every, last_sync
        indices, block, lines = batch.indices, batch.block, batch.lines
        tw = time.perf_counter()
        with stop.hold():  # the journal, the table and the counts take a batch, or none
            try:
                with jp.open("a") as fh:
                    # Written and closed, a batch survives the end of this process (kill -9:
                    # the kernel holds it); on disk, a crash of the machine too. Synced at
                    # most once a second: a sync per batch cost 1.5 ms each (8 % of a
                    # 100000-point sweep's writing), and a crash loses a second at most.
                    fh.write(lines)
                    fh.flush()
                    if tw - last_sync >= SYNC_SECONDS:
                        os.fsync(fh.fileno())
                        last_sync = tw
            except OSError as exc:  # a full disk: say where, and that what is saved stays
                raise AtlasError(
                    f"{jp}: cannot write the journal ({_reason(exc)}); the {computed} points "
                    f"computed before are kept in it: make room, then run again with "
                    "resume=True"
                ) from None
            table.put(indices, block)
            computed += len(indices)
            failed += int(np.count_nonzero(block["status"] == fmt.STATUS["failed"]))
        if time.perf_counter() - last_flush > flush_every:
            tf = time.perf_counter()
            write_atlas(out, table)
            last_flush = time.perf_counter()
            flush_every = max(FLUSH_SECONDS, FLUSH_SPACING * (last_flush - tf))
        write_time += time.perf_counter() - tw
        if progress:
            progress(len(indices), len(todo))

    with stop_between_batches(stop_on) as stop:
        try:
            if len(todo) and serial:
                deal = Batcher(todo)
                while deal.left:
                    batch = deal.take(1)
                    done = evaluate_batch(spec.text, batch, spec.tally_text, batching.BATCH_SECONDS)
                    deal.timed(len(done.indices), done.seconds)
                    deal.give_back(done.left)
                    absorb(done)
            elif len(todo):
                from .sweep_dask import run_dask

                run_dask(spec, todo, workers, scheduler, absorb, dashboard, on_cluster, stop.hold)
        except KeyboardInterrupt:
            # Stopped before any point was saved (journal and table agree: see absorb):
            # leave nothing behind.
            if fresh and computed == 0 and np.all(table.status == fmt.STATUS["missing"]):
                out.unlink(missing_ok=True)
                jp.unlink(missing_ok=True)
                raise SweepInterrupted(
                    out,
                    spec.size,
                    0,
                    stop.signum or signal.SIGINT,
                    wall_time=time.perf_counter() - t0,
                    written=False,
                ) from None
            # What was absorbed is in the journal already; the flush lets the atlas show it
            # before --resume. A second Ctrl-C waits for the flush (the journal would
            # rebuild a damaged atlas, but there is no need).
            tw = time.perf_counter()
            with contextlib.suppress(KeyboardInterrupt), stop.hold():
                write_atlas(out, table)
            write_time += time.perf_counter() - tw
            saved = int(np.count_nonzero(table.status != fmt.STATUS["missing"]))
            n_failed, first = _failures(table)
            raise SweepInterrupted(
                out,
                spec.size,
                saved,
                stop.signum or signal.SIGINT,
                computed=computed,
                failed=failed,
                resumed=resumed,
                wall_time=time.perf_counter() - t0,
                write_time=write_time,
                failed_in_atlas=n_failed,
                first_failure=first,
            ) from None
        except SchedulerError as exc:
            if not computed and fresh:  # e.g. no scheduler at that address: leave no trace
                out.unlink(missing_ok=True)
                jp.unlink(missing_ok=True)
                if exc.then:  # lost before its first batch came back: say what to do
                    raise SchedulerError(
                        f"{exc}: the sweep stopped before any point was saved (nothing is "
                        f"written). {exc.then}, then run the sweep again"
                    ) from None
                raise
            if not computed and not exc.then:
                raise
            # Lost midway: what was absorbed is in the journal; the flush lets the atlas show
            # it, as after Ctrl-C, and --resume computes the rest once a cluster runs again.
            with stop.hold():
                write_atlas(out, table)
            saved = int(np.count_nonzero(table.status != fmt.STATUS["missing"]))
            then = exc.then or (
                "Start the scheduler and its workers again (or sweep without scheduler=... to "
                "run here)"
            )
            raise SchedulerError(
                f"{exc}: the sweep stopped with {saved} of {spec.size} points saved in {out}. "
                f"{then}, then run the sweep again with resume=True"
            ) from None
        except Exception:
            if fresh and computed == 0:  # e.g. no scheduler at that address: leave no trace
                out.unlink(missing_ok=True)
                jp.unlink(missing_ok=True)
            raise
    tw = time.perf_counter()
    if computed or fresh:  # else the atlas is as prepare left it (a read-only one is fine)
        write_atlas(out, table)
    left = int(np.count_nonzero(table.status == fmt.STATUS["missing"]))
    if left:
        # Every point handed out comes back (done or failed) or raises; this guards the
        # bookkeeping itself. The journal stays, so --resume completes the atlas.
        raise AtlasError(f"{left} points of {out} were not computed; run again with resume=True")
    jp.unlink(missing_ok=True)  # everything is in the atlas now
    # (and a journal rewritten in this layout, left half written by a kill: journal.prepare)
    rewrite_path(jp).unlink(missing_ok=True)
    write_time += time.perf_counter() - tw
    n_failed, first = _failures(table)
    return SweepReport(
        out,
        spec.size,
        computed,
        failed,
        resumed,
        time.perf_counter() - t0,
        write_time,
        failed_in_atlas=n_failed,
        first_failure=first,
    )


def _failures(table: fmt.AtlasTable) -> tuple[int, str]:
    """Points of the atlas stored as failed, and the first one's message (grid order): over the
    whole atlas, as a resumed sweep's failures may all be from before, and a sweep whose every
    point failed must not look like a finished study."""
    failed_at = np.flatnonzero(table.status.ravel() == fmt.STATUS["failed"])
    return len(failed_at), str(table.message.ravel()[failed_at[0]]) if len(failed_at) else ""
