"""Checks of single values given to the Python API (shared by the model, simulate, the
analyses): a number or an integer as a Python value, refused by name with ``TypeError`` for a
wrong type, ``ValueError`` for a bad value; and ``Params.replace``'s check of a new chain
length. Apart from model.py (which re-exports them) to keep it short."""

from __future__ import annotations

import reprlib
from typing import Any

import numpy as np


def _show(value: Any) -> str:
    """``str 'abc'``: a value's type and a short repr, for a message."""
    return f"{type(value).__name__} {reprlib.repr(value)}"


def _plain(value: Any) -> Any:
    """A numpy scalar or 0-d array as the Python object it holds."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, np.generic):
        value = value.item()
    return value


def _number(name: str, value: Any, unit: str) -> float:
    """``value`` as a float: a Python or numpy real number or a 0-d array, not a bool, a
    string or a list (``TypeError`` naming ``name``)."""
    if type(value) is float:  # the common case, fast
        return value
    plain = _plain(value)
    if isinstance(plain, bool) or not isinstance(plain, (int, float)):
        raise TypeError(f"{name} must be a number ({unit}), got {_show(value)}")
    try:
        return float(plain)
    except OverflowError:  # an integer beyond any float
        raise ValueError(
            f"{name} = {reprlib.repr(plain)} is not allowed: beyond the range of a float ({unit})"
        ) from None


def _integer(name: str, value: Any, low: int, high: int, *, hint: str = "") -> int:
    """``value`` as an int in ``low ... high``: a Python or numpy integer or a 0-d array of
    one; ``TypeError`` for another type (a bool, or a float even of integer value: 3.0 was
    taken as a size and refused as a count, where one rule serves every integer argument),
    ``ValueError`` out of range, both naming ``name``."""
    plain = _plain(value)
    if isinstance(plain, bool) or not isinstance(plain, int):
        raise TypeError(f"{name} must be an integer, got {_show(value)}")
    if not low <= plain <= high:
        raise ValueError(
            f"{name} = {reprlib.repr(plain)} is not allowed: need an integer {low} ... {high}{hint}"
        )
    return int(plain)


def check_new_length(params: Any, changes: dict[str, Any]) -> None:
    """Refuse new inertias of another count than the string's without the springs to match:
    replace(inertias=[5 values]) on 4 inertias was refused as "stiffnesses has 3 entries: dof
    = 5 needs 4", blaming the lists kept for the one changed; say what changed the length, and
    what else a string of that length needs."""
    from . import _core

    try:
        n = len(changes["inertias"])
    except (KeyError, TypeError):  # inertias kept, or not a list: refused as they are
        return
    kept = [key for key in ("stiffnesses", "dampings") if key not in changes]
    if n == params.dof or not kept or n < 2:
        return
    build = (
        f"pydrill.preset({params.name!r}, dof={n})"
        if params.name in _core.preset_names()
        else f"pydrill.preset(NAME, dof={n}) or Tally.to_params(dof={n})"
    )
    raise ValueError(
        f"inertias has {n} entries, where the string has {params.dof}: a string of {n} "
        f"inertias needs {n - 1} stiffnesses and {n - 1} dampings, and replace() would keep "
        f"this one's {params.dof - 1}; give {' and '.join(kept)} of {n - 1} entries as well, "
        f"or build the {n}-inertia string with {build}"
    )
