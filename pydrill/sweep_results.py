"""What a sweep reports: its result (:class:`SweepReport`), where it runs
(:class:`ClusterInfo`), and its two ways of ending early (:class:`SweepInterrupted`,
:class:`SchedulerError`). Offered as ``pydrill.sweep.*``."""

from __future__ import annotations

import signal
from dataclasses import dataclass
from pathlib import Path
from typing import Any


class SchedulerError(ConnectionError):
    """No Dask cluster to run on: the scheduler given (``--scheduler``) did not answer, or the
    local workers did not start. Nothing is written (an atlas and journal that this sweep
    created are removed). Or the scheduler was lost midway: the points computed until then
    are saved (journal and atlas), and the message says how many; ``resume=True`` computes
    the rest."""

    #: raised midway: what to do before running the sweep again (else "")
    then: str = ""


@dataclass(frozen=True)
class ClusterInfo:
    """Where a Dask sweep runs, handed to ``run_sweep``'s ``on_cluster`` once its points are
    submitted: what to open to watch them (``dashboard``) or to reach the cluster again."""

    scheduler: str  #: the scheduler's address, e.g. ``tcp://127.0.0.1:40321``
    workers: int  #: workers connected when the points were handed out (0: they wait for some)
    dashboard: str | None  #: link to Dask's dashboard (task stream, workers' CPU), if it has one


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C (or another of ``run_sweep``'s ``stop_on`` signals, number ``signum``) during a
    sweep. Everything finished is saved: in the journal, and flushed into the atlas on the way
    out. A KeyboardInterrupt, so code that stops on Ctrl-C still does."""

    def __init__(
        self,
        atlas: Path,
        points: int,
        done: int,
        signum: int = signal.SIGINT,
        *,
        computed: int = 0,
        failed: int = 0,
        resumed: int = 0,
        wall_time: float = 0.0,
        write_time: float = 0.0,
        failed_in_atlas: int = 0,
        first_failure: str = "",
        written: bool = True,
    ):
        self.atlas, self.points, self.done, self.signum = atlas, points, done, signum
        #: False when stopped before any point was saved: the new atlas was removed
        # as in SweepReport: what this run computed (failed of them), found done, and took
        self.computed, self.failed, self.resumed = computed, failed, resumed
        self.wall_time, self.write_time = wall_time, write_time
        self.failed_in_atlas, self.first_failure = failed_in_atlas, first_failure
        self.written = written
        super().__init__(
            f"sweep interrupted: {done} of {points} points are saved in {atlas}; resuming "
            f"(resume=True) computes the other {points - done}"
            if written
            # (it said "0 of N points are saved in ATLAS", an atlas that is not there)
            else f"sweep interrupted before any point was computed: nothing was written "
            f"({atlas} is not made); run it again to start"
        )

    def __reduce__(self) -> tuple[Any, ...]:
        # An exception pickles as type(self)(*self.args), here the message alone, which this
        # __init__ does not take: unpickling (a sweep run in a worker process, copy.copy) failed
        # with a TypeError. Rebuilt with its message as it is (written=False says another)
        # and its fields as its state.
        return (_restore, (type(self), self.args, self.__dict__))


def _restore(cls: type[BaseException], args: tuple[Any, ...], state: dict[str, Any]) -> Any:
    """An exception as pickled by ``SweepInterrupted.__reduce__``, its __init__ not run."""
    exc = cls.__new__(cls, *args)
    exc.args = args
    exc.__dict__.update(state)
    return exc


@dataclass
class SweepReport:
    """What :func:`run_sweep` did: the atlas, its size, the points computed in this run (and
    how many of them failed), those found already done (``resumed``), and the wall time with
    the part of it spent writing (journal and HDF5), in seconds."""

    atlas: Path  #: the atlas written
    points: int  #: points in the grid
    computed: int  #: computed in this run
    failed: int  #: of those, stored as failed (with their messages)
    resumed: int  #: found already done (``resume``)
    wall_time: float  #: s, the whole run
    write_time: float  #: s, of it spent writing the journal and the atlas
    #: points of the atlas stored as failed, this run's and those found done before
    failed_in_atlas: int = 0
    #: the message of the first failed point of the atlas (in grid order), or ""
    first_failure: str = ""

    @property
    def all_failed(self) -> bool:
        """True when the atlas holds failures only: every point failed (``pydrill sweep``
        exits with status 3 then, as for a solver failure)."""
        return self.points > 0 and self.failed_in_atlas == self.points
