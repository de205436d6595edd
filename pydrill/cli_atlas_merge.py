"""``pydrill atlas merge``: atlases of one study made in parts, as one (``atlas_merge``)."""

from __future__ import annotations

import argparse
import textwrap

from .atlas_grid import axis_unit, with_unit
from .cli_options import check_progress, json_document, print_json, writable_place

DESCRIPTION = (
    "Merge atlases of one study made in parts into one atlas: a grid split along an axis "
    "(run as separate jobs on several machines or a batch system's job array, a range added "
    "later). The parts must be the same sweep (model, simulation, what is recorded) but for "
    "the values of one axis, which they must not share; the merged axis runs in increasing "
    "order and every point is kept as its part holds it (done, failed with its message, or "
    "missing). The merged atlas is the one a single sweep over the whole grid writes: the "
    "same data and the same spec digest, so 'pydrill sweep' of the whole grid's spec "
    "--resume takes it as its own. Nothing is overwritten: --out (and --spec) must not "
    "exist; a part whose sweep is running or was stopped (a journal beside it) is refused. "
    "The merged atlas is held in memory with one part at a time (a merge that would not fit "
    "is refused before anything is read)."
)


def _new_file(text: str) -> str:
    """An argparse type for --out/--spec: a new file in a folder that exists."""
    writable_place(text)
    return text


def register_merge(asub, raw) -> None:
    """Add ``atlas merge`` to the ``atlas`` subcommands ``asub``."""
    merge = asub.add_parser(
        "merge",
        help="merge atlases of one sweep split along an axis into one",
        description=textwrap.fill(DESCRIPTION, 79),
        formatter_class=raw,
        epilog="examples:\n"
        "  pydrill atlas merge low-wob.h5 high-wob.h5 --out paper.h5\n"
        "  pydrill atlas merge part-*.h5 --out study.h5 --spec study.toml --json\n"
        "  pydrill sweep study.toml --out study.h5 --resume   # points still missing\n\n"
        "JSON fields: parts, out, spec (the --spec file, or null), axis, values (along it),\n"
        "  range [first, last] (SI), points, status {done, failed, missing}, units {range}",
    )
    merge.add_argument("parts", nargs="+", metavar="PART.h5", help="the atlases to merge")
    merge.add_argument(
        "--out", required=True, metavar="ATLAS.h5", type=_new_file, help="the merged atlas"
    )
    merge.add_argument(
        "--spec",
        metavar="SPEC.toml",
        type=_new_file,
        help="also write the merged atlas's sweep spec there: the parts' with the merged axis "
        "as a list of its values in SI (to --resume points still missing, or to sweep the "
        "grid again)",
    )
    merge.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    merge.set_defaults(handler=cmd_merge)


def cmd_merge(args: argparse.Namespace) -> int:
    from .atlas_merge import merge_atlases

    # Each part's points read, then the merged atlas's written: on a terminal, a bar.
    bar = None

    def progress(points: int, total: int) -> None:
        nonlocal bar
        if bar is None:  # its total known once the parts are checked
            bar = check_progress(total, "merge", unit="pt")
        bar.update(points)

    try:
        report = merge_atlases(args.parts, args.out, spec_out=args.spec, progress=progress)
    finally:
        if bar is not None:
            bar.close()
    counts = report.status
    if not args.json:
        low, high = (with_unit(report.axis, v) for v in report.span)
        line = (
            f"wrote {report.path}: {report.points} points, {report.values} values of "
            f"{report.axis} ({low} ... {high}) from {len(report.parts)} atlases"
        )
        if counts["failed"] or counts["missing"]:
            line += f" ({counts['failed']} failed, {counts['missing']} missing)"
        print(line)
        if args.spec:
            print(f"wrote {args.spec}: its sweep spec")
        if counts["missing"]:
            spec = args.spec or "SPEC.toml"
            hint = "" if args.spec else " (write its spec with --spec)"
            print(
                f"next: pydrill sweep {spec} --out {report.path} --resume   # the "
                f"{counts['missing']} missing points{hint}"
            )
        return 0
    results = {
        "axis": report.axis,
        "values": report.values,
        "range": list(report.span),
        "points": report.points,
        "status": counts,
    }
    inputs = {"parts": args.parts, "out": args.out, "spec": args.spec}
    print_json(json_document(inputs, results, {"range": axis_unit(report.axis)}))
    return 0
