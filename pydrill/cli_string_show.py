"""``pydrill string``: the lumped torsional model of a string, from its pipe tally or one of the
paper's presets, as the other commands build it (with --set's changes)."""

from __future__ import annotations

import argparse
from typing import Any

from .cli_options import _whole, print_json
from .cli_set import add_set_option, say_changed
from .model import _SCALARS, _UNITS, MAX_DOF, PRESETS

#: the friction law's values, which ``string`` reports beside the chain (karnopp_band, a
#: numerical device of one friction model, is none of the string's)
_FRICTION = ("mu_static", "mu_coulomb", "stribeck_decay", "stribeck_velocity")


def register_string(sub, tally_help: str) -> None:
    string = sub.add_parser(
        "string",
        help="the lumped torsional model of a string: from its pipe tally (TOML), or a preset",
        description="Build the lumped chain from a tally: one element per joint (or per --lump\n"
        "joints of drill pipe), stiffness G*I_p/L and inertia rho*I_p*L each; --dof N groups\n"
        "the elements into N-1 springs in series (--dof 2: the paper's two-inertia model).\n"
        "Or show one of the paper's strings: --preset NAME, with --dof or --pipes.\n"
        "Prints the chain, the bit and the friction law (with --set's changes): the string\n"
        "the other commands build from the same options.",
        epilog="examples:\n  pydrill string examples/tallies/paper-eq53.toml --dof 2 --json\n"
        "  pydrill string examples/tallies/paper-eq53.toml --depth 3000m\n"
        "  pydrill string examples/tallies/paper-eq53.toml --set bit_radius=6in\n"
        "  pydrill string --preset reduced-scale --dof 4\n\n"
        "units in the tally: m, ft, in (a bare length is m: one longer than any joint of pipe,\n"
        "15 m, is noted, as a string longer than any well); Pa, GPa, psi; kg/m3, lb/ft3;\n"
        "kg·m2, lb·ft2. Output is SI.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    string.add_argument("tally", metavar="TALLY.toml", nargs="?", help=tally_help)
    string.add_argument(
        "--preset",
        choices=PRESETS,
        help="one of the paper's strings instead of a tally (with --dof or --pipes)",
    )
    size = string.add_mutually_exclusive_group()
    size.add_argument(
        "--dof",
        type=_whole("--dof", f"2 ... {MAX_DOF}"),
        help="inertias: a tally's string reduced to this many (2 ... one per element), or a "
        f"preset's (2 ... {MAX_DOF}; default 4, 2 for real-string)",
    )
    size.add_argument(
        "--pipes",
        type=_whole("--pipes", f"1 ... {MAX_DOF - 3}"),
        help=f"with --preset: drill pipes P, 1 ... {MAX_DOF - 3} (same as --dof P+3)",
    )
    string.add_argument(
        "--lump",
        type=_whole("--lump", ">= 1"),
        help="with a tally: drill-pipe joints per element, >= 1 (default 1)",
    )
    string.add_argument(
        "--depth",
        help="with a tally: lengthen the drill pipe to reach this depth, > 0 (e.g. 3000m, "
        "9800ft; a bare number is m)",
    )
    add_set_option(
        string,
        "change one of the string's scalar values, as often as needed: "
        + ", ".join(_SCALARS)
        + " (SI, or with a unit: bit_damping=100, 'bit_radius=4.5 in'): the string other "
        "commands build with the same --set",
    )
    string.add_argument("--json", action="store_true", help="print one JSON object")
    string.set_defaults(handler=cmd_string)


def cmd_string(args: argparse.Namespace) -> int:
    from .cli_options import json_document
    from .cli_set import _set_refused, set_notes, set_params
    from .cli_string import _say, string_json, string_params, string_units, tally_params

    sets = set_params(args)  # a bad --set is refused before the tally is read
    tally = None
    if args.tally is None:
        if args.preset is None:
            raise ValueError(
                "give a TALLY.toml (a real string, e.g. examples/tallies/paper-eq53.toml) or "
                f"--preset NAME (one of the paper's: {', '.join(PRESETS)})"
            )
        for option, value in (("--depth", args.depth), ("--lump", args.lump)):
            if value is not None:
                raise ValueError(
                    f"{option} needs a TALLY.toml: a preset's length is set by --dof or --pipes"
                )
        p = string_params(args)  # as simulate builds it
    else:
        if args.preset is not None:
            raise ValueError("give TALLY.toml or --preset, not both")
        if args.pipes is not None:
            raise ValueError(
                "--pipes needs --preset: a tally's joints (and --depth) set its pipes; --dof N "
                "reduces its string to N inertias"
            )
        tally, p = tally_params(args.tally, args.depth, args.lump, args.dof)
        try:  # the string the other commands build from this tally with the same --set
            p = p.replace(**sets)
        except ValueError as exc:
            raise _set_refused(exc, sets) from None
        _say(set_notes(args))  # as the preset's string_params says them
    results = {
        "name": tally.name if tally else p.name,
        "dof": p.dof,
        # a preset is a lumped model only: no lengths
        "length": tally.length if tally else None,
        "bha_length": tally.bha_length if tally else None,
        "inertias": list(p.inertias),
        "stiffnesses": list(p.stiffnesses),
        "dampings": list(p.dampings),
        "top_damping": p.top_damping,
        "bit_damping": p.bit_damping,
        "bit_radius": p.bit_radius,
        "friction": {name: getattr(p, name) for name in _FRICTION},
    }
    units = {
        **({"depth": "m"} if tally else {}),
        "length": "m",
        "inertias": "kg·m2",
        "stiffnesses": "N·m/rad",
        "dampings": "N·m·s/rad",
        "top_damping": "N·m·s/rad",
        "bit_damping": "N·m·s/rad",
        "bit_radius": "m",
        "friction": {name: "1" if name.startswith("mu_") else _UNITS[name] for name in _FRICTION},
        **string_units(args),
    }
    if args.json:
        # the tally (or the preset) as the other commands echo it; "dof", the inertias,
        # follows with the results (the tally's own number, or the one asked for)
        inputs = string_json(args) if tally else {"preset": args.preset, **string_json(args)}
        print_json(json_document(inputs, results, units))
        return 0
    say_changed(args)
    _print_chain(p, tally)
    return 0


def _print_chain(p: Any, tally: Any) -> None:
    if tally is not None:
        print(f"{tally.name}: {tally.length:.1f} m ({tally.bha_length:.1f} m BHA), dof {p.dof}")
    else:
        print(f"{p.name}: dof {p.dof} (a preset: a lumped model, no pipe lengths)")
    top = f"J = {p.inertias[0]:.6g} kg m^2"
    if tally is not None and p.inertias[0] != tally.top_inertia:  # its top carries some pipe
        top += f" ({tally.top_inertia:g} + {p.inertias[0] - tally.top_inertia:.4g} of the string)"
    print(f"  top drive   {top}, c_r = {p.top_damping:g} N m s/rad")
    if p.dof <= 12:
        for i, (k, c, j) in enumerate(zip(p.stiffnesses, p.dampings, p.inertias[1:], strict=True)):
            print(
                f"  element {i + 1:3d} k = {k:.6g} N m/rad, c = {c:.6g} N m s/rad, "
                f"J = {j:.6g} kg m^2"
            )
    else:
        print(
            f"  {p.dof - 1} elements; total inertia {sum(p.inertias[1:]):.6g} kg m^2, "
            f"series stiffness {1 / sum(1 / k for k in p.stiffnesses):.6g} N m/rad"
        )
    print(f"  bit         R_b = {p.bit_radius:.6g} m, c_b = {p.bit_damping:g} N m s/rad")
    # The friction law is the string's too (a tally's [bit] sets it): --set changes it here.
    print(
        f"  friction    mu_s = {p.mu_static:g}, mu_c = {p.mu_coulomb:g}, "
        f"gamma_b = {p.stribeck_decay:g}, v_f = {p.stribeck_velocity:g} rad/s"
    )
