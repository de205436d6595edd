"""Driller units in, SI inside: a small, tested conversion table.

``parse(value, kind)`` accepts a number (already SI) or a string with a unit, e.g. ``"5 in"``,
``"3000 ft"``, ``"120 rpm"``, ``"100 kN"``, ``"25 klbf"``, ``"12 kN·m"``, ``"9 kft·lbf"``, and
the oilfield's spellings of them: ``"25 klbs"``, ``"25 kips"``, ``"10 t"`` (a metric tonne-force),
``"6600 ft-lbs"``, ``"6.6 klb-ft"``. ``"tonf"`` and ``"ton"`` are refused: a metric tonne-force
or a US short ton-force (2000 lbf, 9 % less) by usage, a difference that must not be guessed.
"""

from __future__ import annotations

import math
import numbers
import re
import reprlib

import numpy as np

LBF = 4.4482216152605  # N
FT = 0.3048  # m
INCH = 0.0254  # m
TONNE_FORCE = 9806.65  # N: 1 t × g_n
LBM = 0.45359237  # kg: the pound (mass)

# kind -> {unit: factor to SI}
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "km": 1e3, "in": INCH, "ft": FT},
    # tf: the metric tonne-force (a tonne on the bit). The US short ton-force (2000 lbf) is
    # 9 % less, and "tonf" or "ton" names either: refused (see _AMBIGUOUS), not guessed.
    "force": {"N": 1.0, "kN": 1e3, "lbf": LBF, "klbf": 1e3 * LBF, "tf": TONNE_FORCE},
    "torque": {"N·m": 1.0, "kN·m": 1e3, "ft·lbf": FT * LBF, "kft·lbf": 1e3 * FT * LBF},
    "velocity": {"rad/s": 1.0, "rpm": 2 * math.pi / 60},
    "modulus": {
        "Pa": 1.0,
        "GPa": 1e9,
        "MPa": 1e6,
        "psi": LBF / INCH**2,
        "Mpsi": 1e6 * LBF / INCH**2,
    },
    # lb/ft3: pounds (mass) per cubic foot, the field unit of a steel's density (490 lb/ft3)
    "density": {"kg/m3": 1.0, "kg/m^3": 1.0, "g/cm3": 1e3, "lb/ft3": LBM / FT**3},
    # lb·ft2: pound (mass) square feet, the WR² of a US top drive's or rotary table's sheet
    "inertia": {"kg·m2": 1.0, "kg·m^2": 1.0, "lb·ft2": LBM * FT**2},
    "damping": {"N·m·s/rad": 1.0},
    "rate": {"m/s": 1.0, "m/h": 1 / 3600, "m/hr": 1 / 3600, "ft/h": FT / 3600, "ft/hr": FT / 3600},
}
SI = {
    "length": "m",
    "force": "N",
    "torque": "N·m",
    "velocity": "rad/s",
    "modulus": "Pa",
    "density": "kg/m3",
    "inertia": "kg·m2",
    "damping": "N·m·s/rad",
    "rate": "m/s",
}

_ALIASES = {
    "nm": "N·m",
    "n.m": "N·m",
    "n*m": "N·m",
    "n m": "N·m",
    "knm": "kN·m",
    "kn.m": "kN·m",
    "kn*m": "kN·m",
    "kn m": "kN·m",
    '"': "in",
    "inch": "in",
    "inches": "in",
    "feet": "ft",
    "foot": "ft",
    "'": "ft",
    "rad/sec": "rad/s",
    # the oilfield's spellings of a weight on bit
    "lb": "lbf",
    "lbs": "lbf",
    "klb": "klbf",
    "klbs": "klbf",
    "kip": "klbf",
    "kips": "klbf",
    "t": "tf",
    "tonne": "tf",
    "tonnes": "tf",
}
# ... and of a damping, as the commands print it ("N m s/rad") and as torques are spelt: with a
# space or nothing between (N-m-s/rad, N*m*s/rad, N.m.s/rad are read as N·m·s/rad by _canon)
_ALIASES.update({f"n{sep}m{sep}s/rad": "N·m·s/rad" for sep in ("", " ")})
# ... and of an inertia, as printed ("kg m^2", and kg·m² in the docs and the tallies' comments)
_ALIASES.update({f"kg{sep}m{p}": "kg·m2" for sep in (" ", "·") for p in ("2", "^2", "²")})
# ... and of a density, as the docs write steel's (7850 kg/m³; kg·m² was read, kg/m³ refused)
_ALIASES.update({"kg/m³": "kg/m3", "lbm/ft3": "lb/ft3", "lb/ft^3": "lb/ft3", "pcf": "lb/ft3"})
_ALIASES.update({"lb/ft³": "lb/ft3", "lbm/ft^3": "lb/ft3", "lbm/ft³": "lb/ft3"})
# ... and of a field inertia, lb·ft² (lb-ft2, lbm·ft^2, ...): "-", "." and "*" are read as "·"
_ALIASES.update(
    {
        f"{lb}{sep}ft{p}": "lb·ft2"
        for lb in ("lb", "lbm")
        for sep in ("", " ", "·")
        for p in ("2", "^2", "²")
    }
)
# ... and as an atlas's axes write them for CF and netCDF readers (UDUNITS, atlas_schema)
_ALIASES.update({"n m s rad-1": "N·m·s/rad", "rad s-1": "rad/s", "kg m-3": "kg/m3", "m s-1": "m/s"})
# ... and of a torque: ft-lb(s), lb(s)-ft, lbf-ft, ft-lbf and their k (1000) forms, written
# with "-", "·", ".", "*", a space or nothing between ("-", "." and "*" are read as "·").
_FOOT_POUNDS = [("ft", "lbf"), ("ft", "lb"), ("ft", "lbs"), ("lbf", "ft"), ("lb", "ft")]
_ALIASES.update(
    {
        f"{k}{a}{sep}{b}": f"{k}ft·lbf"
        for k in ("", "k")
        for a, b in [*_FOOT_POUNDS, ("lbs", "ft")]
        for sep in ("", "·", " ")
    }
)
#: units that name two different quantities: refused with the choices, never guessed
_AMBIGUOUS = {
    "force": {
        name: "a metric tonne-force (9.80665 kN) is 't', 'tf' or 'tonne'; a US short "
        "ton-force (2000 lbf = 8.896 kN) is 2 klbf per ton"
        for name in ("tonf", "ton", "tons")
    }
}
#: each unit's other spellings, as the error messages list them
_SPELLINGS = {
    "force": {"lbf": "lb, lbs", "klbf": "klb, klbs, kip, kips", "tf": "t, tonne: metric"},
    "torque": {
        "N·m": "Nm, N-m",
        "kN·m": "kNm, kN-m",
        "ft·lbf": "ft-lb, ft-lbs, lb-ft, lbf-ft",
        "kft·lbf": "kft-lb, kft-lbs, klb-ft",
    },
    "damping": {"N·m·s/rad": "N m s/rad, Nms/rad, N-m-s/rad"},
    "inertia": {"kg·m2": "kg m^2, kg·m²", "lb·ft2": "lb-ft2, lbm·ft², lb ft^2"},
    "density": {"kg/m3": "kg/m³", "lb/ft3": "lbm/ft3, lb/ft³, pcf"},
}
_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def parse(value: float | int | str, kind: str) -> float:
    """``value`` in SI units; strings carry their unit. Raises ValueError naming the problem.

    ``kind`` is the quantity, one of ``"length"`` (m), ``"force"`` (N), ``"torque"`` (N·m),
    ``"velocity"`` (rad/s), ``"modulus"`` (Pa), ``"density"`` (kg/m3), ``"inertia"`` (kg·m2),
    ``"damping"`` (N·m·s/rad) or ``"rate"`` (m/s, of penetration); ``UNITS[kind]`` holds the
    units it reads for each (and their factors to SI)."""
    _check_kind(kind)
    a = _article(kind)
    if isinstance(value, bool):
        raise ValueError(f"{value!r} is not {a} {kind}")
    if isinstance(value, int | float):
        try:
            number = float(value)
        except OverflowError:  # an int beyond any float (a TOML integer of 400 digits)
            raise ValueError(
                f"{reprlib.repr(value)} is not a finite {kind}: beyond the range of a float"
            ) from None
        if not math.isfinite(number):
            raise ValueError(f"{value!r} is not a finite {kind}")
        return number
    match = _NUMBER.match(str(value))
    if not match:
        raise ValueError(
            f"{value!r} is not {a} {kind}: write a number and a unit, e.g. '{_example(kind)}'"
        )
    number, unit = float(match.group(1)), match.group(2)
    factor = 1.0 if unit == "" else _factor(unit, kind)
    if factor is None:
        raise ValueError(f"{value!r}: unit {_not_a_unit(unit, kind)}")
    if not math.isfinite(number * factor):  # "1e400 N" was inf, where inf itself is refused
        raise ValueError(
            f"{reprlib.repr(value)} is not a finite {kind}: beyond the range of a float"
        )
    return number * factor


def convert(si_value: float, kind: str, unit: str) -> float:
    """An SI value expressed in ``unit``: any unit :func:`parse` reads for ``kind`` (one of
    the kinds it lists, ``"length"`` ... ``"rate"``; e.g. ``"rpm"``, ``"RPM"``, ``"kft-lbf"``
    for ``"velocity"`` and ``"torque"``). Raises ValueError for an unknown kind or unit,
    listing the allowed ones, and TypeError for a value that is not a number (or array)."""
    _check_kind(kind)
    if (
        isinstance(si_value, bool)
        or not isinstance(si_value, numbers.Real | np.ndarray)
        or (isinstance(si_value, np.ndarray) and si_value.dtype.kind not in "iuf")
    ):
        raise TypeError(f"si_value = {si_value!r} is not allowed: a number (or a numeric array)")
    if not isinstance(unit, str):
        raise TypeError(f"unit = {unit!r} is not allowed: a {kind} unit's name, e.g. {SI[kind]!r}")
    factor = _factor(unit.strip(), kind)
    if factor is None:
        raise ValueError(f"unit = {_not_a_unit(unit, kind)}")
    return si_value / factor


def _not_a_unit(unit: str, kind: str) -> str:
    """Why ``unit`` is refused for ``kind`` ("'ft-lbs' is not ..."), with the units to use."""
    ambiguous = _AMBIGUOUS.get(kind, {}).get(unit.strip().lower())
    if ambiguous is not None:
        return f"{unit!r} is ambiguous: {ambiguous}"
    canon = _canon(unit.strip())
    meant = [k for k in UNITS[kind] if k.lower() == canon.lower()]  # but for m/M: case matters
    if meant:
        return (
            f"{unit!r} is not {_article(kind)} {kind} unit: m is milli, M mega; did you mean "
            f"{meant[0]!r}?"
        )
    return f"{unit!r} is not {_article(kind)} {kind} unit; use one of {_units_of(kind)}"


def _units_of(kind: str) -> str:
    """The units of ``kind``, each with its other spellings: "N, kN, lbf (lb, lbs), ..."."""
    spelt = _SPELLINGS.get(kind, {})
    return ", ".join(f"{u} ({spelt[u]})" if u in spelt else u for u in UNITS[kind])


def _check_kind(kind: str) -> None:
    if not isinstance(kind, str):
        raise TypeError(f"kind = {kind!r} is not allowed: one of " + ", ".join(UNITS))
    if kind not in UNITS:
        raise ValueError(f"unknown quantity kind {kind!r}; use one of " + ", ".join(UNITS))


def _factor(unit: str, kind: str) -> float | None:
    """The factor to SI of ``unit`` (as written, in a canonical spelling, an alias, or in
    another case when that names one unit of ``kind`` only); None if it is none of them."""
    table = UNITS[kind]
    canon = _canon(unit)
    for candidate in (unit, canon, _ALIASES.get(unit.lower(), ""), _ALIASES.get(canon.lower(), "")):
        if candidate in table:
            return table[candidate]
    matches = {
        v for k, v in table.items() if k.lower() == canon.lower() and _same_prefixes(k, canon)
    }
    return matches.pop() if len(matches) == 1 else None


def _canon(unit: str) -> str:
    """``unit`` with its products written as the tables write them: N·m for N-m, N*m, N.m."""
    return unit.replace("-", "·").replace("*", "·").replace(".", "·")


def _same_prefixes(unit: str, written: str) -> bool:
    """Whether ``written``, ``unit`` in another case, keeps the case of each m/M that begins a
    symbol with a letter after it: there case is the prefix, milli or mega ("1 mPa" was read
    as 1 MPa, 10^9 too much, and "1 Mm" as 1 mm). M alone or before a power is still a metre
    ("KN-M", "kg/M3")."""
    parts = zip(re.split(r"[·/]", unit), re.split(r"[·/]", written), strict=True)
    return all(
        len(a) < 2 or not a[1].isalpha() or a[0] not in "mM" or a[0] == b[0] for a, b in parts
    )


def _article(kind: str) -> str:
    return "an" if kind[:1] in "aeiou" else "a"


def _example(kind: str) -> str:
    return {
        "length": "5 in",
        "force": "100 kN",
        "torque": "12 kN·m",
        "velocity": "120 rpm",
        "modulus": "79.3 GPa",
        "density": "7850 kg/m3",
        "inertia": "2122 kg·m2",
        "damping": "50 N·m·s/rad",
        "rate": "30 m/h",
    }[kind]
