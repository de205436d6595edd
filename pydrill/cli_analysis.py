"""The analysis commands of ``pydrill`` at one string and one operating point or branch: hopf,
stability, bifurcation. The (W_ob, u) map lives in :mod:`pydrill.cli_map`, string and window in
:mod:`pydrill.cli_window`."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

from .cli_bifurcation import _cmd_bifurcation
from .cli_map import register_map
from .cli_options import (
    KILO,
    _finite,
    _positive,
    as_options,
    figure_path,
    json_document,
    kilo,
    print_json,
    shown,
)
from .cli_set import say_changed
from .cli_string import (
    _string_options,
    string_inputs,
    string_params,
    string_units,
)
from .cli_string_lists import add_list_options, list_overrides
from .cli_window import register_tally

#: s per inertia squared: what stability's eigenvalues (at n = 4000: 9.4 s), hopf's crossings
#: (at n = 8000: 19-23 s), bifurcation's branch (at n = 8000: 54 s) and map without --check
#: (at n = 8000: 23 s, its crossings) took on a 2-core development machine; all grow as n^2
SQUARE_SECONDS = {"stability": 6e-7, "hopf": 3e-7, "bifurcation": 8.5e-7, "map": 3.6e-7}


def slow_note(command: str, dof: int) -> None:
    """A note on stderr, before the work, when ``command`` on ``dof`` inertias takes a minute
    or more here: --dof 100000 computed an hour and a half without a word."""
    from .cli_sweep_report import duration

    seconds = SQUARE_SECONDS[command] * dof**2
    if seconds >= 60:
        print(
            f"pydrill: note: {command} of {dof} inertias takes roughly {duration(seconds)} "
            "(the time grows as the square of the inertias); --dof N reduces the string",
            file=sys.stderr,
        )


def counted(n: int, one: str, many: str | None = None) -> str:
    """``1 switch``, ``33 switches``: a count with its noun in the number it takes."""
    return f"{n} {one if n == 1 else (many or one + 's')}"


def rpm(omega: float) -> float:
    """A velocity in rad/s as revolutions per minute, what a driller sets and reads."""
    return omega * 30 / math.pi


def register_analysis(sub, PRESETS: Sequence[str]) -> None:
    hopf = sub.add_parser(
        "hopf",
        help="critical Stribeck slopes: where steady drilling loses stability",
        description="Every value of the Stribeck slope delta at which eigenvalues of the steady "
        "state reach the imaginary axis (Hopf: an oscillation is born; fold: lambda = 0), for any "
        "string length, with each Hopf crossing's criticality. Each gives the closed-form boundary "
        "W_ob(Omega) = delta * exp(gamma_b Omega / v_f) / (R_b gamma_b/v_f (mu_s - mu_c)).",
        epilog="examples:\n  pydrill hopf --dof 4\n  pydrill hopf --pipes 100 --json\n"
        "  pydrill hopf --preset real-string --plot hopf.png\n\n"
        "criticality (the first Lyapunov coefficient l1 of each Hopf crossing): subcritical "
        "(l1 > 0): past it the bit jumps to stick-slip, and before it the two coexist; "
        "supercritical (l1 < 0): a small stable oscillation is born.\n"
        "units: delta N*m*s/rad, frequency rad/s, lyapunov 1/s per amplitude^2 (its sign is what "
        "counts: its size depends on how the critical eigenvector is scaled, so compare sizes "
        "only between crossings of one string).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_list_options(_string_options(hopf, PRESETS))
    hopf.add_argument(
        "--omega-max",
        type=_positive("--omega-max", "velocity"),
        help="with --plot: largest steady velocity on the plot (rad/s, > 0, default 20; or 200rpm)",
    )
    hopf.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    hopf.add_argument(
        "--plot", metavar="FILE.png", type=figure_path, help="draw the boundaries W_ob(Omega)"
    )
    hopf.set_defaults(handler=_cmd_hopf)

    stab = sub.add_parser(
        "stability",
        help="steady state, eigenvalues and verdict at one operating point",
        description="The steady state at (W_ob, Omega), or every steady state the torque u can "
        "hold at W_ob, its eigenvalues, whether it is stable, and how far it is from losing that.",
        epilog="examples:\n  pydrill stability --dof 4 --wob 40 --torque 8.3\n"
        "  pydrill stability --dof 4 --wob 100 --omega 2 --json\n"
        "  pydrill stability --tally examples/tallies/paper-eq53.toml --depth 3000m "
        "--wob 60kN --omega 60rpm\n\n"
        "units: wob N, torque N*m, omega rad/s, eigenvalues 1/s.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_list_options(_string_options(stab, PRESETS))
    stab.add_argument(
        "--wob",
        type=_positive("--wob", "force"),
        required=True,
        help="weight on bit (N, > 0; or 100kN, 25klbf, 10t)",
    )
    point = stab.add_mutually_exclusive_group(required=True)
    point.add_argument(
        "--omega",
        type=_positive("--omega", "velocity"),
        help="steady bit velocity (rad/s, > 0; or 120rpm)",
    )
    point.add_argument(
        "--torque",
        type=_finite("--torque", "torque"),
        help="surface torque u (N m, either sign; or 12kN*m, 9kft*lbf, 6600ft-lbs)",
    )
    stab.add_argument(
        "--json",
        action="store_true",
        help="print one JSON object for scripts (of each steady state the 6 leading "
        "eigenvalues, and eigenvalue_count, how many in all)",
    )
    stab.add_argument("--plot", metavar="FILE.png", type=figure_path, help="draw the eigenvalues")
    stab.set_defaults(handler=_cmd_stability)

    bif = sub.add_parser(
        "bifurcation",
        help="branch of steady states with its Hopf (HB) and fold (LP) points",
        description="The steady bit velocity Omega as W_ob varies at fixed torque, or as the "
        "torque varies at fixed W_ob, with its stability, the Hopf points (with frequency, first "
        "Lyapunov coefficient and criticality) and the limit points where the branch folds "
        "(the equilibrium part of the paper's Fig. 11).",
        epilog="examples:\n  pydrill bifurcation --dof 2 --vary wob --torque 8.1\n"
        "  pydrill bifurcation --dof 4 --vary torque --wob 100 --json\n\n"
        "criticality: supercritical (l1 < 0): a small stable oscillation is born; subcritical "
        "(l1 > 0): the motion jumps to a large oscillation or stick-slip, with hysteresis.\n"
        "units: wob N, torque N*m, omega and frequency rad/s, lyapunov 1/s per amplitude^2 (its "
        "sign is what counts; see pydrill hopf --help).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_list_options(_string_options(bif, PRESETS))
    bif.add_argument(
        "--vary", choices=("wob", "torque"), required=True, help="the parameter along the branch"
    )
    bif.add_argument(
        "--torque",
        type=_positive("--torque", "torque"),
        help="fixed surface torque (N m, > 0; or 12kN*m, 6600ft-lbs), with --vary wob",
    )
    bif.add_argument(
        "--wob",
        type=_positive("--wob", "force"),
        help="fixed weight on bit (N, > 0; or 100kN, 25klbf), with --vary torque",
    )
    bif.add_argument(
        "--omega-max",
        type=_positive("--omega-max", "velocity"),
        help="largest Omega on the branch (rad/s, > 0; or 200rpm; default: with --vary wob, "
        "u / (c_r + c_b), "
        "where W_ob reaches 0; with --vary torque, 40)",
    )
    bif.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    bif.add_argument(
        "--plot", metavar="FILE.png", type=figure_path, help="draw the bifurcation diagram"
    )
    bif.set_defaults(handler=_cmd_bifurcation)

    register_tally(sub)
    register_map(sub, PRESETS)


def _cmd_hopf(args: argparse.Namespace) -> int:
    from .bifurcation import crossing_word
    from .stability import critical_deltas, criticality

    if args.omega_max is not None and not args.plot:  # it would be ignored
        raise ValueError("--omega-max needs --plot: it is the plot's largest steady velocity")
    params = string_params(args, list_overrides(args))
    slow_note("hopf", params.dof)
    crossings = critical_deltas(params)
    if args.plot:
        from .plot import save
        from .plot_analysis import hopf_figure

        save(hopf_figure(params, crossings, omega_max=args.omega_max), args.plot)
    if args.json:
        inputs = {**string_inputs(args, params), "dof": params.dof}
        results = {
            "crossings": [
                {
                    "type": c.type,
                    "delta": c.delta,
                    "frequency": c.frequency,
                    "direction": c.direction,
                    "crossing": crossing_word(c.direction),  # the text's word for direction
                    "lyapunov": (l1 := c.lyapunov(params)),
                    "criticality": criticality(l1),
                }
                for c in crossings
            ],
        }
        units = {
            "delta": "N·m·s/rad",
            "frequency": "rad/s",
            "lyapunov": "1/s per amplitude²",
            **string_units(args),
        }
        print_json(json_document(inputs, results, units, args.plot))
        return 0
    hopf = [c for c in crossings if c.type == "hopf"]
    say_changed(args)
    print(
        f"{params.name}, dof {params.dof}: {counted(len(hopf), 'Hopf crossing')}, "
        f"{counted(len(crossings) - len(hopf), 'fold')}"
    )
    print(
        f"{'type':6s} {'delta (N m s/rad)':>18s} {'frequency (rad/s)':>18s}  {'direction':13s}"
        f" {'lyapunov':>10s}  criticality"
    )
    for c in crossings[:40]:
        freq = f"{c.frequency:18.6g}" if c.frequency is not None else f"{'-':>18s}"
        l1 = c.lyapunov(params)
        l1_text = f"{l1:10.4g}" if l1 is not None else f"{'-':>10s}"
        print(
            f"{c.type:6s} {c.delta:18.10g} {freq}  "
            f"{crossing_word(c.direction):13s} "
            f"{l1_text}  {criticality(l1) or '-'}"
        )
    if len(crossings) > 40:
        print(f"... {len(crossings) - 40} more (use --json for all)")
    at_zero = sum(c.multiplicity for c in crossings if c.delta == 0 and c.direction > 0)
    if at_zero:  # a table of zeros says little by itself
        where = (
            "at all"
            if all(c.delta == 0 for c in crossings)
            else "at the top or the bit (c_r + c_b = 0)"
        )
        print(
            f"{counted(at_zero, 'eigenvalue')} {'crosses' if at_zero == 1 else 'cross'} at "
            f"delta = 0: the string has no damping {where}, so steady drilling is unstable at "
            "every W_ob"
        )
    if args.plot:
        print(f"figure: {args.plot}")
    return 0


def _cmd_stability(args: argparse.Namespace) -> int:
    from .stability import stability

    params = string_params(args, list_overrides(args))
    slow_note("stability", params.dof)
    try:
        points = stability(params, args.wob, omega=args.omega, torque=args.torque)
    except ValueError as exc:  # worded for the API: name the option
        raise as_options(exc, {"omega": "--omega"}) from None
    big = kilo(args.wob)  # a real string's W_ob in kN and torques in kN m (were 200000 N)
    given = f"u = {shown(args.torque or 0.0, 'N m', big)}"
    at = f"W_ob = {shown(args.wob, 'N', big)}"
    if args.plot and not points:  # nothing to draw: say so rather than save empty axes
        raise ValueError(
            f"no figure: {given} has no steady rotation at {at}, so there are no eigenvalues "
            "to draw (run without --plot for the verdict)"
        )
    if args.plot:
        from .plot import save
        from .plot_analysis import eigenvalue_figure

        save(eigenvalue_figure(params, points), args.plot)
    if args.json:
        inputs = {
            **string_inputs(args, params),
            "dof": params.dof,
            "wob": args.wob,
            # the one given of the two; the other (null) is each steady state's, below
            "omega": args.omega,
            "torque": args.torque,
        }
        units = {
            "omega": "rad/s",
            "wob": "N",
            "torque": "N·m",
            "delta": "N·m·s/rad",
            "delta_margin": "N·m·s/rad",
            "eigenvalues": "1/s",
            "spectral_abscissa": "1/s",
            **string_units(args),
        }
        results = {"equilibria": [pt.to_dict() for pt in points]}
        print_json(json_document(inputs, results, units, args.plot))
        return 0
    say_changed(args)
    if not points:
        print(
            f"no steady rotation: {given} cannot balance the bit friction at {at} (the bit "
            "sticks, or sticks and slips)"
        )
        return 0
    for pt in points:
        verdict = (
            "STABLE" if pt.stable else f"UNSTABLE ({counted(pt.unstable, 'eigenvalue')} in Re > 0)"
        )
        # W_ob beside the rest of the operating point (the lines said Omega and u only).
        # A real string's torque in kN m too; a laboratory one's 8.3 N m alone (not 0.0083).
        kn = f" ({pt.torque / 1e3:.4g} kN m)" if abs(pt.torque) > KILO else ""
        print(
            f"steady state    Omega = {pt.omega:.6g} rad/s ({rpm(pt.omega):.4g} rpm), "
            f"u = {pt.torque:.6g} N m{kn} at {at}"
        )
        print(f"Stribeck slope  delta = {pt.delta:.6g} N m s/rad")
        # The margin is a distance in delta (the Stribeck slope), so in its unit; the
        # abscissa is the real part of the leading eigenvalue: what its mode grows at.
        mode = "fastest-growing" if pt.spectral_abscissa > 0 else "slowest-decaying"
        print(
            f"verdict         {verdict}; delta margin {pt.delta_margin:.4g} N m s/rad, "
            f"spectral abscissa {pt.spectral_abscissa:.4g} 1/s"
        )
        print(
            "                delta margin: delta's distance to the nearest critical slope "
            "(pydrill hopf lists them)"
        )
        print(f"                spectral abscissa: the growth rate of the {mode} mode")
        lead = ", ".join(f"{z.real:.4g}{z.imag:+.4g}i" for z in pt.eigenvalues[:4])
        more = ", ..." if len(pt.eigenvalues) > 4 else ""  # dof 2 has three: all shown
        print(f"eigenvalues     {lead}{more}")
    if args.plot:
        print(f"figure: {args.plot}")
    return 0
