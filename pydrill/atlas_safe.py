"""The safe operating windows of an atlas: along one axis (W_ob by default), the runs of grid
points where the bit drills steadily from every start and the fastest steady state is stable,
for each value of the other axes. What a driller asks of a regime map ("at 9 kN·m, which
weights on bit are safe?"), answered from the grid without drawing it.

A window is given by its first and last safe grid points: the true edges lie between those
and their unsafe neighbours, within one grid step. A point not computed (missing, failed) is
not safe, so it ends a window; each row counts them, so that a gap is not taken for danger.
Nor does a window run over 0 (a torque axis of both signs): u = 0 is stuck, between the
grid points either side of it. A failed point (the solver gave up) is counted apart from
a missing one (not computed yet, until the sweep is resumed)."""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from . import atlas_format as fmt
from .atlas_grid import not_an_axis

if TYPE_CHECKING:
    from .atlas import Atlas


@dataclass(frozen=True)
class SafeRow:
    """The safe windows along one axis at one value of every other axis (SI)."""

    at: dict[str, float | int]  #: the other axes' grid values
    windows: list[tuple[float, float]]  #: first and last safe grid value of each run
    safe: int  #: safe points along the axis
    points: int  #: points along the axis
    not_done: int  #: of them, missing or failed (not safe, for want of a result)
    #: of those not done, failed: computed, and the solver gave up (the rest are missing, not
    #: computed yet); "not computed" of a failed point sent the user to resume a sweep that
    #: had done all it could
    failed: int = 0


def default_along(atlas: Atlas) -> str:
    """W_ob where the atlas sweeps it (the driller's question), else its first axis."""
    return "wob" if "wob" in atlas.axes else next(iter(atlas.axes))


def safe_windows(
    atlas: Atlas, along: str | None = None, at: dict[str, Any] | None = None
) -> list[SafeRow]:
    """``Atlas.safe_windows``: see there."""
    along = default_along(atlas) if along is None else along  # ("" was taken for None)
    names = list(atlas.axes)
    if not isinstance(along, str):
        raise TypeError(f"along must be an axis's name ({', '.join(names)}) or None, got {along!r}")
    if along not in names:
        raise not_an_axis(along, names)
    at = dict(at or {})
    if along in at:
        raise ValueError(f"{along} is the axis the windows run along; it cannot also be held")
    unknown = sorted(set(at) - set(names))
    if unknown:
        raise not_an_axis(unknown[0], names)
    safe = atlas.safe_region()  # refuses an atlas without stability
    status = atlas._file()["status"][...]
    done, failed = status == fmt.STATUS["done"], status == fmt.STATUS["failed"]
    # Each other axis: the grid point nearest its held value, or every one of them.
    choices: list[list[int]] = []
    for name in names:
        if name == along:
            choices.append([-1])
        elif name in at:
            probe = {n: float(v[0]) for n, v in atlas.axes.items()}
            probe[name] = at[name]
            choices.append([atlas.index("nearest", **probe)[names.index(name)]])
        else:
            choices.append(list(range(len(atlas.axes[name]))))
    values = atlas.axes[along]
    order = np.argsort(values, kind="stable")  # windows run over increasing values
    # Where the grid jumps over 0 (torque -8.3 to 8.3: the string turned the other way), two
    # windows, not one: u = 0 between them is stuck, whatever the grid points either side say.
    ends = np.sign(values[order])
    across = {k for k in range(1, len(order)) if ends[k - 1] * ends[k] < 0}
    axis = names.index(along)
    rows = []
    for pick in itertools.product(*choices):
        index = tuple(slice(None) if k == axis else i for k, i in enumerate(pick))
        ok, computed = safe[index][order], done[index][order]
        runs = []
        start = None
        for k, good in enumerate([*ok.tolist(), False]):  # a sentinel closes the last run
            if start is not None and (not good or k in across):
                runs.append((values[order[start]].item(), values[order[k - 1]].item()))
                start = None
            if good and start is None:
                start = k
        held = {n: atlas.axes[n][i].item() for n, i in zip(names, pick, strict=True) if i >= 0}
        rows.append(
            SafeRow(
                at=held,
                windows=runs,
                safe=int(ok.sum()),
                points=len(values),
                not_done=int((~computed).sum()),
                failed=int(failed[index].sum()),
            )
        )
    return rows


def criterion(initials: Sequence[str]) -> str:
    """What "safe" means for an atlas of these starts, in words."""
    starts = " and from ".join(initials)
    return f"steady from {starts}, and the fastest steady state stable"
