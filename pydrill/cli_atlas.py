"""The atlas commands of ``pydrill``: info, query, plot, export and merge atlases."""

from __future__ import annotations

import argparse
import sys
import textwrap
from pathlib import Path
from typing import Any

from .atlas_grid import axis_unit, grid_unit, leave_out_held, spec_holds, with_unit
from .cli_atlas_export import cmd_export, export_path
from .cli_atlas_info import cmd_info
from .cli_atlas_merge import register_merge
from .cli_atlas_query import axis_values, cmd_query, set_texts, snap_notes
from .cli_atlas_safe import register_safe
from .cli_options import figure_path, json_document, print_json


def register_atlas(sub) -> None:
    at = sub.add_parser(
        "atlas",
        help="inspect, query, find safe windows in, plot, export or merge atlases",
        description="Work with an atlas written by 'pydrill sweep'.",
        epilog="examples:\n  pydrill atlas info paper.h5\n"
        "  pydrill atlas query paper.h5 --wob 100 --torque 8 --json\n"
        "  pydrill atlas query paper.h5 --wob 97 --torque 8.2 --nearest\n"
        "  pydrill atlas plot paper.h5 --out map.png --initial rest\n"
        "  pydrill atlas plot sizes.h5 --out map8.png --x wob --y torque --set dof=8\n"
        "  pydrill atlas safe paper.h5 --set torque=8.5\n"
        "  pydrill atlas export paper.h5 --out paper.nc\n"
        "  pydrill atlas export paper.h5 --out paper.csv --json\n"
        "  pydrill atlas merge low-wob.h5 high-wob.h5 --out paper.h5",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    asub = at.add_subparsers(dest="atlas_command", metavar="ACTION", parser_class=type(at))
    raw = argparse.RawDescriptionHelpFormatter  # the epilogs' lines stay; descriptions: _para
    info = asub.add_parser(
        "info",
        help="axes, status and regime counts",
        description=_para(
            "What an atlas holds: its axes (size and range), how many points are "
            "done, failed or still missing, the regimes counted for each initial condition, the "
            "safe points (steady from every start, and the fastest steady state stable) and "
            "where rest and equilibrium "
            "starts disagree. A journal beside the atlas means a sweep into it is running or was "
            "stopped."
        ),
        formatter_class=raw,
        epilog="examples:\n  pydrill atlas info paper.h5\n  pydrill atlas info paper.h5 --json\n\n"
        "JSON fields: path, pydrill_version, model {string, from (preset or tally),\n"
        "  inertias (null: an axis sets them), held {NAME: SI value}, t_end}, spec_digest\n"
        "  (as written), spec_digest_here (this pydrill's, of the same spec), points,\n"
        "  axes {NAME: {size, min, max}}, initial, status {missing, done, failed},\n"
        "  regimes {INITIAL: {REGIME: count}},\n"
        "  safe_points (null: stability not recorded), coexistence_points,\n"
        "  caveats {INITIAL: {CAVEAT: count}},\n"
        "  journal (its path, or null), journal_points (in the journal, not yet in the atlas),\n"
        "  merged_from (made by 'atlas merge': its parts [{file, pydrill_version, spec_digest,\n"
        "  values}]; else null), part (swept with --part: {k, n, of}; else null),\n"
        "  units {axes {NAME: unit}, model {held {NAME: unit}, t_end}}",
    )
    info.add_argument("atlas", metavar="ATLAS.h5")
    info.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    info.set_defaults(handler=cmd_info)
    query = asub.add_parser(
        "query",
        help="everything recorded at one point",
        description=_para(
            "Everything recorded at one point of the grid: its regime and metrics "
            "from each initial condition, its steady states with their eigenvalues and Hopf "
            "margin, and whether rest and equilibrium starts disagree. Give a value for every "
            "axis of the atlas; without --nearest each must be on the grid."
        ),
        formatter_class=raw,
        epilog="examples:\n  pydrill atlas query paper.h5 --wob 100 --torque 8.5\n"
        "  pydrill atlas query paper.h5 --wob '0.1 kN' --torque 8.4 --nearest\n"
        "  pydrill atlas query damping.h5 --wob 100 --torque 8.5 --set bit_damping=50 --json\n\n"
        "JSON fields: regime, caveat and the metrics (bit_min, bit_max, bit_mean, top_mean,\n"
        "  severity, stuck_fraction, period, stick_events, wall_time, top_min, top_max,\n"
        "  bit_top_ratio) from the first initial\n"
        "  condition; coords, status, by_initial {regime, metrics, caveat}, stability\n"
        "  {omega_eq, delta, spectral_abscissa, hopf_margin, unstable, eigenvalues} (null\n"
        "  without stability recorded), coexistence, safe (what 'atlas safe' lists: every\n"
        "  start steady and the fastest steady state stable; null without stability\n"
        "  recorded), units;\n"
        "  message for a failed point; with --nearest, asked (the values given: coords are\n"
        "  the grid point's)",
    )
    query.add_argument("atlas", metavar="ATLAS.h5")
    from .cli_options import _finite

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
        help="the point's value on any other axis (SI, or with a unit: 'bit_damping=0.05 "
        "N·m·s/rad')",
    )
    query.add_argument("--nearest", action="store_true", help="nearest grid point, not exact")
    query.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    query.set_defaults(handler=cmd_query)
    register_safe(asub, raw)
    plot = asub.add_parser(
        "plot",
        help="regime map on two axes with the analytic boundaries (one axis: a profile)",
        description=_para(
            "The regime map of one initial condition on two axes of the atlas, with the Hopf "
            "boundary (where steady drilling loses stability) and the stuck boundary overlaid, "
            "as in the paper's Figs. 6b and 12 (on other axes than W_ob and u: the stuck "
            "boundary, and where the atlas's eigenvalues say the fastest steady state turns "
            "unstable), and the safe region outlined in white (every start steady, the fastest "
            "steady state stable: what 'atlas safe' lists). Other axes are held at one grid "
            "value each "
            "(--set). With --metric the map is coloured by a value instead: a simulation's "
            "(e.g. severity, stuck_fraction, period) from one start, or a steady state's "
            "(spectral_abscissa, hopf_margin: red where unstable) of the fastest one. An "
            "atlas of one axis, or one whose other axes are all held (--set torque=8.3 on a "
            "(wob, torque) atlas), is drawn as a profile along it instead: the bit velocity from "
            "each start (mean, and a band from least to largest), the fastest steady state "
            "(dashed where unstable), and a strip per start coloured by regime; --metric "
            "plots that value along the axis."
        ),
        epilog="examples:\n  pydrill atlas plot paper.h5 --out map.png\n"
        "  pydrill atlas plot paper.h5 --out severity.png --metric severity\n"
        "  pydrill atlas plot paper.h5 --out growth.pdf --metric spectral_abscissa\n"
        "  pydrill atlas plot sizes.h5 --out map8.png --x wob --y torque --set dof=8\n"
        "  pydrill atlas plot paper.h5 --out along-wob.png --profile --x wob --set torque=8.3",
        formatter_class=raw,
    )
    plot.add_argument("atlas", metavar="ATLAS.h5")
    plot.add_argument(
        "--out",
        required=True,
        metavar="FILE.png",
        type=figure_path,
        help="the figure to write; its suffix is the format (.png, .pdf, .svg, ...)",
    )
    plot.add_argument(
        "--initial",
        choices=("rest", "equilibrium"),
        help="which start to draw, of those the atlas holds: rest or equilibrium (default: the "
        "first it holds)",
    )
    plot.add_argument("--x", metavar="AXIS", help="horizontal axis (default: the first swept)")
    plot.add_argument("--y", metavar="AXIS", help="vertical axis (default: the next swept)")
    plot.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="AXIS=VALUE",
        help="hold another axis at its grid value nearest VALUE (SI, or with a unit: "
        "depth=3000ft; default: its first value); a VALUE beyond half a grid step past either "
        "end is refused",
    )
    plot.add_argument(
        "--profile",
        action="store_true",
        help="draw a profile along --x (default: the first swept axis) instead of a map, every "
        "other axis held (--set): the bit velocity from each start, the fastest steady state "
        "and a regime strip; with --metric, that value along the axis",
    )
    from .atlas_format import EQ_FIELDS, RUN_FIELDS

    plot.add_argument(
        "--metric",
        choices=[*RUN_FIELDS, *EQ_FIELDS],
        metavar="NAME",
        help="colour the map by this value instead of the regime: "
        + ", ".join([*RUN_FIELDS, *EQ_FIELDS]),
    )
    plot.add_argument(
        "--json",
        action="store_true",
        help="print one JSON object: the axes drawn, the grid values held, and the points of "
        "the slice drawn by regime (from --initial)",
    )
    plot.set_defaults(handler=_cmd_plot)
    export = asub.add_parser(
        "export",
        help="write the atlas as netCDF (.nc) or CSV (.csv)",
        description="Write the atlas for other tools. netCDF (.nc, through h5netcdf): "
        "every variable, eigenvalues included, with the axes as coordinates and the regime "
        "names as CF flag meanings, and safe (1 where 'atlas safe' lists the point); it opens "
        "with xarray.open_dataset. CSV (.csv): one row per point and initial condition: the "
        "axes, the regime, the metrics, the caveat (what the run's judgement notes), the "
        "status, a failed point's message, whether rest and equilibrium starts disagree "
        "(coexistence) and safe; each coded column is followed by its names (regime_name, "
        "caveat_name, status_name, coexistence_name). Values in SI, as the atlas holds them "
        "(wob N, torque N·m, depth m, velocities rad/s, times s). No steady states or "
        "eigenvalues (they are netCDF's). The file is written whole or not at all: "
        "an existing file at --out is replaced once the new one is complete, and kept as it "
        "was if writing fails (a full disk). The atlas is read and written by blocks of "
        "rows (65,536 points), so memory stays that of a block however large it is; on a "
        "terminal a bar shows the progress.",
        epilog="examples:\n  pydrill atlas export paper.h5 --out paper.nc\n"
        "  pydrill atlas export paper.h5 --out paper.csv --json\n"
        "  python -c \"import xarray; print(xarray.open_dataset('paper.nc'))\"",
        formatter_class=raw,
    )
    export.add_argument("atlas", metavar="ATLAS.h5")
    export.add_argument(
        "--out",
        required=True,
        metavar="FILE.nc|FILE.csv",
        type=export_path,
        help="the file to write",
    )
    export.add_argument(
        "--json",
        action="store_true",
        help="print one JSON object: the file written, its format, points, rows (CSV) or "
        "variables (netCDF) and size",
    )
    export.set_defaults(handler=cmd_export)
    register_merge(asub, raw)
    at.set_defaults(handler=lambda args: _atlas_usage(at))


def _para(text: str) -> str:
    """A description as argparse's raw formatter shows it: wrapped here, once."""
    return textwrap.fill(text, 79)


def _atlas_usage(parser) -> int:
    """``pydrill atlas`` alone: its actions, then the one-line error ``pydrill`` alone gives."""
    from .cli_parser import EXIT_USAGE, say_error

    parser.print_help(sys.stderr)
    say_error(parser.prog, "error", f"say which action: {parser.prog} ACTION ...", EXIT_USAGE)
    return EXIT_USAGE


def held_first(atlas: Any, x: Any, y: Any, at: dict[str, float], profile: bool) -> list[str]:
    """What a figure of ``atlas`` holds at an axis's first value unasked (not drawn, nor held
    by ``at``), a line each ("torque at its first value, 4 kN·m, of 21 (4 kN·m ... 14 kN·m)"):
    it shows one slice of several, the first, which for a (depth, W_ob, u) atlas is its least
    telling (4 kN·m: stuck almost everywhere)."""
    from .plot_atlas import drawn_axes

    try:
        drawn = drawn_axes(atlas, x, y, at, profile)[:2]
    except ValueError:  # the figure says why
        return []
    lines = []
    for name, values in atlas.axes.items():
        if name in drawn or name in at or len(values) < 2:
            continue
        unit = grid_unit(name, values)
        first, last = (with_unit(name, float(v), unit) for v in (values[0], values[-1]))
        lines.append(f"{name} at its first value, {first}, of {len(values)} ({first} ... {last})")
    return lines


def _cmd_plot(args: argparse.Namespace) -> int:
    from .atlas import Atlas
    from .atlas_format import EQ_FIELDS
    from .plot import save
    from .plot_atlas import NO_STABILITY, atlas_figure

    if Path(args.out).resolve() == Path(args.atlas).resolve():  # (an atlas named f.png)
        raise ValueError(f"--out {args.out} is the atlas itself; give another file")
    at = axis_values(args.set)
    given = set_texts(args.set)
    with Atlas(args.atlas) as atlas:
        if args.metric in EQ_FIELDS and not atlas.spec.record["stability"]:
            raise ValueError(f"--metric {args.metric}: {NO_STABILITY}")
        at = leave_out_held(
            at, atlas.axes, spec_holds(atlas.spec), lambda n: f"--set {n}={given[n]}"
        )
        snap_notes(atlas, at, given, "atlas plot", "drawn")
        for line in held_first(atlas, args.x, args.y, at, args.profile):
            name = line.split(" ")[0]
            print(
                f"pydrill atlas plot: note: holds {line}; --set {name}=VALUE for another",
                file=sys.stderr,
            )
        fig = atlas_figure(
            atlas,
            initial=args.initial,
            x=args.x,
            y=args.y,
            at=at,
            metric=args.metric,
            profile=args.profile,
        )
        save(fig, args.out)
        if args.json:
            print_json(_plot_json(atlas, args, at))
            return 0
    print(f"figure: {args.out}")
    return 0


def _plot_json(atlas: Any, args: argparse.Namespace, at: dict[str, float]) -> dict[str, Any]:
    """``atlas plot --json``: the axes drawn, each other axis's grid value held (as the figure
    holds it: nearest ``--set``, else its first), and the slice's points by regime, from
    ``--initial``, as ``atlas info`` counts them."""
    import numpy as np

    from . import atlas_format as fmt
    from .plot_atlas import drawn_axes, nearest_index

    x, y, profile = drawn_axes(atlas, args.x, args.y, at, args.profile)[:3]
    initial = args.initial or atlas.initials[0]
    held = {
        name: float(values[nearest_index(atlas, name, at[name]) if name in at else 0])
        for name, values in atlas.axes.items()
        if name not in (x, y)
    }
    codes = atlas.sel(method="nearest", initial=initial, **held)["regime"].values
    # as atlas info counts them: the regimes found, a point not done as missing or failed
    regimes = {n: int(np.sum(codes == c)) for n, c in fmt.REGIMES.items() if np.any(codes == c)}
    inputs = {"atlas": args.atlas, "initial": initial, "metric": args.metric}
    results = {
        "x": x,
        "y": y,
        "profile": profile,
        "held": held,
        "points": int(codes.size),
        "regimes": regimes,
    }
    units = {"held": {name: axis_unit(name) for name in held}}
    return json_document(inputs, results, units, plot=args.out)
