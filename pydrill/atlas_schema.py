"""What an atlas holds, by name: the regime, caveat and status codes, the per-run and
per-steady-state fields with their dtypes, fills and units, and the axes' CF units and names.
The file's layout is ``atlas_format``'s; the in-memory table, ``atlas_table``'s."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

FORMAT = "pydrill-atlas"
FORMAT_VERSION = 1
#: the regime of a run whose solver failed, in an atlas and in map/window --check alike
FAILED = "failed"
REGIMES = {
    "steady": 0,
    "stick-slip": 1,
    "stuck": 2,
    "oscillation": 3,
    FAILED: -1,
    "missing": -2,
    "no-steady-state": -3,  # an 'equilibrium' start where no steady state exists
}
REGIME_NAMES = {v: k for k, v in REGIMES.items()}
# What a run's judgement notes (SimulationResult.summary.caveat): kept by kind, not by text;
# each kind's meaning in short (the run's own note says it in full).
CAVEAT_TEXT = {
    "first-wind-up": "the bit had not broken free yet although |u| > T_s; simulate longer",
    "one-stick-phase": "the window held one stick phase of a slow cycle; simulate longer",
    "one-break-away": "the bit broke free and had not stuck again since; simulate longer",
    "growing": "an oscillation still growing away from the steady state; simulate longer",
    "short-window": "the judged window is shorter than the slowest period; simulate longer",
    # (new kinds go last: an atlas stores the codes)
    "late-stick": "the bit slipped, then stuck to the window's end (u <= T_s); simulate longer",
    "run-away": "no steady state holds the bit (c_r + c_b = 0, |u| > T_c): it speeds up for ever",
    "approaching": "steady, its mean still on its way to the steady state; simulate longer",
}
#: caveats a longer run would not lift: the judgement is final, its note says why
FINAL_CAVEATS = ("run-away",)
CAVEATS = {"": 0, **{name: code for code, name in enumerate(CAVEAT_TEXT, start=1)}}
CAVEAT_NAMES = {v: k for k, v in CAVEATS.items()}
STATUS = {"missing": 0, "done": 1, "failed": 2}
# gzip's fastest level: an atlas is rewritten during a sweep, and level 1 writes one 1.5x
# faster than the default 4 for a file 10 % larger (measured on a 15000-point atlas).
GZIP_LEVEL = 1
N_EQ = 2  # a (W_ob, u) has at most two steady states

# The sweep's client is an atlas's only writer (the spec digest and the journal see to that),
# and it writes without HDF5's file lock. A lock is an flock on the open file, shared with
# every process forked while the file is open — and Dask's nanny forks workers from the
# client, at start-up and whenever a lost worker is replaced. A worker forked during a write
# would hold the lock for its whole life, and every later write would fail; so would a write
# while someone ran `pydrill atlas info` on the growing atlas.
WRITER_LOCKING = False

# name -> (dtype, fill, units, description); a run field has the axes and "initial" as dims
RUN_FIELDS = {
    "bit_min": ("f8", math.nan, "rad/s", "least bit velocity in the judged window"),
    "bit_max": ("f8", math.nan, "rad/s", "largest bit velocity in the judged window"),
    "bit_mean": ("f8", math.nan, "rad/s", "mean bit velocity in the judged window"),
    "top_mean": ("f8", math.nan, "rad/s", "mean top-drive velocity in the judged window"),
    "severity": ("f8", math.nan, "1", "(max - min) / (2 mean) of the bit velocity"),
    "stuck_fraction": ("f8", math.nan, "1", "fraction of the judged window spent stuck"),
    "period": ("f8", math.nan, "s", "stick-slip or oscillation period"),
    "stick_events": ("i4", -1, "1", "stick events in the judged window"),
    "wall_time": ("f8", math.nan, "s", "time in the C++ core"),
    "top_min": ("f8", math.nan, "rad/s", "least top-drive velocity in the judged window"),
    "top_max": ("f8", math.nan, "rad/s", "largest top-drive velocity in the judged window"),
    "bit_top_ratio": (
        "f8",
        math.nan,
        "1",
        "largest bit velocity over the mean top-drive velocity (how far the bit overshoots)",
    ),
}
#: Run fields added after the format's first version: an atlas written before reads them as
#: not recorded (NaN) and gains them when a sweep writes it again (--resume).
ADDED_RUN_FIELDS = ("top_min", "top_max", "bit_top_ratio")
EQ_FIELDS = {
    "omega_eq": ("f8", math.nan, "rad/s", "steady bit velocities, fastest first"),
    "delta": ("f8", math.nan, "N m s/rad", "Stribeck slope at each steady state"),
    "spectral_abscissa": ("f8", math.nan, "1/s", "largest real part of the eigenvalues"),
    "hopf_margin": (
        "f8",
        math.nan,
        "N m s/rad",
        "delta distance to the nearest crossing (negative: unstable)",
    ),
    "unstable": ("i2", -1, "1", "eigenvalues in the right half-plane"),
}


#: the units of the axes that are not model parameters (UDUNITS, as CF asks; "1": a count)
AXIS_UNITS = {"wob": "N", "torque": "N m", "dof": "1", "pipes": "1", "depth": "m"}
#: what each axis is, for readers of the file (CF's long_name); a model parameter's below
AXIS_NAMES = {
    "wob": "weight on bit",
    "torque": "surface torque of the top drive",
    "dof": "inertias of the lumped string (degrees of freedom)",
    "pipes": "drill pipes of the lumped string",
    "depth": "bit depth",
    "top_damping": "viscous damping at the top drive (c_r)",
    "bit_damping": "viscous damping at the bit (c_b)",
    "bit_radius": "bit radius (R_b)",
    "mu_coulomb": "Coulomb friction coefficient of the bit (mu_cb)",
    "mu_static": "static friction coefficient of the bit (mu_sb)",
    "stribeck_decay": "Stribeck decay rate (gamma_b)",
    "stribeck_velocity": "Stribeck velocity (v_f)",
    "karnopp_band": "Karnopp band half-width",
}
#: where the model comes from, for the file's CF ``references``
REFERENCE = (
    "E. M. Navarro-Lopez and D. Cortes, Avoiding harmful oscillations in a drillstring "
    "through dynamical analysis, Journal of Sound and Vibration 307 (2007) 152-171"
)


def axis_units(name: str) -> str:
    """The ``units`` attribute of a sweep axis, in ASCII that UDUNITS (and so CF and netCDF
    readers) parse: ``"N m s rad-1"`` for a damping, ``"kg m2"``, ``"rad s-1"``, ``"1"`` for a
    dimensionless one (a friction coefficient); a model parameter's from ``model._UNITS``."""
    from .model import _UNITS

    if name in AXIS_UNITS:
        return AXIS_UNITS[name]
    pretty = _UNITS.get(name, "1")
    if pretty in ("1", "friction coefficient"):
        return "1"
    powers = str.maketrans("²³", "23")
    above, _, below = pretty.translate(powers).partition("/")
    terms = [t for t in above.split("·") if t != "1"]
    for t in filter(None, below.split("·")):
        base = t.rstrip("0123456789")
        terms.append(f"{base}-{t[len(base) :] or 1}")
    return " ".join(terms)


#: what ``coexistence`` says, by its code (the CSV export's ``coexistence_name``)
COEXISTENCE = {"unknown": -1, "no-disagreement": 0, "starts-disagree": 1}


def index_attrs() -> dict[str, dict[str, Any]]:
    """The CF attributes of the variables that are neither axes nor per-run fields: the
    index dimensions, the point status and the coexistence flag. A CF checker asks for a
    ``long_name`` and ``units`` on each coordinate variable, and a flag's meanings."""
    return {
        "initial": {"long_name": "initial condition of the runs (start)"},
        "equilibrium": {"long_name": "steady state, fastest first", "units": "1"},
        "eigenvalue": {"long_name": "eigenvalue, by decreasing real part", "units": "1"},
        "status": {
            "long_name": "whether the point was computed",
            "flag_values": np.array(list(STATUS.values()), dtype="u1"),
            "flag_meanings": " ".join(STATUS),
        },
        "coexistence": {
            "long_name": "1 if rest and equilibrium starts end in different regimes, -1 unknown",
            "flag_values": np.array(list(COEXISTENCE.values()), dtype="i1"),
            "flag_meanings": " ".join(COEXISTENCE),
        },
    }


def regime_attrs() -> dict[str, Any]:
    """The CF attributes of ``regime``: its codes named as pydrill names the regimes
    (``stick-slip``: CF's flag_meanings are separated by blanks only), in every format."""
    return {
        "flag_values": np.array(list(REGIMES.values()), dtype="i1"),
        "flag_meanings": " ".join(REGIMES),
        "long_name": "regime of the run from each start (codes named in flag_meanings)",
    }
