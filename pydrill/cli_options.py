"""The options the ``pydrill`` commands share: numbers with driller units, figure and output
paths checked before any work, and one layout of --json. The string options (``--preset``,
``--tally``, ...) are in ``cli_string``."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path
from typing import Any


class Given(float):
    """A number of the command line, in SI, that remembers whether it was typed ``bare`` (SI)
    or with its unit: a note on a bare 600 for --omega advises "600rpm", one on a typed
    "6000rpm" does not advise writing what was written."""

    bare = True


def typed_bare(value: object) -> bool:
    """Whether ``value`` of an option was typed as a bare number (or came from a default)."""
    return getattr(value, "bare", True)


def _number(name: str, text: str, kind: str | None) -> float:
    """A plain number is SI; with ``kind``, a driller unit may follow (100kN, 120 rpm)."""
    try:
        return Given(text)
    except ValueError:
        pass
    if kind is not None:
        from . import units

        try:
            value = Given(units.parse(text, kind))
            value.bare = False
            return value
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
        return _load(name, text, value, kind)

    return parse


def _finite(name: str, kind: str | None = None):
    def parse(text: str) -> float:
        value = _number(name, text, kind)
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name} must be finite, got {text}")
        return _load(name, text, value, kind)

    return parse


def _duration(name: str):
    """An argparse type: a simulated time (s), > 0 and at most simulate()'s ``MAX_T_END``."""

    def parse(text: str) -> float:
        from .simulate import MAX_T_END, YEAR

        try:
            value = float(text)
        except ValueError:  # "--t-end 10s" said "must be a number": it is one, with a unit
            raise argparse.ArgumentTypeError(
                f"{name} must be a number of seconds without a unit, e.g. 600 for 10 min, got "
                f"{text!r}"
            ) from None
        if not 0 < value <= MAX_T_END:  # (a NaN fails it too)
            raise argparse.ArgumentTypeError(
                f"{name} = {text} is not allowed: need 0 < {name} <= {_count(int(MAX_T_END))} s "
                f"({MAX_T_END / YEAR:.0f} years)"
            )
        return value

    return parse


def _load(name: str, text: str, value: float, kind: str | None) -> float:
    """A force or torque is at most ``MAX_LOAD`` in size, as simulate() takes it: --wob 1e300
    said a note on the laboratory string, then simulate's error; stability answered for it."""
    from .model import MAX_LOAD

    if kind in ("force", "torque") and abs(value) > MAX_LOAD:
        unit = "N" if kind == "force" else "N m"
        raise argparse.ArgumentTypeError(
            f"{name} = {text} is not allowed: at most {_count(int(MAX_LOAD))} {unit} in size (far "
            "above "
            "any drill string's loads)"
        )
    return value


# What a real string's operating values can be. Beyond these a value is possible but most
# likely mistyped: the command says so in a note (cli_string.unit_notes) and goes on.
#: m: the longest wells drilled reach some 15 km of measured depth (extended-reach wells); the
#: deepest, the Kola borehole, 12.3 km
LONGEST_WELL = 15e3
#: N: no drill bit takes 2000 kN (200 t)
HEAVIEST_WOB = 2e6
#: N·m: the strongest top drives deliver some 100-150 kN·m
TOP_DRIVE_TORQUE = 150e3
#: rpm: the fastest top drives turn some 250-300 rpm
TOP_DRIVE_RPM = 300.0
#: s: a day of drilling; a run that long takes minutes and may end at its step limit
LONG_RUN = 86400.0
#: a friction coefficient of a bit on rock is some 0.1 ... 1 (the paper's: 0.5 sliding, 0.8
#: static); above 2 it is most likely mistyped (mu_static = 8 for 0.8)
MOST_FRICTION = 2.0


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


def _whole_number(text: str) -> int | None:
    """``text`` as an int if it is a whole number, written as one ("1000") or in a float's form
    ("1e3", "1000.0": a count of 10^8 steps is written 1e8); None for anything else (1.5, 1e400,
    nan, "ten")."""
    try:
        return int(text)
    except ValueError:
        pass
    try:
        value = float(text)
    except ValueError:
        return None
    return int(value) if math.isfinite(value) and value.is_integer() else None


def _integer(name: str, low: int, high: int):
    """An argparse type: a whole number ``low`` ... ``high`` (1e8 and 1000.0 are whole),
    refused naming the option and the range."""

    def parse(text: str) -> int:
        value = _whole_number(text)
        if value is None:
            raise argparse.ArgumentTypeError(
                f"{name} must be a whole number {_count(low)} ... {_count(high)}, got {text!r}"
            )
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"{name} = {text} is not allowed: need an integer {_count(low)} ... {_count(high)}"
            )
        return value

    return parse


def _whole(name: str, allowed: str):
    """An argparse type: a whole number (1e3 and 1000.0 are), its range checked where the
    string is built (a tally's size bounds it); anything else is refused with the range (was
    "invalid int value: '1e9'")."""

    def parse(text: str) -> int:
        value = _whole_number(text)
        if value is None:
            raise argparse.ArgumentTypeError(
                f"{name} must be a whole number, {allowed}, got {text!r}"
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
    "max_switch_rate": "--max-switch-rate",
    "t_end": "--t-end",
    "rtol": "--rtol",
    "atol": "--atol",
    "initial": "--initial",
}


def as_options(exc: Exception, names: dict[str, str] = OPTION_NAMES) -> Exception:
    """``exc`` with the API's parameter names in its message replaced by the options that set
    them (``max_steps`` -> ``--max-steps``): the same exception, its other attributes kept."""
    import re

    # --set's refusals are in the words typed: "--set 't_end=1': t_end has an option of its
    # own" became "--set '--t-end=1': --t-end has ...", quoting what was not typed
    if exc.args and isinstance(exc.args[0], str) and not exc.args[0].startswith("--set "):
        pattern = r"(?<![\w-])(" + "|".join(map(re.escape, names)) + r")(?![\w])"
        exc.args = (re.sub(pattern, lambda m: names[m.group(1)], exc.args[0]), *exc.args[1:])
    return exc


#: the core's advice on a run that reached its step limit, worded for simulate()'s caller
_STEP_LIMIT_ADVICE = "; raise max_steps or shorten t_end"


def check_failed(exc: Exception, point: str, simulate_line: str, t_end: float) -> Exception:
    """A failed simulation of a ``--check`` (map, window) as the user of that command can act
    on it: which point failed, and how to run it alone with ``pydrill simulate``, which takes
    ``--max-steps``. The core's "raise max_steps or shorten t_end" named a parameter these
    commands do not have. The same exception type, its ``t_reached`` kept."""
    import re

    message = re.sub(r"\(limit max_switch_rate = (\S+) /s\)", r"(more than \1 a second)", str(exc))
    if message.endswith(_STEP_LIMIT_ADVICE):  # the step limit: a shorter run, or more steps
        message = re.sub(r"^max_steps = (\d+) internal", r"the limit of \1 internal", message)
        message = (
            f"{message[: -len(_STEP_LIMIT_ADVICE)]}; shorten --t-end (each check simulates "
            f"{t_end:g} s), or run that point alone with more steps: {simulate_line} "
            f"--t-end {t_end:g} --max-steps 100000000"
        )
    else:
        message += f"; to run that point alone: {simulate_line} --t-end {t_end:g}"
    new = type(exc)(f"the check at {point} failed: {message}")
    new.t_reached = getattr(exc, "t_reached", None)  # type: ignore[attr-defined]
    return new


# What matplotlib writes with what it installs, chosen by the file's suffix. Checked when the
# command line is read, so that a long computation does not end in "format not supported".
from .file_kinds import FIGURE_SUFFIXES  # noqa: E402  (one list, also for the atlas's name)


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


def _list(name: str):
    """An argparse type: comma-separated numbers, none of them empty (``1,,2`` made a string of
    two inertias, ``,`` said "dof = 0 is not allowed" of no option)."""

    def parse(text: str) -> list[float]:
        try:
            return [float(v) for v in text.split(",")]
        except ValueError:
            empty = " (an entry is empty)" if any(not v.strip() for v in text.split(",")) else ""
            raise argparse.ArgumentTypeError(
                f"{name} must be comma-separated numbers, got {text!r}{empty}"
            ) from None

    return parse


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


def bar_size() -> dict[str, int]:
    """tqdm's ``ncols`` and ``nrows`` for a bar on stderr: the terminal's size, or 80 x 24 on
    one that says it is 0 x 0 (a pty nobody sized: ``script`` in a batch job, some CI
    runners), where tqdm hid the bar below its zero rows and drew nothing at all."""
    try:
        size = os.get_terminal_size(sys.stderr.fileno())
    except (OSError, ValueError):  # not a terminal, or stderr closed
        size = os.terminal_size((0, 0))
    return {"ncols": size.columns or 80, "nrows": size.lines or 24}


def check_progress(total: int, what: str, unit: str = "run") -> Any:
    """A progress bar on stderr for the ``total`` simulations of a --check (or the ``total``
    ``unit`` of other long work), on a terminal only (a log or a pipe gets none): 1200 checks
    of a 334-inertia string take minutes, and the command said nothing until the end. Call
    ``update()`` after each; ``close()`` at the end."""
    from tqdm import tqdm

    return tqdm(
        total=total,
        desc=what,
        unit=unit,
        file=sys.stderr,
        disable=not sys.stderr.isatty(),
        **bar_size(),
    )


def print_json(data: Any) -> None:
    """Every command's --json output: one document (laid out by :func:`json_document`),
    indented, strict JSON (no NaN/Infinity, which many parsers refuse; values without a number
    are written as null beforehand)."""
    from .cli_parser import _Parser

    print(json.dumps(data, indent=2, allow_nan=False))
    _Parser.json_sent = True
