"""Reading a pipe tally: TOML text in, a validated Tally out, each fault naming its key."""

from __future__ import annotations

import math
import re
import sys
import tomllib
from dataclasses import replace
from pathlib import Path
from typing import Any

from . import units
from .spec_rules import load_toml, printable
from .suggest import did_you_mean
from .tally import (
    _DEEPEST,
    KINDS,
    LONGEST_JOINT,
    MAX_DEPTH,
    MAX_DIAMETER,
    STEEL_G,
    STEEL_RHO,
    WIDEST_BARE_DIAMETER,
    Section,
    Tally,
    TallyError,
    _show,
)

# The keys each table takes; any other is refused (a typo would silently keep the default).
TOP_DRIVE_KEYS = ("inertia", "damping")
BIT_KEYS = ("diameter", "damping", "mu_coulomb", "mu_static", "stribeck_decay", "stribeck_velocity")
DAMPING_KEYS = ("model", "beta")
STEEL_KEYS = ("shear_modulus", "density")
SECTION_KEYS = ("kind", "count", "length", "od", "id", "shear_modulus", "density")


def _key(where: str, key: str) -> str:
    """A key as a message names it: ``bit.diameter``, or in a section ``section 2 (heavy-weight),
    od`` (a section is no key of the file: see :func:`_section_label`)."""
    return f"{where}, {key}" if where.startswith("section ") else f"{where}.{key}"


def _section_label(n: int, sec: Any) -> str:
    """The ``n``-th [[section]] table (from 0) as the user counts it, top down from 1, with its
    kind where it names one: ``section 3 (drill-collar)``. Messages said "section[0]", an index
    from 0 that the file does not show and the guide does not use."""
    kind = sec.get("kind") if isinstance(sec, dict) else None
    return f"section {n + 1}" + (f" ({kind})" if isinstance(kind, str) and kind in KINDS else "")


def _refuse(key: str, value: Any, allowed: str) -> TallyError:
    return TallyError(f"{key} = {_show(value)} is not allowed: {allowed}")


def _table(doc: dict, key: str, allowed: tuple[str, ...]) -> dict:
    """``doc[key]``, a table of only ``allowed`` keys (empty when absent)."""
    table = doc.get(key, {})
    if not isinstance(table, dict):
        # "malformed tally" leads: a spec naming this tally reports "model.tally: malformed tally".
        raise TallyError(
            f"malformed tally: {key} = {_show(table)} is not allowed: a table, [{key}]"
        )
    _known(table, key, allowed)
    return table


def _known(table: dict, where: str, allowed: tuple[str, ...]) -> None:
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise TallyError(
            f"{_key(where, printable(unknown[0]))}: unknown{did_you_mean(unknown[0], allowed)}; "
            f"allowed: {', '.join(allowed)}"
        )


def _get(
    table: dict,
    key: str,
    where: str,
    kind: str,
    default: float | None = None,
    *,
    zero: bool = False,
    high: float = math.inf,
    note: str = "",
) -> float:
    """A quantity in driller units, finite and > 0 (>= 0 with ``zero``), at most ``high``."""
    if key not in table:
        if default is None:
            raise TallyError(f"{_key(where, key)}: missing")
        return default
    value = table[key]
    try:
        v = units.parse(value, kind)
    except ValueError as exc:
        raise TallyError(f"{_key(where, key)}: {exc}") from None
    if not (v >= 0 if zero else v > 0) or not v <= high:
        unit = units.SI[kind]
        bound = f", at most {high:g} {unit}" if high < math.inf else f" {unit}"
        allowed = f"a finite {kind} {'>=' if zero else '>'} 0{bound}{note}"
        raise _refuse(_key(where, key), value, allowed)
    return v


def _number(table: dict, key: str, where: str, default: float, allowed: str) -> float:
    """A plain number (also one written as a string, "0.8", as float() always took)."""
    value = table.get(key, default)
    try:
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise ValueError
        v = float(value)
    except (ValueError, OverflowError):
        raise _refuse(_key(where, key), value, allowed) from None
    if not math.isfinite(v):
        raise _refuse(_key(where, key), value, allowed)
    return v


def _section(n: int, sec: Any, g: float, rho: float, notes: list[str]) -> Section:
    """Section ``n`` (from 0), with a note appended to ``notes`` on a length most likely
    mistyped."""
    where = _section_label(n, sec)
    if not isinstance(sec, dict):
        raise TallyError(
            f"malformed tally: {where} = {_show(sec)} is not allowed: a table, [[section]]"
        )
    _known(sec, where, SECTION_KEYS)
    kind = sec.get("kind", "other")
    if not isinstance(kind, str) or kind not in KINDS:
        raise _refuse(
            _key(where, "kind"),
            kind,
            f"choose one of {', '.join(KINDS)}{did_you_mean(kind, KINDS)}",
        )
    count = sec.get("count", 1)
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise _refuse(_key(where, "count"), count, "an integer >= 1 (joints)")
    od = _get(sec, "od", where, "length", high=MAX_DIAMETER, note=_inches_hint("od", sec))
    inner = _get(sec, "id", where, "length", 0.0, zero=True)
    if not inner < od:
        raise _refuse(
            _key(where, "id"),
            sec["id"],
            f"need 0 <= id < od = {_show(sec['od'])}"
            + _inches_hint("id", sec, WIDEST_BARE_DIAMETER),
        )
    s = Section(
        kind,
        count,
        _get(sec, "length", where, "length"),
        od,
        inner,
        _get(sec, "shear_modulus", where, "modulus", g),
        _get(sec, "density", where, "density", rho),
    )
    notes.extend(_length_note(where, sec["length"], s.length))
    notes.extend(_diameter_note(where, "od", sec["od"], od))
    notes.extend(_diameter_note(where, "id", sec.get("id"), inner))
    k, j = s.joint_stiffness(), s.joint_inertia()
    # Normal floats (not subnormal): springs in series add 1/k, which a subnormal k overflows.
    if not (sys.float_info.min <= k < math.inf and sys.float_info.min <= j < math.inf):
        raise TallyError(
            f"{where}: a joint's stiffness G·I_p/L = {k:g} N·m/rad and inertia ρ·I_p·L = {j:g} "
            f"kg·m² must be finite and >= {sys.float_info.min:g}: check its length, od, id, "
            "shear_modulus and density"
        )
    return s


def _length_note(where: str, value: Any, length: float) -> list[str]:
    """A note on a joint length written without a unit and longer than any joint: read as m,
    it was most likely feet (or a stand); one written with its unit is taken as meant."""
    if not _bare(value) or length <= LONGEST_JOINT:  # "31 ft" is not bare
        return []
    return [
        f"{_key(where, 'length')} = {_show(value)} is read as {length:g} m per joint (a bare "
        f"number is m): longer than any joint of pipe (at most some {LONGEST_JOINT:g} m); for "
        f'feet write length = "{str(value).strip()} ft"'
    ]


def _bare(value: Any) -> bool:
    """Whether ``value`` is a number written without a unit (31, 31.0, '31'; not "31 ft")."""
    try:
        return not isinstance(value, bool) and math.isfinite(float(value))
    except (TypeError, ValueError, OverflowError):
        return False


def _diameter_note(where: str, key: str, value: Any, diameter: float) -> list[str]:
    """A note on a diameter written without a unit and wider than any pipe or bit: read as m,
    it was most likely inches; one written with its unit is taken as meant."""
    if not _bare(value) or diameter <= WIDEST_BARE_DIAMETER:
        return []
    return [
        f"{_key(where, key)} = {_show(value)} is read as {diameter:g} m (a bare number is m): "
        f"wider than any drill pipe, collar or bit (at most some {WIDEST_BARE_DIAMETER:g} m); "
        f'for inches write {key} = "{str(value).strip()} in"'
    ]


def _in_seconds(table: dict, key: str) -> dict:
    """``table`` with ``key``'s "0.2 s" (or "200 ms") as its number of seconds: a tally takes
    every quantity with its unit, and beta = "0.2 s" was refused as "not a finite number of
    seconds". Anything else as it is, for _number to judge."""
    value = table.get(key)
    match = re.fullmatch(r"\s*(.+?)\s*(s|sec|ms)\s*", value) if isinstance(value, str) else None
    if match is None:
        return table
    try:
        seconds = float(match.group(1)) * (1e-3 if match.group(2) == "ms" else 1.0)
    except ValueError:
        return table
    return {**table, key: seconds} if math.isfinite(seconds) else table  # refused as written


def _bit_note(sections: list[Section]) -> list[str]:
    """A note on a bit listed above other sections: a BHA sheet is often written from the bit
    up, and a tally listed so built the string upside down (the bit next to the top drive,
    the drill pipe at the bottom) without a word. Read as written: a note, not a refusal."""
    bits = [n for n, s in enumerate(sections) if s.kind == "bit"]
    if not bits or bits[0] == len(sections) - 1:
        return []
    n = bits[0]
    return [
        f"section {n + 1} is the bit, with {len(sections) - 1 - n} section(s) listed below it: "
        "a tally lists the string top down, from the top drive to the bit (the last section); "
        "read as written"
    ]


def _inches_hint(key: str, table: dict, wider: float = MAX_DIAMETER) -> str:
    """What a refusal of a bare diameter wider than ``wider`` m adds: it was read as m, and was
    most likely inches (od = 5.5 for 5 1/2 in pipe, the commonest size, was refused as "at most
    5 m" alone, while od = 5 was noted as inches)."""
    value: Any = table.get(key)
    if not _bare(value) or not float(value) > wider:
        return ""
    return f'; a bare number is m: for inches write {key} = "{str(value).strip()} in"'


def parse_tally(text: str, name: str = "tally") -> Tally:
    """A tally from its TOML text. Raises :class:`TallyError` naming the key at fault."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise TallyError(f"not valid TOML: {exc}") from None
    tables = ("top_drive", "bit", "damping", "steel", "section", "name")
    unknown = set(doc) - set(tables)
    if unknown:
        raise TallyError(
            f"{printable(sorted(unknown)[0])}: unknown{did_you_mean(sorted(unknown)[0], tables)}; "
            "allowed: name, [top_drive], [bit], [damping], [steel], [[section]]"
        )
    steel = _table(doc, "steel", STEEL_KEYS)
    g = _get(steel, "shear_modulus", "steel", "modulus", STEEL_G)
    rho = _get(steel, "density", "steel", "density", STEEL_RHO)
    top = _table(doc, "top_drive", TOP_DRIVE_KEYS)
    bit = _table(doc, "bit", BIT_KEYS)
    damp = _table(doc, "damping", DAMPING_KEYS)
    model = damp.get("model", "stiffness-proportional")
    if model != "stiffness-proportional":
        raise _refuse(
            "damping.model", model, "only 'stiffness-proportional' (c = beta * k) is offered"
        )
    allowed = "a finite number of seconds >= 0 (c = beta * k; '0.2 s' or 0.2)"
    beta = _number(_in_seconds(damp, "beta"), "beta", "damping", 0.2, allowed)
    if not beta >= 0:
        raise _refuse("damping.beta", damp["beta"], allowed)
    listed = doc.get("section", [])
    if isinstance(listed, dict):
        raise TallyError(
            "malformed tally: section is a single table: write each one as [[section]]"
        )
    if not isinstance(listed, list):
        raise TallyError(
            f"malformed tally: section = {_show(listed)} is not allowed: "
            "an array of tables, [[section]]"
        )
    sections = []
    notes: list[str] = []
    length = 0.0
    for n, sec in enumerate(listed):
        s = _section(n, sec, g, rho, notes)  # n from 0; a message counts from 1
        try:
            length += s.count * s.length
        except OverflowError:  # a count beyond any float: refused below, as too deep
            length = math.inf
        if not length <= MAX_DEPTH:
            raise _refuse(
                _key(_section_label(n, sec), "count"),
                s.count,
                f"the string reaches {length:g} m here, beyond {MAX_DEPTH:g} m" + _DEEPEST,
            )
        sections.append(s)
    if not sections:
        raise TallyError("section: the tally lists no sections ([[section]] tables)")
    notes.extend(_bit_note(sections))
    mu_coulomb = _number(bit, "mu_coulomb", "bit", 0.5, "a finite number > 0")
    if not mu_coulomb > 0:
        raise _refuse("bit.mu_coulomb", bit["mu_coulomb"], "need 0 < mu_coulomb < mu_static")
    mu_static = _number(bit, "mu_static", "bit", 0.8, "a finite number > mu_coulomb")
    if not mu_static > mu_coulomb:
        if "mu_static" in bit:
            raise _refuse(
                "bit.mu_static", bit["mu_static"], f"need mu_static > mu_coulomb = {mu_coulomb!r}"
            )
        raise _refuse(
            "bit.mu_coulomb",
            bit["mu_coulomb"],
            f"need mu_coulomb < mu_static = {mu_static!r} (the default; give bit.mu_static)",
        )
    decay = _number(bit, "stribeck_decay", "bit", 0.9, "a finite number > 0")
    if not decay > 0:
        raise _refuse("bit.stribeck_decay", bit["stribeck_decay"], "a finite number > 0")
    bit_diameter = _get(
        bit, "diameter", "bit", "length", high=MAX_DIAMETER, note=_inches_hint("diameter", bit)
    )
    notes.extend(_diameter_note("bit", "diameter", bit.get("diameter"), bit_diameter))
    label = doc.get("name", name)
    # Every output line and figure title begins with the name: an empty one printed
    # ": 3023.6 m ...", and a newline or an escape sequence reached the terminal as it was.
    if not isinstance(label, str) or (
        "name" in doc and not (label.strip() and label.isprintable())
    ):
        raise _refuse(
            "name", label, "a string of printable characters, not empty (the string's name)"
        )
    tally = Tally(
        sections=tuple(sections),
        top_inertia=_get(
            top, "inertia", "top_drive", "inertia", note=" (inertias[0] of the chain)"
        ),
        top_damping=_get(top, "damping", "top_drive", "damping", 0.0, zero=True),
        bit_radius=bit_diameter / 2,
        bit_damping=_get(bit, "damping", "bit", "damping", 0.0, zero=True),
        beta=beta,
        mu_coulomb=mu_coulomb,
        mu_static=mu_static,
        stribeck_decay=decay,
        stribeck_velocity=_get(bit, "stribeck_velocity", "bit", "velocity", 1.0),
        name=label,
        notes=tuple(notes),
    )
    # Every parameter passes the model's own validation: one joint of each section is enough
    # (the counts only scale them) and stays fast for a string of millions of joints.
    probe = replace(tally, sections=tuple(replace(s, count=1) for s in sections))
    try:
        probe.to_params(dof=2)
    except ValueError as exc:
        raise TallyError(str(exc)) from None
    return tally


def load_tally(path: str | Path) -> Tally:
    """Read a tally (TOML) file; the string is named after the file.

    Raises :class:`TallyError` (a ``ValueError``) naming the key at fault.
    """
    path = Path(path)
    return load_toml(path, "tally", TallyError, lambda text: parse_tally(text, name=path.stem))
