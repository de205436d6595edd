"""The (W_ob, u) map of what the bit does (the paper's Figs. 6b and 12 in one picture).

Section 3 of the paper: when u ≤ T_s = μ_sb W_ob R_b the quasi-equilibrium of the sliding motion
(the bit held, the string wound to T_e = u) is real and attracting, so the bit can stay stuck;
the lines u = ±μ_sb W_ob R_b bound that region. Section 4: a steady state Ω > 0 drills smoothly
only if it is stable, i.e. its Stribeck slope lies below the first destabilising δ_k. The safe
drilling parameters are where neither happens: a stable steady state and u > T_s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .model import Params
from .stability import Crossing, boundary_wob, critical_deltas, stribeck_slope, unstable_count

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


def stable_torques(
    params: Params, wob: float, crossings: list[Crossing], samples: int = 4000
) -> list[tuple[float, float]]:
    """Intervals of surface torque over which a stable steady state exists at ``wob``."""
    p = params
    c = p.top_damping + p.bit_damping
    g = p.stribeck_decay / p.stribeck_velocity
    # Ω up to where the damping torque alone exceeds any torque of interest.
    omega = np.geomspace(1e-6, 200.0 / g, samples)
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-g * omega)
    u = c * omega + wob * p.bit_radius * mu
    stable = unstable_count(crossings, stribeck_slope(p, wob, omega)) == 0
    intervals = []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], stable.astype(int), [0]])))
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        intervals.append((float(u[a:b].min()), float(u[a:b].max()) if b < len(u) else np.inf))
    return intervals


def operating_map(
    params: Params,
    wob: ArrayLike,
    torque: ArrayLike,
    crossings: list[Crossing] | None = None,
) -> OperatingMap:
    """Classify every (W_ob, u) of the grid ``wob`` × ``torque`` (see :data:`CATEGORIES`)."""
    wob = np.asarray(wob, dtype=float)
    torque = np.asarray(torque, dtype=float)
    if np.any(wob <= 0) or not np.all(np.isfinite(wob)):
        raise ValueError("wob values must be finite and > 0 (N)")
    if crossings is None:
        crossings = critical_deltas(params)
    ts = params.mu_static * wob * params.bit_radius
    category = np.empty((torque.size, wob.size), dtype=np.int8)
    safe_min = np.full(wob.size, np.inf)
    for j, w in enumerate(wob):
        has_stable = np.zeros(torque.size, dtype=bool)
        for lo, hi in stable_torques(params, w, crossings):
            has_stable |= (torque >= lo) & (torque <= hi)
            if hi > ts[j]:
                safe_min[j] = min(safe_min[j], max(lo, ts[j]))
        stuck_possible = np.abs(torque) <= ts[j]
        category[:, j] = np.where(
            has_stable, np.where(stuck_possible, 1, 0), np.where(stuck_possible, 3, 2)
        )
    return OperatingMap(wob, torque, category, ts, safe_min)


def hopf_curve_wu(
    params: Params, delta: float, omega: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The two-parameter Hopf (or fold) curve δ(Ω, W_ob) = δ_k in (W_ob, u), by Ω."""
    omega = np.asarray(omega, dtype=float)
    w = boundary_wob(params, delta, omega)
    p = params
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(
        -p.stribeck_decay * omega / p.stribeck_velocity
    )
    return w, (p.top_damping + p.bit_damping) * omega + w * p.bit_radius * mu
