"""``pydrill atlas export``: an atlas as a netCDF file every netCDF-4 reader takes, or as a
CSV table with each code's name beside it."""

from __future__ import annotations

import argparse
import errno
import os
import secrets
import shlex
import stat
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .cli_options import check_progress, writable_place


def export_path(text: str) -> str:
    """An argparse type for ``atlas export --out``: the format is the suffix."""
    if Path(text).suffix.lower() not in (".nc", ".csv"):
        raise argparse.ArgumentTypeError(f"{text!r}: the suffix must be .nc (netCDF) or .csv")
    writable_place(text)
    return text


#: points an export reads, converts and writes at a time (whole rows of the first axis): its
#: memory is a block's, tens of MB, whatever the atlas's size (made whole in memory, an atlas
#: of 10^6 points took 1 GB to export to netCDF, 2.3 GB to CSV)
BLOCK_POINTS = 2**16


def cmd_export(args: argparse.Namespace) -> int:
    import math

    import numpy as np

    from . import atlas_format as fmt
    from .atlas import Atlas
    from .spec_parts import part_option

    out = Path(args.out)
    if out.resolve() == Path(args.atlas).resolve():
        raise ValueError(f"--out {args.out} is the atlas itself; give another file")
    with Atlas(args.atlas) as atlas:
        atlas.check()  # it is read whole: no code that is none may pass into the export
        missing = int(np.sum(atlas._file()["status"][...] == fmt.STATUS["missing"]))
        part = part_option(atlas.spec.text)  # a part's atlas resumes with its --part
        first, *others = atlas.axes
        per_row = math.prod(len(atlas.axes[name]) for name in others)
        rows = max(1, BLOCK_POINTS // per_row)
        with warnings.catch_warnings():
            # "The specified chunks separate the stored chunks": a block's first and last
            # chunks are read twice, a small price for reading 10^6 points in ~20 blocks
            # (chunk by chunk, h5netcdf's 3 ms a read took a minute).
            warnings.filterwarnings("ignore", "The specified chunks separate", UserWarning)
            ds = atlas.to_xarray(chunks={first: rows, **dict.fromkeys(others, -1)})
        # On a terminal, a bar: 10^6 points take some 10 s to CSV
        points = per_row * len(atlas.axes[first])
        bar = check_progress(points, "export", unit="pt")
        netcdf = out.suffix.lower() == ".nc"
        try:  # the atlas is closed (its xarray view too) whatever fails
            if netcdf:
                _write_whole(out, lambda fd: _write_netcdf(ds, fd, bar))
                written = {"variables": sorted(map(str, ds.data_vars))}
            else:  # .csv, as export_path allows
                lines = _write_whole(out, lambda fd: _write_csv(ds, fd, first, rows, bar))
                written = {"rows": lines}
        finally:
            bar.close()
            ds.close()
    if missing:  # exported as missing: say so, and how to compute them
        print(
            f"pydrill atlas export: note: {missing_note(args.atlas, missing, points, part)}",
            file=sys.stderr,
        )
    if not args.json:
        print(f"wrote {out}")
        return 0
    from .cli_options import json_document, print_json

    results = {"format": "netcdf" if netcdf else "csv", "points": points, **written}
    results["missing"] = missing
    results["bytes"] = out.stat().st_size
    print_json(json_document({"atlas": args.atlas, "out": args.out}, results, {"bytes": "B"}))
    return 0


def missing_note(atlas: str, missing: int, points: int, part: str = "") -> str:
    """Why ``missing`` of the ``points`` of ``atlas`` are missing and what completes them, in
    the words of ``pydrill atlas info``: a sweep writing it now, or one stopped (its journal
    beside it, or not: a journal removed, parts merged before they were complete). ``part``:
    ``" --part K/N"`` for a part's atlas (``spec_parts.part_option``)."""
    from .atlas_lock import writer
    from .journal import journal_path

    count = f"{missing} of {points} points are missing (exported as missing)"
    holder = writer(Path(atlas))
    if holder is not None:
        return f"{count}: a sweep is writing this atlas now ({holder}); export it once done"
    journal = journal_path(Path(atlas)).exists()
    stopped = "a sweep into this atlas was stopped;" if journal else "a stopped sweep?"
    resume = f"pydrill sweep SPEC.toml{part} --out {shlex.quote(atlas)} --resume"
    return f"{count}: {stopped} '{resume}' completes it (SPEC.toml: the spec it was swept from)"


def _write_netcdf(ds, fd: int, bar: Any) -> None:
    """``ds`` (read into dask arrays of blocks of rows) as netCDF-4 into the file open on
    ``fd``, a block at a time; ``bar`` moves as dask's tasks finish. A failed write raises
    its OSError once HDF5 is done with the file (``SinkFile``)."""
    import dask

    from .export_file import SinkFile

    sink = SinkFile(fd)
    try:
        with (
            warnings.catch_warnings(),
            dask.config.set(scheduler="synchronous"),
            _task_progress(bar, sink),
        ):
            # h5netcdf warns that an enum variable's default fill (0) is a regime's code
            # (steady): it masks nothing here, every element is written and no _FillValue
            # attribute is (netCDF-C's ncdump, netCDF4 and xarray read 0 as steady).
            warnings.filterwarnings("ignore", "Creating variable with default fill_value 0")
            _by_chunks(ds).to_netcdf(sink, engine="h5netcdf", encoding=_netcdf_encoding(ds))
        bar.update(bar.total - bar.n)  # (a graph counts keys that are no task: data)
    except Exception:
        if sink.error is None:
            raise
    finally:
        sink.close()
    if sink.error is not None:  # the cause of whatever HDF5 made of it
        raise sink.error


def _task_progress(bar: Any, sink: Any) -> Any:
    """A dask callback moving ``bar`` (counted in points) as the tasks of the computations
    it watches finish, each task a share of the points; and stopping them once a write to
    ``sink`` has failed (the rest would only go to memory: up to the whole file, for
    nothing). HDF5, which never heard of the failure, then closes the file as usual."""
    from dask.callbacks import Callback

    class TaskProgress(Callback):
        tasks = done = 0

        def _start_state(self, dsk: Any, state: Any) -> None:
            self.tasks += len(dsk)

        def _posttask(self, *args: Any) -> None:
            if sink.error is not None:
                raise sink.error
            self.done += 1
            # Forwards only: a computation started later adds its tasks to the count.
            reached = round(bar.total * min(1.0, self.done / max(self.tasks, 1)))
            if reached > bar.n:
                bar.update(reached - bar.n)  # drawn at most 10 times a second, as tqdm does

    return TaskProgress()


def _by_chunks(ds):
    """``ds`` with each variable's blocks made whole rows of its HDF5 chunks (which the
    export keeps): each chunk is then compressed once, whole. Blocks that cut through
    chunks made HDF5 read, inflate and deflate a chunk again for every block."""
    out = ds.copy()
    for name, var in ds.variables.items():
        if var.chunks is None:  # the axes, read whole already
            continue
        block, chunk = var.chunks[0][0], (var.encoding.get("chunksizes") or (1,))[0]
        out[name] = var.chunk({var.dims[0]: max(chunk, block // chunk * chunk)})
    if "regime" in ds:
        # Whole (a byte a point and start): a dask array cast to the encoding's dtype lost
        # the enum type it carries, and ncdump showed codes, not names.
        out["regime"] = ds["regime"].load()
    return out


def _write_csv(ds, fd: int, first: str, rows: int, bar: Any) -> int:
    """``ds`` as a CSV table into the file open on ``fd`` (pydrill.export_csv): its rows."""
    from .export_csv import write_csv

    with open(fd, "wb", closefd=False) as fh:
        return write_csv(ds, fh, first, rows, bar)


def _write_whole(out: Path, fill: Callable[[int], Any]) -> Any:
    """Write ``out`` whole or not at all: ``fill`` writes into a new file beside it (on the
    descriptor it is given, open for reading and writing), put in its place once complete.
    On a failure that file is removed and ``out`` (if there was one) left as it was; the
    OSError names ``out``. As writing into it would: a symlink at ``out`` is followed (the
    file it names is replaced, the link kept), and a file there keeps its permissions."""
    target = out.resolve() if out.is_symlink() else out
    part = target.with_name(f".{target.name}.{secrets.token_hex(4)}.part")
    try:
        mode = stat.S_IMODE(target.stat().st_mode) if target.exists() else None
        if mode is not None and not os.access(target, os.W_OK):  # what writing into it met
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
        # 0o666 as open() makes a file (less the umask); mkstemp's 0o600 would be kept
        fd = os.open(part, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o666)
        try:
            try:
                if mode is not None:
                    os.chmod(fd, mode)
                filled = fill(fd)
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(part, target)
            return filled
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
