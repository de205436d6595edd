"""``--set NAME=VALUE``: the string's scalar parameters (damping at the top drive and the bit,
the bit's radius, the friction law) changed from the command line, for every command that
builds a string from ``--preset`` or ``--tally``; and how the command says what it changed."""

from __future__ import annotations

import argparse
from typing import Any

from .model import _LISTS, _SCALARS, _UNITS
from .suggest import did_you_mean, radius_hint


def add_set_option(parser: Any, help: str) -> None:
    """The ``--set NAME=VALUE`` option (repeatable, into ``args.set_params``) of ``parser``
    (a parser or an argument group)."""
    parser.add_argument(
        "--set", action="append", default=[], dest="set_params", metavar="NAME=VALUE", help=help
    )


#: what each list of the chain has one value per, and its option's metavar (simulate's)
_EACH = {"inertias": "inertia", "stiffnesses": "link", "dampings": "link"}
_METAVARS = {"inertias": "I0,I1,...", "stiffnesses": "K0,K1,...", "dampings": "C0,C1,..."}


def _takes(args: argparse.Namespace) -> tuple[str, ...]:
    """The names this command's ``--set`` takes: window's, without karnopp_band (its checks
    use the exact law), listed in ``args.set_names``; every other command's, all scalars."""
    return tuple(getattr(args, "set_names", None) or _SCALARS)


def _unknown_hint(name: str, args: argparse.Namespace, value: str = "") -> str:
    """The "did you mean" of a ``--set`` name that is none of the string's: one this command's
    --set takes; or, when the name is closest to a list of the chain (top_inertia, inertia:
    inertias), the option that sets that list. "(did you mean 'inertias'?)" sent the user to
    --set inertias=..., which is refused as a list."""
    takes = _takes(args)
    if name.lower().endswith("diameter"):
        return radius_hint(value)
    hint = did_you_mean(name, takes + _LISTS)
    listed = next((key for key in _LISTS if hint == f" (did you mean {key!r}?)"), None)
    if listed is None:
        return hint
    each = f"the {listed} are a list, one value per {_EACH[listed]}"
    option = f"--{listed} {_METAVARS[listed]}"
    # a scalar near the name as well ("damping": top_damping, bit_damping) may be the one meant
    scalar = did_you_mean(name, takes).removeprefix(" (").removesuffix(")")
    also = f"; or {scalar}" if scalar else ""
    if _own_option(listed, args):
        return f" ({each}: give {option}{also})"
    return (  # the commands that take the lists (add_list_options)
        f" ({each}: this command does not change them; pydrill simulate, stability, hopf, "
        f"bifurcation and map do, with {option}{also})"
    )


#: the friction laws --friction picks between (simulate's choices)
_LAWS = ("exact", "karnopp")
_COEFFICIENTS = "the bit's friction coefficients are mu_coulomb (sliding) and mu_static (at rest)"


def _misnamed(name: str, value: str, args: argparse.Namespace, own: str | None) -> str | None:
    """What a ``--set`` name no typo-hint serves means: friction=0.5 was sent to --friction,
    which takes the friction law (exact|karnopp), not a coefficient; mu=0.5 and beta=0.2 got
    no hint (the coefficients are mu_coulomb and mu_static; beta is a tally's element
    damping, its [damping] beta, which --set does not change). None for any other name."""
    lower = name.lower()
    if lower == "friction" and own == "--friction" and value.lower() in _LAWS:
        return f"friction has an option of its own: give --friction {value.lower()}"
    if lower in ("beta", "damping.beta", "damping_beta", "β"):
        return (
            "beta is a tally's element damping (every element's c = beta·k, in s), set as "
            "beta in the [damping] table of the TALLY.toml, which --set does not change: "
            "edit it there"
        )
    if did_you_mean(name, _takes(args)) or not (
        "friction" in lower or lower.startswith("mu") or lower in ("coulomb", "static")
    ):
        return None
    law = (
        f" ({own} picks the friction law, {' or '.join(_LAWS)}, not a coefficient)"
        if lower == "friction" and own == "--friction"
        else ""
    )
    try:
        example = f"{float(value):g}"
    except ValueError:
        example = "0.5"
    return (
        f"{name} is not one of the string's parameters{law}: {_COEFFICIENTS}, "
        f"e.g. --set mu_coulomb={example}"
    )


def option_names(parser: argparse.ArgumentParser, args: argparse.Namespace) -> dict[str, str]:
    """What the user types for each value of the command ``args`` ran: ``{"wob_max":
    "--wob-max", "tally": "TALLY.toml"}`` (an option, or a positional argument's metavar)."""
    for dest in ("command", "atlas_command"):
        sub = next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)
        if sub is None or getattr(args, dest, None) not in sub.choices:
            break
        parser = sub.choices[getattr(args, dest)]
    names = {}
    for action in parser._actions:
        if action.dest in (argparse.SUPPRESS, "help", "set_params"):
            continue
        longest = max(action.option_strings, key=len, default=None)
        names[action.dest] = longest or str(action.metavar or action.dest)
    return names


def _own_option(name: str, args: argparse.Namespace) -> str | None:
    """The option (or argument) of this command that sets ``name``, if one does: --set wob=1
    is refused naming --wob. "give --wob_max" and "give --set_params", "--handler" named no
    option: the names of the namespace are not all options, nor spelt as options are."""
    names = getattr(args, "option_names", None)
    if names is None:  # a namespace built without the parser: the options spelt so
        return f"--{name}" if hasattr(args, name) and name not in _SCALARS else None
    return names.get(name)


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
            own = _own_option(name, args)
            what = _misnamed(name, value, args, own) or (
                f"{name} is a list, one value per {_EACH[name]}"
                + (f": give {own} {_METAVARS[name]}" if own else "")
                if name in _LISTS
                else f"{name} has an option of its own: give {own}"
                if own and own.startswith("-")
                else f"{name} is given as {own}, the command's argument"
                if own
                else f"{name} is not one of the string's parameters"
                + _unknown_hint(name, args, value)
            )
            raise ValueError(f"--set {item!r}: {what}; --set takes " + ", ".join(_takes(args)))
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


def set_notes(args: argparse.Namespace) -> list[str]:
    """:func:`friction_notes` on ``--set``'s values, each judged as it was written."""
    written = {}
    for item in getattr(args, "set_params", None) or []:
        name, _, value = (part.strip() for part in item.partition("="))
        written[name] = value
    sets = set_params(args)
    return friction_notes("--set ", sets, written=written) + _band_in_vain(args, sets)


def _band_in_vain(args: argparse.Namespace, sets: dict[str, float]) -> list[str]:
    """A note on --set karnopp_band where nothing uses it: the band is the Karnopp law's, which
    only simulate --friction karnopp runs (the analyses and the exact law have none); it was
    taken and printed as changed, silently changing nothing, where a spec's is noted."""
    if "karnopp_band" not in sets or getattr(args, "friction", None) == "karnopp":
        return []
    band = f"--set karnopp_band = {sets['karnopp_band']:g} rad/s"
    if getattr(args, "friction", None) is not None:
        return [
            f"{band} has no effect with --friction {args.friction} (the band is the Karnopp "
            "law's); give --friction karnopp to use it"
        ]
    return [
        f"{band} has no effect on what pydrill {args.command} computes (the band is the "
        "Karnopp friction law's, which only pydrill simulate --friction karnopp uses)"
    ]


def friction_notes(
    label: str, values: dict[str, float], verb: str = "=", written: dict | None = None
) -> list[str]:
    """A note on each friction coefficient of ``values`` (mu_static, mu_coulomb) above
    ``cli_options.MOST_FRICTION``, and on a bit_radius wider than any bit, most likely mistyped,
    in the words of ``label`` (the option or key, "--set " or "axes."): ``--set mu_static = 8:
    ...``; other names are passed over. ``written`` holds the values as typed, where known
    ("8.5 m", 8.5): one with its unit is read as written, a bare one is m."""
    from .cli_options import MOST_FRICTION
    from .tally import WIDEST_BARE_DIAMETER

    notes = []
    # --set bit_radius=8.5 (8.5 in meant; a bare number is m) built a bit 17 m across without
    # a word, where the tally refuses a bit diameter beyond 5 m and notes one beyond 1 m.
    radius = values.get("bit_radius")
    if radius is not None and radius > WIDEST_BARE_DIAMETER / 2:
        notes.append(
            f"{label}bit_radius {verb} "
            + _radius_note(label, radius, (written or {}).get("bit_radius"))
            + f": a bit {2 * radius:g} m across, wider than any bit (at most some "
            f"{WIDEST_BARE_DIAMETER:g} m); "
            + _radius_meant(label, radius, (written or {}).get("bit_radius"))
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


def _radius_note(label: str, radius: float, written: object) -> str:
    """A bit radius as its note shows it: "8.5 m" (bare, or in m), '"8.5 ft" (2.591 m)'."""
    from .units import _NUMBER

    text = written.strip() if isinstance(written, str) else ""
    match = _NUMBER.match(text)
    if match is None or match.group(2) in ("", "m"):
        return f"{radius:g} m"
    shown = text if label.startswith("--") else f'"{text}"'
    return f"{shown} ({radius:.4g} m)"


def _radius_meant(label: str, radius: float, written: object) -> str:
    """What the note on a wide bit radius says was most likely meant: a bare number is m, and
    was inches; one with its unit ("8.5 m", "8.5 ft") is read as written, and was inches too
    unless they are its unit ("a bare number is m" of '"8.5 m"' contradicted what was typed)."""
    from .tally import WIDEST_BARE_DIAMETER
    from .units import _NUMBER, INCH, _factor

    match = _NUMBER.match(written) if isinstance(written, str) else None
    unit = match.group(2) if match else ""
    number = match.group(1) if match else f"{radius:g}"
    inches = f"bit_radius={number}in" if label.startswith("--") else f'"{number} in"'
    if not unit:
        return f"a bare number is m: for inches write {inches}"
    # inches only where they make a bit ("850 mm" as 850 in would be 43 m across)
    if _factor(unit, "length") == INCH or not float(number) * INCH <= WIDEST_BARE_DIAMETER / 2:
        return "read as written"
    return f"read as written, in {unit}: if inches were meant, write {inches}"
