"""An open atlas file's datasets as ``pydrill.Atlas`` reads them: each looked up once, and the
list of those a query needs (a file without one of them is damaged). Apart from atlas.py so
that the class that answers queries is not also the one that caches h5py's lookups."""

from __future__ import annotations

from typing import Any

import h5py

from . import atlas_format as fmt


class Objects:
    """An open atlas file's datasets, each looked up once: h5py opens an object anew each time
    it is named (0.05 ms on a 10^6-point atlas), and a point query names some 30, which opening
    the atlas has named already to check them (4 ms): named again, they cost every query
    1.5 ms more."""

    def __init__(self, f: h5py.File) -> None:
        self.attrs = f.attrs
        self._f = f
        self._seen: dict[str, Any] = {}

    def get(self, name: str) -> Any:
        if name not in self._seen:
            self._seen[name] = self._f.get(name)
        return self._seen[name]

    def __getitem__(self, name: str) -> Any:
        found = self.get(name)
        if found is None:
            raise KeyError(f"no dataset {name}")
        return found

    def __contains__(self, name: str) -> bool:
        return self.get(name) is not None


# What the queries read: a file without one of these is damaged, whatever else it holds.
DATASETS = (
    "initial",
    "status",
    "message",
    "regime",
    *(name for name in fmt.RUN_FIELDS if name not in fmt.ADDED_RUN_FIELDS),
    *fmt.EQ_FIELDS,
    "eigenvalues_real",
    "eigenvalues_imag",
    "coexistence",
)
