"""The sweep command of ``pydrill``."""

from __future__ import annotations

import argparse
import signal
from pathlib import Path
from typing import TYPE_CHECKING

from .cli_options import _whole, figure_path, json_document, print_json, writable_place
from .cli_sweep_notes import spec_notes
from .cli_sweep_report import (
    UNITS,
    ClusterLines,
    failures,
    inputs,
    interrupted,
    next_steps,
    progress_bar,
    results_of,
    say,
    say_if_waiting,
)

SWEEP_EPILOG = """\
examples:
  pydrill sweep sweeps/minimal.toml --out minimal.h5
  pydrill sweep sweeps/paper-wob-torque.toml --out paper.h5 --workers 2 --plot paper.png
  pydrill sweep big.toml --dry-run                    # how many points, how long?
  pydrill sweep big.toml --out big.h5 --scheduler tcp://10.0.0.5:8786
  pydrill sweep big.toml --out big.h5 --dashboard     # watch it: the link is printed
  pydrill sweep big.toml --out big.h5 --resume        # after Ctrl-C, kill -9, a lost worker
  pydrill sweep big.toml --part 3/16 --out part3.h5   # one job of 16; then:
  pydrill atlas merge part*.h5 --out big.h5

Results stream into the atlas as they finish (through ATLAS.h5.journal), so an interrupted
sweep loses nothing: --resume computes only the missing points. An atlas of a different spec
is never overwritten.

exit status:
  0    the sweep is complete (points that failed, if any, are stored with their messages
       and counted on stderr)
  2    bad input: the spec, an option, an atlas that may not be written (another sweep's, one
       another process is writing), no Dask scheduler
  3    every point of the atlas failed (as a solver failure of 'pydrill simulate'): the first
       failure's message is printed; the atlas keeps every point's
  130  Ctrl-C, 143 SIGTERM: stopped between batches with the atlas flushed; --resume goes on
"""

if TYPE_CHECKING:
    pass


def register_sweep(sub, positive) -> None:
    sw = sub.add_parser(
        "sweep",
        help="run a parameter sweep (TOML spec) into an HDF5 atlas, with Dask",
        description="Simulate every point of a sweep specification and analyse its steady\n"
        "states, on a local Dask cluster (one process per core) or an existing one, writing\n"
        "an HDF5 atlas of regimes, metrics and eigenvalues.",
        epilog=SWEEP_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sw.add_argument("spec", metavar="SPEC.toml", help="the sweep specification")
    sw.add_argument(
        "--out", metavar="ATLAS.h5", help="the atlas to write (required, except for --dry-run)"
    )
    where = sw.add_mutually_exclusive_group()  # where the points run: one of these, or cores
    where.add_argument(
        "--workers",
        type=_whole("--workers", "1 ... 256"),
        metavar="N",
        help="local worker processes (default: one per core this process may use)",
    )
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on an existing Dask cluster instead: its scheduler's address "
        "(tcp://host:8786) or scheduler file (FILE.json, from dask scheduler --scheduler-file). "
        "Without --workers, --scheduler or --serial, a DASK_SCHEDULER_ADDRESS in the "
        "environment (or Dask's config) is used, as by any Dask client",
    )
    where.add_argument("--serial", action="store_true", help="no Dask: run in this process")
    sw.add_argument(
        "--dashboard",
        action="store_true",
        help="serve Dask's dashboard (task stream, workers' CPU and memory) from the local "
        "cluster while the sweep runs, on 127.0.0.1:8787 (another free port if that one is "
        "taken); its link is printed. Needs bokeh. An existing cluster (--scheduler) serves "
        "its own",
    )
    sw.add_argument(
        "--dashboard-address",
        metavar="HOST:PORT",
        help="serve the dashboard there instead (implies --dashboard), e.g. :8787 on every "
        "interface, to open it from another machine",
    )
    sw.add_argument("--resume", action="store_true", help="complete an interrupted sweep")
    sw.add_argument(
        "--part",
        metavar="K/N",
        help="sweep only part K of N (1 <= K <= N): every N-th value of the spec's first "
        "axis, from the K-th (the parts then cost about the same, and each is a coarser map "
        "of the whole); for sweeps run as separate jobs (a batch system's job array), whose "
        "atlases 'pydrill atlas merge' makes the whole spec's",
    )
    sw.add_argument(
        "--dry-run",
        action="store_true",
        help="compute nothing into an atlas and write nothing: check the spec (and --out, "
        "as the sweep would), count the points to compute, and time a sample of them (about "
        "2 s) to estimate how long the sweep will take",
    )
    sw.add_argument("--json", action="store_true", help="print one JSON object when done")
    sw.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress (a bar on a terminal, else a line every 30 s on stderr); where it "
        "runs, the dashboard link and workers coming and going are still said",
    )
    sw.add_argument(
        "--plot",
        metavar="FILE.png",
        type=figure_path,
        help="draw the regime map when done (a sweep of one axis: its profile along it)",
    )
    sw.set_defaults(handler=_cmd_sweep)


def _refuse_complete(out: str, spec) -> None:
    """Refuse, saying so, to sweep again into an atlas that already holds this whole sweep
    (without --resume the sweep would say "use --resume to complete it", though nothing is
    left to complete)."""
    from pathlib import Path

    from .atlas import Atlas
    from .sweep import AtlasError

    if not Path(out).is_file():
        return
    try:
        with Atlas(out) as atlas:
            s = atlas.summary()
    except (AtlasError, OSError, KeyError, ValueError):
        return  # not an atlas, or a damaged one: the sweep says which
    if s["spec_digest"] != spec.digest or s["status"]["missing"] or s["journal"]:
        return
    failed = s["status"]["failed"]
    raise ValueError(
        f"{out} already holds this sweep, complete: {s['points']} points"
        + (f" ({failed} of them failed; 'pydrill atlas query' shows why)" if failed else "")
        + "; nothing to resume. To compute it again, delete it or give another --out"
    )


def _already_done(out: Path, spec) -> int | None:
    """Points of ``out`` done (in the atlas or its journal), read fast and only to be said:
    None when it is not this sweep's atlas, or another sweep is writing it (the sweep itself
    refuses those, saying why)."""
    import h5py
    import numpy as np

    from . import atlas_format as fmt
    from .atlas_heap import heap_problem
    from .atlas_lock import writer
    from .journal import damage, journal_path, journaled

    if writer(out) is not None:
        return None
    done = np.zeros(spec.size, dtype=bool)
    try:
        if heap_problem(out):  # HDF5 would hang on it: damaged
            raise ValueError("damaged")
        with h5py.File(out, "r") as f:
            if f.attrs.get("spec_digest") != spec.digest:
                return None
            if damage(f, spec) is not None:
                raise ValueError("damaged")
            done |= f["status"][...].ravel() != fmt.STATUS["missing"]
    except FileNotFoundError:
        pass  # a journal alone: the atlas is rebuilt from it
    except (OSError, KeyError, ValueError, TypeError, AttributeError, RuntimeError):
        if not journal_path(out).exists():
            return None  # damaged, nothing to rebuild it from: the sweep refuses, saying why
        # damaged: rebuilt from the journal, whose points are those done
    found = journaled(out)  # the indices alone: 0.1 s for 74000 lines, where a replay takes 4
    done[found[(found >= 0) & (found < spec.size)]] = True
    return int(np.count_nonzero(done))


# The API's words in the sweep's refusals (AtlasError, SchedulerError), and the command line's:
# a CLI user was told "use --resume (resume=True)", a Python keyword that is no flag of theirs.
CLI_WORDS = {"resume=True": "--resume", "scheduler=...": "--scheduler", "out=PATH": "--out"}


SCHEDULER_FORMS = (
    "a scheduler's address (tcp://HOST:PORT) or its scheduler file (FILE.json, from "
    "'dask scheduler --scheduler-file FILE.json'); leave --scheduler out to run on a local "
    "cluster"
)


def cli_words(message: str) -> str:
    """``message`` of the Python API in the command line's words (:data:`CLI_WORDS`)."""
    for api, flag in CLI_WORDS.items():
        message = message.replace(api, flag)
    return message


def _cmd_sweep(args: argparse.Namespace) -> int:
    from .sweep import AtlasError, SchedulerError

    try:
        return _sweep(args)
    except (AtlasError, SchedulerError) as exc:
        exc.args = (cli_words(str(exc)),)  # (the same error, said as the command line says it)
        raise


def _sweep(args: argparse.Namespace) -> int:
    from .spec import load_spec
    from .sweep import SweepInterrupted, run_sweep

    spec = load_spec(args.spec)
    if args.part is not None:
        from .spec_parts import parse_part, spec_part

        try:
            k, n = parse_part(args.part)
        except ValueError as exc:
            raise ValueError(f"--part {exc}") from None
        try:
            spec = spec_part(spec, k, n, Path(args.spec).name)
        except ValueError as exc:
            raise ValueError(f"--part {args.part}: {exc}") from None
        args.part = f"{k}/{n}"  # as the JSON, the dry run and the next steps say it
    spec_notes(spec)
    if args.workers is not None and not 1 <= args.workers <= 256:
        raise ValueError(f"--workers = {args.workers} is not allowed: 1 ... 256")
    if args.scheduler is not None and not args.scheduler.strip():
        # A job script's unset variable (--scheduler "$SCHED_FILE"): it ran on a local
        # cluster, of the login node's cores, as if --scheduler were not there.
        raise ValueError(f"--scheduler {args.scheduler!r} is not allowed: {SCHEDULER_FORMS}")
    dashboard = args.dashboard_address or ("127.0.0.1:8787" if args.dashboard else None)
    if dashboard and (args.serial or args.scheduler):
        raise ValueError(
            "--dashboard serves the local cluster's dashboard: "
            + (
                "an existing cluster (--scheduler) serves its own, and its link is printed"
                if args.scheduler
                else "a --serial sweep has no Dask to watch"
            )
        )
    if dashboard:
        from .dask_connect import check_dashboard

        check_dashboard(
            dashboard, "--dashboard-address" if args.dashboard_address else "--dashboard"
        )
    if args.dry_run:
        from .cli_sweep_dry_run import dry_run

        if args.out is not None and not args.resume:  # refused as the sweep would refuse it
            _refuse_complete(args.out, spec)
        return dry_run(args, spec)
    if args.out is None:
        raise ValueError("--out ATLAS.h5 is required: the atlas to write (or give --dry-run)")
    try:
        writable_place(args.out)
    except argparse.ArgumentTypeError as exc:
        raise ValueError(f"--out {exc}") from None
    if not args.resume:
        _refuse_complete(args.out, spec)
    # A resumed sweep's bar counts the points left from the start (it counted the whole grid
    # until the first batch came back: minutes, for strings of hundreds of pipes), and the
    # journal's replay, a minute for a million points, is said before it sits there.
    done = _already_done(Path(args.out), spec) if args.resume else None
    bar = progress_bar(args, spec.size - (done or 0))
    if done:
        say(
            bar,
            f"sweep: resuming {args.out}: {done} of {spec.size} points are done, "
            f"{spec.size - done} to compute",
        )

    def progress(n: int, total: int) -> None:
        if bar is not None:
            if bar.total != total:
                bar.reset(total=total)
            bar.update(n)

    configured = None
    if args.scheduler is None and args.workers is None and not args.serial:
        from .dask_connect import configured_scheduler

        configured = configured_scheduler()
    on_cluster = ClusterLines(bar, configured, dashboard)
    say_if_waiting(bar, args.scheduler or configured)
    try:
        report = run_sweep(
            spec,
            args.out,
            workers=args.workers,
            scheduler=args.scheduler,
            resume=args.resume,
            progress=progress,
            serial=args.serial,
            # kill, or a batch system's time limit: stop as on Ctrl-C, the atlas flushed.
            stop_on=(signal.SIGINT, signal.SIGTERM),
            dashboard=dashboard,
            on_cluster=on_cluster,
        )
    except SweepInterrupted as exc:
        if bar is not None:
            bar.close()
        return interrupted(args, exc, on_cluster.cluster)
    if bar is not None:
        bar.close()
    if args.plot and report.all_failed:  # a map of failures only says nothing the error does
        args.plot = None
    if args.plot:
        from .atlas import Atlas
        from .cli_atlas import held_first
        from .plot import save
        from .plot_atlas import atlas_figure

        with Atlas(args.out) as atlas:
            for line in held_first(atlas, None, None, {}, False):
                name = line.split(" ")[0]
                say(
                    None,
                    f"pydrill sweep: note: the map holds {line}; 'pydrill atlas plot "
                    f"{args.out} --out FILE.png --set {name}=VALUE' draws another",
                )
            save(atlas_figure(atlas), args.plot)
    if args.json:
        results = results_of(report, on_cluster.cluster, interrupted=False)
        print_json(json_document(inputs(args, report), results, UNITS, args.plot))
    else:
        print(
            f"{report.atlas}: {report.points} point{'' if report.points == 1 else 's'}, "
            f"{report.computed} computed now "
            f"({report.failed} failed), {report.resumed} already done; "
            f"{report.wall_time:.1f} s, of which {report.write_time:.2f} s writing"
        )
        if args.plot:
            print(f"figure: {args.plot}")
    status = failures(report)
    next_steps(args, report, spec)
    return status
