"""Checks of simulate's output request before the run (apart from simulate.py to keep it
short): the output must fit in memory, and its times be normal floats."""

from __future__ import annotations

import sys
from typing import Any


def _check_output_size(t_out: Any, n_out: int, dof: int) -> None:
    """Refuse, before the run, an output larger than this machine's memory: the state (2·dof − 1
    numbers) and its time at every output time, 8 bytes each. --dof 100000 --n-out 1000000
    (1.6 TB) ended in a traceback, "MemoryError: std::bad_alloc"."""
    import os

    times = n_out if t_out is None else len(t_out)
    size = 8.0 * times * (2 * dof)
    try:
        memory = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # not known here: nothing to compare with
        return
    if size > memory:
        given = f"n_out = {n_out}" if t_out is None else f"t_out of {times} times"
        raise ValueError(
            f"{given} is not allowed with dof = {dof}: its output ({times} times of "
            f"{2 * dof - 1} state values, 8 bytes each) would take {_bytes(size)}, more than this "
            f"machine's {_bytes(memory)} of memory; ask for fewer output times"
        )


def _check_normal_times(t_end: float, t_out: list[float] | None, n_out: int) -> None:
    """Refuse output times the core cannot tell from 0: it runs with subnormal numbers (below
    2.2e-308) flushed to zero, so t_end = 5e-324 s was judged "steady" from rest, and t_out
    = [0, 1e-320, 1] came back as times [0, 0, 1]."""
    tiny = sys.float_info.min
    if t_out is None and t_end / (n_out - 1) < tiny:
        raise ValueError(
            f"t_end = {t_end:g} is not allowed with n_out = {n_out}: its output times would be "
            f"{t_end / (n_out - 1):g} s apart, below the smallest normal float ({tiny:.3g}) "
            "the core computes with; need t_end >= (n_out - 1) * 2.2e-308 s"
        )
    for k, t in enumerate(t_out or ()):
        if 0 < t < tiny:
            raise ValueError(
                f"t_out[{k}] = {t:g} is not allowed: an output time is 0 or at least "
                f"{tiny:.3g} s (the smallest normal float, which the core computes with)"
            )


def _bytes(n: float) -> str:
    for unit in ("bytes", "kB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:.3g} {unit}"
        n /= 1000
    raise AssertionError  # (unreachable)
