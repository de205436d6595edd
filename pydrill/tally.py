"""Drill strings from a pipe tally: geometry in, a lumped torsional chain out.

A tally (TOML) lists the string from the top down — drill pipe, heavy-weight pipe, drill
collars, stabilizers, the bit — each section with its joint count, joint length, outer and
inner diameter and steel properties, plus the top drive and the bit–rock law::

    [top_drive]
    inertia = 2122.0                 # kg·m²
    damping = 425.0                  # c_r, N·m·s/rad
    [bit]
    diameter = "12.25 in"
    damping = 50.0                   # c_b: mud on the bit, N·m·s/rad
    [damping]
    model = "stiffness-proportional" # c = beta · k for every element
    beta = 0.2                       # s
    [[section]]
    kind = "drill-pipe"
    count = 100
    length = "9 m"
    od = "5 in"
    id = "4.408 in"

**Lumping rule.** Every joint (or every ``lump`` joints of drill pipe) is one element: a
torsional spring of stiffness G·I_p/L carrying, at its lower end, an inertia ρ·I_p·L, with
I_p = π(OD⁴ − ID⁴)/32. The chain is the top drive, then these elements in order — the paper's
structure (Fig. 2), where each pipe is a spring k_t and an inertia J. Reducing to ``dof`` N
groups the elements into N − 1 consecutive groups of nearly equal element count: springs in series,
inertias summed at the group's lower end; ``dof = 2`` is the paper's two-inertia model (top
drive; whole string and BHA at the bit; one equivalent spring).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, replace
from numbers import Integral, Real
from pathlib import Path
from typing import Any

import numpy as np

from . import units
from .model import Params
from .spec_rules import MAX_DOF  # a string's most inertias, as in sweeps

KINDS = ("drill-pipe", "heavy-weight", "drill-collar", "stabilizer", "bit", "other")
STEEL_G = 79.3e9  # Pa, shear modulus of drill-pipe steel (11.5 Mpsi)
STEEL_RHO = 7850.0  # kg/m³
# The keys each table takes; any other is refused (a typo would silently keep the default).
TOP_DRIVE_KEYS = ("inertia", "damping")
BIT_KEYS = ("diameter", "damping", "mu_coulomb", "mu_static", "stribeck_decay", "stribeck_velocity")
DAMPING_KEYS = ("model", "beta")
STEEL_KEYS = ("shear_modulus", "density")
SECTION_KEYS = ("kind", "count", "length", "od", "id", "shear_modulus", "density")
# The widest pipe or bit: conductor casing is some 1 m across, hole openers 1.5 m; more is a
# unit mistake (and OD⁴ of an absurd diameter overflows).
MAX_DIAMETER = 5.0  # m
# The deepest string: beyond the Earth's radius no string can reach. The deepest borehole ever
# drilled (Kola SG-3) is 12.3 km, but sweeps may go far deeper with lumped joints
# (tests/test_spec.py builds one of 2000 km); MAX_DOF bounds what a string costs.
MAX_DEPTH = 6.371e6  # m
_DEEPEST = " (the Earth's radius; the deepest borehole ever drilled is some 12.3 km)"


class TallyError(ValueError):
    """A tally that cannot describe a string; the message names the key."""


@dataclass(frozen=True)
class Section:
    kind: str
    count: int
    length: float  #: m per joint
    od: float  #: m
    id: float  #: m
    shear_modulus: float = STEEL_G
    density: float = STEEL_RHO

    @property
    def polar_moment(self) -> float:
        """I_p = π (OD⁴ − ID⁴) / 32, m⁴."""
        return math.pi * (self.od**4 - self.id**4) / 32.0

    def joint_stiffness(self) -> float:
        return self.shear_modulus * self.polar_moment / self.length

    def joint_inertia(self) -> float:
        return self.density * self.polar_moment * self.length


@dataclass(frozen=True)
class Tally:
    """A drill string as listed on its pipe tally, top down, in SI units.

    Read one with :func:`load_tally` (or ``parse_tally`` from TOML text); :meth:`at_depth`
    lengthens the drill pipe to a depth, :meth:`to_params` lumps it into the torsional chain
    that :func:`pydrill.simulate` and the stability analysis take.
    """

    sections: tuple[Section, ...]
    top_inertia: float  #: J_0 of top drive and gearbox, kg·m²
    top_damping: float  #: c_r, N·m·s/rad
    bit_radius: float  #: R_b, m (half the bit diameter)
    bit_damping: float  #: c_b, mud on the bit, N·m·s/rad
    beta: float  #: s, element damping c = β k
    mu_coulomb: float = 0.5  #: μ_cb
    mu_static: float = 0.8  #: μ_sb
    stribeck_decay: float = 0.9  #: γ_b
    stribeck_velocity: float = 1.0  #: v_f, rad/s
    name: str = field(default="tally", compare=False)  #: the tally file's stem

    @property
    def length(self) -> float:
        """Measured length of the whole string, m (the depth it reaches)."""
        return sum(s.count * s.length for s in self.sections)

    @property
    def bha_length(self) -> float:
        """Length of everything but the drill pipe (the bottom-hole assembly), m."""
        return sum(s.count * s.length for s in self.sections if s.kind != "drill-pipe")

    def at_depth(self, depth: float) -> Tally:
        """The string that reaches ``depth`` (m): the BHA as listed, drill pipe above it —
        joints added (or removed) from the first drill-pipe section."""
        try:
            value = (
                float(depth) if isinstance(depth, Real) and not isinstance(depth, bool) else None
            )
        except OverflowError:  # an int beyond any float
            value = math.inf
        if value is None or not 0 < value <= MAX_DEPTH:
            shown = _show(depth) if value is None else repr(value)
            raise TallyError(
                f"depth = {shown} m is not allowed: a finite depth > 0, at most {MAX_DEPTH:g} m"
                + _DEEPEST
            )
        depth = value
        pipe = [i for i, s in enumerate(self.sections) if s.kind == "drill-pipe"]
        if not pipe:
            raise TallyError("at_depth needs a drill-pipe section to lengthen")
        i = pipe[0]
        rest = self.length - self.sections[i].count * self.sections[i].length
        need = depth - rest
        if need <= 0:
            raise TallyError(
                f"depth {depth:g} m is shallower than the BHA and other sections ({rest:g} m)"
            )
        count = max(1, math.ceil(need / self.sections[i].length - 1e-9))
        sections = list(self.sections)
        sections[i] = replace(sections[i], count=count)
        return replace(self, sections=tuple(sections))

    def elements(self, lump: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Element stiffnesses, inertias and lengths, top down (``lump`` drill-pipe joints per
        element). Refuses a string of more than ``MAX_DOF`` inertias, naming the lump that fits."""
        if isinstance(lump, bool) or not isinstance(lump, Integral) or lump < 1:
            raise TallyError(
                f"lump = {_show(lump)} is not allowed: an integer >= 1 "
                "(drill-pipe joints per element)"
            )
        lump = int(lump)
        n = self._inertias(lump)
        if n > MAX_DOF:
            raise TallyError(
                f"lump = {lump}: the string ({self.length:g} m) has {n} inertias, "
                f"at most {MAX_DOF} are allowed: {self._lump_hint()}"
            )
        k, j, length = [], [], []
        for s in self.sections:
            per = lump if s.kind == "drill-pipe" else 1
            left = s.count
            while left > 0:
                n = min(per, left)
                k.append(s.joint_stiffness() / n)  # n joints in series
                j.append(s.joint_inertia() * n)
                length.append(s.length * n)
                left -= n
        return np.array(k), np.array(j), np.array(length)

    def _inertias(self, lump: int) -> int:
        """How many inertias ``elements(lump)`` makes, top drive included (without making them)."""
        return 1 + sum(
            -(-s.count // (lump if s.kind == "drill-pipe" else 1)) for s in self.sections
        )

    def _lump_hint(self) -> str:
        """What to do about a string of more than MAX_DOF inertias."""
        pipe = max((s.count for s in self.sections if s.kind == "drill-pipe"), default=0)
        if pipe == 0 or self._inertias(pipe) > MAX_DOF:
            return "its sections other than drill pipe are one inertia a joint: list fewer joints"
        low, high = 1, pipe  # the smallest lump that fits: inertias fall as the lump grows
        while low < high:
            mid = (low + high) // 2
            low, high = (low, mid) if self._inertias(mid) <= MAX_DOF else (mid + 1, high)
        return (
            f"lump more drill-pipe joints into each element (lump >= {low}; --lump {low} on the "
            "command line) or reduce the depth"
        )

    def to_params(self, dof: int | None = None, lump: int = 1) -> Params:
        """The lumped chain (see the module docstring for the rule)."""
        k, j, _ = self.elements(lump)
        if dof is not None:
            if isinstance(dof, bool) or not isinstance(dof, Integral) or not 2 <= dof <= len(k) + 1:
                raise TallyError(
                    f"dof = {_show(dof)} is not allowed: 2 ... {len(k) + 1} for this tally"
                )
            groups = np.array_split(np.arange(len(k)), dof - 1)
            k = np.array([1.0 / np.sum(1.0 / k[g]) for g in groups])
            j = np.array([np.sum(j[g]) for g in groups])
        return Params(
            inertias=(self.top_inertia, *j.tolist()),
            stiffnesses=tuple(k.tolist()),
            dampings=tuple((self.beta * k).tolist()),
            top_damping=self.top_damping,
            bit_damping=self.bit_damping,
            bit_radius=self.bit_radius,
            mu_coulomb=self.mu_coulomb,
            mu_static=self.mu_static,
            stribeck_decay=self.stribeck_decay,
            stribeck_velocity=self.stribeck_velocity,
            name=self.name,
        )


def _show(value: Any) -> str:
    """A value as the tally wrote it (TOML numbers print as written: 0.3, not 0.2999…)."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


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
        raise TallyError(f"{where}.{unknown[0]}: unknown; allowed: {', '.join(allowed)}")


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
            raise TallyError(f"{where}.{key}: missing")
        return default
    value = table[key]
    try:
        v = units.parse(value, kind)
    except ValueError as exc:
        raise TallyError(f"{where}.{key}: {exc}") from None
    if not (v >= 0 if zero else v > 0) or not v <= high:
        unit = units.SI[kind]
        bound = f", at most {high:g} {unit}" if high < math.inf else f" {unit}"
        allowed = f"a finite {kind} {'>=' if zero else '>'} 0{bound}{note}"
        raise _refuse(f"{where}.{key}", value, allowed)
    return v


def _number(table: dict, key: str, where: str, default: float, allowed: str) -> float:
    """A plain number (also one written as a string, "0.8", as float() always took)."""
    value = table.get(key, default)
    try:
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise ValueError
        v = float(value)
    except (ValueError, OverflowError):
        raise _refuse(f"{where}.{key}", value, allowed) from None
    if not math.isfinite(v):
        raise _refuse(f"{where}.{key}", value, allowed)
    return v


def _section(n: int, sec: Any, g: float, rho: float) -> Section:
    where = f"section[{n}]"
    if not isinstance(sec, dict):
        raise TallyError(
            f"malformed tally: {where} = {_show(sec)} is not allowed: a table, [[section]]"
        )
    _known(sec, where, SECTION_KEYS)
    kind = sec.get("kind", "other")
    if not isinstance(kind, str) or kind not in KINDS:
        raise _refuse(f"{where}.kind", kind, f"choose one of {', '.join(KINDS)}")
    count = sec.get("count", 1)
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise _refuse(f"{where}.count", count, "an integer >= 1 (joints)")
    od = _get(sec, "od", where, "length", high=MAX_DIAMETER)
    inner = _get(sec, "id", where, "length", 0.0, zero=True)
    if not inner < od:
        raise _refuse(f"{where}.id", sec["id"], f"need 0 <= id < od = {_show(sec['od'])}")
    s = Section(
        kind,
        count,
        _get(sec, "length", where, "length"),
        od,
        inner,
        _get(sec, "shear_modulus", where, "modulus", g),
        _get(sec, "density", where, "density", rho),
    )
    k, j = s.joint_stiffness(), s.joint_inertia()
    if not (0 < k < math.inf and 0 < j < math.inf):
        raise TallyError(
            f"{where}: a joint's stiffness G·I_p/L = {k:g} N·m/rad and inertia ρ·I_p·L = {j:g} "
            "kg·m² must be finite and > 0: check its length, od, id, shear_modulus and density"
        )
    return s


def parse_tally(text: str, name: str = "tally") -> Tally:
    """A tally from its TOML text. Raises :class:`TallyError` naming the key at fault."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise TallyError(f"not valid TOML: {exc}") from None
    unknown = set(doc) - {"top_drive", "bit", "damping", "steel", "section", "name"}
    if unknown:
        raise TallyError(
            f"{sorted(unknown)[0]}: unknown; allowed: [top_drive], [bit], "
            "[damping], [steel], [[section]]"
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
    beta = _number(damp, "beta", "damping", 0.2, "a finite number of seconds >= 0 (c = beta * k)")
    if not beta >= 0:
        raise _refuse(
            "damping.beta", damp["beta"], "a finite number of seconds >= 0 (c = beta * k)"
        )
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
    length = 0.0
    for n, sec in enumerate(listed):
        s = _section(n, sec, g, rho)
        length += s.count * s.length
        if not length <= MAX_DEPTH:
            raise _refuse(
                f"section[{n}].count",
                s.count,
                f"the string reaches {length:g} m here, beyond {MAX_DEPTH:g} m" + _DEEPEST,
            )
        sections.append(s)
    if not sections:
        raise TallyError("section: the tally lists no sections ([[section]] tables)")
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
    label = doc.get("name", name)
    if not isinstance(label, str):
        raise _refuse("name", label, "a string (the string's name)")
    tally = Tally(
        sections=tuple(sections),
        top_inertia=_get(
            top, "inertia", "top_drive", "inertia", note=" (inertias[0] of the chain)"
        ),
        top_damping=_get(top, "damping", "top_drive", "damping", 0.0, zero=True),
        bit_radius=_get(bit, "diameter", "bit", "length", high=MAX_DIAMETER) / 2,
        bit_damping=_get(bit, "damping", "bit", "damping", 0.0, zero=True),
        beta=beta,
        mu_coulomb=mu_coulomb,
        mu_static=mu_static,
        stribeck_decay=decay,
        stribeck_velocity=_get(bit, "stribeck_velocity", "bit", "velocity", 1.0),
        name=label,
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
    try:
        text = path.read_text()
    except OSError as exc:
        raise TallyError(f"cannot read the tally {path}: {exc.strerror}") from None
    return parse_tally(text, name=path.stem)
