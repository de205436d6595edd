"""Atlases of one study made in parts, merged into one: the grid split along an axis (parts
run as separate jobs on several machines or in a batch system's job array, a range added
later).

The parts must be the same sweep but for one axis's values, which must not overlap; the
merged atlas holds that axis's values in increasing order and every point as its part holds
it (done, failed with its message, or missing). Its spec is the parts' with that axis as a
list, so the merged atlas is the atlas one sweep over the whole grid makes: of the same
spec digest (``pydrill sweep WHOLE.toml --resume`` takes it as its own), and the same data.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import atlas_format as fmt
from .journal import AtlasError, journal_path
from .spec import SweepSpec, parse_spec


@dataclass(frozen=True)
class MergeReport:
    """What :func:`merge_atlases` wrote."""

    path: Path  #: the merged atlas
    parts: list[Path]  #: the atlases merged, in the order given
    axis: str  #: the axis they were merged along
    values: int  #: its values in the merged atlas
    points: int  #: points of the merged grid
    status: dict[str, int] = field(default_factory=dict)  #: points done, failed, missing
    spec_text: str = ""  #: the merged atlas's sweep spec (TOML)
    span: tuple[float, float] = (0.0, 0.0)  #: the merged axis's first and last values (SI)


def merge_atlases(
    parts: Sequence[str | Path],
    out: str | Path,
    *,
    spec_out: str | Path | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> MergeReport:
    """Merge the atlases ``parts`` (two or more; the same sweep but for the values of one
    axis, which do not overlap) into a new atlas ``out``; ``spec_out``, if given, receives its
    sweep spec (TOML: to ``--resume`` points still missing, or to sweep it again).
    ``progress(points, total)`` is called as each part is read and once the atlas is written,
    with the points just done out of a ``total`` of twice the merged grid (read, written).

    Raises ``AtlasError`` for a part that cannot be read (missing, damaged, not an atlas, its
    sweep still running or stopped: a journal beside it) and ``ValueError`` for parts that
    cannot be merged (naming what differs, or a value two parts share), for ``out`` that
    exists, and for a merge that would not fit in memory. Nothing is written unless the
    whole merge succeeds."""
    from . import __version__
    from .atlas import Atlas
    from .atlas_lock import writer_lock
    from .spec_parts import part_option
    from .sweep import model_json

    if isinstance(parts, str | bytes | os.PathLike):  # each of its characters taken for a file
        raise TypeError(
            f"parts must be a list of atlas paths (e.g. ['part1.h5', 'part2.h5']), got one "
            f"path, {os.fsdecode(parts)!r}; the merged atlas is the second argument, out"
        )
    paths = [Path(p) for p in parts]
    if len(paths) < 2:
        raise ValueError(f"give two or more atlases to merge ({len(paths)} given)")
    out, spec_path = Path(out), None if spec_out is None else Path(spec_out)
    seen: dict[Path, Path] = {}
    for p in paths:
        if p.resolve() in seen:
            first = seen[p.resolve()]
            also = "" if str(first) == str(p) else f" (as {first} and as {p})"
            raise ValueError(f"{p} is given twice{also}: each part once")
        seen[p.resolve()] = p
    for target, what in ((out, "the merged atlas"), (spec_path, "its spec")):
        if target is None:
            continue
        if target.resolve() in seen:
            raise ValueError(f"{target}, where {what} would go, is one of the parts")
        if target.exists() or journal_path(target).exists():
            raise ValueError(
                f"{target} exists: give another path for {what}, or remove it first "
                "(a merge never overwrites a file)"
            )
    if spec_path is not None and spec_path.resolve() == out.resolve():
        raise ValueError(f"{out}: the atlas and its spec need two paths")

    specs: list[SweepSpec] = []
    versions: list[str] = []
    for p in paths:
        if journal_path(p).exists():
            option = ""  # a part (what is merged) resumes only with its --part
            with contextlib.suppress(AtlasError, OSError, ValueError):
                with Atlas(p) as stopped:
                    option = part_option(stopped.spec.text)
            raise AtlasError(
                f"{p}: its sweep is running or was stopped (its journal "
                f"{journal_path(p).name} is beside it); finish it first: 'pydrill sweep "
                f"SPEC.toml{option} --out {p} --resume'"
            )
        with Atlas(p) as atlas:
            atlas.check()  # codes read whole: nothing that is no regime passes into the merge
            written = str(atlas._file().attrs.get("spec_digest", ""))
            if written != atlas.spec.digest:
                # Its points are not this spec's: merged, they would pass for them.
                raise AtlasError(
                    f"{p}: its spec makes digest {atlas.spec.digest} in this pydrill "
                    f"({__version__}), but the atlas was "
                    f"written as {written or 'no digest'}: the file was changed after pydrill "
                    f"wrote it, or pydrill {atlas.version} made another model of this spec "
                    "(its points are of that model); sweep that part again to merge it"
                )
            specs.append(atlas.spec)
            versions.append(atlas.version)
    axis = _merge_axis(paths, specs)
    values = np.concatenate([s.axes[axis] for s in specs])
    _no_overlap(paths, specs, axis, values)
    order = np.argsort(values, kind="stable")
    names = ", ".join(p.name for p in paths)
    text = _spec_text(specs[0], axis, values[order], names)
    merged = parse_spec(text, specs[0].tally_text)
    for p, s in zip(paths, specs, strict=True):  # the spec written reads back as meant
        extra = [d for d in merged.differences(s) if not d.startswith(f"axes.{axis}:")]
        if extra or not np.array_equal(merged.axes[axis], values[order]):
            raise RuntimeError(f"pydrill wrote a merged spec that differs from {p}'s: {extra}")
    _check_memory(merged, specs)

    table = fmt.AtlasTable(merged)
    at = list(merged.axes).index(axis)
    # Each part's values' places along the merged axis: a part is read, put there and let go
    # (memory: the merged table and one part, not every part at once).
    rank = np.empty(len(values), dtype=np.intp)
    rank[order] = np.arange(len(values))
    starts = np.cumsum([0] + [len(s.axes[axis]) for s in specs])
    merged_columns = table.columns()
    for k, (p, s) in enumerate(zip(paths, specs, strict=True)):
        try:
            part = fmt.read_table(p, s)
        except (OSError, KeyError, ValueError, RuntimeError) as exc:
            raise AtlasError(f"{p} is damaged or incomplete: {exc}") from None
        where = (slice(None),) * at + (rank[starts[k] : starts[k + 1]],)
        for name, column in part.columns().items():
            merged_columns[name][where] = column
        del part
        if progress is not None:
            progress(s.size, 2 * merged.size)

    with writer_lock(out):
        if out.exists() or journal_path(out).exists():  # made meanwhile: still not ours
            raise ValueError(f"{out} exists now: give another path, or remove it first")
        part_file = out.with_name(f".{out.name}.{secrets.token_hex(4)}.part")
        spec_written = False
        try:
            fmt.create(part_file, merged, model_json(merged), __version__)
            fmt.write(part_file, table)
            _note_parts(part_file, paths, specs, versions, axis)
            if spec_path is not None:
                _write_new(spec_path, text)  # (a file made there meanwhile: FileExistsError)
                spec_written = True
            os.replace(part_file, out)
        except BaseException:
            part_file.unlink(missing_ok=True)
            if spec_written and spec_path is not None:  # ours, of an atlas not there
                with contextlib.suppress(OSError):
                    spec_path.unlink()
            raise
    if progress is not None:
        progress(merged.size, 2 * merged.size)
    counts = {
        k: int(np.count_nonzero(table.status == fmt.STATUS[k]))
        for k in ("done", "failed", "missing")
    }
    ends = (values[order[0]].item(), values[order[-1]].item())
    return MergeReport(out, paths, axis, len(values), merged.size, counts, text, ends)


def _check_memory(merged: SweepSpec, parts: list[SweepSpec]) -> None:
    """Refuse, before reading the parts, a merge that would not fit in memory now: the merged
    table and a part's are held together."""
    import psutil  # a dependency of distributed's

    from .sweep_plan import memory_bytes

    need = memory_bytes(merged) + max(map(memory_bytes, parts))
    free = psutil.virtual_memory().available
    if need > free:
        raise ValueError(
            f"merging into an atlas of {merged.size} points needs about {need / 1e9:.1f} GB "
            f"of memory (the merged atlas and its largest part, read whole), and "
            f"{free / 1e9:.1f} GB is available: merge where there is more memory"
        )


def _merge_axis(paths: list[Path], specs: list[SweepSpec]) -> str:
    """The one axis the parts differ in; ValueError naming any other difference."""
    first = specs[0]
    axis = None
    for p, s in zip(paths[1:], specs[1:], strict=True):
        if list(s.axes) != list(first.axes):
            raise ValueError(
                f"{paths[0]} and {p} have other axes ({' x '.join(first.axes)} against "
                f"{' x '.join(s.axes)}): atlases merge along one axis of the same grid"
            )
        found = first.differences(s)
        axes = {d.split(":")[0].removeprefix("axes.") for d in found if d.startswith("axes.")}
        others = [d for d in found if not d.startswith("axes.")]
        if others:
            raise ValueError(
                f"{paths[0]} and {p} are different sweeps, not parts of one: "
                + "; ".join(others)
                + " (the parts of a merge differ only in one axis's values)"
            )
        if not axes:
            raise ValueError(f"{paths[0]} and {p} are the same sweep (same spec): nothing to merge")
        if len(axes) > 1:
            raise ValueError(
                f"{paths[0]} and {p} differ along {' and '.join(sorted(axes))} ("
                + "; ".join(d for d in found if d.startswith("axes."))
                + "): a merge joins parts along one axis; merge along one of them first, then "
                "those merged along the other"
            )
        if axis is not None and axes != {axis}:
            (other,) = axes
            raise ValueError(
                f"{paths[0]} and {paths[1]} differ along {axis}, {paths[0]} and {p} along "
                f"{other}: a merge joins parts along one axis; merge those at each {other} "
                f"along {axis} first, then the merged ones along {other}"
            )
        axis = axes.pop()
    assert axis is not None
    return axis


def _no_overlap(paths: list[Path], specs: list[SweepSpec], axis: str, values: np.ndarray) -> None:
    """ValueError naming a value of ``axis`` that two parts share (or one part twice)."""
    from .atlas_grid import with_unit

    owner = np.repeat(np.arange(len(specs)), [len(s.axes[axis]) for s in specs])
    order = np.argsort(values, kind="stable")
    same = np.flatnonzero(values[order][1:] == values[order][:-1])
    if same.size:
        i, j = owner[order[same[0]]], owner[order[same[0] + 1]]
        shown = with_unit(axis, values[order[same[0]]].item())
        where = f"both {paths[i]} and {paths[j]}" if i != j else f"{paths[i]} twice"
        raise ValueError(
            f"{axis} = {shown} is in {where}: the parts of a merge must not share a grid "
            "value (which point would the atlas keep?)"
        )


def _spec_text(spec: SweepSpec, axis: str, values: np.ndarray, names: str) -> str:
    from .spec_toml import with_axis

    return with_axis(
        spec.text,
        axis,
        [v.item() for v in values],
        f"Merged by 'pydrill atlas merge' from {names}, along {axis} (its values in SI units).",
    )


def _note_parts(
    path: Path, paths: list[Path], specs: list[SweepSpec], versions: list[str], axis: str
) -> None:
    """Where the atlas came from: ``source`` says merged, ``merged_from`` (JSON) lists the
    parts (file name, the pydrill that wrote it, spec digest, values of ``axis``)."""
    import json

    import h5py

    with h5py.File(path, "r+") as f:
        source = str(f.attrs["source"]).removesuffix(" (pydrill sweep)")
        f.attrs["source"] = f"{source} (pydrill atlas merge of {len(paths)} atlases)"
        f.attrs["merged_from"] = json.dumps(
            [
                {
                    "file": p.name,
                    "pydrill_version": v,
                    "spec_digest": s.digest,
                    "values": len(s.axes[axis]),
                }
                for p, s, v in zip(paths, specs, versions, strict=True)
            ]
        )


def _write_new(path: Path, text: str) -> None:
    """``text`` into a file that must not exist yet."""
    with open(path, "x", encoding="utf-8") as fh:
        fh.write(text)
