"""The tally commands of ``pydrill``: ``window`` (where it is safe to drill, at a depth or
against depth), and ``string`` (the lumped model: ``cli_string_show``) registered beside it."""

from __future__ import annotations

import argparse
import dataclasses

from .cli_options import _duration, _integer, _whole, figure_path, print_json
from .cli_set import add_set_option, say_changed
from .cli_string_show import register_string
from .cli_window_inputs import (
    TALLY_SETS,
    _kilonewtons,
    _rpm,
    _rpms,
    _shown_name,
    _values,
    _window_notes,
    _with_sets,
)

WINDOW_EPILOG = """\
examples:
  pydrill window examples/tallies/paper-eq53.toml --depth 3000m --plot window-3000m.png
  pydrill window examples/tallies/paper-eq53.toml --depth 3000m --check 6 --json
  pydrill window examples/tallies/paper-eq53.toml --depth 500m:5000m:10 --plot window-depth.png
  pydrill window examples/tallies/5.5in-dp-8in-collars.toml --depth 5000ft,10000ft,15000ft
  pydrill window examples/tallies/paper-eq53.toml --depth 3000m --set bit_damping=100

reading it: SAFE = steady drilling is stable (no stick-slip grows from it) and the torque
needed at that speed exceeds the bit's static friction (a stopped bit breaks free). With one
depth the plot is the (W_ob, rpm) window, --check's points on it; with several it is the
window against depth, and a footnote says how each depth's checks came out.
units: depth m or ft (500m:5000m:10 = 10 depths, ends included); wob in kN (a bare number)
or with its unit (60klbf); speeds in rpm."""


#: what the positional TALLY.toml is (its help was empty)
TALLY_HELP = (
    "the string's pipe tally: a TOML file of its top drive, bit and sections (pipe, collars; "
    "count, length, od, id); examples/tallies/ has two, docs/guide/real-strings.md explains them"
)


def register_tally(sub) -> None:
    register_string(sub, TALLY_HELP)

    win = sub.add_parser(
        "window",
        help="safe (W_ob, surface rpm) window of a string from its tally, at one or more depths",
        description="For the string of a tally at a depth: where steady drilling is stable and\n"
        "the bit cannot stay stuck, in weight on bit and surface rpm (exact edges from the\n"
        "stability and sliding analysis); optionally checked by simulations at sample points.",
        epilog=WINDOW_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    win.add_argument("tally", metavar="TALLY.toml", help=TALLY_HELP)
    win.add_argument(
        "--depth",
        required=True,
        help="3000m; 500m,1000m,3000m; or a range 500m:5000m:10 (2 ... 500 depths); each > 0, "
        "a bare number is m",
    )
    win.add_argument(
        "--lump",
        type=_whole("--lump", ">= 1"),
        default=1,
        help="drill-pipe joints per element, >= 1 (default 1)",
    )
    add_set_option(
        win,
        "change one of the tally's values, as often as needed: "
        + ", ".join(TALLY_SETS)
        + " (SI, or with a unit: bit_damping=100, 'bit_radius=4.5 in'): what if the mud "
        "damped the bit more, or the rock were more abrasive",
    )
    win.add_argument(
        "--wob-max",
        type=_kilonewtons("--wob-max"),
        default=3e5,
        help="largest weight on bit on the chart (kN, > 0: default 300; or 60klbf)",
    )
    win.add_argument(
        "--rpm-max",
        type=_rpm("--rpm-max"),
        default=200.0,
        help="largest surface speed on the chart (rpm: default 200; or 20rad/s)",
    )
    win.add_argument(
        "--at-rpm",
        default="15,20,25,30,40,60,90,120,150",
        help="surface speeds at which to report the heaviest safe W_ob (rpm, > 0; or 2rad/s)",
    )
    win.add_argument(
        "--at-wob",
        default="10kN,20kN,30kN,50kN,100kN",
        help="weights on bit at which to report the slowest safe rpm (kN, each > 0; or 5klbf)",
    )
    win.add_argument(
        "--check",
        type=_integer("--check", 0, 20),
        default=0,
        metavar="K",
        help="simulate a K x K sample of the chart at each depth and compare with the verdict "
        "(K <= 20; default 0: none); a check whose simulation fails is counted as 'failed', "
        "with its message, and the others go on (exit status 3 only if every one fails)",
    )
    win.add_argument(
        "--check-dof",
        type=_whole("--check-dof", "2 ... one per element"),
        help="reduce the checking model to this many inertias (2 ... one per element)",
    )
    win.add_argument(
        "--check-from",
        choices=("equilibrium", "rest"),
        default="equilibrium",
        help="start each check near the steady state (default: tests stability) or from rest "
        "(the start-up: tests the stall edge too)",
    )
    win.add_argument(
        "--t-end",
        type=_duration("--t-end"),
        dest="t_end_given",
        metavar="T_END",
        help="simulated time of each check (s, default 120; at most 1e10)",
    )
    win.add_argument("--json", action="store_true", help="print one JSON object")
    win.add_argument(
        "--plot", metavar="FILE.png", type=figure_path, help="draw the window (or against depth)"
    )
    win.set_defaults(handler=_cmd_window, set_names=TALLY_SETS)


def _cmd_window(args: argparse.Namespace) -> int:
    import numpy as np

    from .cli_checks import say_failed_checks
    from .cli_options import check_progress
    from .cli_set import set_notes
    from .cli_string import _say, for_option, load_tally_file, tally_notes
    from .cli_window_report import print_window, window_json
    from .window import parse_depths, window_against_depth

    if args.lump < 1:
        raise ValueError(f"--lump = {args.lump} is not allowed: >= 1")
    if not 0 <= args.check <= 20:
        raise ValueError(f"--check = {args.check} is not allowed: 0 ... 20")
    if not args.check:  # options of the check alone would be ignored without a check
        for option, given in (("--check-dof", args.check_dof), ("--t-end", args.t_end_given)):
            if given is not None:
                raise ValueError(f"{option} needs --check K: it sets how the check simulates")
    written = load_tally_file(args.tally)  # as its file says it (its notes are the file's)
    tally = _with_sets(written, args)
    # Each refusal names its option ("depth 10 m is shallower than the BHA", "dof = 1 is not
    # allowed" of --check-dof, "'3000rpm': unit 'rpm' is not a length unit" said none).
    at_rpm = np.array(_rpms(args.at_rpm))
    at_wob = np.array(_values(args.at_wob, "force", "--at-wob"))
    try:
        depths = parse_depths(args.depth)
        dw = window_against_depth(tally, depths, at_rpm, at_wob, lump=args.lump)
    except ValueError as exc:
        if str(exc).startswith(("--", "lump ")):  # the option, or the lump that fits, named
            raise
        raise for_option(exc, "--depth", "depth") from None
    _window_notes(args, depths, at_rpm, at_wob)
    _say(tally_notes(written, args.tally, own_length=False))  # --depth sets its length
    _say(set_notes(args))  # mu_static=8 for 0.8, as in simulate
    if tally.top_damping + tally.bit_damping == 0:  # a table of zeros and infs says no why
        _say(
            [
                "the tally has no damping at the top drive or the bit (c_r + c_b = 0): the "
                "steady torque never exceeds the static friction, so the bit may stay stuck at "
                "every speed, and no window is safe"
            ]
        )
    grid = _grid_windows(tally, depths, args)
    checks = {}
    if args.check:
        bar = check_progress(args.check**2 * len(depths), "window --check")
        try:
            checks = {d: _checks(tally, d, args, bar) for d in depths}
        except ValueError as exc:
            if not str(exc).startswith("dof "):
                raise
            raise for_option(exc, "--check-dof", "dof") from None
        finally:
            bar.close()
    if args.plot:
        from .cli_window_report import checks_note
        from .plot import save
        from .plot_window import window_depth_figure, window_figure
        from .window import Limits

        shown = _shown_name(tally.name, args)  # the figure says what --set changed
        if len(depths) == 1:
            p = tally.at_depth(depths[0]).to_params(lump=args.lump)
            fig = window_figure(
                shown,
                depths[0],
                Limits.of(p),
                args.wob_max,
                args.rpm_max,
                [c[:3] for c in checks.get(depths[0], [])],
                # the legend says which model the checks simulated, if not the drawn one
                args.check_from
                + ("" if args.check_dof is None else f", {args.check_dof} inertias"),
                float(dw.length[0]),
            )
        else:  # the checks' points are off these curves: the figure says how they came out
            fig = window_depth_figure(
                dataclasses.replace(dw, name=shown),
                args.wob_max,
                args.rpm_max,
                checks_note(checks, args),
            )
        save(fig, args.plot)
    failures = [c[6] for pts in checks.values() for c in pts if c[6] is not None]
    total = sum(len(pts) for pts in checks.values())
    if args.json:
        print_json(window_json(tally, dw, grid, checks, args))
    else:
        say_changed(args)
        print_window(tally, dw, checks, args)
    say_failed_checks("window", failures, total, json=args.json)
    return 0


def _grid_windows(tally, depths, args):
    import numpy as np

    from .window import operating_window

    wob = np.linspace(args.wob_max / 150, args.wob_max, 150)
    rpm = np.linspace(args.rpm_max / 150, args.rpm_max, 150)
    return (
        wob,
        rpm,
        [operating_window(tally.at_depth(d).to_params(lump=args.lump), wob, rpm) for d in depths],
    )


def _checks(tally, depth, args, bar):
    """(wob N, rpm, outcome, stable, cannot stay stuck, mean bit rpm, message) on a K x K
    sample; the verdict is the checking model's. The surface torque is held at the steady
    state's, so the bit may settle at another steady speed (past the fold, u(Ω) is not
    monotone): the outcome is then "steady elsewhere", not "steady". A check whose simulation
    fails (a ``SolverError``) is "failed", its bit rpm None and its message which point and
    the ``pydrill simulate`` line that runs it alone; the message is None for the others."""
    import numpy as np

    from . import SolverError, equilibrium_torque, simulate
    from .cli_checks import FAILED
    from .cli_options import check_failed
    from .cli_string import point_command
    from .window import RPM, Limits

    p = tally.at_depth(depth).to_params(dof=args.check_dof, lump=args.lump)
    lim = Limits.of(p)
    k = args.check
    out = []
    # Cell centres of a K x K division of the chart.
    for w in (np.arange(k) + 0.5) / k * args.wob_max:
        for r in (np.arange(k) + 0.5) / k * args.rpm_max:
            u = equilibrium_torque(p, w, r * RPM)
            t_end = args.t_end_given or 120.0
            stable = bool(w < lim.wob_max_stable(r))
            unstuck = bool(w < lim.wob_max_unstuck(r))
            try:
                res = simulate(p, wob=w, torque=u, initial=args.check_from, t_end=t_end, n_out=2)
            except SolverError as exc:  # which point, and what window's user can do
                point = f"{depth:g} m, W_ob = {w / 1e3:.4g} kN, {r:.4g} rpm"
                more = {"depth": f"{depth:g}m", "dof": args.check_dof, "initial": args.check_from}
                line = point_command(_as_tally(args), float(w), float(u), **more)
                failed = str(check_failed(exc, point, line, t_end))
                out.append((float(w), float(r), FAILED, stable, unstuck, None, failed))
                bar.update()
                continue
            bit_rpm = float(res.summary.bit_mean / RPM)
            outcome = res.regime
            if outcome == "steady" and abs(bit_rpm - r) > 0.01 * r:
                outcome = "steady elsewhere"
            out.append((float(w), float(r), outcome, stable, unstuck, bit_rpm, None))
            bar.update()
    return out


def _as_tally(args: argparse.Namespace) -> argparse.Namespace:
    """window's options as the string options of ``pydrill simulate`` name its string."""
    lump = None if args.lump == 1 else args.lump  # (1, the default)
    return argparse.Namespace(
        tally=args.tally, depth=None, lump=lump, dof=None, set_params=args.set_params
    )
