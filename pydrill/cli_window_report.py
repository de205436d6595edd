"""The ``window`` command's results, as one JSON object and as text tables."""

from __future__ import annotations

import argparse


def _numbers(values) -> list[float | None]:
    """``values`` for JSON: an edge beyond every number (the stick-slip edge at a speed so fast
    that no weight makes it unstable, inf) is null: --at-rpm 10000 --json failed after the work
    with "Out of range float values are not JSON compliant: inf"."""
    import math

    return [float(v) if math.isfinite(v) else None for v in values]


def window_json(tally, dw, grid, checks, args) -> dict:
    import numpy as np

    from .cli_options import json_document
    from .cli_set import set_params
    from .cli_string import string_units

    wob, rpm, windows = grid
    # the tally as the other commands echo it (its file and lump; it held the tally's name),
    # its name beside it as string's; the depths are the window's own
    inputs = {
        "tally": {"file": args.tally, "lump": args.lump},
        "name": tally.name,
        **({"set": set_params(args)} if args.set_params else {}),
        "depths": dw.depth.tolist(),
        "at_rpm": dw.rpm.tolist(),
        "at_wob": dw.wob.tolist(),
        "check": args.check,
        "check_from": args.check_from if checks else None,
        # the inertias of the string the checks simulated (null: each depth's full string,
        # its dof): their verdicts are that model's, not the tables'
        "check_dof": args.check_dof if checks else None,
    }
    results = {
        "wob": wob.tolist(),
        "rpm": rpm.tolist(),
        "windows": [
            {
                "depth": float(d),
                # the string built for it, of whole joints: up to one longer than the depth
                "string_length": float(dw.length[i]),
                "dof": int(dw.dof[i]),
                "delta_limit": float(dw.delta_limit[i]),
                "safe_fraction": float(windows[i].safe.mean()),
                "min_rpm": [None if np.isnan(v) else float(v) for v in windows[i].min_rpm()],
                "wob_max": _numbers(dw.wob_max[i]),
                "wob_max_stable": _numbers(dw.wob_max_stable[i]),
                "rpm_min": _numbers(dw.rpm_min[i]),
                "rpm_min_stable": _numbers(dw.rpm_min_stable[i]),
                # a failed check's outcome is "failed", its bit_rpm null and its message why
                # (null for the others)
                "checks": [
                    {
                        "wob": w,
                        "rpm": r,
                        "outcome": g,
                        "bit_rpm": b,
                        "stable": s,
                        "cannot_stay_stuck": u,
                        "message": m,
                    }
                    for w, r, g, s, u, b, m in checks.get(d, [])
                ],
                "failed_checks": sum(c[6] is not None for c in checks.get(d, [])),
            }
            for i, d in enumerate(dw.depth)
        ],
        "wob_max_unstuck": _numbers(dw.wob_max_unstuck),
        "rpm_min_unstuck": _numbers(dw.rpm_min_unstuck),
        "failed_checks": sum(c[6] is not None for pts in checks.values() for c in pts),
    }
    units = {
        "depths": "m",
        "at_rpm": "rpm",
        "at_wob": "N",
        "wob": "N",
        "rpm": "rpm",
        "min_rpm": "rpm",
        "wob_max": "N",
        "rpm_min": "rpm",
        # the edges each (were without a unit), the checks' points and the depth of each window
        "wob_max_stable": "N",
        "wob_max_unstuck": "N",
        "rpm_min_stable": "rpm",
        "rpm_min_unstuck": "rpm",
        "depth": "m",
        "string_length": "m",
        "bit_rpm": "rpm",
        "delta_limit": "N·m·s/rad",
        **string_units(argparse.Namespace(tally=None, set_params=args.set_params)),
    }
    return json_document(inputs, results, units, args.plot)


def check_agreement(every: list, check_from: str) -> str:
    """How one depth's checks bear out the analysis: from equilibrium, at how many points the
    run stayed steady exactly where steady drilling is stable; from rest, how many safe points
    drilled steadily, and what the start-ups gave where the bit may stay stuck. Of the checks
    simulated; "" when every one failed (nothing agrees or disagrees)."""
    from .atlas_schema import FAILED

    pts = [c for c in every if c[2] != FAILED]
    if not pts:
        return ""
    if check_from == "equilibrium":
        agree = sum((g == "steady") == s for _, _, g, s, *_ in pts)
        simulated = " simulated" if len(pts) < len(every) else ""
        return f"steady exactly where stable at {agree}/{len(pts)}{simulated} points"
    safe = [g for _, _, g, s, u, *_ in pts if s and u]
    said = f"safe points steady from rest {safe.count('steady')}/{len(safe)}"
    # Where a stopped bit may stay stuck (u <= T_s), a start-up can also break free: the
    # wind-up overshoots the static twist. Either is as the verdict says (not safe), so their
    # outcomes are counted, not scored ("stuck 1/3" read as one agreement in three).
    stall = [g for _, _, g, s, u, *_ in pts if s and not u]
    if stall:
        said += "; where the bit may stay stuck: " + ", ".join(
            f"{g} {stall.count(g)}" for g in sorted(set(stall))
        )
    return said


#: the depths the depth chart's note on the checks names; the text output gives every one
NOTE_DEPTHS = 8


def reduced_checks(args) -> str:
    """What says that the checks simulated the string reduced by --check-dof ("" without it):
    the tables, the chart's edges and the title's inertias are the full string's, and nothing
    said that the checks' verdicts were another model's."""
    if args.check_dof is None:
        return ""
    return (
        f"checks simulated on the string reduced to {args.check_dof} inertias "
        f"(--check-dof {args.check_dof}); the window itself is the full string's"
    )


def _sentence(text: str) -> str:
    """``text`` as a sentence after another ("" stays "")."""
    return f" {text[0].upper()}{text[1:]}." if text else ""


def checks_note(checks: dict, args) -> str | None:
    """The depth chart's footnote on ``window --check`` (None without checks). The checks'
    points lie on each depth's own (W_ob, rpm) grid, off the chart's curves (which are at
    --at-rpm and --at-wob): it gives how each depth's came out, as the text output does, and
    how to see them."""
    import textwrap

    if not checks:
        return None
    parts = []
    for d, every in list(checks.items())[:NOTE_DEPTHS]:
        failed = sum(c[6] is not None for c in every)
        said = check_agreement(every, args.check_from)
        if not said:  # all failed ("every check failed (4 failed)" said it twice)
            parts.append(f"{d:,.0f} m: all {failed} checks failed")
        else:
            parts.append(f"{d:,.0f} m: {said}" + (f" ({failed} failed)" if 0 < failed else ""))
    if len(checks) > NOTE_DEPTHS:
        parts.append(f"and {len(checks) - NOTE_DEPTHS} more depths (the text output gives each)")
    k = args.check
    text = f"checks ({k} x {k} simulations per depth from {args.check_from}): " + "; ".join(parts)
    return (
        textwrap.fill(text + "." + _sentence(reduced_checks(args)), width=190)
        + "\nTheir points are on each depth's own window: plot one depth (--depth "
        + f"{next(iter(checks)):.0f}m) to see them."
    )


def print_window(tally, dw, checks, args) -> None:
    import textwrap

    from .cli_checks import failure_lines
    from .units import FT, LBF
    from .window import longer

    print(
        f"{tally.name}: heaviest safe weight on bit, kN (klbf), at surface speed; "
        "* = the stick-slip edge binds, else the stall edge"
    )
    print(f"{'depth m':>8s} {'ft':>6s} {'dof':>4s} " + " ".join(f"{r:>9g}rpm" for r in dw.rpm))
    for i, d in enumerate(dw.depth):
        cells = []
        for k in range(dw.rpm.size):
            w = dw.wob_max[i, k]
            star = "*" if dw.wob_max_stable[i, k] < dw.wob_max_unstuck[k] else " "
            cells.append(
                f"{w / 1e3:6.0f}({w / LBF / 1e3:3.0f}){star}" if w < 1e7 else f"{'-':>12s}"
            )
        print((f"{d:8.0f} {d / FT:6.0f} {int(dw.dof[i]):4d} " + " ".join(cells)).rstrip())
    print("slowest safe surface speed, rpm, at weight on bit")
    print(f"{'depth m':>8s} " + " ".join(f"{w / 1e3:>7.4g} kN" for w in dw.wob))
    for i, d in enumerate(dw.depth):
        cells = []
        for k in range(dw.wob.size):
            star = "*" if dw.rpm_min_stable[i, k] > dw.rpm_min_unstuck[k] else " "
            cells.append(f"{dw.rpm_min[i, k]:9.0f}{star}")
        print((f"{d:8.0f} " + " ".join(cells)).rstrip())
    # Each string is whole joints long: the depth asked (the tables' rows) is not its length.
    pairs = zip(dw.depth, dw.length, strict=True)
    built = [f"{d:g} m (string {n:.6g} m)" for d, n in pairs if longer(d, n)]
    if len(built) > NOTE_DEPTHS:  # a line of 46 depths said little more than this
        most = float((dw.length - dw.depth).max())
        print(
            f"strings of whole joints: up to {most:.3g} m longer than the depths "
            "(--json gives each: string_length)"
        )
    elif built:  # (wrapped between depths, not inside one)
        no_break = [b.replace(" ", "\0") for b in built]
        text = textwrap.fill("strings of whole joints: " + ", ".join(no_break), 120)
        print(text.replace("\0", " "))
    failures = []
    if checks and args.check_dof is not None:  # before the lines it is about
        print(reduced_checks(args))
    for d, every in checks.items():
        counts: dict[str, int] = {}
        for _, _, g, *_ in every:
            counts[g] = counts.get(g, 0) + 1
        failures += [c[6] for c in every if c[6] is not None]
        line = f"checks at {d:.0f} m from {args.check_from}: " + ", ".join(
            f"{k} {v}" for k, v in sorted(counts.items())
        )
        agreement = check_agreement(every, args.check_from)
        print(f"{line}; {agreement}" if agreement else line)
    for line in failure_lines(failures):
        print(line)
    if args.plot:
        print(f"figure: {args.plot}")
