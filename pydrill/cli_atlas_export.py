"""``pydrill atlas export``: an atlas as a netCDF file every netCDF-4 reader takes, or as a
CSV table with each code's name beside it."""

from __future__ import annotations

import argparse
import errno
import os
import secrets
import stat
import warnings
from pathlib import Path
from typing import Any

from .cli_options import writable_place


def export_path(text: str) -> str:
    """An argparse type for ``atlas export --out``: the format is the suffix."""
    if Path(text).suffix.lower() not in (".nc", ".csv"):
        raise argparse.ArgumentTypeError(f"{text!r}: the suffix must be .nc (netCDF) or .csv")
    writable_place(text)
    return text


def cmd_export(args: argparse.Namespace) -> int:
    from .atlas import COUNT_FIELDS, Atlas

    out = Path(args.out)
    if out.resolve() == Path(args.atlas).resolve():
        raise ValueError(f"--out {args.out} is the atlas itself; give another file")
    # The export is made in memory, the atlas closed (its xarray view too, whatever fails),
    # and only then written out, whole or not at all (_write_whole). h5netcdf writing the file
    # itself left a half-written one under --out when a write failed (a full disk), and
    # closing it after the failure crashed Python (a segmentation fault in h5py).
    with Atlas(args.atlas) as atlas:
        atlas.check()  # it is read whole: no code that is none may pass into the export
        ds = atlas.to_xarray()
        try:
            if out.suffix.lower() == ".nc":
                with warnings.catch_warnings():
                    # h5netcdf warns that an enum variable's default fill (0) is a regime's
                    # code (steady): it masks nothing here, every element is written and no
                    # _FillValue attribute is (netCDF-C's ncdump, netCDF4 and xarray read 0 as
                    # steady).
                    warnings.filterwarnings("ignore", "Creating variable with default fill_value 0")
                    data = ds.load().to_netcdf(
                        None, engine="h5netcdf", encoding=_netcdf_encoding(ds)
                    )
            else:  # .csv, as export_path allows
                ds.load()
                keep = [
                    v
                    for v in ds.data_vars
                    if "eigenvalue" not in ds[v].dims
                    and "equilibrium" not in ds[v].dims
                    and (ds[v].dtype.kind != "O" or v == "message")
                ]
                table = ds[keep].to_dataframe()
                for name in COUNT_FIELDS:  # counts as integers, an empty cell where not measured
                    if name in table:
                        table[name] = table[name].astype("Int64")
                _name_codes(table)
                data = table.to_csv().encode()
        finally:
            ds.close()
    _write_whole(out, data)
    print(f"wrote {out}")
    return 0


def _write_whole(out: Path, data: bytes | memoryview) -> None:
    """Write ``data`` to ``out`` whole or not at all: into a new file beside it, put in its
    place once complete. On a failure that file is removed and ``out`` (if there was one)
    left as it was; the OSError names ``out``. As writing into it would: a symlink at ``out``
    is followed (the file it names is replaced, the link kept), and a file there keeps its
    permissions."""
    target = out.resolve() if out.is_symlink() else out
    part = target.with_name(f".{target.name}.{secrets.token_hex(4)}.part")
    try:
        mode = stat.S_IMODE(target.stat().st_mode) if target.exists() else None
        if mode is not None and not os.access(target, os.W_OK):  # what writing into it met
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
        # 0o666 as open() makes a file (less the umask); mkstemp's 0o600 would be kept
        fd = os.open(part, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        try:
            with open(fd, "wb") as fh:
                if mode is not None:
                    os.chmod(fh.fileno(), mode)
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(part, target)
        except BaseException:
            part.unlink(missing_ok=True)
            raise
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(out)) from None


def _netcdf_encoding(ds) -> dict[str, dict[str, Any]]:
    """How the .nc export stores what xarray would store otherwise: ``regime`` as a named
    netCDF enum type, ``regime_t`` (netCDF-C before 4.9.2 cannot read a variable whose enum
    type has no name, as in the atlas: Debian 12's ncdump left ``regime`` out), and the
    coordinates without a ``_FillValue`` (xarray gives float ones NaN; CF coordinates have no
    missing values)."""
    import numpy as np

    from . import atlas_format as fmt

    encoding: dict[str, dict[str, Any]] = {name: {"_FillValue": None} for name in ds.coords}
    if "regime" in ds:
        enum = {"enum": dict(fmt.REGIMES), "enum_name": "regime_t"}
        encoding["regime"] = {"dtype": np.dtype("i1", metadata=enum)}
    return encoding


def _name_codes(table) -> None:
    """Put beside each coded column of an exported table (a DataFrame) its names: regime_name,
    caveat_name ("none" without one), status_name and coexistence_name ("unknown" with one
    start or a point not done), each right after its codes."""
    from . import atlas_format as fmt

    names = {
        "regime": fmt.REGIME_NAMES,
        "caveat": {c: n or "none" for c, n in fmt.CAVEAT_NAMES.items()},
        "status": {c: n for n, c in fmt.STATUS.items()},
        "coexistence": {c: n for n, c in fmt.COEXISTENCE.items()},  # its flag_meanings
    }
    for column, meaning in names.items():
        if column not in table:
            continue
        named = table[column].map(lambda c, meaning=meaning: meaning.get(int(c), "?"))
        table.insert(table.columns.get_loc(column) + 1, f"{column}_name", named)
