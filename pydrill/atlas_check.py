"""Whether an atlas file is laid out as its spec makes it: what a damaged one (a dataset of
another shape or kind, a group for a dataset, an attribute that is not text, codes that are
none) is refused with, by ``--resume`` (``journal.read_existing``) and by ``pydrill.Atlas``,
instead of a traceback from deep inside a replay or a query."""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from . import atlas_format as fmt
from .spec import SweepSpec


def show(v: Any) -> str:
    """A value as a message shows it: its repr, cut to 40 characters."""
    text = repr(v)
    return text if len(text) <= 40 else text[:37] + "..."


#: the root attributes atlas_format.create writes as text (one missing is allowed: an
#: atlas written before it was)
_TEXT_ATTRS: tuple[str, ...] = ("format", "pydrill_version", "spec", "tally", "spec_digest")
_TEXT_ATTRS += ("params", "axes", "fixed", "Conventions", "title", "source", "references")


def layout_problem(f: Any, spec: SweepSpec, *, codes: bool = True) -> str | None:
    """What in the open atlas ``f`` (an ``h5py.File``) differs from the layout that
    ``atlas_format.create`` makes for ``spec``, or None: every dataset there, a dataset (not
    a group) of its shape and kind of number; the axes, starts, status, regime and caveat
    codes those of the spec and schema. A file that passes reads into an ``AtlasTable``,
    and a sweep or a query finds what it expects in it (a dataset of the wrong shape or type
    was a ValueError, TypeError or IndexError from deep inside them). ``codes=False`` leaves
    out the one check that reads whole datasets, the codes (30 ms at 10^6 points: opening an
    atlas for a point query checks the rest, and the query its own point's codes)."""
    import h5py

    shape, n_init = spec.shape, len(spec.initials)
    eig = (*shape, fmt.N_EQ, spec.record["eigenvalues"])
    expected: dict[str, tuple[tuple[int, ...], str]] = {
        "status": (shape, "iu"),
        "message": (shape, "OSU"),
        "regime": ((*shape, n_init), "iu"),
        "coexistence": (shape, "iu"),
        "eigenvalues_real": (eig, "iuf"),
        "eigenvalues_imag": (eig, "iuf"),
        "caveat": ((*shape, n_init), "iu"),
        **{name: ((*shape, n_init), "iuf") for name in fmt.RUN_FIELDS},
        **{name: ((*shape, fmt.N_EQ), "iuf") for name in fmt.EQ_FIELDS},
    }
    optional = {*fmt.ADDED_RUN_FIELDS, "caveat"}  # atlases written before they existed
    if "spec" not in f.attrs:
        return "no attribute spec (the sweep it holds)"
    for name in _TEXT_ATTRS:
        if name in f.attrs and not isinstance(f.attrs[name], str):
            return f"attribute {name} = {show(f.attrs[name])} is not text"
    version = f.attrs.get("format_version", 0)
    if isinstance(version, bool) or not isinstance(version, int | np.integer):
        return f"attribute format_version = {show(version)} is not an integer"
    for name in ("equilibrium", "eigenvalue"):  # the scales of the steady states' datasets
        if not isinstance(f.get(name), h5py.Dataset):
            return f"no dataset {name}"
    for name, (want, kinds) in expected.items():
        ds = f.get(name)
        if ds is None and name in optional:
            continue
        if not isinstance(ds, h5py.Dataset):
            return f"no dataset {name}" if ds is None else f"{name} is not a dataset"
        if ds.shape != want:
            return f"{name} has shape {ds.shape}, not {want}"
        if ds.dtype.kind not in kinds:
            return f"{name} holds {ds.dtype}, not numbers" if kinds != "OSU" else f"{name}: no text"
    try:
        axes = json.loads(f.attrs.get("axes"))
    except (TypeError, ValueError):
        axes = None
    if axes != list(spec.axes):
        return f"attribute axes = {show(f.attrs.get('axes'))} is not {json.dumps(list(spec.axes))}"
    for name, values in spec.axes.items():
        ds = f.get(name)
        if (
            not isinstance(ds, h5py.Dataset)
            or ds.shape != values.shape
            or ds.dtype.kind not in "iuf"
            or not np.array_equal(ds[...], values)
        ):
            return f"axis {name} is not the spec's {len(values)} values"
    ds = f.get("initial")
    starts = ds[...].tolist() if isinstance(ds, h5py.Dataset) and ds.ndim == 1 else None
    if starts is None or [s.decode() if isinstance(s, bytes) else s for s in starts] != list(
        spec.initials
    ):
        return f"initial is not the spec's starts, {', '.join(spec.initials)}"
    coded = {"status": fmt.STATUS, "regime": fmt.REGIMES, "caveat": fmt.CAVEATS}
    coded["coexistence"] = {"unknown": -1, "no": 0, "yes": 1}
    for name, known in coded.items() if codes else ():
        if name in f and not np.all(np.isin(f[name][...], list(known.values()))):
            return code_problem(name, known)
    return None


def code_problem(name: str, known: dict[str, int]) -> str:
    """What ``layout_problem`` says of a dataset ``name`` holding a code not in ``known``."""
    return f"{name} holds codes other than those of {', '.join(n or 'none' for n in known)}"
