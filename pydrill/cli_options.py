"""The options the ``pydrill`` commands share: numbers with driller units, figure and output
paths checked before any work, and the string options (``--preset``/``--dof``/``--pipes`` or
``--tally``/``--depth``/``--lump``) with the string they name."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any


def _number(name: str, text: str, kind: str | None) -> float:
    """A plain number is SI; with ``kind``, a driller unit may follow (100kN, 120 rpm)."""
    try:
        return float(text)
    except ValueError:
        pass
    if kind is not None:
        from . import units

        try:
            return units.parse(text, kind)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(
                f"{name} must be a number, got {text!r} ({exc})"
            ) from None
    raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}")


def _positive(name: str, kind: str | None = None):
    def parse(text: str) -> float:
        value = _number(name, text, kind)
        if not math.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"{name} must be a finite number > 0, got {text}")
        return value

    return parse


def _finite(name: str, kind: str | None = None):
    def parse(text: str) -> float:
        value = _number(name, text, kind)
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name} must be finite, got {text}")
        return value

    return parse


#: above this many N (or N·m) a string is a real one: its forces in kN, its torques in kN·m, in
#: text as on its figures (plot.py draws with this threshold too)
KILO = 5000.0


def kilo(*forces_and_torques: float) -> bool:
    """Whether these are a real string's forces (N) and torques (N·m): any above ``KILO``. Then
    the text gives all of them in kN and kN m (a driller's 60 kN beside 3.8 kN m, not 3800 N m),
    and a laboratory string's stay in N and N m."""
    return any(math.isfinite(v) and abs(v) > KILO for v in forces_and_torques)


def shown(value: float, unit: str, big: bool, fmt: str = "g") -> str:
    """``value`` in SI ``unit`` ("N", "N m"), in kilo-units if ``big`` (see :func:`kilo`):
    ``shown(60000, "N", True)`` is "60 kN"."""
    return f"{value / 1e3:{fmt}} k{unit}" if big else f"{value:{fmt}} {unit}"


def _count(n: int) -> str:
    """A bound as a reader takes it in: 1e12, not 1000000000000."""
    digits = len(str(n)) - 1
    return f"1e{digits}" if n >= 10**6 and n == 10**digits else str(n)


def _integer(name: str, low: int, high: int):
    """An argparse type: an integer ``low`` ... ``high``, refused naming the option."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"{name} = {value} is not allowed: need an integer {_count(low)} ... {_count(high)}"
            )
        return value

    return parse


def _fraction(name: str):
    """An argparse type: a number in (0, 1]."""

    def parse(text: str) -> float:
        value = _number(name, text, None)
        if not 0 < value <= 1:  # (a NaN fails it too)
            raise argparse.ArgumentTypeError(
                f"{name} = {text} is not allowed: need 0 < {name} <= 1 (a fraction of the run)"
            )
        return value

    return parse


#: the API's names of the options in messages from simulate(), as the command line names them
OPTION_NAMES = {
    "window_fraction": "--window",
    "n_out": "--n-out",
    "max_steps": "--max-steps",
    "t_end": "--t-end",
    "rtol": "--rtol",
    "atol": "--atol",
}


def as_options(exc: Exception, names: dict[str, str] = OPTION_NAMES) -> Exception:
    """``exc`` with the API's parameter names in its message replaced by the options that set
    them (``max_steps`` -> ``--max-steps``): the same exception, its other attributes kept."""
    import re

    if exc.args and isinstance(exc.args[0], str):
        pattern = r"(?<![\w-])(" + "|".join(map(re.escape, names)) + r")(?![\w])"
        exc.args = (re.sub(pattern, lambda m: names[m.group(1)], exc.args[0]), *exc.args[1:])
    return exc


# What matplotlib writes with what it installs, chosen by the file's suffix. Checked when the
# command line is read, so that a long computation does not end in "format not supported".
FIGURE_SUFFIXES = tuple(".png .pdf .svg .svgz .eps .ps .jpg .jpeg .tif .tiff .webp".split())


def figure_path(text: str) -> str:
    """An argparse type for ``--plot FILE``: a suffix matplotlib can write, in a directory
    that is (or can be made) writable."""
    if Path(text).suffix.lower() not in FIGURE_SUFFIXES:
        raise argparse.ArgumentTypeError(
            f"{text!r}: a figure's format is its suffix, one of " + ", ".join(FIGURE_SUFFIXES)
        )
    writable_place(text)
    return text


def writable_place(text: str) -> None:
    """Refuse, before any work, an output file in a folder that does not exist (a typo would
    otherwise make a tree of folders, at / if need be), under a file, or in a folder this user
    may not write."""
    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a directory; give a file name in it")
    folder = path.absolute().parent
    for parent in (folder, *folder.parents):
        if parent.exists():
            if not parent.is_dir():
                raise argparse.ArgumentTypeError(f"{text!r}: {parent} is a file, not a directory")
            if parent != folder:
                raise argparse.ArgumentTypeError(
                    f"{text!r}: there is no folder {folder}; make it first (mkdir -p)"
                )
            if not os.access(parent, os.W_OK | os.X_OK):
                raise argparse.ArgumentTypeError(f"{text!r}: cannot write in {parent}")
            return


def os_error_message(exc: OSError, argv: Sequence[str]) -> str:
    """A one-line message for a file that could not be read or written: the option that named
    it (``--plot /proc/x.png: No such file or directory``), not ``[Errno 2] ...``."""
    path = exc.filename
    if path is None or not exc.strerror:
        return str(exc)
    path = os.fsdecode(path)
    reason = exc.strerror
    if isinstance(exc, FileExistsError) and Path(path).exists() and not Path(path).is_dir():
        reason = "a file of that name exists; give a folder"
    named = None
    for k, token in enumerate(argv):
        option, eq, value = token.partition("=")
        if eq and option.startswith("--") and _same_path(value, path):
            named = option
        elif k and argv[k - 1].startswith("--") and _same_path(token, path):
            named = argv[k - 1]
        if named:
            return f"{named} {path}: {reason}"
    return f"{path}: {reason}"


def _same_path(given: str, path: str) -> bool:
    """Whether the command line's ``given`` is ``path`` or a folder it lies in."""
    try:
        a, b = Path(given).absolute(), Path(path).absolute()
    except (OSError, ValueError):
        return False
    return a == b or a in b.parents


def _list(name: str):
    def parse(text: str) -> list[float]:
        try:
            return [float(v) for v in text.split(",") if v.strip()]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} must be comma-separated numbers, got {text!r}"
            ) from None

    return parse


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


def json_document(
    inputs: dict[str, Any],
    results: dict[str, Any],
    units: dict[str, Any] | None = None,
    plot: str | None = None,
) -> dict[str, Any]:
    """Every command's --json object, laid out in one order: the ``inputs`` it was given,
    echoed (the string, the operating point, the files); the ``results``; ``units`` of the
    quantities (a unit, or for a group a dict of them: ``{"axes": {...}}``); last ``plot``, the
    figure's path, present iff a figure was written (--plot given, and neither the save failed
    nor the command stopped first)."""
    both = inputs.keys() & results.keys()
    assert not both and not {"units", "plot"} & (inputs.keys() | results.keys()), both
    data = {**inputs, **results}
    if units is not None:
        data["units"] = units
    if plot is not None:
        data["plot"] = plot
    return data


def string_units(args: argparse.Namespace) -> dict[str, str]:
    """The unit of what :func:`string_json` echoes (nothing for a preset)."""
    return {} if args.tally is None else {"depth": "m"}


def check_progress(total: int, what: str) -> Any:
    """A progress bar on stderr for the ``total`` simulations of a --check, on a terminal only
    (a log or a pipe gets none): 1200 checks of a 334-inertia string take minutes, and the
    command said nothing until the end. Call ``update()`` after each; ``close()`` at the end."""
    from tqdm import tqdm

    return tqdm(
        total=total, desc=what, unit="run", file=sys.stderr, disable=not sys.stderr.isatty()
    )


def print_json(data: Any) -> None:
    """Every command's --json output: one document (laid out by :func:`json_document`),
    indented, strict JSON (no NaN/Infinity, which many parsers refuse; values without a number
    are written as null beforehand)."""
    print(json.dumps(data, indent=2, allow_nan=False))
