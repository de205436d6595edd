"""The ``pydrill`` command.

Bad input ends with a one-line message and exit status 2 (no traceback); a solver failure with
exit status 3. ``--json`` prints exactly one JSON object on stdout for scripts.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence
from typing import Any

from .cli_encoding import writable_output
from .cli_options import (
    _duration,
    _finite,
    _fraction,
    _integer,
    _positive,
    as_options,
    figure_path,
    json_document,
    kilo,
    print_json,
)
from .cli_os_errors import os_error_message
from .cli_parser import EXIT_USAGE, _Parser, error_json, say_error
from .cli_set import say_changed
from .cli_string import (
    _string_options,
    string_json,
    string_params,
    string_units,
)
from .cli_string_lists import add_list_options, list_overrides

EXIT_SOLVER = 3
#: --max-steps at most: a trillion steps is days of computing (simulate() takes up to 2**62)
MAX_STEPS = 10**12

SIMULATE_EPILOG = """\
examples:
  pydrill simulate --wob 100 --torque 8.3                 # paper Fig. 4: stick-slip
  pydrill simulate --wob 160 --torque 8.3 --json          # stuck bit, machine-readable
  pydrill simulate --pipes 10 --wob 100 --torque 8.3 --t-end 600 --plot run.png
  pydrill simulate --wob 40 --torque 8.3 --initial equilibrium --friction karnopp
  pydrill simulate --tally examples/tallies/paper-eq53.toml --depth 3000m --wob 60kN --torque 9kN*m

regimes (judged on the last --window fraction of the run):
  steady       the bit converges to the steady velocity Omega > 0
  stick-slip   the bit repeatedly sticks and slips
  stuck        the bit sticks and stays stuck (it needs u <= T_s = mu_s * W_ob * R_b;
               from rest the string's overshoot can still break it free)
  oscillation  torsional oscillation without sticking: a sustained limit cycle, or one
               still growing away from an unstable steady state (the note says so)

units: wob N, torque N*m, time s, velocities rad/s; or with a unit: wob kN, lbf, klbf (klbs,
kips), t (metric tonne-force: tf, tonne; not "tonf", a metric or a US short ton by usage);
torque kN*m, ft-lbf (ft-lbs, lb-ft), kft-lbf (klb-ft).
"""


def build_parser() -> argparse.ArgumentParser:
    from . import PRESETS, __version__
    from .cli_analysis import register_analysis
    from .cli_atlas import register_atlas
    from .cli_sweep import register_sweep
    from .reproduce import register_reproduce

    parser = _Parser(
        prog="pydrill",
        description="Stick-slip, stuck bits and steady drilling of torsional drillstring models.",
        epilog="Run 'pydrill COMMAND --help' for the options of each command.",
    )
    parser.add_argument("--version", action="version", version=f"pydrill {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    sim = sub.add_parser(
        "simulate",
        help="simulate one operating point and report its regime",
        description="Simulate the string at one (W_ob, u) and judge the regime: steady, "
        "stick-slip, stuck or oscillation. Every stick/slip switch is located exactly by "
        "rootfinding and the integrator restarts there.",
        epilog=SIMULATE_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_list_options(_string_options(sim, PRESETS))
    op = sim.add_argument_group("operating point")
    op.add_argument(
        "--wob",
        type=_positive("--wob", "force"),
        required=True,
        help="weight on bit (N, > 0; or 100kN, 25klbf, 25klbs, 25kips, 10t: t, tf, tonne are a "
        "metric tonne-force)",
    )
    op.add_argument(
        "--torque",
        type=_finite("--torque", "torque"),
        required=True,
        help="surface torque u (N m, either sign; or 12kN*m, 9kft*lbf, 6600ft-lbs, 6.6klb-ft)",
    )
    run = sim.add_argument_group("simulation")
    run.add_argument(
        "--t-end",
        type=_duration("--t-end"),
        default=300.0,
        help="simulated time (s, default 300; at most 1e10)",
    )
    run.add_argument(
        "--initial",
        choices=("rest", "equilibrium"),
        default="rest",
        help="start at rest (default) or near the steady state",
    )
    run.add_argument(
        "--friction",
        choices=("exact", "karnopp"),
        default="exact",
        help="exact event-driven stick/slip (default) or the paper's Eq. 9 band",
    )
    run.add_argument(
        "--method",
        choices=("auto", "dop853", "bdf", "adams", "erk"),
        default="auto",
        help="integrator: auto (by a stiffness estimate, says why), dop853 (explicit "
        "Runge-Kutta 8(5,3), non-stiff strings), bdf (CVODES, stiff strings), adams (CVODES) "
        "or erk (ARKODE explicit Runge-Kutta 7(8))",
    )
    run.add_argument(
        "--rtol",
        type=_positive("--rtol"),
        default=1e-8,
        help="relative tolerance (default 1e-8; 1e-14 ... 0.01)",
    )
    run.add_argument(
        "--atol",
        type=_positive("--atol"),
        default=1e-8,
        help="absolute tolerance (rad and rad/s; default 1e-8; 1e-20 ... 0.001)",
    )
    run.add_argument(
        "--n-out",
        type=_integer("--n-out", 2, 10**8),
        default=3001,
        help="number of output times (default 3001; 2 ... 1e8)",
    )
    run.add_argument(
        "--max-steps",
        type=_integer("--max-steps", 1, MAX_STEPS),
        default=50_000_000,
        help="internal steps allowed over the whole run (default 5e7, at most 1e12): a long "
        "run of a stiff or chattering string may need more",
    )
    run.add_argument(
        "--max-switch-rate",
        type=_positive("--max-switch-rate"),
        default=1e4,
        metavar="RATE",
        help="stick/slip switches per simulated second beyond which a burst of them is "
        "stopped as chattering (default 1e4; > 0)",
    )
    run.add_argument(
        "--window",
        type=_fraction("--window"),
        default=0.5,
        help="fraction of the run (at its end) judged for the regime, 0 < F <= 1 (default 0.5)",
    )
    out = sim.add_argument_group("output")
    out.add_argument("--json", action="store_true", help="print one JSON object for scripts")
    out.add_argument(
        "--plot", metavar="FILE.png", type=figure_path, help="draw velocities and bit torque"
    )
    sim.set_defaults(handler=_cmd_simulate)

    register_analysis(sub, PRESETS)
    register_sweep(sub, _positive)
    register_atlas(sub)
    register_reproduce(sub)
    return parser


def _cmd_simulate(args: argparse.Namespace) -> int:
    from . import SolverError, simulate
    from .simulate import _check_output_size

    try:  # the string first: a refused one is one line, not a note on the load and then it
        params = string_params(args, list_overrides(args))
        _check_output_size(None, args.n_out, params.dof)  # before the note on its size
    except ValueError as exc:
        raise as_options(exc) from None
    size = 16.0 * args.n_out * params.dof  # bytes of output: the state at every output time
    if size > 1e9:  # possible, but a gigabyte of samples is most likely not what was meant
        print(
            f"pydrill: note: --n-out {args.n_out} output times of {params.dof} inertias take "
            f"{size / 1e9:.3g} GB of memory",
            file=sys.stderr,
        )
    try:
        result = simulate(
            params,
            wob=args.wob,
            torque=args.torque,
            t_end=args.t_end,
            initial=args.initial,
            friction=args.friction,
            method=args.method,
            rtol=args.rtol,
            atol=args.atol,
            n_out=args.n_out,
            max_steps=args.max_steps,
            max_switch_rate=args.max_switch_rate,
            window_fraction=args.window,
        )
    except (ValueError, SolverError) as exc:  # worded for the API: name the options instead
        raise as_options(exc) from None
    unsaved = None
    if args.plot:
        from .plot import save, simulation_figure

        try:
            save(simulation_figure(result), args.plot)
        except OSError as exc:  # the results are computed: print them, then say so
            unsaved = exc
    plot = args.plot if unsaved is None else None
    if args.json:
        data = result.to_dict()
        data["note"] = data["note"] and cli_note(data["note"])
        inputs = {"inputs": data.pop("inputs"), **string_json(args)}
        if args.tally is not None:  # as the text names it: the tally's name and length
            inputs["string"] = result.params.name
        units = {**data.pop("units"), **string_units(args)}
        print_json(json_document(inputs, data, units, plot))
    else:
        say_changed(args)
        print(_describe(result, plot, tally=args.tally is not None))
    if unsaved is not None:
        raise unsaved
    return 0


def _describe(result: Any, plot: str | None, tally: bool = False) -> str:
    from .cli_analysis import counted, rpm

    s = result.summary
    st = result.stats
    # A real string's torques in kN m, as its W_ob is in kN (was "T_s = 7468 N m (surface
    # torque 9000)" for --wob 60kN --torque 9kN*m); a laboratory string's stay in N m.
    big = kilo(result.wob, result.torque, s.static_torque)
    scale, unit = (1e3, "kN m") if big else (1.0, "N m")
    # A tally's string is named by its file and depth alone: say which string that made (a
    # joint length typed "9 mm" for "9 m" made a 50 m string, silently).
    string = result.params
    lines = [f"string          {string.name}, {string.dof} inertias"] if tally else []
    lines += [
        f"regime          {s.regime}",
        f"bit velocity    min {s.bit_min:.4g}  max {s.bit_max:.4g}  mean {s.bit_mean:.4g} rad/s"
        f"  (mean {rpm(s.bit_mean):.4g} rpm)",
        f"top velocity    min {s.top_min:.4g}  max {s.top_max:.4g}  mean {s.top_mean:.4g} rad/s"
        f"  (mean {rpm(s.top_mean):.4g} rpm)",
        f"severity        {s.severity:.3g}   (max-min)/(2 mean) of the bit velocity",
        f"stuck           {100 * s.stuck_fraction:.1f} % of [{s.window_start:g}, "
        f"{s.window_end:g}] s, {counted(s.stick_events, 'stick event')}"
        + (f", period {s.period:.4g} s" if s.period else ""),
        "steady states   "
        + (
            ", ".join(
                f"{w:.6g} rad/s ({rpm(w):.4g} rpm{', unstable: past the fold' if past else ''})"
                for w, past in zip(s.omega_equilibrium, result.past_fold(), strict=True)
            )
            if s.omega_equilibrium
            else "none (the torque cannot balance the bit friction)"
        ),
        f"static torque   T_s = {s.static_torque / scale:.4g} {unit} (surface torque "
        f"{_surface_torque(result.torque, big)})",
        f"solver          {st.method} ({st.method_reason}); {counted(st.steps, 'step')}, "
        f"{counted(st.switches, 'switch', 'switches')}, {1e3 * st.wall_time:.1f} ms in the core",
    ]
    if s.note:
        lines.append(f"note            {cli_note(s.note)}")
    if plot:
        lines.append(f"figure          {plot}")
    return "\n".join(lines)


def cli_note(note: str) -> str:
    """A run's note as the command line's user acts on it: its advice names the option
    (``--window``), not the keyword of ``simulate`` (``window_fraction``)."""
    return note.replace("(window_fraction)", "(--window)")


def _surface_torque(torque: float, big: bool) -> str:
    """The surface torque with its unit, in T_s's unless under 1 kN m: "T_s = 8 kN m (surface
    torque 0.0083)", no unit, read as 8.3 kN m where --torque 8.3 (N m) was given."""
    from .cli_options import shown

    return shown(torque, "N m", big and abs(torque) >= 1e3)


def main(argv: Sequence[str] | None = None) -> int:
    line = sys.argv[1:] if argv is None else list(argv)
    _Parser.argv, _Parser.json_sent = line, False
    try:
        with writable_output():
            code = _run(line)
            try:  # here, not at exit: a reader gone before it made that flush fail, status 120
                sys.stdout.flush()
            except BrokenPipeError:
                quiet_stdout()
            return code
    finally:
        _Parser.argv = None


def _run(line: list[str]) -> int:
    from .cli_set import option_names

    parser = build_parser()
    _Parser.line = (parser, line)
    try:
        args = parser.parse_args(line)
    finally:
        _Parser.line = None
    args.option_names = option_names(parser, args)  # for --set's refusal of an option's name
    from . import SolverError
    from .sweep import AtlasError, SchedulerError
    from .tally import TallyError

    # "pydrill atlas query: error: ...", not just "pydrill atlas: ...".
    prog = "pydrill " + " ".join(filter(None, [args.command, getattr(args, "atlas_command", None)]))
    try:
        return int(args.handler(args))
    except BrokenPipeError:  # e.g. piped into head: not an error of ours
        quiet_stdout()
        return 0
    except KeyboardInterrupt:  # Ctrl-C: the user knows why; a traceback would only hide it
        sys.stderr.write(f"\n{prog}: interrupted\n")
        error_json("interrupted", "stopped by Ctrl-C", 130)
        return 130
    except MemoryError:  # e.g. a string or an output too large for this machine
        message = "out of memory: ask for a smaller string or fewer output times"
        say_error(prog, "error", message, EXIT_USAGE)
        return EXIT_USAGE
    except OSError as exc:  # a path that cannot be read or written: name it, and its option
        say_error(prog, "error", os_error_message(exc, line), EXIT_USAGE)
        return EXIT_USAGE
    # Bad input of every kind.
    except (ValueError, TallyError, AtlasError, SchedulerError) as exc:
        say_error(prog, "error", str(exc), EXIT_USAGE)
        return EXIT_USAGE
    except SolverError as exc:
        t = getattr(exc, "t_reached", None)
        where = f" (reached t = {t:g} s)" if t is not None else ""
        say_error(prog, "solver failed", str(exc), EXIT_SOLVER, where, t_reached=t)
        return EXIT_SOLVER


def quiet_stdout() -> None:
    """Point standard output, whose reader has gone (``| head``), at /dev/null: Python flushes
    it again at exit, and that flush failed with a message on stderr ("Exception ignored ...
    BrokenPipeError"). Python's own recipe (the signal module's "Note on SIGPIPE"); standard
    error was closed instead, and a program that called ``main`` lost its own stderr with it."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # not a file (captured): nothing flushes
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)


if __name__ == "__main__":
    raise SystemExit(main())
