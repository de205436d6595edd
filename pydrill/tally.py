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
groups the elements into N − 1 consecutive groups of nearly equal element count: springs in
series, and each element's inertia shared between its group's two ends in proportion to where
it sits along the group's compliance (the static twist interpolated between the ends). Summed at
the group's lower end instead, the reduced string's first frequency converged only like 1/N
(5 % low at dof 8 on the shipped tallies); shared, like 1/N² (0.25 % at dof 8, 0.03 % at dof
20). ``dof = 2`` stays the paper's two-inertia model (top drive; whole string and BHA at the
bit; one equivalent spring), as its Section 4.2 numbers need.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from numbers import Integral, Real
from typing import Any

import numpy as np

from .model import Params
from .spec_rules import MAX_DOF  # a string's most inertias, as in sweeps

KINDS = ("drill-pipe", "heavy-weight", "drill-collar", "stabilizer", "bit", "other")
STEEL_G = 79.3e9  # Pa, shear modulus of drill-pipe steel (11.5 Mpsi)
STEEL_RHO = 7850.0  # kg/m³
# The widest pipe or bit: conductor casing is some 1 m across, hole openers 1.5 m; more is a
# unit mistake (and OD⁴ of an absurd diameter overflows).
MAX_DIAMETER = 5.0  # m
# The deepest string: beyond the Earth's radius no string can reach. The deepest borehole ever
# drilled (Kola SG-3) is 12.3 km, but sweeps may go far deeper with lumped joints
# (tests/test_spec.py builds one of 2000 km); MAX_DOF bounds what a string costs.
MAX_DEPTH = 6.371e6  # m
_DEEPEST = " (the Earth's radius; the deepest borehole ever drilled is some 12.3 km)"
# The longest joint of pipe: range 3 drill pipe is 38-45 ft (at most 13.7 m), collars 30-31 ft.
# A section's length is one joint's (its count says how many); a bare number is m, so one
# longer than this was most likely feet ("length = 31" for 31 ft made a 10 km string). Such a
# length is said in a note, not refused: a section may list stands, or a long tool as one item.
LONGEST_JOINT = 15.0  # m
# The widest pipe or bit a bare number may mean: 36 in conductor bits are 0.91 m across. A
# diameter is written in inches on every tally sheet; a bare one is m, so "od = 5.0" for 5 in
# pipe made a 5 m pipe (its inertia 4.7e8 kg·m², a window and simulations of nothing real)
# and said nothing. Such a diameter is noted, not refused: a hole opener may be wider.
WIDEST_BARE_DIAMETER = 1.0  # m


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

    sections: tuple[Section, ...]  #: the tally's sections, top down (kind, joints, sizes)
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
    #: what the file says that is allowed but most likely mistyped (a bare joint length of
    #: 31, read as m): the command line says these as notes
    notes: tuple[str, ...] = field(default=(), compare=False, repr=False)

    def __repr__(self) -> str:
        # One line, as Params's: the dataclass's own listed every section, field by field.
        joints = sum(s.count for s in self.sections)
        return (
            f"<Tally {self.name!r}: {len(self.sections)} sections, {joints} joints, "
            f"{self.length:.6g} m (BHA {self.bha_length:.6g} m), bit_radius "
            f"{self.bit_radius:.4g} m, top_inertia {self.top_inertia:.4g} kg·m²>"
        )

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
        if value is None:  # said "depth = '3000m' m is not allowed": a number, in m
            unit = (
                f"; for a depth with its unit, pydrill.units.parse({_show(depth)}, 'length')"
                if isinstance(depth, str)
                else ""
            )
            raise TallyError(
                f"depth = {_show(depth)} is not allowed: a number of metres, > 0, at most "
                f"{MAX_DEPTH:g}{unit}"
            )
        if not 0 < value <= MAX_DEPTH:
            raise TallyError(
                f"depth = {value!r} m is not allowed: a finite depth > 0, at most {MAX_DEPTH:g} m"
                + _DEEPEST
            )
        depth = value
        pipe = [i for i, s in enumerate(self.sections) if s.kind == "drill-pipe"]
        if not pipe:
            # Said in the tally's words: "at_depth" is no name a command-line user knows.
            raise TallyError(
                f"depth {depth:g} m: the tally has no drill-pipe section (kind = "
                f'"drill-pipe") to lengthen or shorten to a depth; as listed, its string is '
                f"{self.length:g} m"
            )
        i = pipe[0]
        rest = self.length - self.sections[i].count * self.sections[i].length
        need = depth - rest
        if need <= 0:
            raise TallyError(
                f"depth {depth:g} m is shallower than the BHA and other sections ({rest:g} m)"
            )
        joints = need / self.sections[i].length
        if not math.isfinite(joints):  # a joint so short that no count reaches the depth
            raise TallyError(
                f"depth {depth:g} m needs {need:g} m of drill pipe in joints of "
                f"{self.sections[i].length:g} m: too many joints to count; check the drill "
                "pipe's length"
            )
        count = max(1, math.ceil(joints - 1e-9))
        sections = list(self.sections)
        sections[i] = replace(sections[i], count=count)
        return replace(self, sections=tuple(sections))

    def elements(self, lump: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Element stiffnesses, inertias and lengths, top down (``lump`` drill-pipe joints per
        element). Refuses a string of more than ``MAX_DOF`` inertias, naming the lump that fits."""
        _whole("lump", lump)
        if lump < 1:
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
        top = 0.0  # the inertia of the string's top that a reduction adds to the top drive's
        if dof is not None:
            _whole("dof", dof)
            if not 2 <= dof <= len(k) + 1:
                raise TallyError(
                    f"dof = {_show(dof)} is not allowed: 2 ... {len(k) + 1} for this tally"
                )
            groups = np.array_split(np.arange(len(k)), dof - 1)
            # An extreme tally (density 1e308, say) overflows here: Params then refuses the
            # inf or 0 it makes, naming the entry, and no RuntimeWarning reaches the user.
            with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
                if dof == 2:  # the paper's: one spring, the whole string's inertia at the bit
                    k, j = np.array([1.0 / np.sum(1.0 / k)]), np.array([np.sum(j)])
                else:
                    k, j, top = _shared_inertias(k, j, groups)
        with np.errstate(over="ignore", invalid="ignore"):
            c = self.beta * k
        return Params(
            inertias=(self.top_inertia + top, *j.tolist()),
            stiffnesses=tuple(k.tolist()),
            dampings=tuple(c.tolist()),
            top_damping=self.top_damping,
            bit_damping=self.bit_damping,
            bit_radius=self.bit_radius,
            mu_coulomb=self.mu_coulomb,
            mu_static=self.mu_static,
            stribeck_decay=self.stribeck_decay,
            stribeck_velocity=self.stribeck_velocity,
            name=self.name,
        )


def _shared_inertias(
    k: np.ndarray, j: np.ndarray, groups: list[np.ndarray]
) -> tuple[np.ndarray, np.ndarray, float]:
    """Each group of elements as one spring (in series) between two inertias: the springs,
    the inertias at the groups' lower ends, and the share of the first group that goes to the
    top drive. An element's inertia sits at its lower end, where a static twist across the
    group has reached the share c/C of the group's compliance C above it: that share goes to
    the group's lower end, the rest to its upper end, so the reduced string keeps the whole
    string's inertia and moves it as a slow (static-shaped) twist would."""
    springs, lower, upper = [], [], []
    for g in groups:
        compliance = np.cumsum(1.0 / k[g])
        springs.append(1.0 / compliance[-1])
        down = float(np.sum(j[g] * (compliance / compliance[-1])))
        lower.append(down)
        upper.append(float(np.sum(j[g])) - down)
    inertias = np.array(lower)
    inertias[:-1] += upper[1:]
    return np.array(springs), inertias, upper[0]


def _whole(name: str, value: Any) -> None:
    """Refuse a count that is no integer as every integer argument is (TypeError): a bool, a
    str, or a float even of integer value (3.0)."""
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__} {_show(value)}")


def _show(value: Any) -> str:
    """A value as the tally wrote it (TOML numbers print as written: 0.3, not 0.2999…)."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


# The reader of tally files lives in tally_parse.py and builds the Tally above; its names stay
# importable from here. Imported last, once Tally exists: pydrill/__init__.py imports this
# module first, so tally_parse always finds it complete.
from .tally_parse import (  # noqa: E402, F401 (re-exported: pydrill.tally.parse_tally and kin)
    BIT_KEYS,
    DAMPING_KEYS,
    SECTION_KEYS,
    STEEL_KEYS,
    TOP_DRIVE_KEYS,
    load_tally,
    parse_tally,
)
