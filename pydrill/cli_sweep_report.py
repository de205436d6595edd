"""What ``pydrill sweep`` says while and after it runs: its progress (a bar on a terminal, a
line now and then in a log), where it runs and waits, how to resume it, and what failed."""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path
from typing import Any

from .atlas_grid import grid_unit
from .cli_options import bar_size, json_document, print_json


class LogProgress:
    """Progress for a log rather than a terminal: one line at most every ``every`` seconds,
    none at all for a sweep shorter than that. Speaks tqdm's ``total``/``reset``/``update``/
    ``close``, as the sweep command uses them."""

    def __init__(self, total: int, every: float = 30.0, *, resumed: bool = False) -> None:
        self.total, self.every, self.done = total, every, 0
        self.last = time.monotonic()
        # A resumed sweep counts its rate from its first batch back: before it comes the
        # journal's replay (a minute for a million points), which made a sweep of 2000 points left
        # say "7 points/s, about 4 min 05 s left" when it had seconds to go.
        self.resumed = resumed
        self.first: tuple[float, int] | None = None if resumed else (self.last, 0)

    def reset(self, total: int) -> None:
        self.total, self.done = total, 0
        if self.resumed:
            self.first = None

    def update(self, n: int) -> None:
        self.done += n
        now = time.monotonic()
        if self.first is None:  # (resumed) the first batch back: the rate counts from here
            self.first, self.last = (now, self.done), now
            return
        if now - self.last >= self.every and self.done < self.total:
            self.last = now
            since, before = self.first
            rate = max(self.done - before, 1) / max(now - since, 1e-9)
            left = (self.total - self.done) / rate
            sys.stderr.write(
                f"sweep: {self.done}/{self.total} points ({100 * self.done / self.total:.0f} %), "
                f"{rate:.0f} points/s, about {duration(left)} left\n"
            )
            sys.stderr.flush()

    def close(self) -> None:
        pass


def progress_bar(args: argparse.Namespace, total: int) -> Any:
    """A tqdm bar on a terminal, a ``LogProgress`` in a log (nohup, a batch job), or None
    with --no-progress."""
    if args.no_progress:
        return None
    if sys.stderr.isatty() and not args.json:
        from tqdm import tqdm

        # sized as the terminal, or 80 x 24 on one that says it is 0 x 0 (bar_size)
        return tqdm(total=total, unit="pt", desc="sweep", file=sys.stderr, **bar_size())
    return LogProgress(total, resumed=args.resume)


def say(bar, line: str) -> None:
    """A line on stderr, above a tqdm bar (which stays whole) or in a log."""
    if hasattr(bar, "write"):
        bar.write(line, file=sys.stderr)
    else:
        sys.stderr.write(line + "\n")
        sys.stderr.flush()


def duration(seconds: float) -> str:
    m, s = divmod(round(seconds), 60)
    h, m = divmod(m, 60)
    return f"{h} h {m:02d} min" if h else f"{m} min {s:02d} s" if m else f"{s} s"


class ClusterLines:
    """The sweep's ``on_cluster``: says where it runs (workers, scheduler, dashboard) and,
    later, when an existing cluster's workers come or go; ``cluster`` keeps the first for
    --json (None: the sweep did not run on Dask)."""

    def __init__(self, bar: Any, configured: Any, dashboard: str | None) -> None:
        self.bar, self.configured, self.dashboard = bar, configured, dashboard
        self.cluster: dict[str, object] | None = None

    def __call__(self, info: Any) -> None:
        plural = "s" if info.workers != 1 else ""
        if self.cluster is not None:  # later: the existing cluster's workers came or went
            line = f"sweep: now {info.workers} Dask worker{plural}"
            if info.workers == 0:
                line += " (the points wait for workers to join; Ctrl-C stops, keeping what is done)"
            say(self.bar, line)  # told with or without a progress bar: a log needs it most
            return
        self.cluster = {"scheduler": info.scheduler, "workers": info.workers}
        self.cluster["dashboard"] = info.dashboard
        line = f"sweep: {info.workers} Dask worker{plural}, scheduler {info.scheduler}"
        if self.configured is not None:
            line += f" (from {self.configured.source})"
        if info.workers == 0:
            line += " (none yet: the points wait for workers to join)"
        if info.dashboard:
            line += f", dashboard {info.dashboard}"
            asked = self.dashboard and self.dashboard.rpartition(":")[2]
            if asked not in (None, "0") and f":{asked}/" not in info.dashboard:
                line += f" (port {asked} is taken)"
        say(self.bar, line)


def say_if_waiting(bar: Any, address: Any) -> None:
    """Say that the sweep waits, and for how long, when nothing answers at the scheduler's
    ``address`` (or its scheduler file is not there) yet: else the run would sit silent until
    Dask gives up."""
    from .dask_connect import scheduler_file

    file = scheduler_file(address) if address else None
    if file is not None:
        from .dask_connect import connect_timeout, scheduler_file_address

        if not file.exists():
            say(
                bar,
                f"sweep: no scheduler file {file} yet; waiting up to {connect_timeout():g} s for "
                "a scheduler to write it (distributed.comm.timeouts.connect)",
            )
            return
        try:  # probed below; a file without an address is refused by the sweep itself
            address = scheduler_file_address(file, 0.0)
        except Exception:
            return
    if address:
        from .dask_connect import unanswered

        patience = unanswered(address)
        if patience is not None:
            say(
                bar,
                f"sweep: no Dask scheduler answers at {address} yet; waiting up to "
                f"{patience:g} s for one to start (distributed.comm.timeouts.connect)",
            )


UNITS = {"wall_time": "s", "write_time": "s"}


def inputs(args: argparse.Namespace, run) -> dict:
    """What ``sweep --json`` echoes of its command line: the spec, the atlas written, and the
    part of the spec swept ("K/N", or null: all of it)."""
    return {"spec": args.spec, "atlas": str(run.atlas), "part": args.part}


def results_of(run, cluster, interrupted: bool) -> dict:
    """A sweep's results for --json, from its SweepReport or its SweepInterrupted."""
    results = {
        "interrupted": interrupted,
        "points": run.points,
        "computed": run.computed,
        "failed": run.failed,
        "already_done": run.resumed,
        "wall_time": run.wall_time,
        "write_time": run.write_time,
        "cluster": cluster,
    }
    # The atlas whole (so far, if interrupted): what failed in it, with the first message.
    results["failed_in_atlas"] = run.failed_in_atlas
    results["first_failure"] = run.first_failure or None
    return results


def interrupted(args: argparse.Namespace, exc: Any, cluster: dict[str, object] | None) -> int:
    """Say what an interrupted sweep saved and the command that resumes it (--json: the keys
    of a finished sweep's, with what says it stopped); the exit status, 128 + the signal."""
    # Where it ran, too: without --scheduler a cluster's sweep would resume on the login node.
    where = (
        ["--scheduler", str(args.scheduler)]
        if args.scheduler
        else ["--workers", str(args.workers)]
        if args.workers is not None
        else ["--serial"]
        if args.serial
        else []
    )
    # and as the same part (a part's atlas is refused to the whole spec)
    part = ["--part", args.part] if getattr(args, "part", None) else []
    again = " ".join(
        shlex.quote(a) for a in ("pydrill", "sweep", args.spec, *part, "--out", args.out, *where)
    )
    if args.json:
        results = results_of(exc, cluster, interrupted=True)
        results.update(done=exc.done, resume=f"{again} --resume")
        print_json(json_document(inputs(args, exc), results, UNITS))
    if exc.done == 0 and not Path(exc.atlas).exists():
        sys.stderr.write(
            "pydrill sweep: interrupted before any point was computed; nothing was written\n"
        )
    else:
        sys.stderr.write(
            f"pydrill sweep: interrupted; {exc.done} of {exc.points} points are saved in "
            f"{exc.atlas}\n  to compute the other {exc.points - exc.done}: {again} --resume\n"
        )
    # The shell's convention for "ended by signal N": 128 + N.
    return 128 + int(exc.signum)


def next_steps(args: argparse.Namespace, report: Any, spec: Any) -> None:
    """After a sweep that completed (text output), say on stderr what to ask of the atlas next:
    its safe windows (``atlas safe``, holding all but one other axis of a bigger grid, whose
    every row would be a wall of lines) and, unless --plot drew it, its regime map."""
    if args.json or report.all_failed:
        return
    atlas = shlex.quote(str(report.atlas))
    steps = []  # (command, what it gives): a line each, the command first, to copy whole
    if getattr(args, "part", None) is not None:
        n = int(args.part.split("/")[1])  # (K/N, as cli_sweep._sweep wrote it)
        if n > 1:
            steps.append(
                (
                    f"pydrill atlas merge {atlas} OTHER-PARTS.h5 --out WHOLE.h5",
                    "once the other part is swept"
                    if n == 2
                    else f"once the other {n - 1} parts are swept",
                )
            )
    if spec.record["stability"]:
        along = "wob" if "wob" in spec.axes else next(iter(spec.axes))
        others = [n for n in spec.axes if n != along]
        held = ""
        # One row per value of the other axes: hold all but the first at their middle value.
        for name in others[1:]:
            values = spec.axes[name]
            unit, factor = grid_unit(name, values)
            middle = f"{float(values[len(values) // 2]) / factor:g}"
            held += " --set " + shlex.quote(f"{name}={middle}{'' if unit == '1' else unit}")
        steps.append((f"pydrill atlas safe {atlas}{held}", f"the safe windows along {along}"))
    else:  # no stability recorded: nothing can be called safe (atlas safe refuses)
        steps.append((f"pydrill atlas info {atlas}", "what it found"))
    if not args.plot:
        figure_path = Path(report.atlas).with_suffix(".png")
        if figure_path == Path(report.atlas):  # an atlas called x.png: never the atlas itself
            figure_path = figure_path.with_name(figure_path.stem + "-map.png")
        figure = shlex.quote(str(figure_path))
        steps.append((f"pydrill atlas plot {atlas} --out {figure}", "a regime map"))
    width = max(len(command) for command, _ in steps)
    lines = [f"{command:{width}s}  # {what}" for command, what in steps]
    sys.stderr.write("next: " + "\n      ".join(lines) + "\n")
    sys.stderr.flush()


def failures(report) -> int:
    """Say on stderr what failed, with the first failure's message ("(120 failed)" alone does
    not say why), and the exit status: 3 when every point of the atlas failed — a study
    whose every point failed is an error, not a result (scripts and batch jobs see it)."""
    from .cli import EXIT_SOLVER

    n = report.failed_in_atlas
    if not n:
        return 0
    shown = (
        report.first_failure
        if len(report.first_failure) <= 300
        else (report.first_failure[:297] + "...")
    )
    query = f"'pydrill atlas query {report.atlas} ...' shows each point's message"
    if report.all_failed:
        sys.stderr.write(
            f"pydrill sweep: error: every point failed ({n} of {report.points}); nothing in "
            f"{report.atlas} is a result. The first failure: {shown}\n  {query}; fix the spec, "
            "then sweep again (into another --out, or after deleting this atlas)\n"
        )
        return EXIT_SOLVER
    sys.stderr.write(
        f"pydrill sweep: {n} of {report.points} points failed (stored as failed, with their "
        f"messages). The first: {shown}\n  {query}\n"
    )
    return 0
