"""The sweep and atlas commands of ``pydrill``."""

from __future__ import annotations

import argparse
import json
import shlex
import signal
import sys
import time
from pathlib import Path

SWEEP_EPILOG = """\
examples:
  pydrill sweep sweeps/minimal.toml --out minimal.h5
  pydrill sweep sweeps/paper-wob-torque.toml --out paper.h5 --workers 2 --plot paper.png
  pydrill sweep big.toml --out big.h5 --scheduler tcp://10.0.0.5:8786
  pydrill sweep big.toml --out big.h5 --dashboard     # watch it: the link is printed
  pydrill sweep big.toml --out big.h5 --resume        # after Ctrl-C, kill -9, a lost worker

Results stream into the atlas as they finish (through ATLAS.h5.journal), so an interrupted
sweep loses nothing: --resume computes only the missing points. Ctrl-C or SIGTERM stops the
sweep between batches with the atlas flushed (exit status 130 or 143). An atlas of a
different spec is never overwritten.
"""


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
    sw.add_argument("--out", required=True, metavar="ATLAS.h5", help="the atlas to write")
    where = sw.add_mutually_exclusive_group()  # where the points run: one of these, or cores
    where.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="local worker processes (default: one per core this process may use)",
    )
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on an existing Dask cluster instead: its scheduler's address "
        "(tcp://host:8786) or scheduler file (FILE.json, from dask scheduler --scheduler-file)",
    )
    where.add_argument("--serial", action="store_true", help="no Dask: run in this process")
    sw.add_argument(
        "--dashboard",
        action="store_true",
        help="serve Dask's dashboard (task stream, workers' CPU and memory) from the local "
        "cluster while the sweep runs, on 127.0.0.1:8787 or the next free port; its link is "
        "printed. Needs bokeh. An existing cluster (--scheduler) serves its own",
    )
    sw.add_argument(
        "--dashboard-address",
        metavar="HOST:PORT",
        help="serve the dashboard there instead (implies --dashboard), e.g. :8787 on every "
        "interface, to open it from another machine",
    )
    sw.add_argument("--resume", action="store_true", help="complete an interrupted sweep")
    sw.add_argument("--json", action="store_true", help="print one JSON object when done")
    sw.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress (a bar on a terminal, else a line every 30 s on stderr)",
    )
    sw.add_argument("--plot", metavar="FILE.png", help="draw the regime map when done")
    sw.set_defaults(handler=_cmd_sweep)

    at = sub.add_parser(
        "atlas",
        help="inspect, query, plot or export an atlas",
        description="Work with an atlas written by 'pydrill sweep'.",
        epilog="examples:\n  pydrill atlas info paper.h5\n"
        "  pydrill atlas query paper.h5 --wob 100 --torque 8 --json\n"
        "  pydrill atlas query paper.h5 --wob 97 --torque 8.2 --nearest\n"
        "  pydrill atlas plot paper.h5 --out map.png --initial rest\n"
        "  pydrill atlas plot sizes.h5 --out map8.png --x wob --y torque --set dof=8\n"
        "  pydrill atlas export paper.h5 --out paper.nc",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    asub = at.add_subparsers(dest="atlas_command", metavar="ACTION", parser_class=type(at))
    info = asub.add_parser("info", help="axes, status and regime counts")
    info.add_argument("atlas", metavar="ATLAS.h5")
    info.add_argument("--json", action="store_true")
    info.set_defaults(handler=_cmd_info)
    query = asub.add_parser("query", help="everything recorded at one point")
    query.add_argument("atlas", metavar="ATLAS.h5")
    from .cli import _finite

    kinds = {"wob": "force", "torque": "torque", "depth": "length", "dof": None, "pipes": None}
    for axis, kind in kinds.items():
        query.add_argument(
            f"--{axis}",
            type=_finite(f"--{axis}", kind),
            help=f"{axis} of the point" + (" (SI, or with a unit)" if kind else ""),
        )
    query.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="AXIS=VALUE",
        help="the point's value on any other axis",
    )
    query.add_argument("--nearest", action="store_true", help="nearest grid point, not exact")
    query.add_argument("--json", action="store_true")
    query.set_defaults(handler=_cmd_query)
    plot = asub.add_parser("plot", help="regime map on two axes with the analytic boundaries")
    plot.add_argument("atlas", metavar="ATLAS.h5")
    plot.add_argument("--out", required=True, metavar="FILE.png")
    plot.add_argument("--initial", help="which start to draw (default: the first)")
    plot.add_argument("--x", metavar="AXIS", help="horizontal axis (default: the first swept)")
    plot.add_argument("--y", metavar="AXIS", help="vertical axis (default: the next swept)")
    plot.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="AXIS=VALUE",
        help="hold another axis at its grid value nearest VALUE (default: its first value)",
    )
    plot.set_defaults(handler=_cmd_plot)
    export = asub.add_parser("export", help="write the atlas as netCDF (.nc) or CSV (.csv)")
    export.add_argument("atlas", metavar="ATLAS.h5")
    export.add_argument("--out", required=True, metavar="FILE.nc|FILE.csv")
    export.set_defaults(handler=_cmd_export)
    at.set_defaults(handler=lambda args: _atlas_usage(at))


class _LogProgress:
    """Progress for a log rather than a terminal: one line at most every ``every`` seconds,
    none at all for a sweep shorter than that. Speaks tqdm's ``total``/``reset``/``update``/
    ``close``, as ``_cmd_sweep`` uses them."""

    def __init__(self, total: int, every: float = 30.0) -> None:
        self.total, self.every, self.done = total, every, 0
        self.start = self.last = time.monotonic()

    def reset(self, total: int) -> None:
        self.total, self.done = total, 0

    def update(self, n: int) -> None:
        self.done += n
        now = time.monotonic()
        if now - self.last >= self.every and self.done < self.total:
            self.last = now
            rate = self.done / (now - self.start)
            left = (self.total - self.done) / rate
            sys.stderr.write(
                f"sweep: {self.done}/{self.total} points ({100 * self.done / self.total:.0f} %), "
                f"{rate:.0f} points/s, about {_duration(left)} left\n"
            )
            sys.stderr.flush()

    def close(self) -> None:
        pass


def _duration(seconds: float) -> str:
    m, s = divmod(round(seconds), 60)
    h, m = divmod(m, 60)
    return f"{h} h {m:02d} min" if h else f"{m} min {s:02d} s" if m else f"{s} s"


def _atlas_usage(parser) -> int:
    parser.print_help(sys.stderr)
    return 2


def _cmd_sweep(args: argparse.Namespace) -> int:
    from .plot import save
    from .plot_atlas import atlas_figure
    from .spec import load_spec
    from .sweep import SweepInterrupted, run_sweep

    spec = load_spec(args.spec)
    if args.workers is not None and not 1 <= args.workers <= 256:
        raise ValueError(f"--workers = {args.workers} is not allowed: 1 ... 256")
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
        from .sweep_dask import check_dashboard

        check_dashboard(
            dashboard, "--dashboard-address" if args.dashboard_address else "--dashboard"
        )
    bar = None
    if args.no_progress:
        pass
    elif sys.stderr.isatty() and not args.json:
        from tqdm import tqdm

        bar = tqdm(total=spec.size, unit="pt", desc="sweep", file=sys.stderr)
    else:  # a log file (nohup, a batch job): a plain line now and then
        bar = _LogProgress(spec.size)
    done_before = [0]

    def progress(n: int, total: int) -> None:
        if bar is not None:
            if bar.total != total:
                bar.reset(total=total)
            bar.update(n)
        done_before[0] += n

    def on_cluster(info) -> None:
        if bar is None:
            return
        line = f"sweep: {info.workers} Dask workers, scheduler {info.scheduler}"
        if info.dashboard:
            line += f", dashboard {info.dashboard}"
            asked = dashboard and dashboard.rpartition(":")[2]
            if asked not in (None, "0") and f":{asked}/" not in info.dashboard:
                line += f" (port {asked} is taken)"
        if hasattr(bar, "write"):  # tqdm: above the bar, which stays whole
            bar.write(line, file=sys.stderr)
        else:
            sys.stderr.write(line + "\n")

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
        again = " ".join(shlex.quote(a) for a in ("pydrill", "sweep", args.spec, "--out", args.out))
        if args.json:
            print(
                json.dumps(
                    {
                        "atlas": str(exc.atlas),
                        "interrupted": True,
                        "points": exc.points,
                        "done": exc.done,
                        "resume": f"{again} --resume",
                    }
                )
            )
        sys.stderr.write(
            f"pydrill sweep: interrupted; {exc.done} of {exc.points} points are saved in "
            f"{exc.atlas}\n  to compute the other {exc.points - exc.done}: {again} --resume\n"
        )
        # The shell's convention for "ended by signal N": 128 + N.
        return 128 + exc.signum
    if bar is not None:
        bar.close()
    if args.plot:
        from .atlas import Atlas

        with Atlas(args.out) as atlas:
            save(atlas_figure(atlas), args.plot)
    data = {
        "atlas": str(report.atlas),
        "points": report.points,
        "computed": report.computed,
        "failed": report.failed,
        "already_done": report.resumed,
        "wall_time": report.wall_time,
        "write_time": report.write_time,
        "units": {"wall_time": "s", "write_time": "s"},
    }
    if args.plot:
        data["plot"] = args.plot
    if args.json:
        print(json.dumps(data))
    else:
        print(
            f"{report.atlas}: {report.points} points, {report.computed} computed now "
            f"({report.failed} failed), {report.resumed} already done; "
            f"{report.wall_time:.1f} s, of which {report.write_time:.2f} s writing"
        )
        if args.plot:
            print(f"figure: {args.plot}")
    return 0


def _cmd_info(args: argparse.Namespace) -> int:
    from .atlas import Atlas

    with Atlas(args.atlas) as atlas:
        s = atlas.summary()
    if args.json:
        print(json.dumps(s))
        return 0
    print(
        f"{s['path']}: {s['points']} points, pydrill {s['pydrill_version']}, "
        f"spec {s['spec_digest']}"
    )
    for name, ax in s["axes"].items():
        print(f"  axis {name:12s} {ax['size']:6d} values, {ax['min']:g} ... {ax['max']:g}")
    print("  status  " + ", ".join(f"{k} {v}" for k, v in s["status"].items()))
    for init, counts in s["regimes"].items():
        print(f"  from {init:12s}" + ", ".join(f"{k} {v}" for k, v in counts.items()))
    print(
        f"  safe points {s['safe_points']}, rest/equilibrium disagree at {s['coexistence_points']}"
    )
    if s["journal"]:
        print(
            f"  journal {s['journal']}: a sweep into this atlas is running or was stopped; "
            "'pydrill sweep SPEC.toml --out ATLAS.h5 --resume' completes it"
        )
    return 0


def _axis_values(items: list[str]) -> dict[str, float]:
    """``--set AXIS=VALUE`` options as a dict."""
    out = {}
    for item in items:
        name, _, value = item.partition("=")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise ValueError(f"--set {item!r}: expected AXIS=NUMBER") from None
    return out


def _cmd_query(args: argparse.Namespace) -> int:
    from .atlas import Atlas

    coords = {
        k: getattr(args, k)
        for k in ("wob", "torque", "depth", "dof", "pipes")
        if getattr(args, k) is not None
    }
    coords.update(_axis_values(args.set))
    with Atlas(args.atlas) as atlas:
        try:
            v = atlas.value("nearest" if args.nearest else "exact", **coords)
        except KeyError as exc:
            raise ValueError(exc.args[0]) from None
        initials = atlas.initials
    if args.json:
        first = initials[0]
        flat = {"regime": v["regime"][first], "coords": v["coords"], "status": v["status"]}
        flat.update({k: m[first] for k, m in v["metrics"].items()})
        flat["by_initial"] = {"regime": v["regime"], "metrics": v["metrics"]}
        flat["stability"] = v["stability"]
        flat["coexistence"] = v["coexistence"]
        flat["units"] = {
            "bit_min": "rad/s",
            "bit_max": "rad/s",
            "bit_mean": "rad/s",
            "top_mean": "rad/s",
            "period": "s",
            "omega_eq": "rad/s",
            "wall_time": "s",
            "spectral_abscissa": "1/s",
        }
        if "message" in v:
            flat["message"] = v["message"]
        print(json.dumps(flat))
        return 0
    print(", ".join(f"{k} = {x:g}" for k, x in v["coords"].items()) + f": {v['status']}")
    for init, regime in v["regime"].items():
        m = v["metrics"]
        period = m["period"][init]
        mean, stuck = m["bit_mean"][init], m["stuck_fraction"][init]
        print(
            f"  from {init:12s} {regime:12s} bit mean "
            + ("-" if mean is None else f"{mean:.4g} rad/s")
            + ", stuck "
            + ("-" if stuck is None else f"{100 * stuck:.1f} %")
            + (f", period {period:.4g} s" if period else "")
        )
    st = v["stability"]
    for w, unstable in zip(st["omega_eq"], st["unstable"], strict=True):
        print(
            f"  steady state Omega = {w:.5g} rad/s: "
            + ("stable" if unstable == 0 else f"unstable ({unstable})")
        )
    return 0


def _cmd_plot(args: argparse.Namespace) -> int:
    from .atlas import Atlas
    from .plot import save
    from .plot_atlas import atlas_figure

    at = _axis_values(args.set)
    with Atlas(args.atlas) as atlas:
        save(atlas_figure(atlas, initial=args.initial, x=args.x, y=args.y, at=at), args.out)
    print(f"figure: {args.out}")
    return 0


def _cmd_export(args: argparse.Namespace) -> int:
    from .atlas import Atlas

    out = Path(args.out)
    with Atlas(args.atlas) as atlas:
        ds = atlas.to_xarray()
        if out.suffix == ".nc":
            ds.load().to_netcdf(out, engine="h5netcdf")
        elif out.suffix == ".csv":
            from .atlas import with_regime_names

            ds = with_regime_names(ds.load())
            keep = [
                v
                for v in ds.data_vars
                if "eigenvalue" not in ds[v].dims
                and "equilibrium" not in ds[v].dims
                and (ds[v].dtype.kind != "O" or v == "regime_name")
            ]
            ds[keep].to_dataframe().to_csv(out)
        else:
            raise ValueError(f"--out {out}: the suffix must be .nc or .csv")
        ds.close()
    print(f"wrote {out}")
    return 0
