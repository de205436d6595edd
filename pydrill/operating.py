"""The (W_ob, u) map of what the bit does (the paper's Figs. 6b and 12 in one picture).

Section 3 of the paper: when u ≤ T_s = μ_sb W_ob R_b the quasi-equilibrium of the sliding motion
(the bit held, the string wound to T_e = u) is real and attracting, so the bit can stay stuck;
the lines u = ±μ_sb W_ob R_b bound that region. Section 4: a steady state Ω > 0 drills smoothly
only if it is stable, i.e. its Stribeck slope lies below the first destabilising δ_k. The safe
drilling parameters are where neither happens: a stable steady state and u > T_s.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .model import Params
from .stability import (
    Crossing,
    _check_crossings,
    boundary_wob,
    critical_deltas,
    stribeck_slope,
    unstable_count,
)

#: Category of each (W_ob, u) cell, by code.
CATEGORIES = (
    "stable steady state, cannot stay stuck",  # 0  the paper's safe set: no Hopf, no stuck
    "stable steady state, can stay stuck",  # 1  u ≤ T_s: steady or stuck by history
    "no stable steady state, cannot stay stuck",  # 2  u > T_s: stick-slip or oscillation
    "no stable steady state, can stay stuck",  # 3  u ≤ T_s: stuck (or stick-slip near the line)
)


@dataclass(frozen=True)
class OperatingMap:
    wob: NDArray[np.float64]  #: N, shape (nw,)
    torque: NDArray[np.float64]  #: N·m, shape (nu,)
    category: NDArray[np.int8]  #: shape (nu, nw), codes into CATEGORIES
    static_torque: NDArray[np.float64]  #: T_s(W_ob) = μ_sb W_ob R_b, shape (nw,)
    safe_torque_min: NDArray[np.float64]  #: least u with safe drilling at each W_ob (N·m)

    def fractions(self) -> dict[str, float]:
        return {name: float(np.mean(self.category == code)) for code, name in enumerate(CATEGORIES)}


def _steady_torque(params: Params, wob: float, omega: float) -> float:
    """u of the steady state Ω at ``wob``: the core's friction law, not a copy of it."""
    from . import equilibrium_torque

    if omega == 0.0:  # not a steady state (the core refuses it); its limit Ω → 0+ is T_s
        return params.mu_static * wob * params.bit_radius
    return equilibrium_torque(params, wob, omega)


def stable_torques(
    params: Params, wob: float, crossings: list[Crossing]
) -> list[tuple[float, float]]:
    """Intervals of surface torque over which a stable steady state exists at ``wob``, exact.

    The Stribeck slope δ(Ω) falls from δ(0) to 0 as Ω grows, so stability changes only at the
    Ω_k where δ(Ω_k) = δ_k, a crossing's (closed form, :func:`stribeck_slope` inverted). On each
    piece of Ω between them the count of unstable eigenvalues is constant; u(Ω) = cΩ + T_fb(Ω)
    is convex (u'' = −δ' > 0), so over a piece it is least at Ω_c, where δ(Ω_c) = c, or at an
    end, and greatest at an end (unbounded on the last piece). Each (lo, hi) is open: an end
    is T_s (Ω → 0+, the stuck bit) or u on a stability boundary, held by no stable state.

    ``crossings`` must be ``critical_deltas(params)`` (another string's are refused when they
    can be told apart: a fold elsewhere than at c_r + c_b)."""
    return _stable_torques(params, wob, _check_crossings(params, crossings))


def _stable_torques(
    params: Params, wob: float, crossings: list[Crossing]
) -> list[tuple[float, float]]:
    """:func:`stable_torques` of crossings already checked (any crossings: its arithmetic)."""
    p = params
    g = p.stribeck_decay / p.stribeck_velocity
    top = float(stribeck_slope(p, wob, 0.0))  # δ(0)

    def omega_at(delta: float) -> float:  # δ(Ω) = delta, for 0 < delta <= δ(0)
        return float(np.log(top / delta) / g)

    cuts = sorted(omega_at(c.delta) for c in crossings if 0 < c.delta < top)
    ends = [0.0, *cuts, np.inf]
    c_total = p.top_damping + p.bit_damping
    omega_c = omega_at(c_total) if 0 < c_total < top else 0.0
    pieces = list(itertools.pairwise(ends))
    # Every piece's count at once: one call per piece checked the whole list of crossings
    # each time, O(crossings²) per W_ob, and map --dof 2000 took 100 s, nearly all of it here.
    mids = np.array([a + 1.0 if b == np.inf else 0.5 * (a + b) for a, b in pieces])
    counts = unstable_count(crossings, stribeck_slope(p, wob, mids))
    intervals: list[tuple[float, float]] = []
    for (a, b), count in zip(pieces, counts, strict=True):
        if count != 0:
            continue
        lo = _steady_torque(p, wob, min(max(omega_c, a), b))
        hi = np.inf if b == np.inf else max(_steady_torque(p, wob, a), _steady_torque(p, wob, b))
        intervals.append((lo, hi))
    return intervals


def _grid(name: str, values: ArrayLike) -> NDArray[np.float64]:
    """A grid axis as a 1-d float array: numbers (not strings), finite, at least one."""
    arr = np.atleast_1d(np.asarray(values))
    if arr.dtype.kind not in "iuf" or arr.ndim != 1:
        raise TypeError(f"{name} must be a number or a 1-d sequence of numbers, not {values!r}")
    arr = arr.astype(float)
    if arr.size == 0:
        raise ValueError(f"{name} is empty: give at least one value")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} = {arr[~np.isfinite(arr)][0]} is not allowed: finite values only")
    return arr


def operating_map(
    params: Params,
    wob: ArrayLike,
    torque: ArrayLike,
    crossings: list[Crossing] | None = None,
) -> OperatingMap:
    """Classify every (W_ob, u) of the grid ``wob`` × ``torque`` (see :data:`CATEGORIES`)."""
    wob, torque = _grid("wob", wob), _grid("torque", torque)
    if np.any(wob <= 0):
        raise ValueError(f"wob = {wob[wob <= 0][0]:g} is not allowed: every wob must be > 0 N")
    crossings = (
        critical_deltas(params) if crossings is None else _check_crossings(params, crossings)
    )
    ts = params.mu_static * wob * params.bit_radius
    category = np.empty((torque.size, wob.size), dtype=np.int8)
    safe_min = np.full(wob.size, np.inf)
    # The friction law is odd in Ω, so u < 0 mirrors |u| (the steady state turns backwards
    # at −Ω with the same eigenvalues): the intervals of stable torque hold for |u|.
    size = np.abs(torque)
    for j, w in enumerate(wob):
        has_stable = np.zeros(torque.size, dtype=bool)
        for lo, hi in _stable_torques(params, w, crossings):
            # Open at both ends: an end is T_s, the limit Ω -> 0+ (the stuck bit, not a
            # steady state), or u on a stability boundary. u = T_s was called stable at
            # small W_ob, where stability() finds no steady state at all.
            has_stable |= (size > lo) & (size < hi)
            if hi > ts[j]:
                safe_min[j] = min(safe_min[j], max(lo, ts[j]))
        stuck_possible = size <= ts[j]
        category[:, j] = np.where(
            has_stable, np.where(stuck_possible, 1, 0), np.where(stuck_possible, 3, 2)
        )
    return OperatingMap(wob, torque, category, ts, safe_min)


def hopf_curve_wu(
    params: Params, delta: float, omega: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The two-parameter Hopf (or fold) curve δ(Ω, W_ob) = δ_k in (W_ob, u), by Ω: at the
    ``omega`` (1-D) where its W_ob is at most 1e300 N (beyond, the boundary's exponential
    overflows a float; a figure's axes end far below). A crossing at δ = 0 has no curve in the
    map (its W_ob is 0 at every Ω): empty arrays."""
    omega = np.asarray(omega, dtype=float)
    if delta == 0:  # (the logarithm below divided by it: ZeroDivisionError)
        return np.empty(0), np.empty(0)
    # Ω where W_ob = δ exp(γ_b Ω / v_f) / factor reaches 1e300, in logarithms (no overflow):
    # a string of γ_b = 20 failed every map of its atlas ("wob = inf is not allowed").
    p = params
    factor = p.bit_radius * p.stribeck_decay / p.stribeck_velocity * (p.mu_static - p.mu_coulomb)
    reach = p.stribeck_velocity / p.stribeck_decay * (300 * np.log(10) + np.log(factor / delta))
    omega = np.compress(omega <= reach, omega)
    w = boundary_wob(params, delta, omega)
    # The core's friction law point by point, its checks done once (w > 0 and Ω >= 0 here):
    # 60001 points take 0.04 s this way, 0.8 s through the checked pydrill.equilibrium_torque.
    from . import _core

    core = params.to_core()
    u = [
        params.mu_static * wi * params.bit_radius  # Ω = 0: its limit, T_s
        if om == 0.0
        else _core.equilibrium_torque(core, float(wi), float(om))
        for wi, om in zip(w.ravel(), omega.ravel(), strict=True)
    ]
    return w, np.reshape(u, w.shape)
