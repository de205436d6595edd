"""An atlas's journal, and the atlas's creation or reopening for a sweep.

The journal (``ATLAS.h5.journal``) is what makes a sweep safe to kill: its first line names
the sweep (the spec's digest), then one JSON line per finished point, appended and flushed to
disk a batch at a time by the client, before the point reaches the HDF5 file. ``prepare``
refuses an atlas of another sweep, and on ``--resume`` replays the journal into the atlas,
rebuilding the atlas from it if a kill caught the HDF5 file mid-write.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from . import atlas_format as fmt
from .spec import SweepSpec

JOURNAL_SUFFIX = ".journal"


class AtlasError(RuntimeError):
    """An atlas that cannot be used as asked (damaged, of another sweep, …)."""


def journal_path(path: Path) -> Path:
    """The journal of the atlas ``path``: ``ATLAS.h5.journal``."""
    return path.with_name(path.name + JOURNAL_SUFFIX)


def read_journal(path: Path, spec: SweepSpec, *, repair: bool = True) -> list[dict[str, Any]]:
    """The records of ``path``'s journal, as a list (``iter_journal``)."""
    return list(iter_journal(path, spec, repair=repair))


def iter_journal(path: Path, spec: SweepSpec, *, repair: bool = True) -> Iterator[dict[str, Any]]:
    """The records of ``path``'s journal, one at a time: a journal holds about 1 kB a point,
    and its records as Python objects 5 kB (a list of a 74000-point journal's took 400 MB; a
    million points' would have taken 5 GB on top of the table). A last line cut by a kill (or
    Ctrl-C) mid-write is dropped and, with ``repair``, cut off the file once all are read, so
    that the next append starts on a line of its own; its points are simply computed again."""
    jp = journal_path(path)
    if not jp.exists():
        return
    good = 0  # bytes up to the end of the last whole line
    with jp.open("rb") as fh:  # line by line: a journal may hold millions of points
        for n, raw in enumerate(fh):
            try:
                if not raw.endswith(b"\n"):
                    raise ValueError("no end of line")
                data = json.loads(raw)
            except ValueError as exc:
                if not fh.read(1):  # the last line
                    break
                raise AtlasError(
                    f"{jp}, line {n + 1}, is damaged ({exc}); remove the journal "
                    "to start the sweep over"
                ) from None
            good += len(raw)
            if n == 0:
                if data.get("spec_digest") != spec.digest:
                    raise AtlasError(
                        f"{jp} belongs to another sweep (spec digest "
                        f"{data.get('spec_digest')} != {spec.digest})"
                    )
                continue
            yield data
    if not repair:
        pass
    elif good == 0:  # not even the header survived
        jp.write_text(json.dumps({"spec_digest": spec.digest}) + "\n")
    elif good < jp.stat().st_size:
        os.truncate(jp, good)


def journaled(path: Path) -> np.ndarray:
    """Flat indices of the points in the journal of the atlas ``path`` (none without one),
    read only and fast: a journal may hold millions of lines, and ``pydrill atlas info``
    reads it to show a running sweep's progress between two flushes of the atlas. Lines are
    ``{"i": N, ...}`` as ``run_sweep`` writes them; a last line cut by a kill is skipped."""
    jp = journal_path(path)
    found: list[int] = []
    try:
        fh = jp.open("rb")
    except FileNotFoundError:
        return np.array([], dtype=np.int64)
    with fh:
        next(fh, None)  # the header
        for raw in fh:
            if not raw.endswith(b"\n"):
                break
            if raw.startswith(b'{"i": '):
                found.append(int(raw[6 : raw.index(b",", 6)]))
            else:  # not as written by run_sweep: parse it whole
                with contextlib.suppress(ValueError, KeyError, TypeError):
                    found.append(int(json.loads(raw)["i"]))
    return np.array(found, dtype=np.int64)


def read_existing(spec: SweepSpec, out: Path, *, resume: bool) -> fmt.AtlasTable | None:
    """The table of the atlas ``out`` that a sweep of ``spec`` would continue, read only;
    None when there is no atlas file, or a damaged one that its journal can rebuild. Raises
    ``AtlasError`` for what a sweep must not touch: a file that is not a pydrill atlas, an
    atlas of another spec, a damaged one without a journal, or any of this spec's without
    ``resume``."""
    jp = journal_path(out)
    table = None
    if out.is_dir():
        raise AtlasError(
            f"{out} is a directory; give the atlas a file name, e.g. --out {out / 'atlas.h5'}"
        )
    if out.exists():
        try:
            import h5py

            with h5py.File(out, "r") as f:
                if f.attrs.get("format") != fmt.FORMAT:
                    raise AtlasError(f"{out} exists and is not a pydrill atlas; not touching it")
                digest = f.attrs.get("spec_digest")
                theirs = (f.attrs.get("spec"), f.attrs.get("tally") or None)
            if digest != spec.digest:
                raise AtlasError(
                    f"{out} holds a different sweep ({_what_differs(spec, *theirs)}); choose "
                    "another --out or remove it"
                )
            table = fmt.read_table(out, spec)
        except AtlasError:
            raise
        except (OSError, KeyError, ValueError):
            if not jp.exists():
                raise AtlasError(
                    f"{out} is damaged (not a readable HDF5 atlas) and has no journal to "
                    "rebuild it from"
                ) from None
    if not out.exists():
        # A journal alone (the atlas was removed, or a kill came before it was made): say so,
        # and whose it is, before anything is created beside it.
        digest = _journal_digest(jp)
        if digest is not None and digest != spec.digest:
            raise AtlasError(
                f"{jp} belongs to another sweep (spec digest {digest} != {spec.digest}); "
                "choose another --out, or remove the journal"
            )
        if not resume:
            raise AtlasError(
                f"{jp} holds an interrupted sweep of this spec (its atlas {out.name} is gone); "
                "use --resume (resume=True) to complete it from the journal, or remove the "
                "journal to start over"
            )
    elif not resume:
        raise AtlasError(
            f"{out} already exists for this sweep; use --resume (resume=True) to complete it or "
            "remove it to start over"
        )
    return table


def _journal_digest(jp: Path) -> str | None:
    """The spec digest in a journal's first line; None if it has none readable."""
    try:
        with jp.open("rb") as fh:
            return json.loads(fh.readline()).get("spec_digest")
    except (OSError, ValueError, AttributeError):
        return None


def _what_differs(spec: SweepSpec, text: Any, tally: Any) -> str:
    """How the atlas's sweep (its spec ``text``) differs from ``spec``, key by key; its digest
    when its spec cannot be read."""
    from .spec import parse_spec

    try:
        stored = parse_spec(str(text), tally_text=None if tally is None else str(tally))
    except Exception:
        return f"its spec cannot be read here; this spec's digest is {spec.digest}"
    changes = [c.replace(" here,", " in this spec,").replace(" there", " in the atlas")
               for c in spec.differences(stored)]  # fmt: skip
    shown = "; ".join(changes[:4]) + (f"; and {len(changes) - 4} more" if len(changes) > 4 else "")
    return shown or f"spec digest {stored.digest}, this spec {spec.digest}"


def write_atlas(out: Path, table: fmt.AtlasTable) -> None:
    """``fmt.write``, an OS error (a full disk, a read-only file) named with the atlas and
    what to do: the journal beside it keeps every point, so nothing is lost."""
    try:
        fmt.write(out, table)
    except OSError as exc:
        raise AtlasError(
            f"{out}: cannot write the atlas ({_reason(exc)}); every point computed is kept in "
            f"{journal_path(out).name}: make room or fix the permission, then run again with "
            "--resume (resume=True)"
        ) from None


def _reason(exc: OSError) -> str:
    """An OS error's reason without its errno and h5py's wording around it."""
    if exc.errno is not None:
        return os.strerror(exc.errno)
    return str(exc)


def prepare(
    spec: SweepSpec, out: Path, *, resume: bool, params_json: str, version: str
) -> tuple[fmt.AtlasTable, int]:
    """Open or create the atlas for ``spec``; returns its table and how many points were done."""
    jp = journal_path(out)
    if out.exists() or jp.exists():
        table = read_existing(spec, out, resume=resume)
        if table is None:
            fmt.create(out, spec, params_json, version)
            table = fmt.AtlasTable(spec)
        replayed = table.apply_all(iter_journal(out, spec))
        if replayed or not out.exists():  # a complete atlas, resumed, is left as it is
            write_atlas(out, table)
        done = int(np.sum(table.status != fmt.STATUS["missing"]))
        return table, done
    fmt.create(out, spec, params_json, version)
    with jp.open("w") as fh:
        fh.write(json.dumps({"spec_digest": spec.digest}) + "\n")
        fh.flush()
        os.fsync(fh.fileno())
    return fmt.AtlasTable(spec), 0


def journal_hint(path: Path) -> str:
    """For an atlas missing or unreadable: what its journal holds, if there is one beside it
    (``--resume`` rebuilds the atlas from it)."""
    n = len(np.unique(journaled(path)))
    if not path.with_name(path.name + JOURNAL_SUFFIX).exists():
        return ""
    return (
        f"; but its journal, {path.name}{JOURNAL_SUFFIX}, holds {n} points of a sweep: "
        f"'pydrill sweep SPEC.toml --out {path} --resume' (its spec) rebuilds the atlas"
    )
