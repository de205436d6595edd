"""``pydrill sweep --dry-run``: count a sweep's points and estimate its time, writing nothing."""

from __future__ import annotations

import argparse
import os
import sys

from .atlas_summary import model, model_units
from .cli_atlas_info import axis_line, model_line
from .cli_options import json_document, print_json
from .cli_sweep_report import duration


def _size(n: float) -> str:
    units, k = ("bytes", "kB", "MB", "GB", "TB"), 0
    while n >= 1000 and k < len(units) - 1:
        n, k = n / 1000, k + 1
    return f"{n:.3g} {units[k]}"


def _span(seconds: float) -> str:
    return f"{seconds:.2g} s" if seconds < 10 else duration(seconds)


def dry_run(args: argparse.Namespace, spec) -> int:
    """``pydrill sweep --dry-run``: what the sweep would do and about how long it would take."""
    from .sweep_plan import plan_sweep

    plan = plan_sweep(spec, args.out, resume=args.resume)
    cores = 1 << 30  # no limit but the workers, unless they are local (below)
    if args.serial:
        workers, where = 1, "in this process (--serial)"
    elif args.scheduler is not None:
        workers, where = None, f"on the cluster at {args.scheduler}"
    else:
        from .dask_connect import configured_scheduler

        configured = configured_scheduler()
        if configured is not None and args.workers is None:
            workers, where = None, f"on the cluster at {configured} (from {configured.source})"
        else:
            import dask.system

            workers = args.workers or dask.system.CPU_COUNT
            where = f"on {workers} local worker{'s' if workers != 1 else ''}"
            if workers > dask.system.CPU_COUNT:  # they share the cores: no faster than one each
                where += f" sharing {dask.system.CPU_COUNT} cores"
                cores = dask.system.CPU_COUNT
    compute = plan.compute_seconds
    wall = plan.wall_seconds(min(workers, cores)) if workers else None
    if args.json:
        spread = ("low", "estimate", "high")  # the order of SweepPlan's tuples
        inputs = {
            "dry_run": True,
            "spec": args.spec,
            "part": args.part,
            "atlas": {"path": args.out, "state": plan.atlas},
            "workers": workers,
        }
        results = {
            "points": plan.points,
            "shape": {k: len(v) for k, v in spec.axes.items()},
            "initial": spec.initials,
            "model": model(spec),  # as atlas info --json gives it
            "todo": plan.todo,
            "sampled": plan.sampled,
            "failed": plan.failed,
            "message": plan.message or None,  # the first failure's; null, not "", if none
            "point_seconds": dict(
                zip(
                    spread,
                    (plan.point_seconds_low, plan.point_seconds, plan.point_seconds_high),
                    strict=True,
                )
            ),
            "compute_seconds": dict(zip(spread, compute, strict=True)),
            "wall_seconds": dict(zip(spread, wall, strict=True)) if wall else None,
            "atlas_bytes": plan.atlas_bytes,
            "journal_bytes": plan.journal_bytes,
            "memory_bytes": plan.memory_bytes,
            "memory_available_bytes": _available(),
        }
        units = {
            "point_seconds": "s",
            "compute_seconds": "s",
            "wall_seconds": "s",
            "atlas_bytes": "bytes",
            "journal_bytes": "bytes",
            "memory_bytes": "bytes",
            "memory_available_bytes": "bytes",
            "model": model_units(model(spec)),
        }
        print_json(json_document(inputs, results, units))  # no figure: nothing is drawn
        return 0
    grid = " x ".join(f"{len(v)} {k}" for k, v in spec.axes.items())
    points = f"{plan.points} point" + ("" if plan.points == 1 else "s")
    part = f", part {args.part.replace('/', ' of ')}" if args.part else ""
    print(f"{args.spec}{part}: {points} ({grid}), from " + " and ".join(spec.initials))
    # The string and what the spec holds for the whole sweep (a fixed torque, a depth): the
    # grid's lines alone left a sweep at 9 kN·m looking like one at no torque.
    print(model_line(model(spec)))
    for name, values in spec.axes.items():
        print(axis_line(name, len(values), values[0], values[-1], max(map(len, spec.axes))))
    state = {
        "none": "no --out given",
        "new": f"{args.out}: a new atlas",
        "resume": f"{args.out}: {plan.points - plan.todo} points done, --resume computes the "
        f"other {plan.todo}",
        "complete": f"{args.out}: complete, nothing to compute",
    }[plan.atlas]
    print(f"  atlas   {state}")
    if plan.sampled:
        # ms for a laboratory string's points, s for a long string's (was "1.63e+04 ms")
        sec = plan.point_seconds >= 1 or plan.point_seconds_high >= 1
        scale, unit = (1.0, "s") if sec else (1e3, "ms")
        each = f"{scale * plan.point_seconds:.3g} {unit} each on one core"
        if plan.sampled == plan.todo:  # every point timed: nothing left to estimate
            print(f"  timed   all {plan.todo} points to compute: {each}")
            print(f"  needs   {_span(compute[1])} of computing")
        else:
            low, high = scale * plan.point_seconds_low, scale * plan.point_seconds_high
            print(
                f"  timed   {plan.sampled} of the {plan.todo} points to compute: {each} "
                f"(95 %: {low:.3g} ... {high:.3g} {unit})"
            )
            print(
                f"  needs   about {_span(compute[1])} of computing (95 %: {_span(compute[0])} "
                f"... {_span(compute[2])})"
            )
        if wall:
            start = "" if args.serial else ", plus Dask's start"
            print(f"  runs    {where}: about {_span(wall[1])} at best{start}")
            busy = _busy()
            if busy:  # on stderr, as the other notes: it varies from one minute to the next
                print(f"pydrill: note: {busy}", file=sys.stderr)
        else:
            print(f"  runs    {where}: that time divided among its workers")
    print(f"  writes  about {_size(plan.atlas_bytes)} of data, before compression")
    if plan.journal_bytes:
        print(
            f"  journal up to about {_size(plan.journal_bytes)} beside the atlas while the "
            "sweep runs (removed at the end)"
        )
    free = _available()
    print(
        f"  memory  about {_size(plan.memory_bytes)} in this process (it holds the whole "
        f"atlas); {_size(free)} available now"
    )
    if plan.memory_bytes > free:
        print(
            "  warning that is more than is available: the sweep would refuse to start. Sweep "
            "the grid in parts (split an axis's range), or run where there is more memory"
        )
    if plan.failed and plan.failed == plan.sampled:  # likely the spec, not a corner of it
        print(
            f"  warning every one of the {plan.sampled} points timed failed: the sweep would "
            f"most likely fail whole (exit status 3). The first: {plan.message}"
        )
    elif plan.failed:
        print(
            f"  warning {plan.failed} of the {plan.sampled} points timed failed; the sweep "
            f"would store them as failed. The first: {plan.message}"
        )
    print("dry run: nothing was written")
    return 0


def _available() -> int:
    """Memory available to a new allocation now (bytes)."""
    import psutil  # a dependency of distributed's

    return int(psutil.virtual_memory().available)


def _busy() -> str | None:
    """What to say when other work holds this machine's cores: the estimate is of the cores as
    they were while the points were timed, and a sweep of minutes beside a busy machine's
    other work took 2.2 times it (load 4.5-5.4 on 2 cores). None on an idle machine."""
    import dask.system

    try:
        load = os.getloadavg()[0]
    except OSError:  # not on this platform
        return None
    cores = dask.system.CPU_COUNT
    others = load - 1.0  # this dry run was timing points on one core
    if others < 0.5 * cores:
        return None
    return (
        f"this machine is busy (load {load:.1f} on {cores} cores, this dry run included): its "
        "other work will share the cores with the sweep, which may take longer than this"
    )
