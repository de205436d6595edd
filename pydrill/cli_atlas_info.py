"""``pydrill atlas info``: what an atlas holds, counted (``atlas_summary``), as text or JSON;
and the axis and model lines it shares with ``sweep --dry-run``."""

from __future__ import annotations

import argparse
import shlex
import textwrap
from typing import Any

from .atlas_grid import axis_unit, shown_unit, with_unit
from .cli_options import json_document, print_json


def axis_line(name: str, size: int, low: float, high: float, width: int = 12) -> str:
    """An axis as ``atlas info`` and ``sweep --dry-run`` list it, with its unit; ``width``:
    the longest name of the axes listed together (stribeck_velocity), so that they align."""
    name = name.ljust(max(width, 12))
    if size == 1:
        return f"  axis {name} {size:6d} value,  {with_unit(name.strip(), low)}"
    unit = shown_unit(name.strip(), low, high)
    return (
        f"  axis {name} {size:6d} values, {with_unit(name.strip(), low, unit)} ... "
        f"{with_unit(name.strip(), high, unit)}"
    )


def model_line(m: dict[str, Any]) -> str:
    """The string an atlas is of, as ``atlas info`` shows it: ``model   string paper-eq53
    (tally), 105 inertias, torque 9 kN·m; 100 s from each start``."""
    from .plot_atlas import shown_unit as parameter_unit

    what = f"string {m['string']} (tally)" if m["from"] == "tally" else f"preset {m['string']}"
    parts = [what + ("" if m["inertias"] is None else f", {m['inertias']} inertias")]
    for name, v in m["held"].items():
        if isinstance(v, list | tuple):  # a value per element: shown when few
            shown = f"[{', '.join(f'{x:.4g}' for x in v)}]" if len(v) <= 4 else ""
            unit = parameter_unit(name)
            parts.append(f"{name} {shown} {unit}".rstrip() if shown else f"{name} as given")
        elif name in ("wob", "torque", "depth"):  # 9 kN·m as the spec likely gave it
            parts.append(f"{name} {with_unit(name, v)}")
        else:
            parts.append(f"{name} {v:.4g} {parameter_unit(name)}".rstrip())
    parts[-1] += f"; {m['t_end']:g} s from each start"
    lines = ["  model   " + parts[0]]
    for part in parts[1:]:  # wrapped at 79 between parts, never inside "60 N·m·s/rad"
        if len(lines[-1]) + 2 + len(part) > 79:
            lines[-1] += ","
            lines.append(" " * 10 + part)
        else:
            lines[-1] += ", " + part
    return "\n".join(lines)


def cmd_info(args: argparse.Namespace) -> int:
    from .atlas import Atlas

    with Atlas(args.atlas) as atlas:
        s = atlas.summary()
    if args.json:
        results = dict(s)
        inputs = {"path": results.pop("path")}
        from .atlas_summary import model_units

        units = {"axes": {name: axis_unit(name) for name in s["axes"]}}
        units["model"] = model_units(s["model"])  # a held torque's 9000.0 is N·m
        print_json(json_document(inputs, results, units))
        return 0
    print(
        f"{s['path']}: {s['points']} point{'' if s['points'] == 1 else 's'}, "
        f"pydrill {s['pydrill_version']}, spec {s['spec_digest']}"
    )
    if s["spec_digest_here"] != s["spec_digest"]:
        note = (
            f"note: its spec makes digest {s['spec_digest_here']} in this pydrill: the file "
            f"was changed after pydrill wrote it, or pydrill {s['pydrill_version']} made "
            "another model of this spec (its points are of that model; --resume refuses the atlas)"
        )
        print(textwrap.fill(note, 79, initial_indent="  ", subsequent_indent="        "))
    print(model_line(s["model"]))
    for name, ax in s["axes"].items():
        print(axis_line(name, ax["size"], ax["min"], ax["max"], max(map(len, s["axes"]))))
    print("  status  " + ", ".join(f"{k} {v}" for k, v in s["status"].items()))
    for init, counts in s["regimes"].items():
        print(f"  from {init:12s}" + ", ".join(f"{k} {v}" for k, v in counts.items()))
    # With one start there is nothing to disagree with: no such count.
    disagree = (
        f", rest/equilibrium disagree at {s['coexistence_points']}" if len(s["initial"]) > 1 else ""
    )
    safe = s["safe_points"]
    safe = "unknown (stability not recorded)" if safe is None else safe
    print(f"  safe points {safe}{disagree}")
    for init, counts in s["caveats"].items():
        from . import atlas_format as fmt

        longer = {k: v for k, v in counts.items() if k not in fmt.FINAL_CAVEATS}
        if longer:
            notes = ", ".join(f"{k} {v}" for k, v in longer.items())
            print(f"  caveats from {init}: {notes} (points to simulate longer; query shows which)")
        if n := counts.get("run-away"):
            note = (
                f"run-away from {init}: {n} point{'s' * (n > 1)} (c_r + c_b = 0 and |u| > T_c: "
                "no steady state holds the bit, which speeds up without bound)"
            )
            print(textwrap.fill(note, 79, initial_indent="  ", subsequent_indent="        "))
    if s["part"]:
        p = s["part"]
        note = (
            f"part    {p['k']} of {p['n']} of {p['of']} (pydrill sweep --part): 'pydrill "
            "atlas merge' joins the parts"
        )
        print(textwrap.fill(note, 79, initial_indent="  ", subsequent_indent="          "))
    if s["merged_from"]:
        parts = ", ".join(str(p.get("file", "?")) for p in s["merged_from"] if isinstance(p, dict))
        note = f"merged from {parts} (pydrill atlas merge)"
        print(textwrap.fill(note, 79, initial_indent="  ", subsequent_indent="    "))
    if s["journal"]:
        from pathlib import Path

        from .atlas_lock import writer

        more = s["journal_points"]
        held = f"holds {more} more points, not yet in the atlas" if more else "is there"
        holder = writer(Path(args.atlas))  # the sweep writing it now, if one is
        part = "" if s["part"] is None else f" --part {s['part']['k']}/{s['part']['n']}"
        resume = f"pydrill sweep SPEC.toml{part} --out {shlex.quote(args.atlas)} --resume"
        why = (
            f"a sweep is writing this atlas now ({holder})"
            if holder is not None
            else f"a sweep into this atlas was stopped; '{resume}' completes it (SPEC.toml: "
            "the spec it was swept from)"
        )
        print(f"  journal {s['journal']} {held}:\n          {why}")
    return 0
