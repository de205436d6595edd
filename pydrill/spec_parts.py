"""Part K of N of a sweep: every N-th value of its first axis from the K-th, for sweeps run
as separate jobs (a batch system's job array, several machines without one Dask cluster),
whose atlases ``pydrill atlas merge`` makes one: the whole spec's atlas, as one sweep would
write it. Every N-th value, not a run of consecutive ones: the parts then cost about the same
(a run could hold all the slow stick-slip points), and each part's atlas is already a coarser
map of the whole grid.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .spec import SweepSpec

_PART = re.compile(r"^\s*(\d+)\s*/\s*(\d+)\s*$")


def parse_part(text: str) -> tuple[int, int]:
    """``"K/N"`` as (K, N), 1 <= K <= N; ValueError naming what is allowed."""
    m = _PART.match(text)
    if not m:
        raise ValueError(
            f"{text!r} is not allowed: K/N, part K of N (e.g. 3/16), K and N whole numbers"
        )
    k, n = int(m.group(1)), int(m.group(2))
    if n < 1 or not 1 <= k <= n:
        raise ValueError(f"{text!r} is not allowed: K/N with N >= 1 and K in 1 ... N")
    return k, n


#: how a part's spec says which part it is (its first line, a comment spec_part writes)
_SAYS_PART = re.compile(r"^# Part (\d+) of (\d+) of (.+?): values ")


def part_of(text: str) -> dict[str, Any] | None:
    """Which part of which spec a spec's text is, as ``spec_part`` wrote it: ``{"k", "n",
    "of"}`` (``of``: the whole spec's file name), or None for any other spec."""
    m = _SAYS_PART.match(text)
    if m is None:
        return None
    return {"k": int(m.group(1)), "n": int(m.group(2)), "of": m.group(3)}


def spec_part(spec: SweepSpec, k: int, n: int, name: str = "the spec") -> SweepSpec:
    """Part ``k`` of ``n`` (1 <= k <= n) of ``spec``: every ``n``-th value of its first axis,
    from the ``k``-th (the parts differ in length by one value at most); everything else as
    in ``spec``. ``name`` (the spec's file) goes into the
    part's text, in a comment. ValueError for a ``k``, ``n`` not allowed, or ``n`` beyond the
    axis's values."""
    from .spec import parse_spec
    from .spec_toml import with_axis

    for label, v in (("k", k), ("n", n)):
        if isinstance(v, bool) or not isinstance(v, int | np.integer):
            raise TypeError(f"{label} = {v!r} is not allowed: a whole number")
    if n < 1 or not 1 <= k <= n:
        raise ValueError(f"part {k} of {n} is not allowed: n >= 1 and k in 1 ... n")
    axis, values = next(iter(spec.axes.items()))
    if n > len(values):
        raise ValueError(
            f"{n} parts of the first axis, {axis}, which has {len(values)} value"
            f"{'s' * (len(values) != 1)}: at most {len(values)} parts (it is the axis shared out; "
            "put the longest first in [axes] to share it among more)"
        )
    kept = values[k - 1 :: n]
    header = (
        f"Part {k} of {n} of {name}: values {k}, {k + n}, {k + 2 * n}, ... of {axis} "
        f"({len(kept)} of its {len(values)}, in SI units), by 'pydrill sweep --part'. "
        "'pydrill atlas merge' makes the parts' atlases one."
    )
    text = with_axis(spec.text, axis, [v.item() for v in kept], header)
    return parse_spec(text, spec.tally_text)


def part_hint(spec: SweepSpec, text: Any, digest: Any) -> str:
    """``"; it is part K of N of this spec: ..."`` when an atlas whose spec is ``text`` (with
    ``digest``, as stored) is that part of ``spec``: a part's atlas resumed without its
    ``--part`` read as another sweep's. ``""`` otherwise."""
    part = part_of(str(text))
    if part is None:
        return ""
    k, n = part["k"], part["n"]
    ours = part_of(spec.text)  # resumed as another part of the same spec (--part 2/2 for 1/2)?
    try:
        theirs = digest.decode() if isinstance(digest, bytes) else str(digest)
        if ours is not None:
            return _other_part(spec, ours, part, str(text), theirs)
        if theirs != spec.part(k, n).digest:
            return ""
    except (ValueError, UnicodeDecodeError):  # this first axis has under n values: not it
        return ""
    return (
        f"; it is part {k} of {n} of this spec: resume it as that part (--part {k}/{n}; from "
        f"Python, spec.part({k}, {n}))"
    )


def _other_part(spec: SweepSpec, ours: dict, part: dict, text: str, digest: str) -> str:
    """``part_hint`` for ``spec``, part ``ours`` of a spec, and an atlas of its part ``part``
    (its spec ``text``, ``digest``): another part of the same spec when both say they are
    parts of as many and the atlas's spec is ``spec`` but for its share of the first axis."""
    import tomllib

    from .spec import SpecError, parse_spec
    from .spec_toml import with_axis

    k, n = part["k"], part["n"]
    if ours["n"] != n or ours["k"] == k:  # (the file's name may differ: the content is checked)
        return ""
    axis = next(iter(spec.axes))
    try:
        values = tomllib.loads(text)["axes"][axis]
        if parse_spec(with_axis(spec.text, axis, values), spec.tally_text).digest != digest:
            return ""
    except (tomllib.TOMLDecodeError, KeyError, TypeError, SpecError):
        return ""
    return (
        f"; it is part {k} of {n} of {part['of']}, not part {ours['k']}: resume it as that "
        f"part (--part {k}/{n}; from Python, the whole spec's .part({k}, {n}))"
    )


def part_option(text: str) -> str:
    """``" --part K/N"`` for an atlas swept as a part (its spec ``text`` says so, see
    ``part_of``), else ``""``: what a command that resumes it must add (without it, --resume
    is refused: the whole spec is another sweep)."""
    part = part_of(text)
    return "" if part is None else f" --part {part['k']}/{part['n']}"
