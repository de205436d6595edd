"""The string options the single-run commands share: ``--preset`` with ``--dof``/``--pipes``,
or ``--tally`` with ``--depth``/``--lump``, the string they name, the notes a bare number's unit
earns on it, and what ``--json`` echoes of them."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from typing import Any

from .cli_options import (
    HEAVIEST_WOB,
    KILO,
    LONG_RUN,
    LONGEST_WELL,
    TOP_DRIVE_RPM,
    TOP_DRIVE_TORQUE,
    _whole,
    typed_bare,
)
from .cli_set import _set_refused, add_set_option, friction_notes, set_notes, set_params
from .cli_string_lists import list_refused
from .model import _SCALARS, _UNITS, MAX_DOF


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
        "--depth",
        help="with --tally: lengthen the drill pipe to this depth, > 0 (3000m, 9800ft; a bare "
        "number is m)",
    )
    group.add_argument(
        "--lump",
        type=_whole("--lump", ">= 1"),
        help="with --tally: drill-pipe joints per element, >= 1 (default 1)",
    )
    size = group.add_mutually_exclusive_group()
    size.add_argument(
        "--dof",
        type=_whole("--dof", f"2 ... {MAX_DOF}"),
        help=f"number of inertias, 2 ... {MAX_DOF} (default 4, or 2 for --preset real-string; with "
        "--tally: reduce its string to these, at most one per element)",
    )
    size.add_argument(
        "--pipes",
        type=_whole("--pipes", f"1 ... {MAX_DOF - 3}"),
        help=f"number of drill pipes P, 1 ... {MAX_DOF - 3} (same as --dof P+3)",
    )
    add_set_option(
        group,
        "change one of the string's parameters, as often as needed: "
        + ", ".join(_SCALARS)
        + " (SI, or with a unit: bit_damping=0.05, 'bit_radius=4.5 in', stribeck_velocity=10rpm)",
    )
    return group


def load_tally_file(path: str):
    """The tally at ``path``; a fault in it is said with the file's name (it said
    "section 1 (drill-pipe), odd: unknown", which file left to guess)."""
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
            meters = units.parse(depth, "length")
            tally = tally.at_depth(meters)
        except ValueError as exc:
            raise for_option(exc, "--depth", "depth") from None
    lump = 1 if lump is None else lump
    if lump < 1:
        raise ValueError(f"--lump = {lump} is not allowed: >= 1")
    try:
        params = tally.to_params(dof=dof, lump=lump)
    except ValueError as exc:
        for api in ("dof", "lump"):
            if str(exc).startswith(f"{api} "):
                raise for_option(exc, f"--{api}", api) from None
        raise
    if depth is not None:  # once the string is built: a refusal is one line, no note before it
        depth_note(meters, depth)
    _say(tally_notes(tally, path, depth is None))
    return tally, params


def _no_tally_options(args: argparse.Namespace) -> None:
    """Refuse the options of a tally's string when no tally is given."""
    for option, value in (("--depth", args.depth), ("--lump", args.lump)):
        if value is not None:
            raise ValueError(
                f"{option} needs --tally: a preset's length is set by --dof or --pipes"
            )


def string_params(args: argparse.Namespace, overrides: dict[str, Any] | None = None):
    """The string that ``_string_options`` name: a preset of ``--dof`` (or ``--pipes``)
    inertias, or a tally's (``--tally``, ``--depth``, ``--lump``, reduced to ``--dof``), with
    ``overrides`` of its fields (``--inertias``, ...). The notes on the values typed follow
    once it is built: a refused string is one line, not a note and then the error."""
    from . import preset

    sets = set_params(args)
    if args.tally is None:
        _no_tally_options(args)
        try:
            params = preset(
                args.preset or "reduced-scale",
                dof=args.dof,
                pipes=args.pipes,
                **(overrides or {}),
                **sets,
            )
        except ValueError as exc:
            if "for preset 'real-string'" in str(exc):  # the core's words are for C++ users
                size = (
                    f"--dof {args.dof}"
                    if args.dof is not None
                    else f"--pipes {args.pipes}"
                    if args.pipes is not None
                    else "a string of another length (--inertias ...)"
                )
                raise ValueError(
                    f"{size} is not allowed with --preset real-string: it is the paper's 2-DOF "
                    "string (Eq. 53); give --dof 2, or the string pipe by pipe from a tally: "
                    "--tally TALLY.toml [--depth D] [--dof N] (examples/tallies/paper-eq53.toml "
                    "is the paper's)"
                ) from None
            for api in ("dof", "pipes"):  # a size given as 1e9: "--dof = ...", not "dof = ..."
                if str(exc).startswith(f"{api} "):
                    raise for_option(exc, f"--{api}", api) from None
            raise list_refused(exc, overrides or {}) or _set_refused(exc, sets) from None
        if args.preset == "real-string":
            unit_notes(args)
        else:
            lab_notes(args)
        return params
    if args.preset is not None:
        raise ValueError("give --preset or --tally, not both")
    if args.pipes is not None:
        raise ValueError(
            "--pipes is not allowed with --tally: the tally's joints (and --depth) set them; "
            "--dof N reduces its string to N inertias"
        )
    tally, params = tally_params(args.tally, args.depth, args.lump, args.dof)
    for key, values in (overrides or {}).items():
        # An override must fit the tally's string, whose size the tally sets: a list of
        # another length said "stiffnesses has 111 entries: dof = 2 needs 1" of no option.
        need = params.dof if key == "inertias" else params.dof - 1
        if len(values) != need:
            raise ValueError(
                f"--{key} has {len(values)} values, but the tally's string has {params.dof} "
                f"inertias: give {need} (one per {'inertia' if key == 'inertias' else 'link'}), "
                f"or leave --{key} out"
            )
    # Titles and reports say which depth: strings of one tally differ by it alone.
    try:
        params = params.replace(
            name=f"{tally.name} at {tally.length:.1f} m", **(overrides or {}), **sets
        )
    except ValueError as exc:  # a tally's string of --dampings -1,...: named as a preset's
        raise list_refused(exc, overrides or {}) or _set_refused(exc, sets) from None
    unit_notes(args)
    return params


def unit_notes(args: argparse.Namespace) -> None:
    """A bare number is SI, but a driller thinks in kN and rpm: on a real string, a weight of
    a few newtons or a speed of hundreds of rpm was most likely typed in the wrong unit; a
    value beyond what any rig does (a 60000 kN weight, 6000 rpm) most likely mistyped. Said on
    stderr, and the command goes on (the value may be meant)."""
    notes = []
    for option, key in (("--wob", "wob"), ("--wob-max", "wob_max")):
        wob = getattr(args, key, None)
        if wob is not None and 0 < wob < 1000.0:
            notes.append(
                f"{option} is {wob:g} N, light for a real string: a bare number is N; for kN "
                f"write {wob:g}kN"
                if typed_bare(wob)
                else f"{option} is {wob:g} N, light for a real string (tens to hundreds of kN)"
            )
        elif wob is not None and wob > HEAVIEST_WOB:
            notes.append(
                f"{option} is {wob / 1e3:g} kN, heavier than any drill bit takes (at most some "
                f"{HEAVIEST_WOB / 1e3:g} kN, {HEAVIEST_WOB / 1e4:g} t)"
            )
    for option, key in (("--torque", "torque"), ("--torque-max", "torque_max")):
        torque = getattr(args, key, None)
        if torque is not None and 0 < abs(torque) < 100.0 and typed_bare(torque):
            notes.append(
                f"{option} is {torque:g} N m, light for a real string: a bare number is N m; "
                f"for kN m write {torque:g}kN*m"
            )
        elif torque is not None and abs(torque) > TOP_DRIVE_TORQUE:
            notes.append(
                f"{option} is {torque / 1e3:g} kN m, more than any top drive delivers (the "
                f"strongest some {TOP_DRIVE_TORQUE / 1e3:g} kN m)"
            )
    omega = getattr(args, "omega", None)
    if omega is not None and omega > 30.0 and typed_bare(omega):
        notes.append(
            f"--omega is {omega:g} rad/s = {omega * 30 / math.pi:.0f} rpm: a bare number is "
            f"rad/s; for rpm write {omega:g}rpm"
        )
    elif omega is not None and omega * 30 / math.pi > TOP_DRIVE_RPM:
        notes.append(
            f"--omega is {omega * 30 / math.pi:.4g} rpm, faster than any top drive turns (some "
            f"{TOP_DRIVE_RPM:g} rpm at most)"
        )
    _say(notes + set_notes(args) + run_notes(args))


def lab_notes(args: argparse.Namespace) -> None:
    """A real string's W_ob on the laboratory string (the default preset, W_ob some 100 N) was
    most likely meant for a real string, its --tally forgotten: --wob 60kN found a steady state
    at 31579 rad/s and said nothing. Said on stderr; the command goes on."""
    notes = []
    for option, key, unit, typical in (
        ("--wob", "wob", "kN", "W_ob is some 100 N"),
        ("--wob-max", "wob_max", "kN", "W_ob is some 100 N"),
        ("--torque", "torque", "kN m", "torque is some 10 N m"),
        ("--torque-max", "torque_max", "kN m", "torque is some 10 N m"),
    ):
        value = getattr(args, key, None)
        if value is not None and abs(value) > KILO:
            notes.append(
                f"{option} is {value / 1e3:g} {unit}, on the reduced-scale laboratory string "
                f"(its {typical}); for a real string give --tally TALLY.toml or --preset "
                "real-string"
            )
    _say(notes + set_notes(args) + run_notes(args))


def run_notes(args: argparse.Namespace) -> list[str]:
    """The notes on a simulated time: more than a day of drilling (--t-end 1e9 ran for minutes
    to end at the step limit; the stick-slip it looks for repeats within seconds)."""
    t_end = getattr(args, "t_end", None)
    if t_end is None or t_end <= LONG_RUN:
        return []
    days = f"{t_end / LONG_RUN:.3g}"
    days += " day" if days == "1" else " days"  # 86401 s was "(1 days)"
    return [
        f"--t-end is {t_end:g} s ({days}) of drilling: a run that long "
        "takes minutes and may end at its step limit; stick-slip repeats within seconds"
    ]


def depth_note(depth: float, text: str, feet: str | None = None) -> None:
    """A depth beyond the longest well ever drilled (--depth 30000m built a 3334-inertia string
    and said nothing): most likely mistyped. Said on stderr; the command goes on. ``text`` is
    the depth as written; a bare number's note says how to write feet (``feet``, else it
    with ft: window's list of depths gives the whole list in feet)."""
    if depth > LONGEST_WELL:
        feet = feet or f"{text.strip()}ft"
        bare = f"; a bare number is m: for feet write {feet}" if _bare(text) else ""
        _say(
            [
                f"--depth {depth / 1e3:g} km is longer than any well ever drilled (the longest "
                f"reach some {LONGEST_WELL / 1e3:g} km, the deepest, the Kola borehole, 12.3 km)"
                + bare
            ]
        )


def tally_notes(tally: Any, path: str, own_length: bool = True) -> list[str]:
    """The notes on a tally's file: a joint length most likely mistyped (``tally.notes``) and,
    with ``own_length`` (no --depth lengthened it), a string longer than any well ever drilled
    (a bare "length = 310", read as m for 310 ft, made a 100 km string and said nothing)."""
    notes = [f"{path}: {note}" for note in tally.notes]
    mu = {"mu_static": tally.mu_static, "mu_coulomb": tally.mu_coulomb}
    notes += friction_notes(f"{path}: bit.", mu)
    if own_length and tally.length > LONGEST_WELL:
        notes.append(
            f"{path}: the string is {tally.length / 1e3:g} km long, longer than any well ever "
            f"drilled (the longest reach some {LONGEST_WELL / 1e3:g} km, the deepest, the Kola "
            "borehole, 12.3 km): check the sections' counts and lengths"
        )
    return notes


def _bare(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _say(notes: list[str]) -> None:
    for note in notes:
        print(f"pydrill: note: {note}", file=sys.stderr)


def point_command(args: argparse.Namespace, wob: float, torque: float, **more: Any) -> str:
    """The ``pydrill simulate`` command line of the string ``args`` name at (``wob``,
    ``torque``), with ``more`` options (``dof=10``, ``initial="rest"``; None left out): what a
    failed check advises running alone. A real string's loads in kN and kN m."""
    import shlex

    options: dict[str, Any] = {}
    if args.tally is not None:
        options.update(tally=args.tally, depth=args.depth, lump=args.lump, dof=args.dof)
    else:
        options.update(preset=args.preset, dof=args.dof, pipes=args.pipes)
    options.update(more)
    if abs(wob) > KILO or abs(torque) > KILO:
        options.update(wob=f"{wob / 1e3:.8g}kN", torque=f"{torque / 1e3:.8g}kNm")
    else:
        options.update(wob=f"{wob:.8g}", torque=f"{torque:.8g}")
    words = ["pydrill", "simulate"]
    for key, value in options.items():
        if value is not None:
            words += [f"--{key.replace('_', '-')}", shlex.quote(str(value))]
    from .cli_string_lists import list_overrides

    for key, values in list_overrides(args).items():  # map's check of a string of lists
        words += [f"--{key}", ",".join(repr(v) for v in values)]
    for item in getattr(args, "set_params", None) or []:  # the string --set changed
        words += ["--set", shlex.quote(item)]
    return " ".join(words)


def string_json(args: argparse.Namespace) -> dict[str, Any]:
    """What ``--json`` adds about the string: the parameters ``--set`` changed (SI), and a
    tally's file, depth and lump (nothing else for a preset)."""
    sets = {"set": set_params(args)} if getattr(args, "set_params", None) else {}
    if args.tally is None:
        return sets
    from . import units

    depth = None if args.depth is None else units.parse(args.depth, "length")
    return {"tally": {"file": args.tally, "depth": depth, "lump": args.lump or 1}, **sets}


def string_inputs(args: argparse.Namespace, params: Any) -> dict[str, Any]:
    """The string as the analysis commands' ``--json`` echo it, as simulate's does: a preset's
    name under ``preset``; a tally's file, depth and lump under ``tally`` and the string it made
    under ``string``, with ``preset`` null (it held "paper-eq53 at 3001.5 m", no preset); the
    parameters ``--set`` changed under ``set``."""
    from .cli_string_lists import list_overrides

    lists = list_overrides(args)  # as simulate's inputs echo them: those given
    if args.tally is None:
        return {"preset": params.name, **string_json(args), **lists}
    return {"preset": None, **string_json(args), "string": params.name, **lists}


def string_units(args: argparse.Namespace) -> dict[str, str]:
    """The units of what :func:`string_json` and :func:`string_inputs` echo."""
    from .cli_string_lists import LIST_UNITS, list_overrides

    # (a friction coefficient is a pure number, as the JSON's other ratios)
    units = {n: "1" if n.startswith("mu_") else _UNITS[n] for n in set_params(args)}
    units.update({key: LIST_UNITS[key] for key in list_overrides(args)})
    return units if args.tally is None else {"depth": "m", **units}
