"""What a sweep would do, before it does it: ``pydrill sweep SPEC.toml --dry-run``.

A sweep of a million points on a laptop, or a cluster job that must ask for its hours up
front, wants to know its cost first. The plan checks the spec and the atlas as the sweep
would (the same refusals), and times a sample of the points it would compute, drawn in the
sweep's own pseudo-random order so that the sample spreads over the whole grid: slow
stick-slip corners and cheap stuck ones alike. It writes nothing: not the atlas, not its
journal (a journal's cut last line is left for the sweep to cut)."""

from __future__ import annotations

import math
import numbers
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import atlas_format as fmt
from .file_kinds import atlas_name_problem
from .journal import AtlasError, iter_journal, journal_path, read_existing
from .journal_lines import line as journal_line
from .spec import SweepSpec, _require_spec

#: two-sided 95 % normal quantile, for the range of the estimate
Z95 = 1.96


@dataclass(frozen=True)
class SweepPlan:
    """What :func:`plan_sweep` found: the grid, the points a run would compute (``todo``; the
    others are in the atlas or its journal already), and the time of the ``sampled`` points
    on one core, in seconds per point, with the 95 % range of the mean over the points to
    compute. ``failed``: sampled points whose solver failed, with the first ``message``."""

    points: int  #: points in the grid
    todo: int  #: points a run would compute
    atlas: str  #: "none" (no atlas given), "new", "resume" or "complete"
    sampled: int  #: points timed
    failed: int  #: of those, failed (a run would store them as failed)
    message: str  #: the first failure's message, or ""
    point_seconds: float  #: mean time per point on one core, with encoding its results, s
    point_seconds_low: float  #: low end of that mean's 95 % range, s
    point_seconds_high: float  #: high end of that mean's 95 % range, s
    atlas_bytes: int  #: the atlas's data, uncompressed (compression makes it smaller)
    journal_bytes: int  #: the journal at its largest (one JSON line per point; removed at the end)
    memory_bytes: int = 0  #: memory of the sweep's own process: the whole atlas, and more to write

    @property
    def compute_seconds(self) -> tuple[float, float, float]:
        """(low, estimate, high) core-seconds to compute the ``todo`` points."""
        return (
            self.todo * self.point_seconds_low,
            self.todo * self.point_seconds,
            self.todo * self.point_seconds_high,
        )

    def wall_seconds(self, workers: int) -> tuple[float, float, float]:
        """(low, estimate, high) wall time on ``workers`` cores at best: the computing
        divided among them, without the cluster's start. ``workers``: an integer >= 1."""
        if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
            raise _refused("workers", workers, "an integer >= 1")
        low, estimate, high = (s / int(workers) for s in self.compute_seconds)
        return low, estimate, high


def _refused(name: str, value: object, allowed: str) -> Exception:
    """The error for a refused ``value``: TypeError when it is not even the right type (not a
    number, a bool, a float where an integer is asked), else ValueError."""
    kind = numbers.Integral if "integer" in allowed else numbers.Real
    wrong_type = isinstance(value, bool) or not isinstance(value, kind)
    error = TypeError if wrong_type else ValueError
    return error(f"{name} = {value!r} is not allowed: {allowed}")


def _todo(spec: SweepSpec, out: Path | None, resume: bool) -> tuple[np.ndarray, str]:
    """The points a sweep into ``out`` would compute, refusing as ``journal.prepare`` would,
    but reading only."""
    everything = np.arange(spec.size)
    if out is None:
        return everything, "none"
    jp = journal_path(out)
    if not (out.exists() or jp.exists()):
        problem = atlas_name_problem(out)
        if problem:
            raise AtlasError(problem)
        return everything, "new"
    from .atlas_lock import AtlasBusy, writer

    holder = writer(out)
    if holder is not None:
        raise AtlasBusy.of(out, holder)
    done = np.zeros(spec.size, dtype=bool)
    table = read_existing(spec, out, resume=resume)
    if table is not None:
        done |= table.status.ravel() != fmt.STATUS["missing"]
    for rec in iter_journal(out, spec, repair=False):  # one at a time: it may be gigabytes
        done[rec["i"]] = True
    todo = np.flatnonzero(~done)
    return todo, "resume" if len(todo) else "complete"


def plan_sweep(
    spec: SweepSpec,
    out: str | Path | None = None,
    *,
    resume: bool = False,
    budget: float = 2.0,
    most: int = 256,
    least: int = 3,
) -> SweepPlan:
    """Check ``spec`` against the atlas ``out`` (refusing, with ``AtlasError``, what
    ``run_sweep`` would refuse) and time the points a run would compute, in the sweep's
    order: at least ``least`` (or all there are), then more until ``budget`` seconds have
    gone or ``most`` are timed. Computes in this process; writes nothing.

    ``spec``: a :class:`SweepSpec` (``pydrill.load_spec(path)``); ``budget``: seconds,
    finite and > 0; ``most``: an integer >= 1; ``least``: an integer >= 0. The 95 % range
    needs two points timed: with one of several, it is 0 ... inf (the command line times at
    least three)."""
    from .sweep import dealing_order, evaluate_point
    from .sweep_points import encode_batch

    _require_spec(spec)
    if (
        isinstance(budget, bool)
        or not isinstance(budget, numbers.Real)
        or not (math.isfinite(budget) and budget > 0)
    ):
        raise _refused("budget", budget, "a finite number of seconds > 0")
    for name, value, low in (("most", most, 1), ("least", least, 0)):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
            raise _refused(name, value, f"an integer >= {low}")

    todo, state = _todo(spec, None if out is None else Path(out), resume)
    order = dealing_order(todo)
    times: list[float] = []
    records: list[dict] = []
    line_bytes = 0  # of the sampled points' journal lines
    failed, message = 0, ""
    if len(order):
        evaluate_point(spec, int(order[0]))  # untimed: the first call loads what it needs
    start = time.perf_counter()
    for i in order[:most]:
        t0 = time.perf_counter()
        rec = evaluate_point(spec, int(i))
        times.append(time.perf_counter() - t0)
        records.append(rec)
        line_bytes += len(journal_line(rec))
        if rec["status"] == "failed":
            failed += 1
            message = message or rec["message"]
        if len(times) >= least and time.perf_counter() - start > budget:
            break
    # A worker also encodes what it computed (the atlas's columns, the journal's lines) before
    # it hands a batch back: some 80 us a point, a twentieth of a dof-4 point's 1.2-1.7 ms,
    # which the estimate left out. Timed on the sample's records together, as a batch does it.
    if records:
        t0 = time.perf_counter()
        encode_batch(spec, records)
        encoding = (time.perf_counter() - t0) / len(records)
        times = [t + encoding for t in times]
    k, n = len(times), len(todo)
    mean = float(np.mean(times)) if k else 0.0
    half = 0.0
    if 1 < k < n:  # the sample's spread; none when every point to compute was timed
        finite = math.sqrt((n - k) / (n - 1))  # sampling without replacement
        half = Z95 * float(np.std(times, ddof=1)) / math.sqrt(k) * finite
    elif k == 1 < n:  # one point says nothing of the spread: no range, not a sure one
        half = math.inf
    row = fmt.AtlasTable(spec, points=1).columns()
    return SweepPlan(
        points=spec.size,
        todo=n,
        atlas=state,
        sampled=k,
        failed=failed,
        message=message,
        point_seconds=mean,
        point_seconds_low=max(mean - half, 0.0),
        point_seconds_high=mean + half,
        atlas_bytes=spec.size * sum(a.nbytes for a in row.values() if a.dtype.kind != "O"),
        journal_bytes=round(spec.size * line_bytes / k) if k else 0,
        memory_bytes=memory_bytes(spec),
    )


#: the table's size, times this, is what the sweep's process holds at its peak (measured: 3.8 GB
#: for a 10^7-point sweep whose table is 2.9 GB; writing the atlas copies a column at a time).
#: At 10^6 points (a 394 MB table): 1.25x for a new sweep, 1.28x resuming an atlas; a journal's
#: replay holds some 50 MB of records more, whatever its length (atlas_table.REPLAY_CHUNK).
MEMORY_FACTOR = 1.3


def memory_bytes(spec: SweepSpec) -> int:
    """Memory the sweep's own process (the client) needs: it holds the whole atlas as a table
    (every column, and a reference per point for the failure messages), and more while it
    writes the file. The workers need little: a batch at a time."""
    row = fmt.AtlasTable(spec, points=1).columns()
    return round(MEMORY_FACTOR * spec.size * sum(a.nbytes for a in row.values()))


def check_memory(spec: SweepSpec) -> None:
    """Refuse, before anything is allocated or written, a sweep whose table would not fit in
    the memory available now: it would swap the machine to a halt, or be killed part way."""
    import psutil  # a dependency of distributed's

    need, free = memory_bytes(spec), psutil.virtual_memory().available
    if need > free:
        raise ValueError(
            f"this sweep of {spec.size} points needs about {need / 1e9:.1f} GB of memory in this "
            f"process (it holds the whole atlas), and {free / 1e9:.1f} GB is available: sweep "
            "the grid in parts (an atlas each: split an axis's range), or run where there is "
            "more memory"
        )
