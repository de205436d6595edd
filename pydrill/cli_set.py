"""``--set NAME=VALUE``: the string's scalar parameters (damping at the top drive and the bit,
the bit's radius, the friction law) changed from the command line, for every command that
builds a string from ``--preset`` or ``--tally``; and how the command says what it changed."""

from __future__ import annotations

import argparse
from typing import Any

from .model import _LISTS, _SCALARS, _UNITS
from .suggest import did_you_mean


def add_set_option(parser: Any, help: str) -> None:
    """The ``--set NAME=VALUE`` option (repeatable, into ``args.set_params``) of ``parser``
    (a parser or an argument group)."""
    parser.add_argument(
        "--set", action="append", default=[], dest="set_params", metavar="NAME=VALUE", help=help
    )


def set_params(args: argparse.Namespace) -> dict[str, float]:
    """``--set NAME=VALUE`` options as ``{name: SI value}``: the string's scalar parameters
    (a preset's or a tally's), each once, a VALUE with a unit where the parameter measures
    something (``bit_radius=4.5in``, ``top_damping=50 N·m·s/rad``; a bare number is SI)."""
    from .atlas_grid import coordinate

    out: dict[str, float] = {}
    for item in getattr(args, "set_params", None) or []:
        name, equals, value = (part.strip() for part in item.partition("="))
        if not (name and equals and value):
            raise ValueError(
                f"--set {item!r}: expected NAME=VALUE, e.g. bit_damping=0.05 or bit_radius=4.5in"
            )
        if name not in _SCALARS:
            what = (
                f"{name} is a list, one value per {'inertia' if name == 'inertias' else 'link'}"
                + (f": give --{name}" if hasattr(args, name) else "")
                if name in _LISTS
                else f"{name} has an option of its own: give --{name}"
                if hasattr(args, name)
                else f"{name} is not one of the string's parameters"
                + did_you_mean(name, _SCALARS + _LISTS)
            )
            raise ValueError(f"--set {item!r}: {what}; --set takes " + ", ".join(_SCALARS))
        if name in out:  # --set a=1 --set a=2: the last would win, silently
            raise ValueError(f"--set {item!r}: {name} is given twice; give each parameter once")
        try:
            out[name] = coordinate(name, value)
        except ValueError as exc:  # "bit_radius = '3 kg': unit 'kg' is not a length unit; ..."
            raise ValueError(f"--set {item!r}: {exc}") from None
    return out


def set_line(args: argparse.Namespace) -> str | None:
    """The first line of a command's text output when ``--set`` changed the string: what it
    changed, in SI (``changed         bit_damping = 0.05 N·m·s/rad, bit_radius = 0.1016 m``),
    so that a report read later says which string it was. None without ``--set``."""
    sets = set_params(args)
    if not sets:
        return None
    shown = [
        f"{name} = {value:.6g}" + ("" if name.startswith("mu_") else f" {_UNITS[name]}")
        for name, value in sets.items()
    ]
    return "changed         " + ", ".join(shown)


def say_changed(args: argparse.Namespace) -> None:
    """Print :func:`set_line`, if ``--set`` changed anything."""
    line = set_line(args)
    if line:
        print(line)


def _set_refused(exc: ValueError, sets: dict[str, float]) -> ValueError:
    """The string's refusal of a ``--set`` value, naming the option ("--set mu_static = 0.1 is
    not allowed: need mu_static > mu_coulomb (0.5)"); any other refusal as it is."""
    for name in sets:
        if str(exc).startswith(f"{name} "):
            return type(exc)(f"--set {exc}")
    return exc


def friction_notes(label: str, values: dict[str, float], verb: str = "=") -> list[str]:
    """A note on each friction coefficient of ``values`` (mu_static, mu_coulomb) above
    ``cli_options.MOST_FRICTION``, and on a bit_radius wider than any bit, most likely mistyped,
    in the words of ``label`` (the option or key, "--set " or "axes."): ``--set mu_static = 8:
    ...``; other names are passed over."""
    from .cli_options import MOST_FRICTION
    from .tally import WIDEST_BARE_DIAMETER

    notes = []
    # --set bit_radius=8.5 (8.5 in meant; a bare number is m) built a bit 17 m across without
    # a word, where the tally refuses a bit diameter beyond 5 m and notes one beyond 1 m.
    radius = values.get("bit_radius")
    if radius is not None and radius > WIDEST_BARE_DIAMETER / 2:
        inches = f"bit_radius={radius:g}in" if label.startswith("--") else f'"{radius:g} in"'
        notes.append(
            f"{label}bit_radius {verb} {radius:g} m: a bit {2 * radius:g} m across, wider than "
            f"any bit (at most some {WIDEST_BARE_DIAMETER:g} m); a bare number is m: for "
            f"inches write {inches}"
        )
    for name in ("mu_static", "mu_coulomb"):
        value = values.get(name)
        if value is None or not value > MOST_FRICTION:
            continue
        meant = f"; {value / 10:g} meant?" if value / 10 <= MOST_FRICTION else ""
        notes.append(
            f"{label}{name} {verb} {value:g}: a friction coefficient above any bit's on rock "
            f"(some 0.1 ... 1; most likely mistyped above {MOST_FRICTION:g}{meant})"
        )
    return notes
