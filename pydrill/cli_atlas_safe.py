"""``pydrill atlas safe``: the safe operating windows of an atlas along one axis, for each
value of the others (``atlas_safe``), as text or JSON."""

from __future__ import annotations

import argparse
import textwrap
from typing import Any

from .atlas_grid import axis_unit, grid_unit, leave_out_held, spec_holds, with_unit
from .cli_atlas_query import axis_values, set_texts, snap_notes
from .cli_options import json_document, print_json

DESCRIPTION = (
    "The safe operating windows of an atlas: along one axis (W_ob unless --along says "
    "another), the runs of grid points where the bit drills steadily from every start the "
    "atlas holds and the fastest steady state is stable, for each value of the other axes "
    "(or only at those given with --set). A window is given by its first and last safe grid "
    "values: the true edges lie within one grid step beyond them (at the grid's own ends, "
    "the atlas says nothing of what lies past them). A point without a result is not safe "
    "and ends a window: a row counts those that failed (the solver gave up) and those not "
    "computed (missing). Needs an atlas swept with stability recorded."
)


def register_safe(asub, raw) -> None:
    """Add ``atlas safe`` to the ``atlas`` subcommands ``asub``."""
    safe = asub.add_parser(
        "safe",
        help="the safe windows along one axis (W_ob by default)",
        description=textwrap.fill(DESCRIPTION, 79),
        formatter_class=raw,
        epilog="examples:\n  pydrill atlas safe paper.h5\n"
        "  pydrill atlas safe paper.h5 --set torque=8.5\n"
        "  pydrill atlas safe paper.h5 --along torque --set wob=100 --json\n"
        "  pydrill atlas safe depth.h5 --set depth=3000m\n\n"
        "JSON fields: along, criterion, rows [{at {AXIS: value}, windows [[first, last]],\n"
        "  beyond [[below, above]] (the grid values just outside each window, between which\n"
        "  and its ends the true edges lie; null past the grid's end), safe_points, points,\n"
        "  not_done (failed + missing), failed, missing}], fixed {NAME: value} (what the\n"
        "  spec holds for the whole sweep), units {along, at {AXIS: unit}, fixed}; values in SI",
    )
    safe.add_argument("atlas", metavar="ATLAS.h5")
    safe.add_argument(
        "--along",
        metavar="AXIS",
        help="the axis the windows run along (default: wob if swept, else the first axis)",
    )
    safe.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="AXIS=VALUE",
        help="only at the grid value of another axis nearest VALUE (SI, or with a unit: "
        "torque=9kN·m); a VALUE beyond half a grid step past either end is refused",
    )
    safe.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    safe.set_defaults(handler=cmd_safe)


def cmd_safe(args: argparse.Namespace) -> int:
    from .atlas import Atlas
    from .atlas_safe import criterion, default_along

    at = axis_values(args.set)
    given = set_texts(args.set)
    with Atlas(args.atlas) as atlas:
        at = leave_out_held(
            at, atlas.axes, spec_holds(atlas.spec), lambda n: f"--set {n}={given[n]}"
        )
        along = args.along or default_along(atlas)
        if along in at:
            how = "--along" if args.along else "the default --along"
            raise ValueError(
                f"--set {along}={given[along]}: {along} is the axis the windows run along "
                f"({how}); hold another axis, or give another with --along"
            )
        snap_notes(atlas, at, given, "atlas safe", "answered")
        try:
            rows = atlas.safe_windows(along, **at)
        except KeyError as exc:  # worded for the Python API: name the option
            name = exc.args[0].split(" ")[0]
            option = f"--set {name}={given[name]}" if name in given else f"--along {along}"
            raise ValueError(f"{option}: {exc.args[0]}") from None
        axes = dict(atlas.axes)
        initials = atlas.initials
        fixed = dict(atlas.spec.fixed)  # what the spec holds for the whole sweep ([model])
    unit = {name: grid_unit(name, values) for name, values in axes.items()}
    if args.json:
        results = {
            "along": along,
            "criterion": criterion(initials),
            "rows": [
                {
                    "at": row.at,
                    "windows": [list(w) for w in row.windows],
                    "beyond": [_beyond(axes[along], w) for w in row.windows],
                    "safe_points": row.safe,
                    "points": row.points,
                    "not_done": row.not_done,
                    "failed": row.failed,
                    "missing": row.not_done - row.failed,
                }
                for row in rows
            ],
            "fixed": fixed,
        }
        units = {"along": axis_unit(along), "at": {n: axis_unit(n) for n in axes if n != along}}
        units["fixed"] = {n: axis_unit(n) for n in fixed}
        print_json(json_document({"atlas": args.atlas}, results, units))
        return 0
    # What every row shares is said once, in the first line: the spec's fixed values, an axis
    # held by --set or of one value (", depth = 3000 m" on every row was a wall of repeats).
    shared = {n: v for n, v in rows[0].at.items() if all(row.at[n] == v for row in rows)}
    said = [f"{n} = {with_unit(n, v, grid_unit(n, [v]))}" for n, v in fixed.items()]
    said += [f"{n} = {with_unit(n, v, unit[n])}" for n, v in shared.items()]
    place = f", at {', '.join(said)}" if said else ""
    print(f"{args.atlas}: safe windows along {along}{place}")
    print(f"  safe: {criterion(initials)}")
    labels = [
        ", ".join(f"{n} = {with_unit(n, v, unit[n])}" for n, v in row.at.items() if n not in shared)
        for row in rows
    ]
    width = max(len(label) + 1 for label in labels)  # every value shared: no label
    for label, row in zip(labels, rows, strict=True):
        shown = _windows(row, along, unit[along])
        print(f"  {label + ':':{width}s}  {shown}" if label else f"  {shown}")
    if len(rows) > 1:
        print(f"  {sum(1 for row in rows if row.windows)} of {len(rows)} have a safe window")
    if any(row.windows for row in rows):  # no window, no edges to place
        print(_edges_note(rows, along, axes[along], unit[along]))
    return 0


def _beyond(values: Any, window: tuple[float, float]) -> list[float | None]:
    """The grid values just outside a window's ends, between which and the window's ends its
    true edges lie; None past the grid's own end, where the atlas says nothing."""
    grid = sorted(float(v) for v in values)
    k, j = grid.index(window[0]), grid.index(window[1])
    return [grid[k - 1] if k > 0 else None, grid[j + 1] if j + 1 < len(grid) else None]


def _edges_note(rows: list, along: str, values: Any, unit: tuple[str, float]) -> str:
    """Where the true edges lie: within a grid step beyond each window's ends, except at the
    grid's own ends, past which the atlas says nothing (a window from W_ob's first value is
    not known to end there: safe 20 kN ... 80 kN on a grid from 20 kN)."""
    lo, hi = float(min(values)), float(max(values))
    ends = {end for row in rows for w in row.windows for end in w}
    note = "  (the true edges lie within a grid step beyond each window's ends"
    more = ";\n   "  # the grid's ends on a line of their own
    first, last = with_unit(along, lo, unit), with_unit(along, hi, unit)
    if lo in ends and hi in ends:
        return note + more + f"one from {first} or to {last}, the grid's ends, may go on past them)"
    if lo in ends:
        return note + more + f"one from {first}, the grid's first value, may begin below it)"
    if hi in ends:
        return note + more + f"one to {last}, the grid's last value, may go on above it)"
    return note + ")"


def _windows(row: Any, along: str, unit: tuple[str, float]) -> str:
    """``wob 20 kN ... 80 kN (4 of 10 points)``, ``none (0 of 10 points)``."""

    def show(lo: float, hi: float) -> str:
        first = with_unit(along, lo, unit)
        return first if lo == hi else f"{first} ... {with_unit(along, hi, unit)}"

    what = f"{along} " + ", ".join(show(*w) for w in row.windows) if row.windows else "none"
    count = f"{row.safe} of {row.points} points"
    # a failed point was computed, and its solver gave up: "not computed" is a missing one's
    if row.failed:
        count += f"; {row.failed} failed"
    if row.not_done > row.failed:
        count += f"; {row.not_done - row.failed} not computed"
    return f"{what} ({count})"
