"""The atlas commands of ``pydrill``: info, query, plot and export an atlas."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .cli import figure_path


def register_atlas(sub) -> None:
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
    plot.add_argument("--out", required=True, metavar="FILE.png", type=figure_path)
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


def _atlas_usage(parser) -> int:
    parser.print_help(sys.stderr)
    return 2


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
