"""The string options the single-run commands share: ``--preset`` with ``--dof``/``--pipes``,
or ``--tally`` with ``--depth``/``--lump``, the string they name, the notes a bare number's unit
earns on it, and what ``--json`` echoes of them."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from typing import Any

from .cli_options import KILO


def _string_options(parser: argparse.ArgumentParser, presets: Sequence[str]):
    group = parser.add_argument_group(
        "string",
        "one of the paper's strings (--preset), or a real one from its pipe tally (--tally)",
    )
    group.add_argument(
        "--preset",
        choices=presets,
        default=None,
        help="parameter set (default: reduced-scale)",
    )
    group.add_argument(
        "--tally",
        metavar="TALLY.toml",
        help="the string of a pipe tally instead (see 'pydrill string'): one inertia per joint",
    )
    group.add_argument(
        "--depth", help="with --tally: lengthen the drill pipe to this depth (3000m, 9800ft)"
    )
    group.add_argument(
        "--lump", type=int, help="with --tally: drill-pipe joints per element (default 1)"
    )
    size = group.add_mutually_exclusive_group()
    size.add_argument(
        "--dof",
        type=int,
        help="number of inertias, >= 2 (default 4, or 2 for --preset real-string; with --tally: "
        "reduce its string to these)",
    )
    size.add_argument("--pipes", type=int, help="number of drill pipes P (same as --dof P+3)")
    return group


def load_tally_file(path: str):
    """The tally at ``path``; a fault in it is said with the file's name (it said
    "section[0].odd: unknown", which file left to guess)."""
    from .tally import TallyError, load_tally

    try:
        return load_tally(path)
    except TallyError as exc:
        if path in str(exc):  # "cannot read the tally PATH: ..." names it already
            raise
        raise TallyError(f"{path}: {exc}") from None


def for_option(exc: ValueError, option: str, api: str | None = None) -> ValueError:
    """``exc`` (of its own type) saying which option it is about: the API's name that starts its
    message replaced by the option ("dof = 1 is not allowed" -> "--dof = 1 is not allowed"),
    else the option put in front ("--depth: '3000rpm': unit 'rpm' is not a length unit")."""
    import re

    message = str(exc)
    if api is not None and re.match(rf"{api}\b", message):
        return type(exc)(option + message[len(api) :])
    return type(exc)(f"{option}: {message}")


def tally_params(path: str, depth: str | None, lump: int | None, dof: int | None):
    """The tally at ``path`` (lengthened to ``depth``, e.g. ``"3000m"``), as a string of one
    element per ``lump`` joints, reduced to ``dof`` inertias: ``(tally, params)``. A bad value
    is refused naming its option (--depth, --lump, --dof) and the tally's faults its file."""
    from . import units

    tally = load_tally_file(path)
    if depth is not None:
        try:
            tally = tally.at_depth(units.parse(depth, "length"))
        except ValueError as exc:
            raise for_option(exc, "--depth", "depth") from None
    lump = 1 if lump is None else lump
    if lump < 1:
        raise ValueError(f"--lump = {lump} is not allowed: >= 1")
    try:
        return tally, tally.to_params(dof=dof, lump=lump)
    except ValueError as exc:
        for api in ("dof", "lump"):
            if str(exc).startswith(f"{api} "):
                raise for_option(exc, f"--{api}", api) from None
        raise


def _no_tally_options(args: argparse.Namespace) -> None:
    """Refuse the options of a tally's string when no tally is given."""
    for option, value in (("--depth", args.depth), ("--lump", args.lump)):
        if value is not None:
            raise ValueError(
                f"{option} needs --tally: a preset's length is set by --dof or --pipes"
            )


def string_params(args: argparse.Namespace):
    """The string that ``_string_options`` name: a preset of ``--dof`` (or ``--pipes``)
    inertias, or a tally's (``--tally``, ``--depth``, ``--lump``, reduced to ``--dof``)."""
    from . import preset

    if args.tally is None:
        _no_tally_options(args)
        if args.preset == "real-string":
            unit_notes(args)
        else:
            lab_notes(args)
        return preset(args.preset or "reduced-scale", dof=args.dof, pipes=args.pipes)
    if args.preset is not None:
        raise ValueError("give --preset or --tally, not both")
    if args.pipes is not None:
        raise ValueError(
            "--pipes is not allowed with --tally: the tally's joints (and --depth) set them; "
            "--dof N reduces its string to N inertias"
        )
    tally, params = tally_params(args.tally, args.depth, args.lump, args.dof)
    # Titles and reports say which depth: strings of one tally differ by it alone.
    params = params.replace(name=f"{tally.name} at {tally.length:.1f} m")
    unit_notes(args)
    return params


def unit_notes(args: argparse.Namespace) -> None:
    """A bare number is SI, but a driller thinks in kN and rpm: on a real string, a weight of
    a few newtons or a speed of hundreds of rpm was most likely typed in the wrong unit.
    Said on stderr, and the command goes on (the value may be meant)."""
    wob, omega = getattr(args, "wob", None), getattr(args, "omega", None)
    notes = []
    if wob is not None and 0 < wob < 1000.0:
        notes.append(
            f"--wob is {wob:g} N, light for a real string: a bare number is N; for kN write "
            f"{wob:g}kN"
        )
    if omega is not None and omega > 30.0:
        notes.append(
            f"--omega is {omega:g} rad/s = {omega * 30 / math.pi:.0f} rpm: a bare number is "
            f"rad/s; for rpm write {omega:g}rpm"
        )
    for note in notes:
        print(f"pydrill: note: {note}", file=sys.stderr)


def lab_notes(args: argparse.Namespace) -> None:
    """A real string's W_ob on the laboratory string (the default preset, W_ob some 100 N) was
    most likely meant for a real string, its --tally forgotten: --wob 60kN found a steady state
    at 31579 rad/s and said nothing. Said on stderr; the command goes on."""
    wob = getattr(args, "wob", None)
    if wob is not None and wob > KILO:
        print(
            f"pydrill: note: --wob is {wob / 1e3:g} kN, on the reduced-scale laboratory string "
            "(its W_ob is some 100 N); for a real string give --tally TALLY.toml or --preset "
            "real-string",
            file=sys.stderr,
        )


def string_json(args: argparse.Namespace) -> dict[str, Any]:
    """What ``--json`` adds about a tally's string (nothing for a preset)."""
    if args.tally is None:
        return {}
    from . import units

    depth = None if args.depth is None else units.parse(args.depth, "length")
    return {"tally": {"file": args.tally, "depth": depth, "lump": args.lump or 1}}


def string_units(args: argparse.Namespace) -> dict[str, str]:
    """The unit of what :func:`string_json` echoes (nothing for a preset)."""
    return {} if args.tally is None else {"depth": "m"}
