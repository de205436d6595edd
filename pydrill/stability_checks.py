"""Checks of the stability functions' numbers, going in (``_checked``: finite, in range) and
coming out of the core (``_finite``: not overflowed), and the memory a grid takes
(``_check_grid_memory``). Apart from stability.py to keep it short;
``pydrill.window`` takes ``_checked`` too."""

from __future__ import annotations

import reprlib

import numpy as np
from numpy.typing import ArrayLike, NDArray


def _checked(name: str, value: ArrayLike, low: float, strict: bool) -> NDArray[np.float64]:
    """``value`` as a float array, every element finite and > ``low`` (>= with not
    ``strict``); else a TypeError (not numbers) or ValueError naming ``name`` and the value."""
    a = np.asarray(value)
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{name} = {value!r} is not allowed: must be a number or an array of them")
    a = a.astype(float, copy=False)
    ok = np.isfinite(a) & ((a > low) if strict else (a >= low))
    if not np.all(ok):
        allowed = f"must be a finite number {'>' if strict else '>='} {low:g}"
        if a.ndim == 0:
            raise ValueError(f"{name} = {float(a):g} is not allowed: {allowed}")
        where = np.unravel_index(int(np.argmin(ok)), a.shape)
        at = ", ".join(map(str, where))
        raise ValueError(f"{name}[{at}] = {float(a[where]):g} is not allowed: each {allowed}")
    return a


def _finite(name: str, value: object, what: str, result: list[float]) -> NDArray[np.float64]:
    """The core's ``result`` as an array, refused by ``name`` where it has overflowed: a delta
    of 1e308 gave a Jacobian of inf (and eigenvalues a LinAlgError), 1e300 coefficients
    Hurwitz determinants of inf and nan."""
    a = np.array(result, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError(
            f"{name} = {reprlib.repr(value)} is not allowed: its {what} is beyond the range of "
            "a float (it overflows); give a smaller one"
        )
    return a


#: bytes per point that stability_map holds at once: the slopes, their product's temporary,
#: the searchsorted indices and the counts, 8 bytes each
GRID_BYTES_PER_POINT = 32


def _check_grid_memory(n_omega: int, n_wob: int) -> None:
    """Refuse, before it is allocated, a ``stability_map`` grid larger than the memory
    available now: numpy's lazy pages let a grid past it start, and the kernel's OOM killer
    then ended the whole process part way (two axes of 1e5 values take 320 GB)."""
    import psutil  # a dependency of distributed's

    need = GRID_BYTES_PER_POINT * n_omega * n_wob
    free = psutil.virtual_memory().available
    if need > free:
        raise ValueError(
            f"a grid of {n_wob} wob x {n_omega} omega values is not allowed here: it needs about "
            f"{need / 1e9:.3g} GB of memory and {free / 1e9:.3g} GB is available; give shorter "
            "axes, or map the grid in parts"
        )
