"""An atlas's journal, and the atlas's creation or reopening for a sweep.

The journal (``ATLAS.h5.journal``) is what makes a sweep safe to kill: its first line names
the sweep (the spec's digest) and the layout of its lines, then one JSON line per finished
point (:mod:`journal_lines`), appended and flushed to disk a batch at a time by the client,
before the point reaches the HDF5 file. ``prepare``
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
from .atlas_check import layout_problem
from .atlas_check import show as _show
from .atlas_heap import heap_problem
from .journal_lines import RUN_KEYS, STABILITY_KEYS, Layout, header, line
from .journal_records import is_int, quick_problem, record_problem
from .spec import SweepSpec
from .spec_parts import part_hint

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
    """The records of ``path``'s journal, one at a time: a journal holds about 0.5 kB a point,
    and its records as Python objects 5 kB (a list of a 74000-point journal's took 400 MB; a
    million points' would have taken 5 GB on top of the table). A last line cut by a kill (or
    Ctrl-C) mid-write is dropped and, with ``repair``, cut off the file once all are read, so
    that the next append starts on a line of its own; its points are simply computed again."""
    jp = journal_path(path)
    if not jp.exists():
        return
    good = 0  # bytes up to the end of the last whole line
    size = spec.size
    layout = Layout({})
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
                digest = data.get("spec_digest") if isinstance(data, dict) else None
                if digest != spec.digest:
                    raise AtlasError(
                        f"{jp} belongs to another sweep (spec digest {digest} != {spec.digest})"
                    )
                try:
                    layout = Layout(data)
                except ValueError as exc:
                    raise AtlasError(
                        f"{jp}, line 1, is damaged ({exc}); remove the journal to start the "
                        "sweep over"
                    ) from None
                continue
            data = layout.record(data)
            problem = quick_problem(data, size)
            if problem:
                raise AtlasError(
                    f"{jp}, line {n + 1}, is damaged ({problem}); remove the journal "
                    "to start the sweep over"
                )
            yield data
    if not repair:
        pass
    elif good == 0:  # not even the header survived
        jp.write_text(header(spec.digest))
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
            i = None
            start = 1 if raw.startswith(b"[") else 6 if raw.startswith(b'{"i": ') else 0
            if start:  # a line of either layout, as run_sweep writes them
                with contextlib.suppress(ValueError):  # '"3"', 'NaN', no comma: not ours
                    i = int(raw[start : raw.index(b",", start)])
            if i is None:  # not as written by run_sweep: parse it whole
                with contextlib.suppress(ValueError, KeyError, TypeError, IndexError):
                    data = json.loads(raw)
                    i = data[0] if isinstance(data, list) else data["i"]
            # an index the replay would refuse is no point (nor an OverflowError for numpy)
            if is_int(i, 0, 2**63 - 1):
                found.append(i)
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
            f"{out} is a directory; give the atlas a file name, e.g. {out / 'atlas.h5'}"
        )
    if out.exists():
        if not _hdf5(out):  # (a CSV at --out was called "damaged (not a readable HDF5 atlas)")
            raise AtlasError(f"{out} is not an atlas (not an HDF5 file); choose another out=PATH")
        try:
            import h5py

            # Before HDF5 reads a text attribute: a damaged global heap hangs it (atlas_heap).
            problem = heap_problem(out)
            if problem:
                raise _Damaged(problem)
            with h5py.File(out, "r") as f:
                if not _is_text(f.attrs.get("format"), fmt.FORMAT):
                    raise AtlasError(f"{out} exists and is not a pydrill atlas; not touching it")
                digest = f.attrs.get("spec_digest")
                theirs = (f.attrs.get("spec"), f.attrs.get("tally") or None)
                if not _is_text(digest, spec.digest):
                    raise AtlasError(
                        f"{out} holds a different sweep "
                        f"({_what_differs(spec, *theirs, digest, f.attrs.get('pydrill_version'))})"
                        f"{part_hint(spec, theirs[0], digest)}; choose another out=PATH or "
                        "remove it"
                    )
                problem = damage(f, spec)
                if problem:
                    raise _Damaged(problem)
            table = fmt.read_table(out, spec)
        except AtlasError:
            raise
        # RuntimeError: h5py's for a damaged B-tree or checksum; TypeError, AttributeError: a
        # dataset replaced by a group, an attribute of another type
        except (OSError, KeyError, ValueError, TypeError, AttributeError, RuntimeError) as exc:
            if not jp.exists() and out.stat().st_size == 0:
                raise AtlasError(
                    f"{out} is empty (0 bytes), not an atlas (nothing was ever written to "
                    "it), and has no journal to rebuild it from; remove it to sweep anew, "
                    "or choose another out=PATH"
                ) from None
            if not jp.exists():
                what = str(exc) if isinstance(exc, _Damaged) else "not a readable HDF5 atlas"
                # What to do next, as every other refusal here says it: nothing can mend it.
                raise AtlasError(
                    f"{out} is damaged ({what}) and has no journal to rebuild it from; remove "
                    "it to sweep anew, or choose another out=PATH"
                ) from None
    if not out.exists():
        # A journal alone (the atlas was removed, or a kill came before it was made): say so,
        # and whose it is, before anything is created beside it.
        digest = _journal_digest(jp)
        if digest is not None and digest != spec.digest:
            raise AtlasError(
                f"{jp} belongs to another sweep (spec digest {digest} != {spec.digest}); "
                "choose another out=PATH, or remove the journal"
            )
        if not resume:
            raise AtlasError(
                f"{jp} holds an interrupted sweep of this spec (its atlas {out.name} is gone); "
                "use resume=True to complete it from the journal, or remove the journal to "
                "start over"
            )
    elif not resume:
        raise AtlasError(
            f"{out} already exists for this sweep; use resume=True to complete it or remove it "
            "to start over"
        )
    return table


def _hdf5(path: Path) -> bool:
    """Whether ``path`` may be an HDF5 file: its signature at 0, 512, 1024, … bytes (where
    HDF5 looks for it), or too short to tell (a truncated atlas: damaged, not another file)."""
    import h5py

    try:
        return path.stat().st_size < 8 or bool(h5py.is_hdf5(path))
    except OSError:  # unreadable: h5py says why below
        return True


class _Damaged(ValueError):
    """An atlas whose layout is not the one its spec makes (:func:`layout_problem`)."""


def damage(f: Any, spec: SweepSpec) -> str | None:
    """What is wrong with the open atlas ``f`` (an ``h5py.File`` whose spec_digest is
    ``spec``'s), or None: a layout that is not the one ``spec`` makes, or a spec attribute
    that is not that sweep's."""
    return layout_problem(f, spec) or _spec_problem(
        spec, f.attrs.get("spec"), f.attrs.get("tally") or None
    )


def _spec_problem(spec: SweepSpec, text: str, tally: str | None) -> str | None:
    """What is wrong with the spec attribute (``text``, and its ``tally``) of an atlas whose
    spec_digest is ``spec``'s, or None: a text that is not the sweep of that digest was put
    there after pydrill wrote both (its points were computed for the digest's sweep, and a
    reader of the atlas would take them for the text's)."""
    from .spec import SpecError, parse_spec

    try:
        if parse_spec(text, tally_text=tally).digest == spec.digest:
            return None  # (the same sweep, perhaps formatted otherwise)
    except SpecError:
        pass
    return (
        f"its spec attribute was changed after pydrill wrote it: its spec_digest is this "
        f"spec's, {spec.digest}, but the spec it holds differs: {_what_differs(spec, text, tally)}"
    )


def _is_text(value: Any, text: str) -> bool:
    """``value == text`` for an attribute of any type (an array's == is no bool)."""
    return isinstance(value, str) and value == text


def _journal_digest(jp: Path) -> str | None:
    """The spec digest in a journal's first line; None if it has none readable."""
    try:
        with jp.open("rb") as fh:
            return json.loads(fh.readline()).get("spec_digest")
    except (OSError, ValueError, AttributeError):
        return None


def _what_differs(
    spec: SweepSpec, text: Any, tally: Any, digest: Any = None, version: Any = None
) -> str:
    """How the atlas's sweep (its spec ``text``) differs from ``spec``, key by key; its digest
    when its spec cannot be read; that its ``digest`` is not its spec's if they are the same
    (the atlas written by pydrill ``version``)."""
    from .spec import parse_spec

    try:
        stored = parse_spec(str(text), tally_text=None if tally is None else str(tally))
    except Exception:
        return f"its spec cannot be read here; this spec's digest is {spec.digest}"
    changes = [c.replace(" here,", " in this spec,").replace(" there", " in the atlas")
               for c in spec.differences(stored)]  # fmt: skip
    shown = "; ".join(changes[:4]) + (f"; and {len(changes) - 4} more" if len(changes) > 4 else "")
    if not shown and stored.digest == spec.digest:
        # Either the attribute was edited, or the pydrill that wrote it built another model
        # from the same text: a digest covers the model a spec makes, and the rules that make
        # it (how a tally is reduced to dof inertias, say) can change between versions.
        return (
            f"its spec is this one, but its spec_digest {_show(digest)} is not that spec's "
            f"({spec.digest}): the file was changed after pydrill wrote it, or the pydrill that "
            f"wrote it (version {_show(version)}) made another model of this spec; sweep again "
            "into another out=PATH"
        )
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
            "resume=True"
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
        existing = read_existing(spec, out, resume=resume)
        table = fmt.AtlasTable(spec) if existing is None else existing
        try:
            replayed = table.apply_all(iter_journal(out, spec))
        except (KeyError, TypeError, ValueError, IndexError, AttributeError, OverflowError) as exc:
            # A record the table cannot hold: the journal's fault, named with its line, not a
            # traceback from inside the replay. Nothing has been written yet.
            raise _damaged_record(jp, spec, exc) from None
        if existing is None:  # created once the journal has replayed: a damaged one leaves none
            fmt.create(out, spec, params_json, version)
        if replayed or not out.exists():  # a complete atlas, resumed, is left as it is
            write_atlas(out, table)
        if jp.exists():
            _in_this_layout(out, spec)
        done = int(np.sum(table.status != fmt.STATUS["missing"]))
        return table, done
    fmt.create(out, spec, params_json, version)
    with jp.open("w") as fh:
        fh.write(header(spec.digest))
        fh.flush()
        os.fsync(fh.fileno())
    return fmt.AtlasTable(spec), 0


def _in_this_layout(out: Path, spec: SweepSpec) -> None:
    """A journal that a sweep will append to, in the layout of the lines it appends: one
    written by an earlier pydrill (lines as whole objects, or another order of values) is
    written again, its records as they were, to a file beside it that then replaces it
    (once; a kill meanwhile leaves the old journal whole)."""
    jp = journal_path(out)
    with jp.open("rb") as fh:
        try:
            layout = Layout(json.loads(fh.readline()))
        except (ValueError, AttributeError):  # read_existing and the replay refused it first
            return
    if layout.runs == RUN_KEYS and layout.stability == STABILITY_KEYS:
        return
    tmp = rewrite_path(jp)
    with tmp.open("w") as fh:
        fh.write(header(spec.digest))
        for rec in iter_journal(out, spec, repair=False):
            fh.write(line(rec))
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, jp)


def rewrite_path(jp: Path) -> Path:
    """Where :func:`_in_this_layout` writes a journal again before it replaces ``jp``."""
    return jp.with_name(jp.name + ".new")


def _damaged_record(jp: Path, spec: SweepSpec, exc: Exception) -> AtlasError:
    """The error for a journal whose replay failed with ``exc``: its first line that
    :func:`record_problem` refuses, found by reading it again (once, on failure only)."""
    if not jp.exists():  # (the atlas's own table failed: read_existing checks its layout)
        return AtlasError(f"cannot replay into {jp.with_suffix('')}: {type(exc).__name__}: {exc}")
    with jp.open("rb") as fh:
        try:
            layout = Layout(json.loads(fh.readline()))
        except (ValueError, AttributeError):
            layout = Layout({})
        for n, raw in enumerate(fh, start=2):
            try:
                problem = record_problem(layout.record(json.loads(raw)), spec)
            except ValueError:
                break  # a last line cut by a kill: the replay skipped it
            if problem:
                return AtlasError(
                    f"{jp}, line {n}, is damaged ({problem}); remove the journal "
                    "to start the sweep over"
                )
    return AtlasError(
        f"{jp} holds a record that cannot be replayed ({type(exc).__name__}: {exc}); remove "
        "the journal to start the sweep over"
    )


def empty_file(path: Path) -> str:
    """The refusal of an atlas file of 0 bytes (touched, or made by a shell's ``>``), which
    holds nothing: "truncated or corrupt?" and "damaged" sent the user looking for damage.
    What to do: its journal's rebuild, if there is one, else sweep into it anew."""
    hint = journal_hint(path)
    if hint:
        return f"{path} is empty (0 bytes), not an atlas" + hint
    return (
        f"{path} is empty (0 bytes), not an atlas: nothing was ever written to it; give an "
        f"atlas a sweep wrote, or remove it and sweep into it (pydrill sweep SPEC.toml --out "
        f"{path})"
    )


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
