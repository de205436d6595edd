"""The HDF5 layout of an atlas: creating the file, writing a sweep's table into it, reading it back.

One file per sweep. The sweep's axes are HDF5 dimension scales (plus ``initial``,
``equilibrium`` and ``eigenvalue``), so the file opens in xarray (``engine="h5netcdf"``) with the
right coordinates. ``regime`` is an HDF5 enumeration (of the named type ``regime_t``);
everything is chunked and compressed. The spec text, its digest, the model parameters and the
pydrill version are root attributes; ``status`` says, point by point, what has been computed.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from .atlas_schema import (
    ADDED_RUN_FIELDS,
    AXIS_NAMES,
    AXIS_UNITS,
    CAVEAT_NAMES,
    CAVEAT_TEXT,
    CAVEATS,
    COEXISTENCE,
    EQ_FIELDS,
    FINAL_CAVEATS,
    FORMAT,
    FORMAT_VERSION,
    GZIP_LEVEL,
    N_EQ,
    REFERENCE,
    REGIME_NAMES,
    REGIMES,
    RUN_FIELDS,
    STATUS,
    WRITER_LOCKING,
    axis_units,
    index_attrs,
    regime_attrs,
)
from .atlas_table import AtlasTable
from .spec import SweepSpec

# The schema's names and the table are read here too, as fmt.STATUS or fmt.AtlasTable.
__all__ = [
    "ADDED_RUN_FIELDS",
    "AXIS_NAMES",
    "AXIS_UNITS",
    "CAVEATS",
    "CAVEAT_NAMES",
    "CAVEAT_TEXT",
    "COEXISTENCE",
    "EQ_FIELDS",
    "FINAL_CAVEATS",
    "FORMAT",
    "FORMAT_VERSION",
    "GZIP_LEVEL",
    "N_EQ",
    "REFERENCE",
    "REGIMES",
    "REGIME_NAMES",
    "RUN_FIELDS",
    "STATUS",
    "WRITER_LOCKING",
    "AtlasTable",
    "axis_units",
    "create",
    "index_attrs",
    "read_table",
    "regime_attrs",
    "write",
]


#: HDF5 object versions an atlas is written with: those of HDF5 1.8 to 1.10, which every
#: netCDF-C reader opens. "latest" wrote the objects of the writing library's own version
#: (HDF5 2.0 in h5py 3.16), and netCDF-C on an HDF5 1.10 or 1.12 (Debian 12's ncdump, R's
#: ncdf4, older MATLABs) refused the whole file: "NetCDF: HDF error".
LIBVER = ("v108", "v110")


#: Bytes of a chunk before compression. A point query reads (and inflates) one chunk of each
#: of some 25 datasets: with 64 x 64 grid points a chunk, 64 kB to 512 kB each, that took
#: 9-13 ms on a 10^6-point atlas of smooth or random data (0.4 ms on an empty one, whose
#: chunks are all fill). 16 kB chunks take 2.5-3.5 ms and compress as well; 8 kB ones 1.6 ms,
#: but read whole (a resume, a plot, xarray) more slowly.
CHUNK_BYTES = 16 * 1024


def _chunks(shape: tuple[int, ...], itemsize: int, grid: int) -> tuple[int, ...] | None:
    """Chunks of a dataset of ``shape`` whose first ``grid`` axes are the sweep's: the other
    axes (starts, steady states, eigenvalues: a few values a point) whole, and about
    ``CHUNK_BYTES`` of points, as square on the grid as its sizes allow. None (contiguous)
    for a dataset of under 64 values."""
    if not shape or math.prod(shape) < 64:
        return None
    inner = shape[grid:]
    left = max(1, CHUNK_BYTES // (itemsize * math.prod(inner)))  # points a chunk
    edges = list(shape[:grid])
    # The shortest axes first: one shorter than its even share is taken whole, and the
    # others share what it leaves. Then the chunks along an axis are made equal: 37 values
    # in chunks of 35 would store a second chunk of 35 for the last 2 (19 and 18 instead).
    for n, axis in enumerate(sorted(range(grid), key=lambda a: shape[a])):
        edge = max(1, min(shape[axis], int(left ** (1.0 / (grid - n)) + 1e-9)))
        edges[axis] = -(-shape[axis] // -(-shape[axis] // edge))
        left = max(1, left // edge)
    return (*edges, *inner)


def _storage(shape: tuple[int, ...], itemsize: int, grid: int) -> dict[str, Any]:
    """``create_dataset``'s chunks and compression for a dataset (``_chunks``)."""
    chunks = _chunks(shape, itemsize, grid)
    if chunks is None:
        return {"chunks": None}
    return {"chunks": chunks, "compression": "gzip", "compression_opts": GZIP_LEVEL}


def create(path: Path, spec: SweepSpec, params_json: str, version: str) -> None:
    """A new atlas with every point missing (overwrites ``path``: callers check first)."""
    from .atlas_lock import writing

    with writing(path):
        _create(path, spec, params_json, version)


def _blank(spec: SweepSpec) -> AtlasTable:
    """A table of ``spec`` with every point missing, as read-only views of one point's values
    (the shapes, types and fill values that ``create`` makes datasets of): a whole table is
    some 400 bytes a point, 0.4 GB held for nothing at 10^6 points."""
    table = AtlasTable(spec, points=1)

    def grid(a: np.ndarray) -> np.ndarray:
        return np.broadcast_to(a, (*spec.shape, *a.shape[1:]))

    table.status, table.message = grid(table.status), grid(table.message)
    table.regime, table.caveat = grid(table.regime), grid(table.caveat)
    table.runs = {name: grid(a) for name, a in table.runs.items()}
    table.eqs = {name: grid(a) for name, a in table.eqs.items()}
    table.eig, table.coexistence = grid(table.eig), grid(table.coexistence)
    return table


def _create(path: Path, spec: SweepSpec, params_json: str, version: str) -> None:
    table = _blank(spec)
    # Objects in creation order, the regime's named type first: netCDF-C reads them in that
    # order, and before 4.9.2 (Debian 12's 4.9.0) it dropped a variable whose enum type has
    # no name, or whose type it met only after it (in alphabetical order, "regime" < "regime_t").
    with h5py.File(path, "w", libver=LIBVER, locking=WRITER_LOCKING, track_order=True) as f:
        f["regime_t"] = h5py.enum_dtype(REGIMES, basetype="i1")
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
        k = spec.record["eigenvalues"]
        ev = f.create_dataset("eigenvalue", data=np.arange(k, dtype="i2"))
        ev.make_scale("eigenvalue")
        cf = index_attrs()
        for ds in (init, eq, ev):
            ds.attrs.update(cf[ds.name.lstrip("/")])

        def make(name, data, extra, **attrs):
            # A fresh table holds one value everywhere: made the fill value, no chunk is
            # written until a point is (a 10^6-point atlas: 0.03 s and 0.05 MB, was 2.5 s
            # and 33 MB).
            ds = f.create_dataset(
                name,
                shape=data.shape,
                dtype=data.dtype,
                **_storage(data.shape, data.dtype.itemsize, len(scales)),
                fillvalue=data.flat[0] if data.size else 0,
            )
            for axis, scale in enumerate(scales):
                ds.dims[axis].attach_scale(scale)
            for j, s in enumerate(extra):
                ds.dims[len(scales) + j].attach_scale(s)
            for key, value in attrs.items():
                ds.attrs[key] = value
            return ds

        reg = f.create_dataset(
            "regime",
            shape=table.regime.shape,
            dtype=f["regime_t"],
            **_storage(table.regime.shape, 1, len(scales)),
            fillvalue=REGIMES["missing"],
        )
        for axis, scale in enumerate(scales):
            reg.dims[axis].attach_scale(scale)
        reg.dims[len(scales)].attach_scale(init)
        reg.attrs.update(regime_attrs())
        make("status", table.status, [], **cf["status"])
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
        make("coexistence", table.coexistence, [], **cf["coexistence"])
        _make_caveat(f, spec, table.caveat)


def _make_per_run(f: h5py.File, spec: SweepSpec, name: str, data: np.ndarray, fill: Any):
    """A dataset of one value per point and start, on the atlas's scales."""
    ds = f.create_dataset(
        name,
        shape=data.shape,
        dtype=data.dtype,
        **_storage(data.shape, data.dtype.itemsize, len(spec.axes)),
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
    # Every array is read from the file, so none is made and filled first (an AtlasTable of
    # the grid's shape: 0.5-1 s of filling at 10^6 points, thrown away): a table of no rows,
    # given the grid's arrays below.
    table = AtlasTable(spec, points=0)
    table.points = None
    n_init, k = len(spec.initials), spec.record["eigenvalues"]
    with h5py.File(path, "r") as f:
        table.status = f["status"][...]
        table.message = np.array(
            [m.decode() if isinstance(m, bytes) else m for m in f["message"][...].ravel()],
            dtype=object,
        ).reshape(spec.shape)
        table.regime = f["regime"][...].astype("i1")
        for name, (dtype, fill, *_) in RUN_FIELDS.items():
            if name in f:
                table.runs[name] = f[name][...]
            else:  # an added field is missing from atlases written before it: not measured
                table.runs[name] = np.full((*spec.shape, n_init), fill, dtype=dtype)
        for name in EQ_FIELDS:
            table.eqs[name] = f[name][...]
        # Into one array: real + 1j * imag made four temporaries of up to its size (the
        # eigenvalues are a third of the table: 0.4 GB more at 10^6 points).
        table.eig = np.empty((*spec.shape, N_EQ, k), dtype="c16")
        table.eig.real[...] = f["eigenvalues_real"][...]
        table.eig.imag[...] = f["eigenvalues_imag"][...]
        table.coexistence = f["coexistence"][...]
        if "caveat" in f:
            table.caveat = f["caveat"][...]
        else:  # atlases written before it: no caveats recorded
            table.caveat = np.zeros((*spec.shape, n_init), dtype="i1")
    return table
