"""``xarray.open_dataset(path, engine="pydrill")``: an atlas as ``Atlas.to_xarray`` reads it.

Registered with xarray by installing pydrill (entry point ``pydrill`` of the group
``xarray.backends``). xarray loads it when it first lists its engines, so this module imports
nothing heavy of pydrill's until an atlas is opened; pydrill itself never imports it, so that
importing pydrill does not import xarray.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from xarray.backends import BackendEntrypoint


class AtlasBackend(BackendEntrypoint):
    """An atlas read as ``Atlas.to_xarray`` reads it, not as the bare file: it is checked
    first (a damaged global heap hung HDF5 under ``engine="h5netcdf"``: here it is an
    ``AtlasError`` naming the damage), read from a copy of the last complete write while a
    sweep writes it, and has ``safe`` (1 where every start drills steadily and the fastest
    steady state is stable) and the counts' fills as NaN. ``chunks``, ``drop_variables``,
    ``decode_*`` and the other arguments xarray handles work as for any engine. The file is
    closed by ``Dataset.close()`` (or ``with``), as with xarray's engines."""

    description = "pydrill regime atlases (HDF5): checked, with the safe region"
    open_dataset_parameters = ("filename_or_obj", "drop_variables")

    def open_dataset(
        self, filename_or_obj: Any, *, drop_variables: str | Iterable[str] | None = None
    ) -> Any:
        from .atlas import Atlas

        if not isinstance(filename_or_obj, str | Path):
            raise TypeError(
                "engine='pydrill' opens an atlas by its path, not a "
                f"{type(filename_or_obj).__name__}: give the file's name"
            )
        with Atlas(filename_or_obj) as atlas:
            ds = atlas.to_xarray()  # on a handle of its own: it outlives the Atlas
        if isinstance(drop_variables, str):
            drop_variables = [drop_variables]
        out = ds.drop_vars(list(drop_variables or []), errors="ignore")
        out.set_close(ds.close)  # what drop_vars makes has no close of its own
        return out

    def guess_can_open(self, filename_or_obj: Any) -> bool:
        """Never: an atlas is an HDF5 file, which xarray's own engines claim first, and to
        decide would mean reading its attributes, which a damaged heap hangs HDF5 on. Ask for
        ``engine="pydrill"``."""
        return False
