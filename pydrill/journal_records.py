"""Whether a line of a sweep's journal is a point's record that can be replayed into its atlas.

A journal line is checked cheaply on every replay (``quick_problem``: the point, status and
message) and whole only when it fails to replay (``record_problem``), so that the replay of a
long journal stays fast.
"""

from __future__ import annotations

from typing import Any, TypeGuard

from . import atlas_format as fmt
from .atlas_check import show as _show
from .spec import SweepSpec


def is_int(v: Any, low: int, high: int) -> TypeGuard[int]:
    return isinstance(v, int) and not isinstance(v, bool) and low <= v <= high


def _is_name(v: Any, names: dict[str, int]) -> bool:
    return isinstance(v, str) and v in names


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _field_problem(name: str, v: Any, dtype: str) -> str | None:
    """What is wrong with the value ``v`` of a float (f8) or integer (i2, i4) field."""
    if v is None:
        return None
    if dtype.startswith("i"):
        bits = 8 * int(dtype[1:])
        if not is_int(v, -(2 ** (bits - 1)), 2 ** (bits - 1) - 1):
            return f"{name} = {_show(v)} is not an integer of {bits} bits"
    elif not _is_number(v):
        return f"{name} = {_show(v)} is not a number"
    return None


def quick_problem(rec: Any, size: int) -> str | None:
    """What makes a journal line's ``rec`` name no point of a grid of ``size``, or no status or
    message, or None: checked on every line (a negative or fractional index silently wrote
    another point; one past the grid was an IndexError; a message not text failed the
    atlas's write). The rest of a record is checked only if it fails to replay
    (:func:`record_problem`: checking all of every line would slow a replay 2.5 times)."""
    if not isinstance(rec, dict):
        return f"{_show(rec)} is not a point's record"
    i = rec.get("i")
    if not is_int(i, 0, size - 1):
        return f"point i = {_show(i)} is not allowed: an integer 0 ... {size - 1}"
    if not _is_name(rec.get("status"), fmt.STATUS):
        return f"status = {_show(rec.get('status'))} is not one of {', '.join(fmt.STATUS)}"
    if not isinstance(rec.get("message", ""), str):  # else a TypeError writing the atlas
        return f"message = {_show(rec['message'])} is not text"
    return None


def record_problem(rec: Any, spec: SweepSpec) -> str | None:
    """What makes a journal line's ``rec`` unfit to replay into ``spec``'s atlas, or None:
    a name or value of the wrong kind (a KeyError or TypeError from deep inside the replay)."""
    problem = quick_problem(rec, spec.size)
    if problem:
        return problem
    runs = rec.get("runs", {})
    if not isinstance(runs, dict):
        return f"runs = {_show(runs)} is not a table of runs"
    for init in spec.initials:
        run = runs.get(init)
        if run is None:
            continue
        if not isinstance(run, dict):
            return f"runs.{init} = {_show(run)} is not a run"
        if not _is_name(run.get("regime"), fmt.REGIMES):
            return f"runs.{init}.regime = {_show(run.get('regime'))} is not a regime"
        if not _is_name(run.get("caveat") or "", fmt.CAVEATS):
            return f"runs.{init}.caveat = {_show(run.get('caveat'))} is not a caveat"
        for name, (dtype, *_) in fmt.RUN_FIELDS.items():
            problem = _field_problem(f"runs.{init}.{name}", run.get(name), dtype)
            if problem:
                return problem
    stab = rec.get("stability")
    if stab:
        if not isinstance(stab, dict):
            return f"stability = {_show(stab)} is not a table"
        for name, (dtype, *_) in fmt.EQ_FIELDS.items():
            values = stab.get(name, [])
            if not isinstance(values, list):
                return f"stability.{name} = {_show(values)} is not a list"
            for v in values[: fmt.N_EQ]:
                problem = _field_problem(f"stability.{name}", v, dtype)
                if problem:
                    return problem
        eig = stab.get("eigenvalues", [])
        if not isinstance(eig, list) or not all(
            isinstance(row, list)
            and all(
                isinstance(pair, list) and len(pair) == 2 and all(map(_is_number, pair))
                for pair in row
            )
            for row in eig
        ):
            return f"stability.eigenvalues = {_show(eig)} is not lists of [real, imag] pairs"
    co = rec.get("coexistence")
    if co is not None and not (isinstance(co, bool) or is_int(co, -1, 1)):
        return f"coexistence = {_show(co)} is not one of true, false, null, -1, 0, 1"
    return None
