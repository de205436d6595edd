"""An atlas as an ``xarray.Dataset``: through h5netcdf, with what older atlases lack added
(units, long names, flags) and each count's fill read as missing."""

from __future__ import annotations

import io
import numbers
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeAlias

import numpy as np

from . import atlas_format as fmt

#: integer fields whose fill, -1, marks "not measured" (not a regime code: those have names)
COUNT_FIELDS = tuple(
    name
    for name, (dtype, fill, *_) in {**fmt.RUN_FIELDS, **fmt.EQ_FIELDS}.items()
    if dtype.startswith("i") and fill == -1
)


#: what ``Atlas.to_xarray`` takes as ``chunks``, as ``xarray.open_dataset`` does: by dimension
#: (``{}``: the file's own), ``"auto"`` (dask's size), a size for every dimension (-1: whole),
#: or None (no dask)
Chunks: TypeAlias = "Mapping[str, int | str | tuple[int, ...] | None] | int | str | None"


def checked_chunks(chunks: Any) -> Any:
    """``chunks`` if ``xarray.open_dataset`` takes it (see ``Chunks``), else a TypeError or
    ValueError naming what it takes."""
    if chunks is None or isinstance(chunks, Mapping):
        return chunks
    if isinstance(chunks, str):
        if chunks != "auto":
            raise ValueError(f"chunks = {chunks!r} is not allowed: the only name is 'auto'")
        return chunks
    if isinstance(chunks, numbers.Integral) and not isinstance(chunks, bool):
        if chunks < 1 and chunks != -1:
            raise ValueError(f"chunks = {chunks!r} is not allowed: a size of 1 or more, or -1")
        return int(chunks)
    raise TypeError(
        "chunks must be a dict of sizes by dimension (e.g. {'wob': 100}), 'auto', an int "
        f"(-1: whole) or None, got {chunks!r}"
    )


def to_xarray(source: Path | io.BytesIO, axes: Mapping[str, Any], chunks: Chunks = None) -> Any:
    """``Atlas.to_xarray`` of the atlas in ``source`` (a file or the copy taken while a sweep
    writes it), whose sweep's axes are ``axes``; ``chunks`` as ``xarray.open_dataset``'s."""
    import xarray as xr

    chunks = checked_chunks(chunks)
    # Chunked, the failure messages too: xarray decodes a text variable whole on opening
    # (70 bytes a point), so they are read by blocks through h5py instead (_lazy_messages).
    by_blocks = chunks is not None and _has_messages(source)
    ds = opened = xr.open_dataset(
        source,
        engine="h5netcdf",
        chunks=chunks,
        drop_variables=["message"] if by_blocks else None,
    )
    close = opened.close
    unknown = sorted(set(chunks) - set(ds.dims)) if isinstance(chunks, Mapping) else []
    if unknown:  # xarray let them pass (a typo, and the chunks asked for were not made)
        close()
        raise ValueError(
            f"chunks: {unknown[0]!r} is not a dimension of this atlas; its dimensions: "
            + ", ".join(map(str, ds.dims))
        )
    if by_blocks:
        ds, close = _lazy_messages(ds, source, axes, opened.close)
    if "message" in ds and ds["message"].dims != tuple(axes):
        # Atlases written before ``message`` had its dimension scales: xarray guessed its
        # dimensions from their lengths.
        ds = ds.assign(message=(tuple(axes), ds["message"].values, ds["message"].attrs))
    for name in axes:
        if ds[name].attrs.get("units") == "SI":  # atlases written before axis_units
            ds[name].attrs["units"] = fmt.axis_units(name)
    if "regime" in ds:  # as the atlas names them (older atlases: without a long_name)
        ds["regime"].attrs.update(fmt.regime_attrs())
    for name, attrs in fmt.index_attrs().items():  # (older atlases: without some)
        if name in ds:
            ds[name].attrs.update(attrs)
    for name in COUNT_FIELDS:
        # A count's fill (-1: failed, missing, no such steady state) is not a count: read
        # as NaN, as xarray reads any CF _FillValue, so that means and exports skip it.
        if name in ds and "_FillValue" not in ds[name].encoding:
            count = ds[name]
            ds[name] = count.where(count != -1)
            ds[name].encoding.update(dtype=count.dtype, _FillValue=count.dtype.type(-1))
    ds = with_safe(ds)
    # What assign makes has no close of its own: its close() left the file open, for as long
    # as the dataset (or its dask arrays, or a traceback that names it) lived. The dataset
    # opened has its own: made its own closer (nothing assigned: an atlas without stability,
    # no ``safe``), its close() called itself without end.
    if ds is not opened:
        ds.set_close(close)
    return ds


def _has_messages(source: Path | io.BytesIO) -> bool:
    import h5py

    with h5py.File(source, "r") as f:
        return isinstance(f.get("message"), h5py.Dataset)


def _lazy_messages(ds, source, axes: Mapping[str, Any], close):
    """``ds`` with the atlas's ``message`` as a dask array read through h5py in the blocks of
    ``status`` (on the same axes: as ``chunks`` made them, whatever it was), and the close of
    both files."""
    import dask.array as da
    import h5py

    f = h5py.File(source, "r")
    text = f["message"]
    blocks = ds["status"].chunks or tuple(-1 for _ in axes)
    # Objects known to be text (xarray's mark, as it decodes them): written back as
    # variable-length text without first being read whole to find out what they are.
    meta = np.empty((0,) * len(axes), dtype=np.dtype("O", metadata={"element_type": str}))
    values = da.from_array(text.asstr(), chunks=blocks, asarray=False, name=False, meta=meta)
    attrs = {k: v for k, v in text.attrs.items() if k == "long_name"}
    order = [name for name in f if name in ds.data_vars or name == "message"]  # the file's
    ds = ds.assign(message=(tuple(axes), values, attrs))[order]

    def close_both() -> None:
        close()
        f.close()

    return ds, close_both


#: ``safe``'s attributes: what it means, and its two values named as CF flags
SAFE_ATTRS = {
    "long_name": "1 where every start drills steadily and the fastest steady state is stable "
    "(what pydrill atlas safe lists)",
    "flag_values": np.array([0, 1], dtype="i1"),
    "flag_meanings": "unsafe safe",
}


def with_safe(ds):
    """``ds`` with a ``safe`` variable on the axes: 1 where every start drills steadily and the
    fastest steady state is stable (``Atlas.safe_region``), 0 elsewhere (a point not computed
    too). None without stability recorded (``[record] stability = false``): there a steady run
    alone does not say its steady state is stable."""
    import tomllib

    if not {"regime", "unstable", "initial", "equilibrium"} <= set(ds.variables):
        return ds
    try:
        record = tomllib.loads(ds.attrs.get("spec", "")).get("record", {})
    except tomllib.TOMLDecodeError:
        return ds
    if not record.get("stability", True):
        return ds
    steady = (ds["regime"] == fmt.REGIMES["steady"]).all("initial")
    stable = ds["unstable"].isel(equilibrium=0, drop=True) == 0  # a fill (NaN) is not 0
    safe = (steady & stable).astype("i1")
    safe.attrs = dict(SAFE_ATTRS)  # its own alone (``unstable``'s units came along: "1")
    return ds.assign(safe=safe)


def with_regime_names(ds):
    """``ds`` with a ``regime_name`` variable: the regime codes as their names."""
    if "regime" not in ds:
        return ds
    names = {c: n for n, c in fmt.REGIMES.items()}
    values = np.vectorize(lambda c: names.get(int(c), "?"), otypes=[object])(ds["regime"].values)
    return ds.assign(regime_name=(ds["regime"].dims, values))
