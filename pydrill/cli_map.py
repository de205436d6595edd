"""The ``pydrill map`` command: the (W_ob, u) plane of a string classified by whether a stable
steady state exists and whether the bit can stay stuck (the paper's Figs. 6b and 12), with
simulations from rest to check it (``--check K``)."""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from .cli_checks import FAILED, failure_lines, say_failed_checks
from .cli_options import (
    _duration,
    _integer,
    _positive,
    check_failed,
    check_progress,
    figure_path,
    json_document,
    kilo,
    print_json,
    shown,
)
from .cli_set import say_changed
from .cli_string import (
    _string_options,
    point_command,
    string_inputs,
    string_params,
    string_units,
)
from .cli_string_lists import add_list_options, list_overrides


def register_map(sub, PRESETS: Sequence[str]) -> None:
    """Add ``pydrill map`` to the subcommands ``sub``."""
    omap = sub.add_parser(
        "map",
        help="(W_ob, u) map: stable steady drilling, stuck bit, neither (Figs. 6b and 12)",
        description="Classify weight on bit and surface torque: whether a stable steady state "
        "exists (Hopf analysis) and whether the bit can stay stuck (u <= T_s, the sliding "
        "analysis). The paper's safe drilling parameters have a stable steady state and "
        "u > T_s. With --check K, simulations from rest on a K x K grid show where stick-slip "
        "actually happens (it coexists with the stable steady state near the sliding boundary).",
        epilog="examples:\n  pydrill map --dof 4 --plot map.png\n"
        "  pydrill map --dof 2 --check 10 --json\n\nunits: wob N, torque N*m.\n\n"
        "--json: category[i][j] is the category (an index into categories) at torque[i] and "
        'wob[j],\nas category_axes says: ["torque", "wob"]; safe_torque_min[j] is at wob[j].',
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_list_options(_string_options(omap, PRESETS))
    omap.add_argument(
        "--wob-max",
        type=_positive("--wob-max", "force"),
        help="largest W_ob (N, > 0; or 200kN; default 250 N for reduced-scale, 200 kN for "
        "real-string or a tally)",
    )
    omap.add_argument(
        "--torque-max",
        type=_positive("--torque-max", "torque"),
        help="largest u (N m, > 0; or 20kN*m; default a tenth of --wob-max: 25 N m at 250 N)",
    )
    omap.add_argument(
        "--check",
        type=_integer("--check", 0, 40),
        default=0,
        metavar="K",
        help="simulate from rest on a K x K grid and overlay the regimes (K <= 40; default 0: "
        "no simulations); a check whose simulation fails is counted as 'failed', with its "
        "message, and the others go on (exit status 3 only if every one fails)",
    )
    omap.add_argument(
        "--t-end",
        type=_duration("--t-end"),
        help="simulated time of each check (s, default 300; at most 1e10)",
    )
    omap.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    omap.add_argument("--plot", metavar="FILE.png", type=figure_path, help="draw the map")
    omap.set_defaults(handler=_cmd_map)


def _cmd_map(args: argparse.Namespace) -> int:
    import numpy as np

    from .operating import CATEGORIES, operating_map
    from .stability import critical_deltas

    if args.check < 0 or args.check > 40:
        raise ValueError(f"--check = {args.check} is not allowed: need 0 <= K <= 40")
    if not args.check and args.t_end is not None:
        raise ValueError("--t-end needs --check K: it is the simulated time of each check")
    params = string_params(args, list_overrides(args))
    from .cli_analysis import slow_note  # (not at the top: cli_analysis registers map)

    slow_note("map", params.dof)
    wob_max = args.wob_max or (250.0 if params.name == "reduced-scale" else 2e5)
    torque_max = args.torque_max or 0.1 * wob_max
    wob = np.linspace(wob_max / 200, wob_max, 200)
    torque = np.linspace(torque_max / 200, torque_max, 200)
    crossings = critical_deltas(params)
    omap = operating_map(params, wob, torque, crossings)
    checks = _checks(args, params, wob_max, torque_max) if args.check else []
    failures = [m for *_, m in checks if m is not None]
    if args.plot:
        from .plot import save
        from .plot_map import operating_figure

        save(operating_figure(params, omap, crossings, [c[:3] for c in checks]), args.plot)
    if args.json:
        inputs = {
            **string_inputs(args, params),
            "dof": params.dof,
            "wob_max": wob_max,
            "torque_max": torque_max,
            "check": args.check,
            "t_end": (args.t_end or 300.0) if args.check else None,  # of each check
        }
        results = {
            "categories": list(CATEGORIES),
            "fractions": omap.fractions(),
            "wob": omap.wob.tolist(),
            "torque": omap.torque.tolist(),
            "category": omap.category.tolist(),
            # its indices, outer first: the array alone did not say which was which
            "category_axes": ["torque", "wob"],
            "safe_torque_min": [None if not np.isfinite(v) else v for v in omap.safe_torque_min],
            # a failed check's regime is "failed", its message why (null for the others)
            "checks": [{"wob": w, "torque": u, "regime": r, "message": m} for w, u, r, m in checks],
            "failed_checks": len(failures),
        }
        units = {
            "wob": "N",
            "torque": "N·m",
            "wob_max": "N",
            "torque_max": "N·m",
            "safe_torque_min": "N·m",
            "t_end": "s",
            **string_units(args),
        }
        print_json(json_document(inputs, results, units, args.plot))
        say_failed_checks("map", failures, len(checks), json=True)
        return 0
    big = kilo(wob_max)  # a real string's in kN and kN m (was "W_ob 0..200000 N")
    say_changed(args)
    print(
        f"{params.name}, dof {params.dof}: W_ob 0..{shown(wob_max, 'N', big)}, "
        f"u 0..{shown(torque_max, 'N m', big)}"
    )
    for name, frac in omap.fractions().items():
        print(f"  {100 * frac:5.1f} %  {name}")
    _print_safe(params, crossings, wob_max, big)
    if checks:
        counts: dict[str, int] = {}
        for _, _, regime, _ in checks:
            counts[regime] = counts.get(regime, 0) + 1
        print("simulated from rest: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
        for line in failure_lines(failures):
            print(line)
    if args.plot:
        print(f"figure: {args.plot}")
    say_failed_checks("map", failures, len(checks), json=False)
    return 0


def _checks(args: argparse.Namespace, params, wob_max: float, torque_max: float):
    """(W_ob, u, regime, message) of the simulations from rest on the K x K grid of ``--check
    K``; the message is None but of a failed one (a ``SolverError``), whose regime is "failed"
    and whose message says its point and the ``pydrill simulate`` line that runs it alone (it
    said "raise max_steps", which map has not). The other checks go on (one failure stopped
    them all)."""
    import numpy as np

    from . import SolverError, simulate

    t_end = args.t_end or 300.0
    big = kilo(wob_max, torque_max)
    checks: list[tuple[float, float, str, str | None]] = []
    bar = check_progress(args.check**2, "map --check")
    try:
        for w in np.linspace(wob_max / args.check, wob_max, args.check):
            for u in np.linspace(torque_max / args.check, torque_max, args.check):
                try:
                    regime = simulate(params, wob=w, torque=u, t_end=t_end, n_out=301).regime
                    message = None
                except SolverError as exc:  # the solver alone: Ctrl-C, bad input go on up
                    point = f"W_ob = {shown(w, 'N', big, '.4g')}, u = {shown(u, 'N m', big, '.4g')}"
                    line = point_command(args, float(w), float(u))
                    regime, message = FAILED, str(check_failed(exc, point, line, t_end))
                checks.append((float(w), float(u), regime, message))
                bar.update()
    finally:
        bar.close()
    return checks


def _print_safe(params, crossings, wob_max: float, big: bool) -> None:
    """The torques that drill safely at five weights on bit, exact (the sliding boundary T_s
    and the stable intervals of the steady states): what an engineer reads the map for. The
    percentages above are of the rectangle drawn, and answered no question of a driller."""
    import numpy as np

    from .operating import stable_torques

    k, force, torque = (1e3, "kN", "kN m") if big else (1.0, "N", "N m")
    print(
        "safe u at each W_ob: steady drilling is stable (from 'stable from' up) and u > T_s "
        "(the bit cannot stay stuck)"
    )
    print(
        f"  {f'W_ob ({force})':>10s} {f'T_s ({torque})':>11s} {'stable from':>12s}  "
        f"safe u ({torque})"
    )
    for w in np.linspace(wob_max / 5, wob_max, 5):
        ts = params.mu_static * w * params.bit_radius
        pieces = stable_torques(params, float(w), crossings)
        safe = [(max(lo, ts), hi) for lo, hi in pieces if hi > ts]
        text = ", ".join(
            f"> {lo / k:.4g}" if hi == np.inf else f"{lo / k:.4g} ... {hi / k:.4g}"
            for lo, hi in safe
        )
        start = f"{pieces[0][0] / k:12.4g}" if pieces else f"{'-':>12s}"
        print(f"  {w / k:10.4g} {ts / k:11.4g} {start}  {text or 'none'}")
