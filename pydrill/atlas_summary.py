"""An atlas whole, counted: what ``pydrill.Atlas.summary`` returns and ``pydrill atlas info``
prints (points by status, regime and caveat, safe and coexistence points, and what a journal
beside the atlas holds that the atlas does not yet). Apart from atlas.py, whose queries read
points and slices, because only this reads every dataset through and the journal too."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import atlas_format as fmt
from .journal import JOURNAL_SUFFIX, journaled
from .spec_parts import part_of

if TYPE_CHECKING:
    from .atlas import Atlas
    from .spec import SweepSpec


def summary(atlas: Atlas) -> dict[str, Any]:
    """``atlas.summary()``: see there."""
    f = atlas._file()
    atlas.check()
    status = f["status"][...]
    codes = f["regime"][...]
    journal = atlas.path.with_name(atlas.path.name + JOURNAL_SUFFIX)
    regimes = {}
    for j, init in enumerate(atlas.initials):
        regimes[init] = {
            name: int(np.sum(codes[..., j] == code))
            for name, code in fmt.REGIMES.items()
            if np.any(codes[..., j] == code)
        }
    caveats = {}
    if "caveat" in f:
        notes = f["caveat"][...]
        for j, init in enumerate(atlas.initials):
            counts = {
                name: int(np.sum(notes[..., j] == code))
                for name, code in fmt.CAVEATS.items()
                if code and np.any(notes[..., j] == code)
            }
            if counts:
                caveats[init] = counts
    return {
        "path": str(atlas.path),
        "pydrill_version": atlas.version,
        "model": model(atlas.spec),
        # The digest the writer stored, which a --resume compares with its spec's; and the
        # digest this pydrill makes of the spec stored beside it. They differ when the file
        # was edited, or when the pydrill that wrote it made another model of that spec (the
        # points are that model's): info says so.
        "spec_digest": str(f.attrs["spec_digest"]),
        "spec_digest_here": atlas.spec.digest,
        "points": int(np.prod(atlas.shape)),
        "axes": {
            name: {"size": len(v), "min": v.min().item(), "max": v.max().item()}
            for name, v in atlas.axes.items()
        },
        "initial": list(atlas.initials),
        "status": {name: int(np.sum(status == code)) for name, code in fmt.STATUS.items()},
        "regimes": regimes,
        # None when stability was not recorded (see safe_region)
        "safe_points": (
            int(np.sum(atlas.safe_region())) if atlas.spec.record["stability"] else None
        ),
        "coexistence_points": int(np.sum(f["coexistence"][...] == 1)),
        # Judgements that carry a note, by start and kind (runs to simulate longer; a
        # run-away, fmt.FINAL_CAVEATS, is final)
        "caveats": caveats,
        # A journal beside the atlas: a sweep is running, or was stopped; what it holds
        # but the atlas does not yet is completed by --resume.
        "journal": str(journal) if journal.exists() else None,
        "journal_points": journal_only(atlas.path, status),
        # Made by 'pydrill atlas merge': its parts (file, pydrill_version, spec_digest,
        # values along the merged axis); None for an atlas a sweep wrote.
        "merged_from": merged_from(f),
        # Swept by 'pydrill sweep --part K/N' (its spec says so): {k, n, of}; else None.
        "part": part_of(atlas.spec.text),
    }


def merged_from(f: Any) -> list[dict[str, Any]] | None:
    """The parts an atlas was merged from (``atlas_merge``), or None."""
    import json

    text = f.attrs.get("merged_from")
    if text is None:
        return None
    try:
        parts = json.loads(text)
    except (TypeError, ValueError):  # written by hand, or damaged: say nothing of parts
        return None
    return parts if isinstance(parts, list) else None


def model(spec: SweepSpec) -> dict[str, Any]:
    """What string the atlas is of, held how: its name (a preset's, or the tally's), where it
    comes from, its inertias (None where a size or depth axis changes them), the model
    parameters and operating values held fixed (SI), and how long each start was simulated."""
    if spec.tally_text is not None:
        from .tally import parse_tally

        name, source = parse_tally(spec.tally_text).name, "tally"
    else:
        name, source = spec.preset, "preset"
    resized = {"dof", "pipes"} & set(spec.axes) or ("depth" in spec.axes and spec.dof is None)
    held = {k: v for k, v in spec.overrides.items() if k not in ("tally", "lump")}
    return {
        "string": name,
        "from": source,
        "inertias": None if resized else spec.params_at(spec.coords(0)).dof,
        "held": {**spec.fixed, **held},  # the operating values first
        "t_end": float(spec.simulation["t_end"]),
    }


def model_units(m: dict[str, Any]) -> dict[str, Any]:
    """The units of ``model(spec)``'s values, for a --json ``units`` table: each held value's
    (SI: N, N·m, m, a parameter's own) and the simulated time's."""
    from .atlas_grid import axis_unit

    return {"held": {name: axis_unit(name) for name in m["held"]}, "t_end": "s"}


def journal_only(path: Path, status: np.ndarray) -> int:
    """Points the journal of the atlas at ``path`` holds and the atlas does not yet: a running
    sweep's progress since its last flush, or what --resume takes back after a kill."""
    indices = journaled(path)
    indices = indices[(indices >= 0) & (indices < status.size)]
    missing = status.ravel()[indices] == fmt.STATUS["missing"]
    return len(np.unique(indices[missing]))
