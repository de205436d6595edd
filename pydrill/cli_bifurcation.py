"""``pydrill bifurcation``: the steady states of one string as W_ob or u varies, their Hopf
and fold points (HB1, HB2, ... from the highest speed, LP), as a table, JSON or a figure. Its
options are registered with the other analysis commands' in :mod:`pydrill.cli_analysis`."""

from __future__ import annotations

import argparse
import math

from .cli_options import json_document, kilo, print_json
from .cli_set import say_changed
from .cli_string import string_inputs, string_params, string_units
from .cli_string_lists import list_overrides


def _cmd_bifurcation(args: argparse.Namespace) -> int:
    from .bifurcation import branch
    from .cli_analysis import slow_note  # (cli_analysis registers this command)

    if args.vary == "wob" and args.torque is None:
        raise ValueError("--vary wob needs --torque (the surface torque held fixed, N m)")
    if args.vary == "torque" and args.wob is None:
        raise ValueError("--vary torque needs --wob (the weight on bit held fixed, N)")
    if args.vary == "wob" and args.wob is not None:
        raise ValueError("--wob is not allowed with --vary wob: the branch varies it")
    if args.vary == "torque" and args.torque is not None:
        raise ValueError("--torque is not allowed with --vary torque: the branch varies it")
    params = string_params(args, list_overrides(args))
    slow_note("bifurcation", params.dof)
    omega_max_note(args.omega_max)
    b = branch(params, vary=args.vary, torque=args.torque, wob=args.wob, omega_max=args.omega_max)
    if args.plot:
        from .plot import save
        from .plot_analysis import bifurcation_figure

        save(bifurcation_figure(params, b), args.plot)
    if args.json:
        results = b.to_dict()
        inputs = {
            **string_inputs(args, params),
            "dof": params.dof,
            "vary": results.pop("vary"),
            "fixed": results.pop("fixed"),  # the torque (N·m) or weight on bit (N) held
        }
        units = {
            "wob": "N",
            "torque": "N·m",
            "omega": "rad/s",
            "frequency": "rad/s",
            "delta": "N·m·s/rad",
            "lyapunov": "1/s per amplitude²",  # as hopf's: the same l1 (was "per (rad/s)²")
            "fixed": "N·m" if b.vary == "wob" else "N",
            **string_units(args),
        }
        print_json(json_document(inputs, results, units, args.plot))
        return 0
    # A real string's in kN and kN m, as on its figure (was "u = 12000 N m", W_ob 104333.9 N).
    big = kilo(b.fixed, *(pt.wob for pt in b.points))
    k, force, torque = (1e3, "kN", "kN m") if big else (1.0, "N", "N m")
    fixed = (
        f"u = {b.fixed / k:g} {torque}" if b.vary == "wob" else f"W_ob = {b.fixed / k:g} {force}"
    )
    say_changed(args)
    print(f"{params.name}, dof {params.dof}: steady states as {b.vary} varies at {fixed}")
    if not b.points:  # the header of an empty table said nothing; the branch's stability does
        print(_no_points(b))
    else:
        print(
            f"{'point':5s} {f'wob ({force})':>12s} {f'torque ({torque})':>13s} "
            f"{'omega (rad/s)':>14s} {'rpm':>7s} {'freq (rad/s)':>13s} {'lyapunov':>11s}  "
            "criticality"
        )
    for pt in b.points:  # from the highest Ω down, as the labels count: HB1 first
        freq = f"{pt.frequency:13.6g}" if pt.frequency else f"{'-':>13s}"
        l1 = f"{pt.lyapunov:11.4g}" if pt.lyapunov is not None else f"{'-':>11s}"
        # A point where the steady state is unstable anyway changes nothing one can see.
        n = pt.others_unstable
        others = f"({n} other eigenvalue{'s' if n > 1 else ''} unstable)" if n else ""
        print(
            f"{pt.label:5s} {pt.wob / k:12.8g} {pt.torque / k:13.8g} {pt.omega:14.8g} "
            f"{pt.omega * 30 / math.pi:7.1f} {freq} {l1}  "
            + " ".join(x for x in (pt.criticality, others) if x)
        )
    if args.plot:
        print(f"figure: {args.plot}")
    return 0


#: rad/s (9549 rpm): no drill string turns this fast, nor the laboratory rig
FASTEST_OMEGA = 1e3


def omega_max_note(omega_max: float | None) -> None:
    """A note on stderr for an --omega-max beyond any drill string's speed (1e5 rad/s is
    about a million rpm), as unit_notes gives for --omega: most likely mistyped. The command
    goes on: the branch still starts near Omega = 0, so its points are the same."""
    from .cli_analysis import rpm
    from .cli_options import TOP_DRIVE_RPM
    from .cli_string import _say

    if omega_max is not None and omega_max > FASTEST_OMEGA:
        _say(
            [
                f"--omega-max is {omega_max:g} rad/s = {rpm(omega_max):.3g} rpm, faster than "
                f"any drill string turns (a top drive some {TOP_DRIVE_RPM:g} rpm at most)"
            ]
        )


def _no_points(b) -> str:
    """What a branch without Hopf or fold points says: its extent and its stability (it
    printed the header of an empty table, and "no Hopf or fold point on this branch")."""
    if b.omega.size == 0:
        return "no Hopf or fold point: no steady state on this branch"
    unstable = int((b.unstable > 0).sum())
    state = (
        "stable along all of it"
        if unstable == 0
        else "unstable along all of it"
        if unstable == b.unstable.size
        else "stable in part"
    )
    return (
        f"no Hopf or fold point on this branch (Omega {b.omega.min():.4g} ... "
        f"{b.omega.max():.4g} rad/s): the steady state is {state}"
    )
