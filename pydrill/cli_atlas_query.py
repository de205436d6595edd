"""``pydrill atlas query``: everything recorded at one point of an atlas, as text or JSON;
and the ``--set AXIS=VALUE`` options that query and plot share."""

from __future__ import annotations

import argparse
import math
from typing import Any

from .atlas_grid import axis_unit, grid_unit, leave_out_held, spec_holds, with_unit
from .cli_options import json_document, print_json


def _json_unit(unit: str) -> str:
    """A unit of the atlas table as the other ``--json`` documents write it ("N·m·s/rad")."""
    return unit.replace(" ", "·")


def _typed(name: str, value: float) -> float | int:
    """A value asked for on a count axis (dof, pipes) as the integer ``coords`` gives."""
    return int(value) if name in ("dof", "pipes") and float(value).is_integer() else value


def axis_values(items: list[str]) -> dict[str, float]:
    """``--set AXIS=VALUE`` options as a dict of SI values: a VALUE may carry a unit, as the
    spec and ``--wob``, ``--depth`` take it (``torque=8 kN·m``, ``depth=3000ft``)."""
    from .atlas_grid import coordinate

    out = {}
    for item in items:
        name, equals, value = (part.strip() for part in item.partition("="))
        if not (name and equals and value):
            raise ValueError(
                f"--set {item!r}: expected AXIS=VALUE (a number, or with a unit: depth=3000ft)"
            )
        if name in out:  # --set torque=8 --set torque=9: the last won, silently
            raise ValueError(
                f"--set {item!r}: {name} is given twice; give each axis once (a map or a "
                "query is at one value; 'atlas safe' without --set lists every value)"
            )
        try:
            out[name] = coordinate(name, value)
        except ValueError as exc:  # "wob = '80 m': unit 'm' is not a force unit; ..."
            raise ValueError(f"--set {item!r}: {exc}") from None
    return out


def set_texts(items: list[str]) -> dict[str, str]:
    """What each ``--set AXIS=VALUE`` gave, as typed (``3000ft``): for its messages."""
    return {name.strip(): value.strip() for name, _, value in (i.partition("=") for i in items)}


def snap_notes(atlas: Any, at: dict[str, float], given: dict[str, str], command: str, how: str):
    """Refuse a ``--set`` value ``at`` of no axis of ``atlas``, or past its grid (its option
    ``given`` named), and note on stderr each that is not a grid value: the nearest is taken,
    and said (``atlas safe --set torque=8.4`` answered for 8.3 N·m without a word)."""
    import sys

    from .atlas_grid import not_an_axis, on_grid
    from .plot_atlas import nearest_index

    for name, value in at.items():
        if name not in atlas.axes:  # as 'atlas safe' says it (was "a held axis = 'x' ...")
            raise ValueError(f"--set {name}={given[name]}: {not_an_axis(name, atlas.axes)}")
        try:
            k = nearest_index(atlas, name, value)
        except ValueError as exc:
            raise ValueError(f"--set {name}={given[name]}: {exc}") from None
        grid = float(atlas.axes[name][k])
        if not on_grid(atlas.axes[name], k, value):  # say so: what is shown is the grid's
            print(
                f"pydrill {command}: note: --set {name}={given[name]} is not a grid value; "
                f"{how} at the nearest, {name} = "
                f"{with_unit(name, grid, grid_unit(name, atlas.axes[name]))}",
                file=sys.stderr,
            )


def cmd_query(args: argparse.Namespace) -> int:
    from . import atlas_format as fmt
    from .atlas import Atlas

    coords = {
        k: getattr(args, k)
        for k in ("wob", "torque", "depth", "dof", "pipes")
        if getattr(args, k) is not None
    }
    option = {name: f"--{name}" for name in coords}  # which option gave each value
    given = set_texts(args.set)
    for name, value in axis_values(args.set).items():
        if name in coords:  # --wob 80 --set wob=120: which one was meant?
            raise ValueError(
                f"{name} is given twice (--{name} {coords[name]:g} and --set {name}={value:g}); "
                "give it once"
            )
        coords[name] = value
        option[name] = f"--set {name}={given[name]}"
    with Atlas(args.atlas) as atlas:
        at = leave_out_held(coords, atlas.axes, spec_holds(atlas.spec), option.__getitem__)
        try:
            v = atlas.value("nearest" if args.nearest else "exact", **at)
        except KeyError as exc:  # worded for the Python API: say the option instead
            message = exc.args[0].replace("method='nearest' (--nearest)", "--nearest")
            name = message.split(" ")[0]
            if name in option and " is not an axis " in message:  # which option gave it
                message = f"{option[name]}: {message}"
            raise ValueError(message) from None
        initials = atlas.initials
        # safe as 'atlas safe' lists it (None: stability not recorded, nothing is called safe)
        safe = (
            bool(atlas.safe_region()[atlas.index("exact", **v["coords"])])
            if atlas.spec.record["stability"]
            else None
        )
        # each coordinate in its axis's unit (9 kN·m on an axis of 6 ... 12 kN·m)
        unit = {name: grid_unit(name, values) for name, values in atlas.axes.items()}
    if args.json:
        first = initials[0]
        # asked: the values given; coords: the grid point's (the same unless --nearest)
        inputs = {"atlas": args.atlas, "asked": {k: _typed(k, x) for k, x in coords.items()}}
        flat = {"regime": v["regime"][first], "coords": v["coords"], "status": v["status"]}
        if "message" in v:
            flat["message"] = v["message"]
        flat.update({k: m[first] for k, m in v["metrics"].items()})
        flat["caveat"] = v["caveat"][first]
        flat["by_initial"] = {"regime": v["regime"], "metrics": v["metrics"], "caveat": v["caveat"]}
        flat["stability"] = v["stability"]
        flat["coexistence"] = v["coexistence"]
        flat["safe"] = safe
        # Every field's unit from the table the atlas's own "units" attributes come from
        # (dimensionless ones too, so a script need not guess), and the axes'.
        units: dict[str, Any] = {  # a unit each, and the axes' units as a dict (coords)
            name: _json_unit(unit)
            for name, (_, _, unit, _) in {**fmt.RUN_FIELDS, **fmt.EQ_FIELDS}.items()
        }
        units["eigenvalues"] = "1/s"
        units["coords"] = {name: axis_unit(name) for name in v["coords"]}
        print_json(json_document(inputs, flat, units))
        return 0
    print(
        ", ".join(f"{k} = {with_unit(k, x, unit[k])}" for k, x in v["coords"].items())
        + f": {v['status']}"
    )
    moved = {k: x for k, x in at.items() if f"{x:g}" != f"{v['coords'][k]:g}"}
    if args.nearest and moved:  # say it: the point shown is not the one asked for
        asked = ", ".join(f"{k} = {with_unit(k, x, unit[k])}" for k, x in moved.items())
        print(f"  (the grid point nearest {asked})")
    if "message" in v:
        print(f"  {v['message']}")
    for init, regime in v["regime"].items():
        m = v["metrics"]
        period = m["period"][init]
        mean, stuck = m["bit_mean"][init], m["stuck_fraction"][init]
        if mean is None and stuck is None:  # not simulated: no steady state to start from
            print(f"  from {init:12s} {regime}")
            continue
        print(
            f"  from {init:12s} {regime:12s} bit mean "
            + ("-" if mean is None else f"{mean:.4g} rad/s")
            + ", stuck "
            + ("-" if stuck is None else f"{100 * stuck:.1f} %")
            + (f", period {period:.4g} s" if period else "")
        )
        caveat = v["caveat"][init]
        if caveat:
            print(f"    caveat: {caveat} ({fmt.CAVEAT_TEXT[caveat]})")
    st = v["stability"]
    if st is None:  # not recorded: say so, rather than nothing (as for no steady state)
        print("  steady states: not recorded ([record] stability = false)")
    rows = [] if st is None else zip(st["omega_eq"], st["unstable"], strict=True)
    for k, (w, unstable) in enumerate(rows):
        print(
            f"  steady state Omega = {w:.5g} rad/s ({w * 30 / math.pi:.4g} rpm): "
            + (
                "stable"
                if unstable == 0
                else f"unstable ({plural(unstable, 'eigenvalue')} with Re > 0)"
            )
        )
        # Why: how far into either half-plane the eigenvalues reach, and the Stribeck slope
        # still to go to (or past) the nearest Hopf crossing.
        why = []
        abscissa, margin = st["spectral_abscissa"][k], st["hopf_margin"][k]
        if abscissa is not None:
            why.append(f"spectral abscissa {abscissa:.4g} 1/s")
        if margin is not None:
            why.append(f"Hopf margin {margin:.4g} N·m·s/rad")
        if why:
            print("    " + ", ".join(why))
    if safe is not None:  # the verdict 'atlas safe' counts, and why not
        print(f"  safe: {_verdict(safe, v)}")
    return 0


def _verdict(safe: bool, v: dict[str, Any]) -> str:
    """'yes (...)' or 'no (what fails)': steady from every start, and the fastest steady
    state stable, is what ``Atlas.safe_region`` calls safe."""
    if safe:  # in the words of 'atlas safe': "steady from rest and from equilibrium"
        starts = " and from ".join(v["regime"])
        return f"yes (steady from {starts}, the fastest steady state stable)"
    status = v["status"]
    # A start that ended as the point did (failed, missing) is said once, with the point:
    # "the point is failed, failed from rest, failed from equilibrium" said it three times.
    why = [
        f"{regime} from {init}"
        for init, regime in v["regime"].items()
        if regime not in ("steady", status)
    ]
    unstable = v["stability"]["unstable"]
    if not why and unstable and unstable[0]:
        why.append("the fastest steady state is unstable")
    if status == "failed":
        gave_up = [init for init, regime in v["regime"].items() if regime == status]
        whence = f" from {' and from '.join(gave_up)}" if gave_up else ""
        why.insert(0, f"the point failed{whence}: the solver gave up, no result to judge")
    elif status != "done":
        why.insert(0, f"the point is {status}: not computed yet")
    return "no" + (f" ({', '.join(why)})" if why else "")


def plural(n: int, word: str) -> str:
    """``3 eigenvalues``, ``1 eigenvalue``."""
    return f"{n} {word}" + ("" if n == 1 else "s")
