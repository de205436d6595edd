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
from pathlib import Path
from typing import Any

import numpy as np

from . import units
from .model import Params

KINDS = ("drill-pipe", "heavy-weight", "drill-collar", "stabilizer", "bit", "other")
STEEL_G = 79.3e9  # Pa, shear modulus of drill-pipe steel (11.5 Mpsi)
STEEL_RHO = 7850.0  # kg/m³


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
        element)."""
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

    def to_params(self, dof: int | None = None, lump: int = 1) -> Params:
        """The lumped chain (see the module docstring for the rule)."""
        k, j, _ = self.elements(lump)
        if dof is not None:
            if dof < 2 or dof > len(k) + 1:
                raise TallyError(f"dof = {dof} is not allowed: 2 ... {len(k) + 1} for this tally")
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


def _get(table: dict, key: str, where: str, kind: str | None, default: Any = None) -> Any:
    if key not in table:
        if default is None:
            raise TallyError(f"{where}.{key}: missing")
        return default
    value = table[key]
    if kind is None:
        return value
    try:
        v = units.parse(value, kind)
    except ValueError as exc:
        raise TallyError(f"{where}.{key}: {exc}") from None
    return v


def parse_tally(text: str, name: str = "tally") -> Tally:
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
    steel = doc.get("steel", {})
    g = _get(steel, "shear_modulus", "steel", "modulus", STEEL_G)
    rho = _get(steel, "density", "steel", "density", STEEL_RHO)
    top = doc.get("top_drive", {})
    bit = doc.get("bit", {})
    damp = doc.get("damping", {"model": "stiffness-proportional", "beta": 0.2})
    if damp.get("model", "stiffness-proportional") != "stiffness-proportional":
        raise TallyError("damping.model: only 'stiffness-proportional' (c = beta * k) is offered")
    beta = float(damp.get("beta", 0.2))
    if not beta >= 0:
        raise TallyError(f"damping.beta = {beta!r}: must be >= 0 s")
    sections = []
    for n, sec in enumerate(doc.get("section", [])):
        where = f"section[{n}]"
        kind = sec.get("kind", "other")
        if kind not in KINDS:
            raise TallyError(f"{where}.kind = {kind!r}: choose one of {', '.join(KINDS)}")
        count = sec.get("count", 1)
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise TallyError(f"{where}.count = {count!r}: an integer >= 1")
        s = Section(
            kind,
            count,
            _get(sec, "length", where, "length"),
            _get(sec, "od", where, "length"),
            _get(sec, "id", where, "length", 0.0),
            _get(sec, "shear_modulus", where, "modulus", g),
            _get(sec, "density", where, "density", rho),
        )
        for key in ("length", "od"):
            if not getattr(s, key) > 0:
                raise TallyError(f"{where}.{key} = {getattr(s, key)!r} m: must be > 0")
        if not 0 <= s.id < s.od:
            raise TallyError(f"{where}.id = {s.id:g} m: need 0 <= id < od = {s.od:g} m")
        sections.append(s)
    if not sections:
        raise TallyError("section: the tally lists no sections ([[section]] tables)")
    diameter = _get(bit, "diameter", "bit", "length")
    if not diameter > 0:
        raise TallyError("bit.diameter: must be > 0")
    tally = Tally(
        sections=tuple(sections),
        top_inertia=_get(top, "inertia", "top_drive", "inertia"),
        top_damping=_get(top, "damping", "top_drive", "damping", 0.0),
        bit_radius=diameter / 2,
        bit_damping=_get(bit, "damping", "bit", "damping", 0.0),
        beta=beta,
        mu_coulomb=float(bit.get("mu_coulomb", 0.5)),
        mu_static=float(bit.get("mu_static", 0.8)),
        stribeck_decay=float(bit.get("stribeck_decay", 0.9)),
        stribeck_velocity=float(bit.get("stribeck_velocity", 1.0)),
        name=str(doc.get("name", name)),
    )
    try:
        tally.to_params(dof=2)  # every parameter passes the model's own validation
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
