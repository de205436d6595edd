"""The HDF5 layout of an atlas, and the in-memory table a sweep fills.

One file per sweep. The sweep's axes are HDF5 dimension scales (plus ``initial``,
``equilibrium`` and ``eigenvalue``), so the file opens in xarray (``engine="h5netcdf"``) with the
right coordinates. ``regime`` is an HDF5 enumeration; everything is chunked and compressed. The
spec text, its digest, the model parameters and the pydrill version are root attributes;
``status`` says, point by point, what has been computed.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from .spec import SweepSpec

FORMAT = "pydrill-atlas"
FORMAT_VERSION = 1
REGIMES = {
    "steady": 0,
    "stick-slip": 1,
    "stuck": 2,
    "oscillation": 3,
    "failed": -1,
    "missing": -2,
    "no-steady-state": -3,  # an 'equilibrium' start where no steady state exists
}
REGIME_NAMES = {v: k for k, v in REGIMES.items()}
# What a run's judgement notes (SimulationResult.summary.caveat): kept by kind, not by text;
# each kind's meaning in short (the run's own note says it in full).
CAVEAT_TEXT = {
    "first-wind-up": "the bit had not broken free yet although |u| > T_s; simulate longer",
    "one-stick-phase": "the window held one stick phase of a slow cycle; simulate longer",
    "one-break-away": "the bit broke free once and had not stuck again; simulate longer",
    "growing": "an oscillation still growing away from the steady state; simulate longer",
    "short-window": "the judged window is shorter than the slowest period; simulate longer",
    # (new kinds go last: an atlas stores the codes)
    "late-stick": "the bit slipped, then stuck to the window's end (u <= T_s); simulate longer",
}
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

# name -> (dtype, fill, dims beyond the axes, units, description)
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


def regime_attrs() -> dict[str, Any]:
    """The CF attributes of ``regime``: its codes named as pydrill names the regimes
    (``stick-slip``: CF's flag_meanings are separated by blanks only), in every format."""
    return {
        "flag_values": np.array(list(REGIMES.values()), dtype="i1"),
        "flag_meanings": " ".join(REGIMES),
        "long_name": "regime of the run from each start (codes named in flag_meanings)",
    }


def _chunks(shape: tuple[int, ...]) -> tuple[int, ...] | None:
    if not shape or math.prod(shape) < 64:
        return None
    return tuple(min(s, 64) for s in shape)


#: records a journal's replay holds and stores at a time (``AtlasTable.apply_all``): ~5 kB of
#: Python objects each, 20 MB in all, whatever the journal's length
REPLAY_CHUNK = 4096


@dataclass
class AtlasTable:
    """All of an atlas's point data in memory; a sweep updates it, then writes it whole.

    With ``points=m`` the table has m rows instead of the grid's shape: a worker fills such a
    block with its batch, and the client puts the block into the grid in one assignment per
    field (applying records one by one cost the client, which shares the cores with the
    workers, about 5 % of a sweep's wall time)."""

    spec: SweepSpec
    points: int | None = None
    status: np.ndarray = field(init=False)
    message: np.ndarray = field(init=False)
    regime: np.ndarray = field(init=False)
    runs: dict[str, np.ndarray] = field(init=False)
    eqs: dict[str, np.ndarray] = field(init=False)
    eig: np.ndarray = field(init=False)
    coexistence: np.ndarray = field(init=False)
    caveat: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        shape = self.spec.shape if self.points is None else (self.points,)
        n_init = len(self.spec.initials)
        k = self.spec.record["eigenvalues"]
        self.status = np.zeros(shape, dtype="u1")
        self.message = np.full(shape, "", dtype=object)
        self.regime = np.full((*shape, n_init), REGIMES["missing"], dtype="i1")
        self.runs = {n: np.full((*shape, n_init), f[1], dtype=f[0]) for n, f in RUN_FIELDS.items()}
        self.eqs = {n: np.full((*shape, N_EQ), f[1], dtype=f[0]) for n, f in EQ_FIELDS.items()}
        self.eig = np.full((*shape, N_EQ, k), complex(math.nan, math.nan), dtype="c16")
        self.coexistence = np.full(shape, -1, dtype="i1")
        self.caveat = np.zeros((*shape, n_init), dtype="i1")

    def columns(self) -> dict[str, np.ndarray]:
        """Every per-point array by name; the point axes come first."""
        return {
            "status": self.status,
            "message": self.message,
            "regime": self.regime,
            **{f"run:{k}": v for k, v in self.runs.items()},
            **{f"eq:{k}": v for k, v in self.eqs.items()},
            "eig": self.eig,
            "coexistence": self.coexistence,
            "caveat": self.caveat,
        }

    def put(self, indices: np.ndarray, block: dict[str, np.ndarray]) -> None:
        """Put the rows of a block (``AtlasTable(spec, points=m).columns()``) at the flat
        grid indices ``indices``."""
        n = self.status.size
        for name, array in self.columns().items():
            array.reshape(n, *array.shape[self.status.ndim :])[indices] = block[name]

    def apply(self, rec: dict[str, Any], row: int | None = None) -> None:
        """Store one point's record at its flat index (or at ``row`` of a block)."""
        self._apply(rec, rec["i"] if row is None else row, self._flat())

    def apply_all(self, records: Iterable[dict[str, Any]], chunk: int | None = None) -> int:
        """Store every record of ``records``, as ``put`` stores a block: each field of
        ``chunk`` records at a time in one assignment (an iterator is read ``chunk`` records
        at a time, so a journal of millions of points is never held whole); returns how many.
        Record by record, a million-point journal's replay took over a minute, most of it in
        numpy's per-element assignments (~50 a record)."""
        flat, n = self._flat(), 0
        it = iter(records)
        while part := list(itertools.islice(it, chunk or REPLAY_CHUNK)):
            self._apply_block(part, flat)
            n += len(part)
        return n

    def _apply_block(self, part: list[dict[str, Any]], flat: dict[str, np.ndarray]) -> None:
        """``_apply`` of each record of ``part``, field by field; a record's absent values
        are stored as their fill, as ``put`` stores a block's."""
        idx = np.array([rec["i"] for rec in part], dtype=np.int64)
        flat["status"][idx] = [STATUS[rec["status"]] for rec in part]
        messages = np.empty(len(part), dtype=object)
        messages[:] = [rec.get("message", "") for rec in part]
        flat["message"][idx] = messages
        for j, init in enumerate(self.spec.initials):
            runs = [rec.get("runs", {}).get(init) for rec in part]
            # the point failed before this start ran
            gone = [
                r is None and rec["status"] == "failed" for r, rec in zip(runs, part, strict=True)
            ]
            flat["regime"][idx[np.array(gone, dtype=bool)], j] = REGIMES["failed"]
            ran = np.array([r is not None for r in runs], dtype=bool)
            got = [r for r in runs if r is not None]
            if not got:
                continue
            at = idx[ran]
            flat["regime"][at, j] = [REGIMES[r["regime"]] for r in got]
            flat["caveat"][at, j] = [CAVEATS[r.get("caveat") or ""] for r in got]
            for name, (_, fill, _, _) in RUN_FIELDS.items():
                values = [r.get(name) for r in got]
                flat[f"run:{name}"][at, j] = [fill if v is None else v for v in values]
        stabs = [(k, rec["stability"]) for k, rec in enumerate(part) if rec.get("stability")]
        if stabs:
            at = idx[[k for k, _ in stabs]]
            for name, (_, fill, _, _) in EQ_FIELDS.items():
                rows = []
                for _, stab in stabs:
                    vals = [fill if v is None else v for v in list(stab.get(name, []))[:N_EQ]]
                    rows.append(vals + [fill] * (N_EQ - len(vals)))
                flat[f"eq:{name}"][at] = rows
            eig = flat["eig"]
            k = eig.shape[-1]
            block = np.full((len(stabs), N_EQ, k), complex(math.nan, math.nan))
            for row, (_, stab) in enumerate(stabs):
                for e, values in enumerate(stab.get("eigenvalues", [])[:N_EQ]):
                    for m, (re, im) in enumerate(values[:k]):
                        block[row, e, m] = complex(re, im)
            eig[at] = block
        co = [
            (k, rec["coexistence"])
            for k, rec in enumerate(part)
            if rec.get("coexistence") is not None
        ]
        if co:
            flat["coexistence"][idx[[k for k, _ in co]]] = [int(v) for _, v in co]

    def _flat(self) -> dict[str, np.ndarray]:
        """Views of the arrays with the point axes flattened (they share memory with them)."""
        n = self.status.size
        k = self.eig.shape[-1]
        return {
            "status": self.status.reshape(n),
            "message": self.message.reshape(n),
            "regime": self.regime.reshape(n, -1),
            "caveat": self.caveat.reshape(n, -1),
            "coexistence": self.coexistence.reshape(n),
            "eig": self.eig.reshape(n, N_EQ, k),
            **{f"run:{name}": a.reshape(n, -1) for name, a in self.runs.items()},
            **{f"eq:{name}": a.reshape(n, N_EQ) for name, a in self.eqs.items()},
        }

    def _apply(self, rec: dict[str, Any], i: int, flat: dict[str, np.ndarray]) -> None:
        flat["status"][i] = STATUS[rec["status"]]
        flat["message"][i] = rec.get("message", "")
        runs = rec.get("runs", {})
        for j, init in enumerate(self.spec.initials):
            run = runs.get(init)
            if run is None:
                if rec["status"] == "failed":  # the point failed before this start ran
                    flat["regime"][i, j] = REGIMES["failed"]
                continue
            flat["regime"][i, j] = REGIMES[run["regime"]]
            flat["caveat"][i, j] = CAVEATS[run.get("caveat") or ""]
            for name, (_, fill, _, _) in RUN_FIELDS.items():
                v = run.get(name)
                flat[f"run:{name}"][i, j] = fill if v is None else v
        stab = rec.get("stability")
        if stab:
            for name, (_, fill, _, _) in EQ_FIELDS.items():
                vals = list(stab.get(name, []))[:N_EQ]
                row = [fill if v is None else v for v in vals] + [fill] * (N_EQ - len(vals))
                flat[f"eq:{name}"][i] = row
            eig = flat["eig"]
            k = eig.shape[-1]
            for e, row in enumerate(stab.get("eigenvalues", [])[:N_EQ]):
                for m, (re, im) in enumerate(row[:k]):
                    eig[i, e, m] = complex(re, im)
        if rec.get("coexistence") is not None:
            flat["coexistence"][i] = int(rec["coexistence"])

    def missing(self) -> np.ndarray:
        """Flat indices of the points still to compute."""
        return np.flatnonzero(self.status.ravel() == STATUS["missing"])


def create(path: Path, spec: SweepSpec, params_json: str, version: str) -> None:
    """A new atlas with every point missing (overwrites ``path``: callers check first)."""
    from .atlas_lock import writing

    with writing(path):
        _create(path, spec, params_json, version)


def _create(path: Path, spec: SweepSpec, params_json: str, version: str) -> None:
    table = AtlasTable(spec)
    with h5py.File(path, "w", libver="latest", locking=WRITER_LOCKING) as f:
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["pydrill_version"] = version
        f.attrs["spec"] = spec.text
        f.attrs["tally"] = spec.tally_text or ""
        f.attrs["spec_digest"] = spec.digest
        f.attrs["params"] = params_json
        f.attrs["axes"] = json.dumps(list(spec.axes))
        f.attrs["fixed"] = json.dumps(spec.fixed)
        # What a netCDF/CF reader looks for first (no date: a resumed atlas equals an
        # uninterrupted run's, and timing metadata is kept out of the file).
        f.attrs["Conventions"] = "CF-1.8"
        if spec.tally_text:
            from .tally import parse_tally

            string = f"string {parse_tally(spec.tally_text).name}"
        else:
            string = spec.preset
        if spec.dof and not {"dof", "pipes"} & set(spec.axes):
            string += f", dof {spec.dof}"
        f.attrs["title"] = (
            f"pydrill regime atlas: {string}, over {' x '.join(spec.axes)}, from "
            + " and ".join(spec.initials)
        )
        f.attrs["source"] = f"pydrill {version} (pydrill sweep)"
        f.attrs["references"] = REFERENCE
        scales = []
        for name, values in spec.axes.items():
            d = f.create_dataset(name, data=values)
            d.make_scale(name)
            d.attrs["units"] = axis_units(name)
            d.attrs["long_name"] = AXIS_NAMES.get(name, name)
            scales.append(d)
        init = f.create_dataset("initial", data=np.array(spec.initials, dtype=h5py.string_dtype()))
        init.make_scale("initial")
        eq = f.create_dataset("equilibrium", data=np.arange(N_EQ, dtype="i1"))
        eq.make_scale("equilibrium")
        eq.attrs["long_name"] = "steady state, fastest first"
        k = spec.record["eigenvalues"]
        ev = f.create_dataset("eigenvalue", data=np.arange(k, dtype="i2"))
        ev.make_scale("eigenvalue")

        def make(name, data, extra, **attrs):
            # A fresh table holds one value everywhere: made the fill value, no chunk is
            # written until a point is (a 10^6-point atlas: 0.56 s and 1.8 MB, was 2.5 s
            # and 33 MB).
            ds = f.create_dataset(
                name,
                shape=data.shape,
                dtype=data.dtype,
                chunks=_chunks(data.shape),
                compression="gzip" if _chunks(data.shape) else None,
                compression_opts=GZIP_LEVEL if _chunks(data.shape) else None,
                fillvalue=data.flat[0] if data.size else 0,
            )
            for axis, scale in enumerate(scales):
                ds.dims[axis].attach_scale(scale)
            for j, s in enumerate(extra):
                ds.dims[len(scales) + j].attach_scale(s)
            for key, value in attrs.items():
                ds.attrs[key] = value
            return ds

        enum = h5py.enum_dtype(REGIMES, basetype="i1")
        reg = f.create_dataset(
            "regime",
            shape=table.regime.shape,
            dtype=enum,
            chunks=_chunks(table.regime.shape),
            compression="gzip" if _chunks(table.regime.shape) else None,
            compression_opts=GZIP_LEVEL if _chunks(table.regime.shape) else None,
            fillvalue=REGIMES["missing"],
        )
        for axis, scale in enumerate(scales):
            reg.dims[axis].attach_scale(scale)
        reg.dims[len(scales)].attach_scale(init)
        reg.attrs.update(regime_attrs())
        make(
            "status",
            table.status,
            [],
            flag_values=np.array(list(STATUS.values()), "u1"),
            flag_meanings=" ".join(STATUS),
        )
        # Empty until a point fails (an unwritten string reads as ""): creating 10^6 empty
        # strings took 0.4 s.
        msg = f.create_dataset("message", shape=table.message.shape, dtype=h5py.string_dtype())
        msg.attrs["long_name"] = "why the point failed (empty unless it did)"
        # Its own axes, or xarray would guess them from the lengths (and pick wrongly).
        for axis, scale in enumerate(scales):
            msg.dims[axis].attach_scale(scale)
        for name, (_, _, unit, desc) in RUN_FIELDS.items():
            ds = make(name, table.runs[name], [init], units=unit, long_name=desc)
            _mark_fill(ds, name)
        for name, (_, _, unit, desc) in EQ_FIELDS.items():
            ds = make(name, table.eqs[name], [eq], units=unit, long_name=desc)
            _mark_fill(ds, name)
        make(
            "eigenvalues_real",
            table.eig.real,
            [eq, ev],
            units="1/s",
            long_name="leading eigenvalues, real part",
        )
        make(
            "eigenvalues_imag",
            table.eig.imag,
            [eq, ev],
            units="rad/s",
            long_name="leading eigenvalues, imaginary part",
        )
        make(
            "coexistence",
            table.coexistence,
            [],
            long_name="1 if rest and equilibrium starts end in different regimes, -1 unknown",
        )
        _make_caveat(f, spec, table.caveat)


def _make_per_run(f: h5py.File, spec: SweepSpec, name: str, data: np.ndarray, fill: Any):
    """A dataset of one value per point and start, on the atlas's scales."""
    chunks = _chunks(data.shape)
    ds = f.create_dataset(
        name,
        shape=data.shape,
        dtype=data.dtype,
        chunks=chunks,
        compression="gzip" if chunks else None,
        compression_opts=GZIP_LEVEL if chunks else None,
        fillvalue=fill,
    )
    for axis, scale in enumerate(spec.axes):
        ds.dims[axis].attach_scale(f[scale])
    ds.dims[len(spec.axes)].attach_scale(f["initial"])
    return ds


def _make_added(f: h5py.File, spec: SweepSpec, name: str, data: np.ndarray) -> None:
    """An ``ADDED_RUN_FIELDS`` dataset, for an atlas written before it existed."""
    _, fill, unit, desc = RUN_FIELDS[name]
    ds = _make_per_run(f, spec, name, data, fill)
    ds.attrs["units"] = unit
    ds.attrs["long_name"] = desc
    _mark_fill(ds, name)


def _mark_fill(ds, name: str) -> None:
    """A count's fill (-1: not measured) named as CF's ``_FillValue``: xarray and netCDF
    readers then read it as missing, not as a count of -1 (a mean over the atlas counted
    the failed points' -1). A float's fill is NaN, missing already."""
    dtype, fill, *_ = RUN_FIELDS.get(name) or EQ_FIELDS[name]
    if dtype.startswith("i"):
        ds.attrs["_FillValue"] = np.array(fill, dtype=dtype)


def _make_caveat(f: h5py.File, spec: SweepSpec, data: np.ndarray) -> None:
    """The ``caveat`` dataset; also added to an atlas written before it existed, when resumed."""
    ds = _make_per_run(f, spec, "caveat", data, 0)
    ds.attrs["flag_values"] = np.array(list(CAVEATS.values()), dtype="i1")
    ds.attrs["flag_meanings"] = " ".join(k or "none" for k in CAVEATS)
    ds.attrs["long_name"] = "what the run's judgement notes (0: nothing)"


def write(path: Path, table: AtlasTable) -> None:
    """Write the whole table into an existing atlas (readers see it whole: ``atlas_lock``)."""
    from .atlas_lock import writing

    with writing(path), h5py.File(path, "r+", locking=WRITER_LOCKING) as f:
        f["status"][...] = table.status
        if any(table.message.ravel()):  # messages are only ever added: all "" is as created
            f["message"][...] = table.message.astype(h5py.string_dtype())
        f["regime"][...] = table.regime
        for name in RUN_FIELDS:
            if name not in f:
                _make_added(f, table.spec, name, table.runs[name])
            f[name][...] = table.runs[name]
        for name in EQ_FIELDS:
            f[name][...] = table.eqs[name]
        f["eigenvalues_real"][...] = table.eig.real
        f["eigenvalues_imag"][...] = table.eig.imag
        f["coexistence"][...] = table.coexistence
        if "caveat" not in f:
            _make_caveat(f, table.spec, table.caveat)
        f["caveat"][...] = table.caveat


def read_table(path: Path, spec: SweepSpec) -> AtlasTable:
    """Load an atlas's point data (raises OSError/KeyError on a damaged file)."""
    table = AtlasTable(spec)
    with h5py.File(path, "r") as f:
        table.status = f["status"][...]
        table.message = np.array(
            [m.decode() if isinstance(m, bytes) else m for m in f["message"][...].ravel()],
            dtype=object,
        ).reshape(spec.shape)
        table.regime = f["regime"][...].astype("i1")
        for name in RUN_FIELDS:
            if name in f:  # (an added field is missing from atlases written before it)
                table.runs[name] = f[name][...]
        for name in EQ_FIELDS:
            table.eqs[name] = f[name][...]
        table.eig = f["eigenvalues_real"][...] + 1j * f["eigenvalues_imag"][...]
        table.coexistence = f["coexistence"][...]
        if "caveat" in f:  # atlases written before it: no caveats recorded
            table.caveat = f["caveat"][...]
    return table
