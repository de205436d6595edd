"""Operating windows: for a string at a depth, the (W_ob, surface rpm) where drilling is safe.

In steady drilling every element, the top drive included, turns at Ω, so surface rpm and Ω are
one axis. At (W_ob, Ω) the steady state needs the torque u = (c_r + c_b)Ω + W_ob R_b μ_b(Ω);
it is *safe* when it is stable (its Stribeck slope below the string's first destabilising δ_k)
and the bit cannot stay stuck (u > T_s = μ_sb W_ob R_b, Section 3): the paper's intersection
of no-Hopf and no-stuck, on the axes a driller sets.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .model import Params
from .stability import Crossing, critical_deltas, stribeck_slope, unstable_count

RPM = 2 * np.pi / 60


@dataclass(frozen=True)
class Window:
    wob: NDArray[np.float64]  #: N, shape (nw,)
    rpm: NDArray[np.float64]  #: surface rpm, shape (nr,)
    stable: NDArray[np.bool_]  #: (nr, nw): the steady state is stable
    unstick: NDArray[np.bool_]  #: (nr, nw): u > T_s, the bit cannot stay stuck
    torque: NDArray[np.float64]  #: (nr, nw): surface torque of the steady state, N·m

    @property
    def safe(self) -> NDArray[np.bool_]:
        return self.stable & self.unstick

    def min_rpm(self) -> NDArray[np.float64]:
        """Least safe surface rpm at each W_ob (NaN where no rpm of the grid is safe)."""
        out = np.full(self.wob.size, np.nan)
        for j in range(self.wob.size):
            ok = np.flatnonzero(self.safe[:, j])
            if ok.size:
                out[j] = self.rpm[ok[0]]
        return out


def operating_window(
    params: Params, wob: ArrayLike, rpm: ArrayLike, crossings: list[Crossing] | None = None
) -> Window:
    wob = np.asarray(wob, dtype=float)
    rpm = np.asarray(rpm, dtype=float)
    if np.any(wob <= 0) or np.any(rpm <= 0):
        raise ValueError("wob and rpm values must be > 0")
    if crossings is None:
        crossings = critical_deltas(params)
    p = params
    omega = rpm[:, None] * RPM
    w = wob[None, :]
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(
        -p.stribeck_decay * omega / p.stribeck_velocity
    )
    torque = (p.top_damping + p.bit_damping) * omega + w * p.bit_radius * mu
    stable = unstable_count(crossings, stribeck_slope(p, w, omega)) == 0
    unstick = torque > p.mu_static * w * p.bit_radius
    return Window(wob, rpm, stable, np.broadcast_to(unstick, stable.shape).copy(), torque)
