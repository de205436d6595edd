"""What ``pydrill window`` reads beside its tally: speeds (a bare number is rpm), weights on bit
(a bare number is kN), each refused naming its option; and the notes on values beyond what any
rig does."""

from __future__ import annotations

import argparse
import dataclasses
import math

from .cli_options import HEAVIEST_WOB, LONGEST_WELL, TOP_DRIVE_RPM, _load
from .model import _SCALARS

RPM = 2 * math.pi / 60  # rad/s per rpm

# No drill bit takes 2000 kN (200 t): a bare number that large was meant in newtons.
LARGEST_BARE_KN = HEAVIEST_WOB / 1e3


#: the string's parameters a tally sets, which ``window --set`` may change (the Karnopp band
#: is none of them: the window and its checks use the exact friction law)
TALLY_SETS = tuple(name for name in _SCALARS if name != "karnopp_band")


def _rpm(option: str):
    """A surface speed for the chart: a bare number is rpm (as the chart shows it), or any
    speed with its unit (200rpm, 20rad/s); --rpm-max 200rpm was refused as "not a number"."""

    def parse(text: str) -> float:
        try:
            return _speed(text, option)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return parse


def _speed(text: str, option: str) -> float:
    """``text`` in rpm: a bare number, or a speed with its unit; refused unless finite, > 0."""
    from . import units

    try:
        value = float(text)
    except ValueError:
        try:
            value = units.parse(text, "velocity") / RPM
        except ValueError as exc:
            raise ValueError(f"{option} must be a speed, got {text.strip()!r} ({exc})") from None
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{option} must be a finite speed > 0 (rpm), got {text.strip()!r}")
    return value


def _bare_kn(value: float, option: str) -> float:
    """A bare number of a weight-on-bit option, in kN, as newtons."""
    if value > LARGEST_BARE_KN:
        raise ValueError(
            f"{option} {value:g}: bare numbers are kN here, and {value:g} kN is no weight on bit; "
            f"write {value:g}N for newtons"
        )
    return value * 1e3


def _kilonewtons(option: str):
    """A weight on bit for a real string: a bare number is kN (as the chart and table show
    it), or any force with its unit (60klbf, 60000N)."""

    def parse(text: str) -> float:
        from . import units

        try:
            number = float(text)
        except ValueError:
            number = None
        if number is not None:
            try:
                value = _bare_kn(number, option)
            except ValueError as exc:
                raise argparse.ArgumentTypeError(str(exc)) from None
        else:
            try:
                value = units.parse(text, "force")
            except ValueError as exc:
                raise argparse.ArgumentTypeError(
                    f"{option} must be a force (60 = 60 kN, or 60klbf), got {text!r} ({exc})"
                ) from None
        if not value > 0 or value == float("inf"):
            raise argparse.ArgumentTypeError(f"{option} must be a finite force > 0, got {text}")
        return _load(option, text, value, "force")

    return parse


def _values(text: str, kind: str, option: str) -> list[float]:
    from . import units

    out = []
    for v in (v.strip() for v in text.split(",")):
        if not v:
            continue
        try:  # a bare number is kN, as on the chart (forces are the only kind asked here)
            number = float(v)
        except ValueError:
            try:
                out.append(units.parse(v, kind))
            except ValueError as exc:  # which option: there are two lists of values
                raise ValueError(f"{option}: {exc}") from None
            continue
        out.append(_bare_kn(number, option))
    if not out or any(not v > 0 for v in out):
        raise ValueError(f"{option}: give a comma-separated list of values > 0, got {text!r}")
    try:  # at most MAX_LOAD, as --wob-max ("1e300N" overflowed the window's edges)
        return [_load(option, text, v, kind) for v in out]
    except argparse.ArgumentTypeError as exc:
        raise ValueError(str(exc)) from None


def _window_notes(args: argparse.Namespace, depths, at_rpm, at_wob) -> None:
    """Values beyond what any rig does, most likely mistyped: a depth beyond the longest well
    (--depth 30000m), a speed no top drive turns (--rpm-max 5000), a weight no bit takes; said
    on stderr, and the window goes on (as cli_string.unit_notes for the other commands)."""
    from .cli_string import _say, depth_note, run_notes

    deepest = max(depths)
    if deepest > LONGEST_WELL:
        depth_note(deepest, *_as_written(args.depth, deepest))
    notes = []
    for option, fastest in (("--rpm-max", args.rpm_max), ("--at-rpm", max(at_rpm))):
        if fastest > TOP_DRIVE_RPM:
            notes.append(
                f"{option} {fastest:g} rpm is faster than any top drive turns (some "
                f"{TOP_DRIVE_RPM:g} rpm at most)"
            )
    if args.rpm_max < 1.0:  # a chart of the speeds where no bit drills
        notes.append(f"--rpm-max {args.rpm_max:g} rpm: the chart ends below 1 rpm")
    if args.wob_max < 1e3:
        notes.append(f"--wob-max {args.wob_max / 1e3:g} kN: the chart ends below 1 kN")
    for option, heaviest in (("--wob-max", args.wob_max), ("--at-wob", max(at_wob))):
        if heaviest > HEAVIEST_WOB:
            notes.append(
                f"{option} {heaviest / 1e3:g} kN is heavier than any drill bit takes (at most "
                f"some {HEAVIEST_WOB / 1e3:g} kN, {HEAVIEST_WOB / 1e4:g} t)"
            )
    _say(notes + run_notes(argparse.Namespace(t_end=args.t_end_given)))


def _as_written(text: str, depth: float) -> tuple[str, str | None]:
    """The depth of ``--depth text`` (a list, or ranges) as written, and the whole option in
    feet where its depths are all bare numbers (m): --depth 30000,1000 was noted as "30000m",
    without the "a bare number is m" that --depth 30000 gets."""
    from .cli_string import _bare

    parts = [part.strip() for part in text.split(",") if part.strip()]
    ends = [end.strip() for part in parts for end in part.split(":")[:2]]  # (not a count)
    written = next((end for end in ends if _parses_to(end, depth)), f"{depth:g}m")
    if not all(_bare(end) for end in ends):
        return written, None
    feet = [":".join(b + "ft" if k < 2 else b for k, b in enumerate(p.split(":"))) for p in parts]
    return written, ",".join(feet)


def _parses_to(text: str, depth: float) -> bool:
    from . import units

    try:
        return units.parse(text, "length") == depth
    except ValueError:
        return False


def _rpms(text: str) -> list[float]:
    """Surface speeds in rpm: bare numbers are rpm, or any speed with its unit."""
    out = [_speed(v, "--at-rpm") for v in text.split(",") if v.strip()]
    if not out:
        raise ValueError(f"--at-rpm: give a comma-separated list of speeds > 0, got {text!r}")
    return out


def _with_sets(tally, args: argparse.Namespace):
    """The tally with ``--set``'s values (each refused as ``--set ...`` if the string refuses
    it: the string of the tally as written is built to check them)."""
    from .cli_set import _set_refused, set_params

    sets = set_params(args)
    for name in sets:
        if name not in TALLY_SETS:  # karnopp_band: a Params field, none of a tally's
            raise ValueError(
                f"--set {name}: the window and its checks use the exact friction law, which "
                f"has no band; window's --set takes " + ", ".join(TALLY_SETS)
            )
    if not sets:
        return tally
    from .model import _check_friction

    changed = dataclasses.replace(tally, **sets)
    mu = [name for name in ("mu_coulomb", "mu_static") if name in sets]
    try:
        if len(mu) == 1:  # blame the coefficient --set changed, not the tally's one it kept
            _check_friction(changed.mu_coulomb, changed.mu_static, changed=mu[0])
        changed.to_params()
    except ValueError as exc:
        raise _set_refused(exc, sets) from None
    return changed


def _shown_name(name: str, args: argparse.Namespace) -> str:
    """The tally's name as a figure shows it: with what ``--set`` changed in it."""
    from .cli_set import set_line

    line = set_line(args)
    return f"{name} ({line.removeprefix('changed').strip()})" if line else name
