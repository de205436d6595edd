"""The notes ``pydrill sweep`` gives on a spec before it runs: values that are most likely
not what was meant (a depth beyond any well, a bare number in the wrong unit, a Karnopp band
with the exact law). Said on stderr; the sweep goes on."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .spec import SweepSpec


def spec_notes(spec: SweepSpec) -> None:
    """The notes the single-run commands give on implausible values (cli_string), on a
    spec's: a depth beyond the longest well (depth = "30 km" swept a 3334-inertia string
    quietly), a real string's W_ob or torque beyond what any bit or top drive takes, a friction
    coefficient above any bit's, a Karnopp band with the exact law. Said on stderr, before
    anything runs; the sweep goes on (the values may be meant)."""
    from .cli_options import HEAVIEST_WOB, LONGEST_WELL, TOP_DRIVE_TORQUE
    from .cli_set import friction_notes
    from .spec_sections import held_in_vain

    def largest(name: str) -> float | None:
        values = spec.axes.get(name, [spec.fixed[name]] if name in spec.fixed else [])
        return max((abs(float(v)) for v in values), default=None)

    key = {
        name: ("axes." if name in spec.axes else "model.") + name
        for name in ("depth", "wob", "torque")
    }
    import tomllib

    doc = tomllib.loads(spec.text)
    notes = tally_file_notes(spec)
    depth = largest("depth")
    if depth is not None and depth > LONGEST_WELL:
        # "a bare number is m" of depth = "30 km" contradicted what was written
        written = _written_largest(doc, "depth", depth)
        bare = (
            f'; a bare number is m: for feet write "{written:g} ft"'
            if isinstance(written, int | float)
            else ""
        )
        notes.append(
            f"{key['depth']} reaches {depth / 1e3:g} km, longer than any well ever drilled (the "
            f"longest some {LONGEST_WELL / 1e3:g} km){bare}"
        )
    if spec.tally_text is not None or spec.preset == "real-string":
        wob, torque = largest("wob"), largest("torque")
        if wob is not None and wob > HEAVIEST_WOB:
            notes.append(
                f"{key['wob']} reaches {wob / 1e3:g} kN: no drill bit takes over "
                f"{HEAVIEST_WOB / 1e3:g} kN"
            )
        if torque is not None and torque > TOP_DRIVE_TORQUE:
            notes.append(
                f"{key['torque']} reaches {torque / 1e3:g} kN·m: the strongest top drives give "
                f"some {TOP_DRIVE_TORQUE / 1e3:g} kN·m"
            )
    # friction coefficients beyond any bit's, and a bit radius wider than any bit's, on any
    # string (a laboratory one's too); a swept bit_radius = [8.5] was said nothing of
    swept: dict[str, float] = {
        n: float(max(spec.axes[n]))
        for n in ("mu_static", "mu_coulomb", "bit_radius")
        if n in spec.axes
    }
    radius = {"bit_radius": _written_largest(doc, "bit_radius", swept.get("bit_radius"))}
    notes += friction_notes("axes.", swept, "reaches", written=radius)
    written = doc.get("model", {})  # "8.5 m" or 8.5, as the spec has it
    notes += friction_notes("model.", dict(spec.overrides), written=written) + held_in_vain(spec)
    for note in notes:
        print(f"pydrill: note: {note}", file=sys.stderr)


def _written_largest(doc: dict, name: str, largest: float | None) -> object:
    """``name``'s value as the spec writes it (in [axes] or [model]) that is ``largest``:
    8.5 or "8.5 m", for a note to say whether it was bare; None if none is."""
    from .atlas_grid import coordinate

    raw = doc.get("axes", {}).get(name, doc.get("model", {}).get(name))
    items = [raw.get("start"), raw.get("stop")] if isinstance(raw, dict) else raw
    for item in items if isinstance(items, list) else [items]:
        try:
            if largest is not None and coordinate(name, item) == largest:
                return item
        except (TypeError, ValueError):  # the spec has refused what it could not read
            continue
    return None


def tally_file_notes(spec: SweepSpec) -> list[str]:
    """A tally string's notes, as simulate and window give them: a bare joint length most
    likely meant in feet (31 read as 31 m made a 10 km string that a sweep swept silently),
    and, unless a depth sets the length, a string longer than any well."""
    if spec.tally_text is None:
        return []
    import tomllib

    from .cli_string import tally_notes
    from .tally import parse_tally

    path = tomllib.loads(spec.text).get("model", {}).get("tally", "model.tally")
    own_length = "depth" not in spec.axes and "depth" not in spec.fixed
    return tally_notes(parse_tally(spec.tally_text), str(path), own_length)
